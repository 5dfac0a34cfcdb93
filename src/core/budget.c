/* budget.c - sources, the all / floor / alone runs, shares with intervals,
 * ranks (the inverse limits are in budget_limit.c). */
#include "budget.h"
#include "lab_onboard.h"
#include "thermal.h"
#include "memory.h"
#include "modelform.h"
#include "montecarlo.h"
#include "report.h"
#include "verdict.h"
#include "sensitivity.h"
#include "stats_blocks.h"
#include "status.h"
#include "unit_store.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double get_value(const sunmc_config *cfg, const config_key *k)
{
    return *(const double *)config_value_cptr(k, cfg);
}

void budget_set_tolerance(sunmc_config *cfg, const config_key *key, double value)
{
    *(double *)config_value_ptr(key, cfg) = value;
}

static int add_source(budget_result *b, const config_key *k, const char *name, int kind,
                      double value, char *err, size_t errlen)
{
    for (int i = 0; i < b->n; i++)
        if (b->src[i].key == k)
            return SUNMC_OK; /* a noise key of two streams: one source */
    if (b->n >= BUDGET_MAX_SOURCES)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "more than %d error sources",
                          BUDGET_MAX_SOURCES);
    budget_source *s = &b->src[b->n++];
    snprintf(s->name, sizeof s->name, "%s", name);
    s->key = k;
    s->kind = kind;
    s->tolerance = value;
    return SUNMC_OK;
}

/* The family's noise keys with a value > 0. */
static int noise_sources(const sunmc_config *c, budget_result *b, char *err, size_t errlen)
{
    const sensor_family *fam = c->family;
    for (const family_noise *nz = fam->noise; nz && nz->name; nz++)
        for (const char *const *dotted = nz->keys; *dotted; dotted++) {
            const config_key *k = config_find_dotted(fam, *dotted);
            if (!k || k->type != KEY_DOUBLE)
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "family %s: noise key %s is not a number key", fam->name,
                                  *dotted);
            double v = get_value(c, k);
            if (v > 0 && (!nz->active || nz->active(c))) {
                int rc = add_source(b, k, *dotted, BUDGET_NOISE, v, err, errlen);
                if (rc)
                    return rc;
            }
        }
    return SUNMC_OK;
}

void budget_row(const sunmc_config *c, int *angle, int *band)
{
    *angle = c->family->n_angles(c) - 1;
    *band = 0;
    for (int i = 1; i < c->bands_deg.n; i++)
        if (c->bands_deg.hi[i] - c->bands_deg.lo[i] >=
            c->bands_deg.hi[*band] - c->bands_deg.lo[*band])
            *band = i;
}

int budget_sources(const sunmc_config *c, budget_result *b, char *err, size_t errlen)
{
    memset(b, 0, sizeof *b);
    const sensor_family *fam = c->family;
    budget_row(c, &b->angle, &b->band);
    for (const config_key *k = fam->keys; k && k->section; k++) {
        if (!config_is_tolerance(k, fam) || !(get_value(c, k) > 0))
            continue;
        int rc = add_source(b, k, k->name, BUDGET_TOLERANCE, get_value(c, k), err, errlen);
        if (rc)
            return rc;
    }
    int rc = noise_sources(c, b, err, errlen);
    if (rc)
        return rc;
    if (b->n == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "no tolerance or noise is above 0: the budget has no error source");
    return SUNMC_OK;
}

/* The statistics of row r of units' summary rows into out. */
static int row_stats(const sunmc_config *c, const unit_result *res, long units, int angle,
                     int band, budget_stats *out)
{
    int nr = report_n_rows(c);
    summary_row *rows = calloc((size_t)nr, sizeof *rows);
    int st = rows ? report_summarize(c, res, units, rows) : SUNMC_ENOMEM;
    if (st == SUNMC_OK) {
        const summary_row *r = &rows[report_primary_row(c, angle, band)];
        memset(out, 0, sizeof *out);
        out->before_mean = r->rms_before_mean;
        out->after_mean = r->rms_after_mean;
        out->yield = r->spec_yield; /* the spec's verdict (verdict.h), every band it names */
        out->yield_ci = r->spec_yield_ci;
        out->fit_failures = r->fit_failures;
    }
    free(rows);
    return st;
}

