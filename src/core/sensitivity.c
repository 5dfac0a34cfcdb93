/* sensitivity.c - Sobol indices by pick-freeze on the per-purpose random
 * streams (sensitivity.h). */
#include "sensitivity.h"
#include "report.h"
#include "thermal.h"
#include "budget.h"
#include "montecarlo.h"
#include "status.h"
#include "unit_store.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int add_source(sens_result *s, const char *name, int kind, const char *keys,
                      uint32_t stream, char *err, size_t errlen)
{
    if (s->n >= SENS_MAX_SOURCES)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "more than %d random inputs",
                          SENS_MAX_SOURCES);
    sens_source *src = &s->src[s->n++];
    snprintf(src->name, sizeof src->name, "%s", name);
    snprintf(src->keys, sizeof src->keys, "%s", keys);
    src->kind = kind;
    src->stream = stream;
    return SUNMC_OK;
}

/* The value of a "section.key" number key of c's family; 0 when unknown. */
static double dotted_value(const sunmc_config *c, const char *dotted)
{
    char err[SUNMC_ERRLEN];
    double v;
    return config_get_number(c, dotted, &v, err, sizeof err) == SUNMC_OK ? v : 0.0;
}

/* A noise stream is an input when any key scaling it is > 0. */
static int noise_sources(const sunmc_config *c, sens_result *s, char *err, size_t errlen)
{
    for (const family_noise *nz = c->family->noise; nz && nz->name; nz++) {
        char keys[2 * CONFIG_STR_MAX] = "";
        int on = 0;
        for (const char *const *k = nz->keys; *k; k++) {
            on |= dotted_value(c, *k) > 0;
            size_t len = strlen(keys);
            snprintf(keys + len, sizeof keys - len, "%s%s", len ? ", " : "", *k);
        }
        on &= !nz->active || nz->active(c);
        int rc = on ? add_source(s, nz->name, SENS_NOISE, keys, nz->stream, err, errlen) : 0;
        if (rc)
            return rc;
    }
    return SUNMC_OK;
}

int sens_sources(const sunmc_config *c, sens_result *s, char *err, size_t errlen)
{
    memset(s, 0, sizeof *s);
    const sensor_family *fam = c->family;
    budget_row(c, &s->angle, &s->band);
    if (!fam->deviations && !fam->noise)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "family %s declares no random inputs: no sensitivity", fam->name);
    for (int e = 0; e < fam->n_deviations; e++) {
        const deviation_spec *d = &fam->deviations[e];
        const tolerance *t = (const tolerance *)(const void *)(c->fam.bytes + d->tol_offset);
        if (!(t->value > 0) || t->dist == DIST_FIXED)
            continue;
        char keys[2 * CONFIG_STR_MAX];
        snprintf(keys, sizeof keys, "tolerance.%s", d->name);
        int rc = add_source(s, d->name, SENS_TOLERANCE, keys, RNG_STREAM_TOLERANCE + d->stream,
                            err, errlen);
        if (rc)
            return rc;
    }
    int rc = noise_sources(c, s, err, errlen);
    if (rc)
        return rc;
    if (s->n == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "no random input varies (every tolerance 0 or fixed, every noise 0)");
    return SUNMC_OK;
}

int sens_random_inputs(const sunmc_config *c)
{
    sens_result *s = malloc(sizeof *s);
    char err[SUNMC_ERRLEN];
    if (!s)
        return -1;
    (void)sens_sources(c, s, err, sizeof err); /* its count, also when it refuses */
    int n = s->n;
    free(s);
    return n;
}

/* Y before and after of config c's units res[0, units): NaN without a
 * fit. */
static void y_of(const sunmc_config *c, const sens_result *s, const unit_result *res,
                 long units, double *yb, double *ya)
{
    for (long u = 0; u < units; u++) {
        double b = unit_primary_before(c, &res[u], s->angle, s->band);
        double a = unit_primary_after(c, &res[u], s->angle, s->band);
        int ok = res[u].fit_status == UNIT_FIT_OK && isfinite(b) && isfinite(a);
        yb[u] = ok ? b : NAN;
        ya[u] = ok ? a : NAN;
    }
}

