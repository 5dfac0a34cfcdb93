/* lab_sim.c - what the files of `sunmc simulate` share between families
 * (lab.h): the head of truth.csv with the simulated unit's deviations. */
#include "lab.h"

#ifndef SUNMC_VERSION
#define SUNMC_VERSION "0.0.0"
#endif

void lab_sim_truth_head(FILE *f, const sunmc_config *c, const lab_unit_ref *ref,
                        const char *const *dev_names, const double *dev_values, int n_dev)
{
    fprintf(f, "# sunmc %s simulate: truth of unit %ld of %s, seed %ld\n", SUNMC_VERSION,
            ref->unit, ref->config, c->seed);
    for (int i = 0; i < n_dev; i++)
        fprintf(f, "# %s = %.17g\n", dev_names[i], dev_values[i]);
}