long budget_units_run(const sunmc_config *c, long units)
{
    return units > 1 && sens_random_inputs(c) == 0 ? 1 : units;
}

/* The units [0, units) of c into res (no systematic pass: the budget reads
 * none).  Units [0, head) go through store `head_store` and the rest
 * through `store` (either NULL: none; unit_store.h); a config without a
 * random input runs unit 0 and copies it. */
static int run_units(const sunmc_config *c, long units, int threads, unit_store *head_store,
                     long head, unit_store *store, unit_result *res, char *err, size_t errlen)
{
    long run = budget_units_run(c, units);
    sunmc_config t = *c;
    t.no_systematic = 1;
    head = head_store && head <= run ? head : 0;
    int st = head > 0 ? mc_run_store(&t, head_store, 0, head, threads, res, NULL, NULL, err,
                                     errlen)
                      : SUNMC_OK;
    if (st == SUNMC_OK && head < run)
        st = mc_run_store(&t, store, head, run, threads, res + head, NULL, NULL, err, errlen);
    for (long u = run; st == SUNMC_OK && u < units; u++) {
        res[u] = res[0]; /* the same unit: no random input varies */
        res[u].unit = u;
    }
    return st;
}

/* Units [0, n) of res failing the spec's verdict, by why, into out. */
static void count_fails(const sunmc_config *c, const unit_result *res, long n, budget_stats *out)
{
    out->fail_coverage = out->fail_spec = 0;
    for (long u = 0; u < n; u++) {
        verdict v;
        verdict_unit(c, &res[u], verdict_angle(c), VERDICT_WORST, &v);
        out->fail_coverage += v.why == VERDICT_COVERAGE;
        out->fail_spec += v.why == VERDICT_OVER_SPEC;
    }
}

/* One budget Monte Carlo of c over units [0, units) (see run_units for
 * the stores): its statistics into out, each unit's squares into
 * sq_before / sq_after (may be NULL), and when 0 < head <= units also the
 * statistics of units [0, head) into head_out: the run a smaller run of
 * the same config would have made (a unit depends on (seed, unit) only). */
static int monte_carlo(const sunmc_config *c, long units, int threads, int angle, int band,
                       unit_store *head_store, unit_store *store, budget_stats *out,
                       double *sq_before, double *sq_after, long head, budget_stats *head_out,
                       char *err, size_t errlen)
{
    int mst = memory_check_run(c, 0, units, threads, 1, 0, err, errlen);
    if (mst != SUNMC_OK)
        return mst;
    unit_result *res = calloc((size_t)units, sizeof *res);
    int st = res ? SUNMC_OK : SUNMC_ENOMEM;
    if (st == SUNMC_ENOMEM)
        sunmc_fail(err, errlen, st, "out of memory for %ld units", units);
    if (st == SUNMC_OK)
        st = run_units(c, units, threads, head_store, head, store, res, err, errlen);
    if (st == SUNMC_OK && ((st = row_stats(c, res, units, angle, band, out)) != SUNMC_OK ||
                           (head > 0 && head <= units &&
                            (st = row_stats(c, res, head, angle, band, head_out)) != SUNMC_OK)))
        sunmc_fail(err, errlen, st, "out of memory summarising %ld units", units);
    if (st == SUNMC_OK) {
        count_fails(c, res, units, out);
        if (head > 0 && head <= units)
            count_fails(c, res, head, head_out);
        for (long u = 0; u < units && (sq_before || sq_after); u++) {
            double bef = unit_primary_before(c, &res[u], angle, band);
            double aft = unit_primary_after(c, &res[u], angle, band);
            int ok = res[u].fit_status == UNIT_FIT_OK && isfinite(bef) && isfinite(aft);
            if (sq_before)
                sq_before[u] = ok ? bef * bef : NAN;
            if (sq_after)
                sq_after[u] = ok ? aft * aft : NAN;
        }
    }
    free(res);
    return st;
}

