/* montecarlo.h - run units [first, end) of a config in parallel.
 *
 * OpenMP over units, dynamic schedule, one family workspace per thread.
 * results[u - first] is filled for each unit; since a unit's draws depend
 * only on (seed, u) and aggregation is in unit order, the results do not
 * depend on the thread count.
 */
#ifndef SUNMC_MONTECARLO_H
#define SUNMC_MONTECARLO_H

#include "config.h"
#include "family.h"

/* Called from one thread now and then (done units, total); may be NULL. */
typedef void (*mc_progress_fn)(long done, long total, void *ctx);

/* threads: 0 = OpenMP's default.  Returns SUNMC_OK, or the first error of a
 * family workspace allocation or unit run (message in err). */
int mc_run(const sunmc_config *c, const sensor_family *fam, long first, long end, int threads,
           unit_result *results, mc_progress_fn progress, void *ctx, char *err, size_t errlen);

#endif