/* Keep the rows finite in every run (A, B, each A_B^i), compacting each of
 * the (d + 2) columns of y (units each, before then after); their count. */
static long pair_rows(double *y, int cols, long units)
{
    long k = 0;
    for (long u = 0; u < units; u++) {
        int ok = 1;
        for (int j = 0; j < 2 * cols; j++)
            ok = ok && isfinite(y[(size_t)j * (size_t)units + (size_t)u]);
        if (!ok)
            continue;
        for (int j = 0; j < 2 * cols; j++)
            y[(size_t)j * (size_t)units + (size_t)k] = y[(size_t)j * (size_t)units + (size_t)u];
        k++;
    }
    return k;
}

/* Mean and variance (divisor 2n) of the 2n values of A and B. */
static void moments(const double *fa, const double *fb, long n, double *mean, double *var)
{
    double s = 0, ss = 0;
    for (long j = 0; j < n; j++)
        s += fa[j] + fb[j];
    double m = n > 0 ? s / (double)(2 * n) : NAN;
    for (long j = 0; j < n; j++)
        ss += (fa[j] - m) * (fa[j] - m) + (fb[j] - m) * (fb[j] - m);
    *mean = m;
    *var = n > 0 ? ss / (double)(2 * n) : NAN;
}

/* Indices of the paired rows into s, before (after = 0) or after. */
static int indices(const sunmc_config *c, sens_result *s, const double *y, long units, long n,
                   int after, char *err, size_t errlen)
{
    int cols = s->n + 2;
    size_t nn = (size_t)n;
    double *fab = malloc((size_t)s->n * (nn ? nn : 1) * sizeof *fab);
    stats_sobol_index *idx = malloc((size_t)s->n * sizeof *idx);
    int rc = fab && idx ? SUNMC_OK : SUNMC_ENOMEM;
    const double *fa = y + (size_t)(after * cols) * (size_t)units;
    const double *fb = fa + (size_t)units;
    for (int i = 0; rc == SUNMC_OK && i < s->n; i++)
        memcpy(fab + (size_t)i * nn, fa + (size_t)(2 + i) * (size_t)units, nn * sizeof *fab);
    if (rc == SUNMC_OK)
        rc = stats_sobol(fa, fb, fab, nn, (size_t)s->n, SENS_BOOTSTRAP, SENS_BOOT_SEED,
                         c->confidence, idx, err, errlen);
    else
        sunmc_fail(err, errlen, rc, "out of memory for the indices of %ld units", n);
    for (int i = 0; rc == SUNMC_OK && i < s->n; i++)
        *(after ? &s->src[i].after : &s->src[i].before) = idx[i];
    if (rc == SUNMC_OK)
        moments(fa, fb, n, after ? &s->mean_after : &s->mean_before,
                after ? &s->var_after : &s->var_before);
    free(fab);
    free(idx);
    return rc;
}

/* Run j's config: A (j = 0), B (j = 1), A with input j - 2's stream from B. */
static void run_config(const sunmc_config *c, const sens_result *s, int j, sunmc_config *t)
{
    *t = *c;
    t->pick.n = 0;
    t->no_systematic = 1; /* the indices read no systematic part */
    if (j == 1)
        t->seed = s->seed_b;
    if (j >= 2) {
        t->pick.seed = s->seed_b;
        t->pick.n = 1;
        t->pick.stream[0] = s->src[j - 2].stream;
    }
}

/* Where mc_run_each's results go: run j's column of y (stride units),
 * from unit first on. */
typedef struct {
    const sens_result *s;
    const sunmc_config *t;
    long units, first;
    int cols;
    double *y;
    sens_progress_fn progress;
    void *ctx;
} sens_sink;

static int sens_each(int j, const unit_result *res, long n, void *ctx, char *err, size_t errlen)
{
    const sens_sink *k = ctx;
    size_t at = (size_t)k->first;
    y_of(&k->t[j], k->s, res, n, k->y + (size_t)j * (size_t)k->units + at,
         k->y + (size_t)(k->cols + j) * (size_t)k->units + at);
    return SUNMC_OK;
}

static void sens_done(long done, long total, void *ctx)
{
    const sens_sink *k = ctx;
    k->progress("Monte Carlo runs", (int)done, (int)total, k->ctx);
}