int budget_monte_carlo(const sunmc_config *c, long units, int threads, int angle, int band,
                       budget_stats *out, double *sq_before, double *sq_after, char *err,
                       size_t errlen)
{
    return monte_carlo(c, units, threads, angle, band, NULL, NULL, out, sq_before, sq_after, 0,
                       NULL, err, errlen);
}

int budget_monte_carlo_today(const sunmc_config *c, const budget_result *b, budget_stats *out,
                             int threads, long *reused, char *err, size_t errlen)
{
    unit_store *store = unit_store_serves(b->today_store, c, 0, c->budget_units)
                            ? b->today_store
                            : NULL;
    long reads = unit_store_reads(store);
    int rc = monte_carlo(c, c->budget_units, threads, b->angle, b->band, NULL, store, out, NULL,
                         NULL, 0, NULL, err, errlen);
    *reused = store ? budget_units_run(c, c->budget_units) - (unit_store_reads(store) - reads)
                    : 0;
    return rc;
}

/* Per-unit squares of the runs: all, floor, then each source alone; before
 * and after.  run r's values at sq[(2 r + after) * units]. */
typedef struct {
    long units;
    int runs;
    double *sq;
    long *block;      /* the sampling block of each kept unit (NULL: random sampling) */
    long block_units; /* run.sampling_block */
} budget_squares;

static double *squares(budget_squares *q, int run, int after)
{
    return q->sq + (size_t)(2 * run + after) * (size_t)q->units;
}

/* Under a sampling design (block != NULL) the interval from the block
 * totals (stats_blocks.h). */
static void set_share(budget_share *s, const double *x, const double *a, const long *block,
                      size_t n, double conf)
{
    char err[SUNMC_ERRLEN];
    if (stats_blocks_ratio_t(x, a, block, n, conf, &s->v, &s->ci, err, sizeof err) != SUNMC_OK)
        s->ci.lo = s->ci.hi = NAN; /* a config outside the key table's range */
    s->significant = s->ci.lo > 0 || s->ci.hi < 0;
}

/* Keep the units with a value in every run, before and after (the pairs
 * the shares are over); their count. */
static long pair_units(budget_squares *q)
{
    long k = 0;
    for (long u = 0; u < q->units; u++) {
        int ok = 1;
        for (int r = 0; r < q->runs; r++)
            ok = ok && isfinite(squares(q, r, 0)[u]) && isfinite(squares(q, r, 1)[u]);
        if (!ok)
            continue;
        for (int r = 0; r < 2 * q->runs; r++)
            q->sq[(size_t)r * (size_t)q->units + (size_t)k] =
                q->sq[(size_t)r * (size_t)q->units + (size_t)u];
        if (q->block)
            q->block[k] = u / q->block_units;
        k++;
    }
    return k;
}

/* Shares over the n paired units, before (after = 0) or after calibration:
 * the floor, each source's increment over the floor, and the rest. */
static int shares(const sunmc_config *c, budget_result *b, budget_squares *q, long n, int after)
{
    size_t len = (size_t)(n > 0 ? n : 1);
    double *x = malloc(2 * len * sizeof *x), *rest = x ? x + len : NULL;
    if (!x)
        return SUNMC_ENOMEM;
    const double *all = squares(q, 0, after), *floor = squares(q, 1, after);
    for (long u = 0; u < n; u++)
        rest[u] = all[u] - floor[u];
    set_share(after ? &b->floor_after : &b->floor_before, floor, all, q->block, (size_t)n,
              c->confidence);
    for (int i = 0; i < b->n; i++) {
        const double *alone = squares(q, 2 + i, after);
        for (long u = 0; u < n; u++) {
            x[u] = alone[u] - floor[u];
            rest[u] -= x[u];
        }
        budget_source *s = &b->src[i];
        set_share(after ? &s->share_after : &s->share_before, x, all, q->block, (size_t)n,
                  c->confidence);
    }
    set_share(after ? &b->interaction_after : &b->interaction_before, rest, all, q->block,
              (size_t)n, c->confidence);
    free(x);
    return SUNMC_OK;
}

/* Whether a share stands outside the Monte Carlo noise: its interval
 * excludes 0 and it is at least BUDGET_SHARE_RESOLUTION (as printed, two
 * decimals of a percent, it is not 0.00 %). */
