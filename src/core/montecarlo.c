/* montecarlo.c - the parallel loop over units. */
#include "montecarlo.h"
#include "status.h"

#include <omp.h>
#include <stdio.h>

/* Units handed to a thread at a time: small enough to balance two cores. */
#define MC_CHUNK 4

int mc_run(const sunmc_config *c, const sensor_family *fam, long first, long end, int threads,
           unit_result *results, mc_progress_fn progress, void *ctx, char *err, size_t errlen)
{
    int status = SUNMC_OK;
    long done = 0;
    long total = end - first;
    if (threads > 0)
        omp_set_num_threads(threads);

#pragma omp parallel
    {
        char terr[SUNMC_ERRLEN] = "";
        void *ws = fam->workspace_alloc(c, terr, sizeof terr);
        if (!ws) {
#pragma omp critical(mc_error)
            if (status == SUNMC_OK)
                status = sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s", terr);
        }
#pragma omp for schedule(dynamic, MC_CHUNK)
        for (long u = first; u < end; u++) {
            int st;
#pragma omp atomic read
            st = status;
            if (!ws || st != SUNMC_OK)
                continue;
            int rs = fam->unit_run(c, u, ws, &results[u - first]);
            if (rs != SUNMC_OK) {
#pragma omp critical(mc_error)
                if (status == SUNMC_OK)
                    status = sunmc_fail(err, errlen, rs, "unit %ld: simulation failed", u);
            }
            long d;
#pragma omp atomic capture
            d = ++done;
            if (progress && omp_get_thread_num() == 0)
                progress(d, total, ctx);
        }
        if (ws)
            fam->workspace_free(ws);
    }
    return status;
}
