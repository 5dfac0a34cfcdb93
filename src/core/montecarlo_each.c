/* montecarlo_each.c - the same units of several configs, a config to a
 * thread (montecarlo.h: mc_run_each). */
#include "montecarlo.h"
#include "modelform.h"
#include "status.h"
#include "unit_store.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

/* Shared state of the parallel region. */
typedef struct {
    const sunmc_config *const *c;
    int n;
    unit_store *store;
    const unsigned char *served; /* n flags: config i's readings come from the store */
    long first, end;
    mc_each_fn each;
    void *ctx;
    mc_progress_fn progress;
    void *progress_ctx;
    long done;
    int status;
    char *err;
    size_t errlen;
} each_shared;

static void each_fail(each_shared *s, int st, const char *msg)
{
#pragma omp critical(mc_each_error)
    if (s->status == SUNMC_OK)
        s->status = sunmc_fail(s->err, s->errlen, st, "%s", msg);
}

static int failed(each_shared *s)
{
    int st;
#pragma omp atomic read
    st = s->status;
    return st != SUNMC_OK;
}

/* The store's units read, shared among the team (an orphaned `omp for`). */
static void fill_store(each_shared *s)
{
    char terr[SUNMC_ERRLEN] = "";
    const sunmc_config *c = s->c[0];
    void *ws = s->store ? c->family->workspace_alloc(c, terr, sizeof terr) : NULL;
    if (s->store && !ws)
        each_fail(s, SUNMC_ENOMEM, terr);
#pragma omp for schedule(dynamic, 1)
    for (long u = s->first; u < s->end; u++) {
        int held;
        void *rd = ws && !failed(s) ? unit_store_slot(s->store, u, &held) : NULL;
        if (!rd || held)
            continue;
        if (c->family->unit_read(c, u, ws, rd) == SUNMC_OK)
            unit_store_fill(s->store, u);
        else
            each_fail(s, SUNMC_EINPUT, "reading the validation failed");
    }
    if (ws)
        c->family->workspace_free(ws);
}

/* Config i's units in order into buf, then to the sink. */
static int run_config(each_shared *s, int i, unit_result *buf, char *terr, size_t tlen)
{
    const sunmc_config *c = s->c[i];
    const sensor_family *fam = c->family;
    sunmc_config mfc;
    const sunmc_config *mf;
    modelform_pass pass = {NULL, NULL, NULL};
    int st = modelform_setup(c, &mfc, &mf, terr, tlen);
    if (st == SUNMC_OK)
        st = modelform_pass_init(&pass, mf, terr, tlen);
    void *ws = st == SUNMC_OK ? fam->workspace_alloc(c, terr, tlen) : NULL;
    if (!ws) {
        modelform_pass_free(&pass);
        return st == SUNMC_OK ? SUNMC_ENOMEM : st;
    }
    for (long u = s->first; u < s->end && st == SUNMC_OK && !failed(s); u++) {
        int held = 0;
        void *rd = s->served[i] ? unit_store_slot(s->store, u, &held) : NULL;
        unit_result *r = &buf[u - s->first];
        st = rd && held ? fam->unit_finish(c, u, ws, rd, r) : fam->unit_run(c, u, ws, r);
        if (st == SUNMC_OK)
            st = modelform_pass_run(&pass, c, u, r);
        if (st != SUNMC_OK)
            snprintf(terr, tlen, "unit %ld: simulation failed", u);
    }
    fam->workspace_free(ws);
    modelform_pass_free(&pass);
    if (st == SUNMC_OK && !failed(s))
        st = s->each(i, buf, s->end - s->first, s->ctx, terr, tlen);
    return st;
}

static void run_configs(each_shared *s)
{
    unit_result *buf = malloc((size_t)(s->end - s->first) * sizeof *buf);
    if (!buf)
        each_fail(s, SUNMC_ENOMEM, "out of memory for a block of results");
#pragma omp for schedule(dynamic, 1)
    for (int i = 0; i < s->n; i++) {
        char terr[SUNMC_ERRLEN] = "";
        if (!buf || failed(s))
            continue;
        int st = run_config(s, i, buf, terr, sizeof terr);
        if (st != SUNMC_OK)
            each_fail(s, st, terr);
        long d;
#pragma omp atomic capture
        d = ++s->done;
        if (s->progress && omp_get_thread_num() == 0)
            s->progress(d, s->n, s->progress_ctx);
    }
    free(buf);
}

int mc_run_each(const sunmc_config *const *c, int n, struct unit_store *store, long first,
                long end, int threads, mc_each_fn each, void *ctx, mc_progress_fn progress,
                void *progress_ctx, char *err, size_t errlen)
{
    if (n <= 0 || end <= first)
        return SUNMC_OK;
    unsigned char *served = calloc((size_t)n, 1);
    if (!served)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    if (!unit_store_bind(store, c[0], first, end))
        store = NULL;
    for (int i = 0; store && i < n; i++)
        served[i] = (unsigned char)unit_store_serves(store, c[i], first, end);
    each_shared s = {c,    n,        store,        served, first, end,      each, ctx,
                     progress, progress_ctx, 0, SUNMC_OK, err,   errlen};
    if (threads > 0)
        omp_set_num_threads(threads);
#pragma omp parallel
    {
        fill_store(&s);
        run_configs(&s);
    }
    free(served);
    return s.status;
}