static int share_counts(const budget_share *s)
{
    return s->significant && isfinite(s->v) && fabs(s->v) >= BUDGET_SHARE_RESOLUTION;
}

/* A share as the ranking sees it: 0 when inside the noise or not formed,
 * so that noise orders nothing. */
static double rank_share(const budget_share *s)
{
    return share_counts(s) ? s->v : 0.0;
}

/* Whether source x ranks before y: one with a share outside the noise
 * before one with none, then the after-calibration share, then the
 * before-calibration share (each counted only outside the noise). */
static int ranks_before(const budget_source *x, const budget_source *y)
{
    if (x->in_noise != y->in_noise)
        return y->in_noise;
    double ax = rank_share(&x->share_after), ay = rank_share(&y->share_after);
    if (ax != ay)
        return ax > ay;
    return rank_share(&x->share_before) > rank_share(&y->share_before);
}

/* Rank the sources (a stable insertion sort: equal ones in source order);
 * those whose shares are all inside the noise last, marked in_noise. */
static void rank_sources(budget_result *b)
{
    for (int i = 0; i < b->n; i++) {
        budget_source *s = &b->src[i];
        s->in_noise = !share_counts(&s->share_after) && !share_counts(&s->share_before);
        b->order[i] = i;
    }
    for (int i = 1; i < b->n; i++) {
        int x = b->order[i], j = i;
        while (j > 0 && ranks_before(&b->src[x], &b->src[b->order[j - 1]])) {
            b->order[j] = b->order[j - 1];
            j--;
        }
        b->order[j] = x;
    }
    for (int i = 0; i < b->n; i++)
        b->src[b->order[i]].rank = i + 1;
}

/* The runs after "all sources" (index r of the squares: 1 the floor, 2 + i
 * source i alone; n + 2 no tolerance), their configs and names. */
typedef struct {
    sunmc_config cfg[BUDGET_MAX_SOURCES + 2];
    char what[BUDGET_MAX_SOURCES + 2][2 * CONFIG_STR_MAX];
    int order[BUDGET_MAX_SOURCES + 2]; /* the order they run in */
    int n;
} budget_plan;

static void plan_runs(const sunmc_config *c, const budget_result *b, budget_plan *p)
{
    sunmc_config floor = *c, no_tol = *c;
    for (int i = 0; i < b->n; i++) {
        budget_set_tolerance(&floor, b->src[i].key, 0.0);
        if (b->src[i].kind == BUDGET_TOLERANCE)
            budget_set_tolerance(&no_tol, b->src[i].key, 0.0);
    }
    p->n = b->n + 2;
    p->cfg[0] = floor;
    snprintf(p->what[0], sizeof p->what[0], "floor (nominal design, no noise)");
    for (int i = 0; i < b->n; i++) {
        p->cfg[1 + i] = floor;
        budget_set_tolerance(&p->cfg[1 + i], b->src[i].key, b->src[i].tolerance);
        snprintf(p->what[1 + i], sizeof p->what[1 + i], "%s alone", b->src[i].name);
    }
    p->cfg[b->n + 1] = no_tol;
    snprintf(p->what[b->n + 1], sizeof p->what[b->n + 1], "no tolerance (design and noise)");
    /* each run followed by the later ones that read the same validation
     * (unit_readings_same): one store serves them in turn */
    unsigned char done[BUDGET_MAX_SOURCES + 2] = {0};
    int k = 0;
    for (int i = 0; i < p->n; i++) {
        if (done[i])
            continue;
        p->order[k++] = i;
        for (int j = i + 1; j < p->n; j++)
            if (!done[j] && unit_readings_same(&p->cfg[i], &p->cfg[j])) {
                p->order[k++] = j;
                done[j] = 1;
            }
    }
}

/* The floor, each source alone and no tolerance, in plan order through one
 * store; b->unit_runs and b->reused_units count them. */