/* The d + 2 runs' configs: A, B, then A with each input's stream from B. */
typedef struct {
    int cols;
    sunmc_config *t;
    const sunmc_config *runs[SENS_MAX_SOURCES + 2];
    unit_store *store; /* A's validation readings, for the runs that read the same */
} sens_plan;

static int plan_alloc(const sunmc_config *c, const sens_result *s, long capacity, sens_plan *p,
                      char *err, size_t errlen)
{
    p->cols = s->n + 2;
    p->store = NULL;
    p->t = malloc((size_t)p->cols * sizeof *p->t);
    if (!p->t)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for %d runs", p->cols);
    for (int j = 0; j < p->cols; j++) {
        run_config(c, s, j, &p->t[j]);
        p->runs[j] = &p->t[j];
    }
    return unit_store_alloc_upto(c, capacity, SENS_STORE_MAX_BYTES, &p->store, err, errlen);
}

static void plan_free(sens_plan *p)
{
    unit_store_free(p->store);
    free(p->t);
}

/* Units [first, end) of the d + 2 runs, a run to a thread (mc_run_each:
 * the runs share no barrier); A's validation readings read first into the
 * store, which finishes the runs reading the same (A, and the A_B^i of an
 * input only the campaign draws from: unit_readings_same).  Column j of y
 * (stride units) is run j's before, column cols + j its after. */
static int sens_runs(sens_plan *p, long first, long end, long units, int threads,
                     sens_progress_fn progress, void *ctx, sens_result *s, double *y,
                     char *err, size_t errlen)
{
    for (int j = 1; p->store && j < p->cols; j++)
        s->reused_units += unit_readings_same(&p->t[0], &p->t[j]) ? end - first : 0;
    if (progress)
        progress("Monte Carlo runs", 1, p->cols, ctx);
    sens_sink sink = {s, p->t, units, first, p->cols, y, progress, ctx};
    return mc_run_each(p->runs, p->cols, p->store, first, end, threads, sens_each, &sink,
                       progress ? sens_done : NULL, &sink, err, errlen);
}

/* The paired rows of the first n units of y (stride units) and their
 * indices into s. */
static int estimate(const sunmc_config *c, sens_result *s, double *y, long units, long n,
                    char *err, size_t errlen)
{
    int cols = s->n + 2;
    /* each column to stride n (columns move down only: in place) */
    for (int j = 1; n < units && j < 2 * cols; j++)
        memmove(y + (size_t)j * (size_t)n, y + (size_t)j * (size_t)units,
                (size_t)n * sizeof *y);
    s->units = n;
    s->paired_units = pair_rows(y, cols, n);
    if (s->paired_units < STUDY_MIN_UNITS)
        return sunmc_fail(err, errlen, SUNMC_EDOM,
                          "only %ld of %ld units have a fit in every run, fewer than the %d "
                          "the indices need: not enough units (more --units, or a config "
                          "whose units can be fitted: `sunmc run` counts the failed fits)",
                          s->paired_units, n, STUDY_MIN_UNITS);
    int rc = indices(c, s, y, n, s->paired_units, 0, err, errlen);
    return rc == SUNMC_OK ? indices(c, s, y, n, s->paired_units, 1, err, errlen) : rc;
}

const char *const sens_until_names[SENS_UNTIL_STATS] = {"st", "s1", "st_before", "s1_before"};

/* The widest half-width of u's statistic over s's inputs. */
static double widest(const sens_result *s, int stat)
{
    double w = 0;
    for (int i = 0; i < s->n; i++) {
        const stats_sobol_index *x =
            stat == SENS_UNTIL_ST || stat == SENS_UNTIL_S1 ? &s->src[i].after : &s->src[i].before;
        int st = stat == SENS_UNTIL_ST || stat == SENS_UNTIL_ST_BEFORE;
        double h = st ? 0.5 * (x->st_hi - x->st_lo) : 0.5 * (x->s1_hi - x->s1_lo);
        w = isnan(h) ? INFINITY : fmax(w, h);
    }
    return w;
}

