/* test_ess_grid.h - a synthetic ESS campaign grid for the fit suites:
 * alphas -62..62 deg in step_deg on each of nb beta lines, weight 1, for a
 * model of kind `kind` (enum ess_model_kind); readings left to the test. */
#ifndef SUNMC_TEST_ESS_GRID_H
#define SUNMC_TEST_ESS_GRID_H

#include "test_util.h"
#include "ess_calib.h"
#include "units.h"

static inline ess_calib_workspace *test_ess_grid(int kind, double step_deg, const double *betas,
                                                 int nb)
{
    long na = (long)floor(124.0 / step_deg + 1e-9) + 1;
    ess_calib_workspace *cw = ess_calib_alloc_kind((size_t)(na * nb), kind);
    assert_non_null(cw);
    size_t i = 0;
    for (int k = 0; k < nb; k++)
        for (long j = 0; j < na; j++, i++) {
            cw->alpha_rad[i] = (-62 + j * step_deg) * RAD_PER_DEG;
            cw->beta_rad[i] = betas[k] * RAD_PER_DEG;
            cw->weight[i] = 1;
        }
    return cw;
}

#endif