static int planned_runs(const sunmc_config *c, budget_result *b, budget_squares *q, int threads,
                        int run, budget_progress_fn progress, void *ctx, char *err,
                        size_t errlen)
{
    budget_plan *p = malloc(sizeof *p);
    unit_store *store = NULL;
    int rc = p ? unit_store_alloc_upto(c, q->units, BUDGET_STORE_MAX_BYTES, &store, err,
                                       errlen)
               : sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the budget's runs");
    if (rc == SUNMC_OK)
        plan_runs(c, b, p);
    for (int k = 0; rc == SUNMC_OK && k < p->n; k++) {
        int r = p->order[k];
        budget_stats *out = r == 0 ? &b->floor : r <= b->n ? &b->src[r - 1].alone
                                                           : &b->no_tolerance;
        int keep = r <= b->n; /* the squares of the floor and the alone runs */
        if (progress)
            progress(p->what[r], ++run, b->n + 4, ctx);
        long reads = unit_store_reads(store), made = budget_units_run(&p->cfg[r], q->units);
        rc = monte_carlo(&p->cfg[r], q->units, threads, b->angle, b->band, NULL, store, out,
                         keep ? squares(q, 1 + r, 0) : NULL, keep ? squares(q, 1 + r, 1) : NULL,
                         0, NULL, err, errlen);
        b->unit_runs += made;
        if (store && k > 0 && unit_readings_same(&p->cfg[p->order[k - 1]], &p->cfg[r]))
            b->reused_units += made - (unit_store_reads(store) - reads);
    }
    unit_store_free(store);
    free(p);
    return rc;
}

static int after_parts(const sunmc_config *c, budget_result *b, long units, int threads,
                       char *err, size_t errlen);

/* The Monte Carlo runs: all, then floor, each source alone, no tolerance,
 * then the all-sources units by kind (after_parts). */
static int budget_runs(const sunmc_config *c, budget_result *b, budget_squares *q, int threads,
                       budget_progress_fn progress, void *ctx, char *err, size_t errlen)
{
    int rc;
    if (progress)
        progress("all sources", 1, 4 + b->n, ctx);
    /* the inverse limits' yield at today's values is this run's first
     * report.budget_units units: kept, not run again for every source, and
     * their readings kept for the searches of a source they do not read */
    b->today_units = c->budget_units <= q->units ? c->budget_units : 0;
    if (b->today_units > 0 &&
        (rc = unit_store_alloc(c, b->today_units, &b->today_store, err, errlen)))
        return rc;
    if ((rc = monte_carlo(c, q->units, threads, b->angle, b->band, b->today_store, NULL, &b->all,
                          squares(q, 0, 0), squares(q, 0, 1), b->today_units, &b->today, err,
                          errlen)))
        return rc;
    b->unit_runs = q->units;
    if ((rc = planned_runs(c, b, q, threads, 1, progress, ctx, err, errlen)))
        return rc;
    if (progress)
        progress("all sources by kind (systematic and model-form passes)", 4 + b->n, 4 + b->n,
                 ctx);
    return after_parts(c, b, q->units, threads, err, errlen);
}

/* Unit u's squares after calibration in three parts (modelform.h) into
 * x[3], over the total *a; 0 when the unit has no value for every one. */
static int unit_parts(const unit_result *r, int angle, int band, double x[BUDGET_PARTS],
                      double *a)
{
    double aft = r->rms_after[angle][band], sys = r->rms_after_sys[angle][band];
    double mf = r->rms_after_mf[angle][band];
    if (r->fit_status != UNIT_FIT_OK || !isfinite(aft) || !isfinite(sys) || !isfinite(mf))
        return 0;
    *a = aft * aft;
    x[BUDGET_PART_NOISE] = aft * aft - sys * sys;
    x[BUDGET_PART_ESTIMATION] = sys * sys - mf * mf;
    x[BUDGET_PART_MODEL_FORM] = mf * mf;
    return 1;
}

/* The on-board part of unit u (budget.h): its parts from the double run
 * dbl, the on-board run's mean square after as the total *a and x[BUDGET_PARTS]
 * its excess over the double's; 0 when either has no value. */
static int unit_parts_onboard(const unit_result *ob, const unit_result *dbl, int angle, int band,
                              double x[BUDGET_PARTS + 1], double *a)
{
    double a_dbl, aft = ob->rms_after[angle][band];
    if (!unit_parts(dbl, angle, band, x, &a_dbl) || ob->fit_status != UNIT_FIT_OK ||
        !isfinite(aft))
        return 0;
    *a = aft * aft;
    x[BUDGET_PARTS] = *a - a_dbl;
    return 1;
}