/* The check after a block of units [0, n): the indices of a copy of y. */
static int until_check(const sunmc_config *c, const sens_result *s, const double *y, long units,
                       long n, sens_until *u, char *err, size_t errlen)
{
    int cols = s->n + 2;
    double *cy = malloc((size_t)(2 * cols) * (size_t)n * sizeof *cy);
    sens_result *cs = malloc(sizeof *cs);
    int rc = cy && cs ? SUNMC_OK : sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    for (int j = 0; rc == SUNMC_OK && j < 2 * cols; j++)
        memcpy(cy + (size_t)j * (size_t)n, y + (size_t)j * (size_t)units, (size_t)n * sizeof *cy);
    if (rc == SUNMC_OK) {
        *cs = *s;
        rc = estimate(c, cs, cy, n, n, err, errlen);
    }
    if (rc == SUNMC_EDOM) /* too few fitted units so far: go on */
        rc = SUNMC_OK, u->reached = INFINITY;
    else if (rc == SUNMC_OK)
        u->reached = widest(cs, u->stat);
    u->met = rc == SUNMC_OK && u->reached <= u->halfwidth;
    free(cy);
    free(cs);
    return rc;
}

/* Checks what sens_run and sens_run_until share; allocates y. */
static int sens_start(const sunmc_config *c, long units, sens_result *s, double **y, char *err,
                      size_t errlen)
{
    int rc = sens_sources(c, s, err, errlen);
    if (rc)
        return rc;
    if (units < STUDY_MIN_UNITS)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "sensitivity needs at least %d units, not %ld",
                          STUDY_MIN_UNITS, units);
    /* the bootstrap resamples units as independent rows; a design's units
     * are not (sampling.h), so its intervals would be too narrow */
    if (c->sampling != CONFIG_SAMPLING_RANDOM)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "sensitivity's bootstrap intervals need independent units: set "
                          "run.sampling = random (a design's blocks are not independent rows)");
    s->units = units;
    s->seed = c->seed;
    s->seed_b = c->seed ^ SENS_SEED_B_XOR;
    int cols = s->n + 2;
    *y = malloc((size_t)(2 * cols) * (size_t)units * sizeof **y);
    if (!*y)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for %ld units x %d runs",
                          units, cols);
    return SUNMC_OK;
}

/* sens_run (until NULL: one block of every unit, progress per run) and
 * sens_run_until (blocks of until->block, a check after each, progress
 * per block). */
static int run_blocks(const sunmc_config *c, long units, sens_until *until, int threads,
                      sens_progress_fn progress, void *ctx, sens_result *s, char *err,
                      size_t errlen)
{
    double *y = NULL;
    int rc = sens_start(c, units, s, &y, err, errlen);
    long block = until && until->block < units ? until->block : units, end = 0;
    int blocks = (int)((units + block - 1) / block);
    sens_plan p = {0};
    if (until) {
        until->met = 0;
        until->reached = INFINITY;
    }
    if (rc == SUNMC_OK)
        rc = plan_alloc(c, s, block, &p, err, errlen);
    for (int b = 0; rc == SUNMC_OK && end < units && !(until && until->met); b++) {
        long first = end;
        end = units - first < block ? units : first + block;
        if (until && progress)
            progress("block", b + 1, blocks, ctx);
        rc = sens_runs(&p, first, end, units, threads, until ? NULL : progress, ctx, s, y, err,
                       errlen);
        if (rc == SUNMC_OK && until)
            rc = until_check(c, s, y, units, end, until, err, errlen);
    }
    if (rc == SUNMC_OK)
        rc = estimate(c, s, y, units, end, err, errlen);
    plan_free(&p);
    free(y);
    return rc;
}

int sens_run(const sunmc_config *c, long units, int threads, sens_progress_fn progress,
             void *ctx, sens_result *s, char *err, size_t errlen)
{
    return run_blocks(c, units, NULL, threads, progress, ctx, s, err, errlen);
}

int sens_run_until(const sunmc_config *c, long units, sens_until *until, int threads,
                   sens_progress_fn progress, void *ctx, sens_result *s, char *err,
                   size_t errlen)
{
    if (!(until->halfwidth > 0) || until->block < 1 || until->stat < 0 ||
        until->stat >= SENS_UNTIL_STATS)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--until: a half-width > 0 and blocks of "
                                                     "at least 1 unit");
    return run_blocks(c, units, until, threads, progress, ctx, s, err, errlen);
}
