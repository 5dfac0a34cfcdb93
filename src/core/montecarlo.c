/* montecarlo.c - the parallel loop over units, whole or in blocks. */
#include "montecarlo.h"
#include "status.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

/* Units handed to a thread at a time: small enough to balance two cores. */
#define MC_CHUNK 4

/* Shared state of one parallel region. */
typedef struct {
    const sunmc_config *c;
    const sensor_family *fam;
    int status;
    long done, total;
    mc_progress_fn progress;
    void *ctx;
    char *err;
    size_t errlen;
} mc_shared;

static void mc_fail(mc_shared *s, int st, const char *msg, long u)
{
#pragma omp critical(mc_error)
    if (s->status == SUNMC_OK)
        s->status = u < 0 ? sunmc_fail(s->err, s->errlen, st, "%s", msg)
                          : sunmc_fail(s->err, s->errlen, st, "unit %ld: simulation failed", u);
}

/* Units [first, end) into results[u - first], shared by the calling team
 * (an orphaned `omp for`; its end is a barrier). */
static void run_units(mc_shared *s, void *ws, long first, long end, unit_result *results)
{
#pragma omp for schedule(dynamic, MC_CHUNK)
    for (long u = first; u < end; u++) {
        int st;
#pragma omp atomic read
        st = s->status;
        if (!ws || st != SUNMC_OK)
            continue;
        int rs = s->fam->unit_run(s->c, u, ws, &results[u - first]);
        if (rs != SUNMC_OK)
            mc_fail(s, rs, "", u);
        long d;
#pragma omp atomic capture
        d = ++s->done;
        if (s->progress && omp_get_thread_num() == 0)
            s->progress(d, s->total, s->ctx);
    }
}

/* Each thread's family workspace (NULL after a failure, recorded in s). */
static void *workspace(mc_shared *s)
{
    char terr[SUNMC_ERRLEN] = "";
    void *ws = s->fam->workspace_alloc(s->c, terr, sizeof terr);
    if (!ws)
        mc_fail(s, SUNMC_ENOMEM, terr, -1);
    return ws;
}

int mc_run(const sunmc_config *c, const sensor_family *fam, long first, long end, int threads,
           unit_result *results, mc_progress_fn progress, void *ctx, char *err, size_t errlen)
{
    mc_shared s = {c, fam, SUNMC_OK, 0, end - first, progress, ctx, err, errlen};
    if (threads > 0)
        omp_set_num_threads(threads);
#pragma omp parallel
    {
        void *ws = workspace(&s);
        run_units(&s, ws, first, end, results);
        if (ws)
            fam->workspace_free(ws);
    }
    return s.status;
}

int mc_stream(const sunmc_config *c, const sensor_family *fam, const mc_plan *p, long *done,
              char *err, size_t errlen)
{
    long bsize = p->block_units > 0 ? p->block_units : 1;
    long span = p->end - p->first;
    unit_result *buf = calloc((size_t)(span < bsize ? (span > 0 ? span : 1) : bsize), sizeof *buf);
    if (!buf)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for a block of %ld units",
                          bsize);
    mc_shared s = {c, fam, SUNMC_OK, 0, span, p->progress, p->progress_ctx, err, errlen};
    long handed = 0;
    int stop = 0;
    if (p->threads > 0)
        omp_set_num_threads(p->threads);
#pragma omp parallel
    {
        void *ws = workspace(&s);
        for (long b0 = p->first; b0 < p->end; b0 += bsize) {
            long b1 = b0 + bsize < p->end ? b0 + bsize : p->end;
            run_units(&s, ws, b0, b1, buf);
            /* The block is complete (barrier): one thread hands it on while
             * the others wait, so every thread sees the same stop. */
#pragma omp single
            if (s.status == SUNMC_OK) {
                int st = p->sink(buf, b1 - b0, p->sink_ctx, &stop, err, errlen);
                if (st != SUNMC_OK)
                    s.status = st;
                else
                    handed += b1 - b0;
            }
            if (stop || s.status != SUNMC_OK)
                break;
        }
        if (ws)
            fam->workspace_free(ws);
    }
    free(buf);
    if (done)
        *done = handed;
    return s.status;
}