/* The same units as res (config t) validated in double instead of
 * calibration.onboard's form, into *dbl (NULL when t's form is double). */
static int onboard_double_run(const sunmc_config *t, budget_result *b, long run, int threads,
                              unit_result **dbl, char *err, size_t errlen)
{
    lab_onboard_spec s;
    *dbl = NULL;
    b->onboard_name[0] = '\0';
    int rc = lab_onboard_config(t, &s, err, errlen);
    if (rc != SUNMC_OK || s.form == LAB_ONBOARD_DOUBLE)
        return rc;
    snprintf(b->onboard_name, sizeof b->onboard_name, "%s", lab_onboard_source_name(&s));
    sunmc_config d = *t;
    snprintf(d.onboard, sizeof d.onboard, "double");
    if (!(*dbl = calloc((size_t)run, sizeof **dbl)))
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for %ld units", run);
    b->unit_runs += 2 * run;
    return mc_run(&d, 0, run, threads, *dbl, NULL, NULL, err, errlen);
}

/* The all-sources run's units again with the systematic pass and a
 * model-form pass each: the parts of its mean square after calibration
 * (at the lab's condition) into b->part_after (and b->part_onboard). */
static int after_parts(const sunmc_config *c, budget_result *b, long units, int threads,
                       char *err, size_t errlen)
{
    sunmc_config t = *c;
    t.no_systematic = 0;
    t.model_form_every = 1;
    long run = budget_units_run(&t, units);
    unit_result *res = calloc((size_t)run, sizeof *res), *dbl = NULL;
    double *v = malloc((size_t)run * (BUDGET_PARTS + 2) * sizeof *v); /* parts, total, onboard */
    long *block = c->sampling != CONFIG_SAMPLING_RANDOM ? malloc((size_t)run * sizeof *block)
                                                        : NULL;
    int rc = res && v && (block || c->sampling == CONFIG_SAMPLING_RANDOM)
                 ? mc_run(&t, 0, run, threads, res, NULL, NULL, err, errlen)
                 : sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for %ld units", run);
    if (rc == SUNMC_OK)
        rc = onboard_double_run(&t, b, run, threads, &dbl, err, errlen);
    long n = 0;
    for (long u = 0; rc == SUNMC_OK && u < run; u++) {
        double x[BUDGET_PARTS + 1], a;
        if (dbl ? !unit_parts_onboard(&res[u], &dbl[u], b->angle, b->band, x, &a)
                : !unit_parts(&res[u], b->angle, b->band, x, &a))
            continue;
        for (int k = 0; k < BUDGET_PARTS; k++)
            v[(size_t)k * (size_t)run + (size_t)n] = x[k];
        v[(size_t)BUDGET_PARTS * (size_t)run + (size_t)n] = a;
        v[(size_t)(BUDGET_PARTS + 1) * (size_t)run + (size_t)n] = dbl ? x[BUDGET_PARTS] : 0.0;
        if (block)
            block[n] = u / c->sampling_block;
        n++;
    }
    for (int k = 0; rc == SUNMC_OK && k < BUDGET_PARTS; k++)
        set_share(&b->part_after[k], v + (size_t)k * (size_t)run,
                  v + (size_t)BUDGET_PARTS * (size_t)run, block, (size_t)n, c->confidence);
    if (rc == SUNMC_OK && dbl)
        set_share(&b->part_onboard, v + (size_t)(BUDGET_PARTS + 1) * (size_t)run,
                  v + (size_t)BUDGET_PARTS * (size_t)run, block, (size_t)n, c->confidence);
    b->part_units = n;
    b->unit_runs += 2 * run;
    free(res);
    free(dbl);
    free(v);
    free(block);
    return rc;
}

/* Every source's inverse limit, a source to a thread: each search is a
 * chain of small runs (report.budget_units units) whose next value depends
 * on the last, so the searches, not their units, are what the threads
 * share (one parallel region instead of a region per run, each ending with
 * a thread waiting).  A search's result does not depend on the thread that
 * made it; the first failure's message goes to err. */
static int inverse_limits(const sunmc_config *c, budget_result *b, int threads,
                          budget_progress_fn progress, void *ctx, char *err, size_t errlen)
{
    int rc = SUNMC_OK, done = 0;
    if (threads > 0)
        omp_set_num_threads(threads);
#pragma omp parallel
    {
#pragma omp for schedule(dynamic, 1)
        for (int i = 0; i < b->n; i++) {
            char terr[SUNMC_ERRLEN] = "", what[2 * CONFIG_STR_MAX];
            int failed;
#pragma omp atomic read
            failed = rc;
            if (failed)
                continue;
            int st = budget_inverse_limit(c, b, &b->src[i], 1, terr, sizeof terr);
#pragma omp critical(budget_limits)
            {
                if (st != SUNMC_OK && rc == SUNMC_OK)
                    rc = sunmc_fail(err, errlen, st, "%s", terr);
                snprintf(what, sizeof what, "%s inverse limit", b->src[i].name);
                if (progress)
                    progress(what, ++done, b->n, ctx);
            }
        }
    }
    return rc;
}

long budget_reused_units(const budget_result *b)
{
    long n = b->reused_units;
    for (int i = 0; i < b->n; i++)
        n += b->src[i].limit_reused;
    return n;
}

long budget_unit_runs(const budget_result *b)
{
    long n = b->unit_runs;
    for (int i = 0; i < b->n; i++)
        n += b->src[i].limit_units;
    return n;
}

int budget_run(const sunmc_config *c, long units, int threads, int with_limits,
               budget_progress_fn progress, void *ctx, budget_result *b, char *err,
               size_t errlen)
{
    int rc = budget_sources(c, b, err, errlen);
    if (rc)
        return rc;
    if (units < STUDY_MIN_UNITS)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "budget needs at least %d units, not %ld",
                          STUDY_MIN_UNITS, units);
    b->units = units;
    budget_squares q = {units, 2 + b->n, NULL, NULL, c->sampling_block};
    /* Before any work: each run's units held whole, and the squares of
     * every run kept for the paired shares. */
    double squares = (double)(2 * q.runs) * (double)units * sizeof *q.sq;
    rc = memory_check_run(c, 0, units, threads, 1, 0, err, errlen);
    if (rc == SUNMC_OK && squares + memory_run_bytes(c, units, threads, 1) >
                              memory_available_bytes() && memory_available_bytes() > 0)
        rc = memory_check_run(c, 0, units, threads, 1,
                              memory_available_bytes() - squares, err, errlen);
    if (rc)
        return rc;
    q.sq = malloc((size_t)(2 * q.runs) * (size_t)(units > 0 ? units : 1) * sizeof *q.sq);
    if (q.sq && c->sampling != CONFIG_SAMPLING_RANDOM &&
        !(q.block = malloc((size_t)(units > 0 ? units : 1) * sizeof *q.block))) {
        free(q.sq);
        q.sq = NULL;
    }
    if (!q.sq)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for %ld units x %d runs",
                          units, q.runs);
    rc = budget_runs(c, b, &q, threads, progress, ctx, err, errlen);
    if (rc == SUNMC_OK) {
        b->paired_units = pair_units(&q);
        if (b->paired_units < STUDY_MIN_UNITS)
            rc = sunmc_fail(err, errlen, SUNMC_EDOM,
                            "only %ld of %ld units have a fit in every run (all sources, the "
                            "floor, each source alone), fewer than the %d the shares need: not "
                            "enough units (more --units, or a config whose units can be "
                            "fitted: `sunmc run` counts the failed fits)",
                            b->paired_units, units, STUDY_MIN_UNITS);
        else if (shares(c, b, &q, b->paired_units, 0) || shares(c, b, &q, b->paired_units, 1))
            rc = sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the shares");
        rank_sources(b);
    }
    free(q.sq);
    free(q.block);
    if (rc || !with_limits) {
        unit_store_free(b->today_store);
        b->today_store = NULL;
        return rc;
    }
    rc = inverse_limits(c, b, threads, progress, ctx, err, errlen);
    unit_store_free(b->today_store);
    b->today_store = NULL;
    return rc;
}
