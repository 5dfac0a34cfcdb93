/* allocate.c - the cheapest tolerances meeting the yield target (allocate.h). */
#include "allocate.h"
#include "report.h"
#include "status.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Bisection steps on log lambda, and its range. */
#define LAMBDA_STEPS 60
#define LOG_LAMBDA_SPAN 60.0
/* Greedy loosening: factor per step, passes over the sources. */
#define LOOSEN_FACTOR 1.1
#define LOOSEN_PASSES 8
#define POWER_MIN 1.0
#define POWER_MAX 6.0
#define POWER_DEFAULT 2.0
#define SHARE_FLOOR 0.01

/* The per-unit surrogate (allocate.h). */
typedef struct {
    long n;
    int m;
    double spec2;
    double *base, *inter, *d; /* d[i * n + u] */
    double s_sum;
} surrogate;

static double cost_of(const allocate_source *s, double v, double k)
{
    return s->weight * pow(s->today / v, k);
}

static int collect_sources(const sunmc_config *c, allocate_result *a, char *err, size_t errlen)
{
    budget_result *b = calloc(1, sizeof *b);
    if (!b)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    int rc = budget_sources(c, b, err, errlen);
    a->n = 0;
    if (rc == SUNMC_EINPUT) /* no source at all: said below */
        rc = SUNMC_OK;
    for (int i = 0; rc == SUNMC_OK && i < b->n; i++) {
        const budget_source *bs = &b->src[i];
        const tolerance *t = (const tolerance *)config_value_cptr(bs->key, c);
        if (bs->kind != BUDGET_TOLERANCE || t->dist == DIST_FIXED)
            continue;
        allocate_source *s = &a->src[a->n++];
        snprintf(s->name, sizeof s->name, "%s", bs->name);
        s->key = bs->key;
        s->today = t->value;
        s->weight = t->cost;
        s->lo = t->value / ALLOCATE_RANGE;
        s->hi = fmin(t->value * ALLOCATE_PROBE, bs->key->max);
    }
    a->angle = b->angle;
    a->band = b->band;
    free(b);
    if (rc == SUNMC_OK && a->n == 0)
        rc = sunmc_fail(err, errlen, SUNMC_EINPUT,
                        "no tolerance above 0 that is not fixed: nothing to allocate");
    return rc;
}

/* The smallest pass count of n whose lower bound meets the target; -1
 * when not even n of n does. */
static long needed_pass(const sunmc_config *c, long n)
{
    stats_interval ci;
    report_yield_ci(c, n, n, &ci);
    if (!(ci.lo >= c->yield_target))
        return -1;
    long lo = 0, hi = n; /* lower bound grows with the count: bisect */
    while (hi - lo > 1) {
        long mid = lo + (hi - lo) / 2;
        report_yield_ci(c, mid, n, &ci);
        if (ci.lo >= c->yield_target)
            hi = mid;
        else
            lo = mid;
    }
    return hi;
}

/* One Monte Carlo of cfg on seed: per-unit RMS^2 after (may be NULL) and
 * the yield with its interval. */
static int run_mc(const sunmc_config *cfg, const allocate_result *a, long seed, int threads,
                  double *sq, double *yield, stats_interval *ci, char *err, size_t errlen)
{
    sunmc_config t = *cfg;
    t.seed = seed;
    budget_stats st;
    int rc = budget_monte_carlo(&t, a->units, threads, a->angle, a->band, &st, NULL, sq, err,
                                errlen);
    if (rc == SUNMC_OK) {
        *yield = st.yield;
        *ci = st.yield_ci;
    }
    return rc;
}

static double surrogate_yield(const surrogate *g, const allocate_source *src, const double *x)
{
    double add = 0;
    for (int i = 0; i < g->m; i++)
        add += fmax(src[i].ms_share, 0.0) * x[i];
    double scale = g->s_sum > 0 ? add / g->s_sum : 1.0;
    long pass = 0;
    for (long u = 0; u < g->n; u++) {
        double r = g->base[u] + g->inter[u] * scale;
        for (int i = 0; i < g->m; i++)
            r += g->d[(size_t)i * (size_t)g->n + (size_t)u] * x[i];
        pass += isfinite(r) && r <= g->spec2;
    }
    return (double)pass / (double)g->n;
}

/* x_i = (t_i / today_i)^p_i of tolerance values v. */
static void x_of_values(const allocate_source *src, int m, const double *v, double *x)
{
    for (int i = 0; i < m; i++)
        x[i] = pow(v[i] / src[i].today, src[i].power);
}

/* The Lagrange shape at log lambda (allocate.h): values into v.  A source
 * whose mean share is below SHARE_FLOOR of the average (none measured, or
 * negative: it helps alone) counts with that floor, so that it too is
 * tightened as lambda grows. */
static void values_at(const allocate_source *src, int m, double k, double log_lambda, double *v)
{
    double avg = 0;
    for (int i = 0; i < m; i++)
        avg += fmax(src[i].ms_share, 0.0) / m;
    for (int i = 0; i < m; i++) {
        const allocate_source *s = &src[i];
        double share = fmax(s->ms_share, SHARE_FLOOR * avg);
        if (s->weight == 0 || !(share > 0)) {
            v[i] = s->weight == 0 ? s->hi : s->lo;
            continue;
        }
        double p = s->power, e = 1.0 / (k / p + 1.0);
        double lx = e * (log(k * s->weight / (p * share)) - log_lambda);
        double val = s->today * exp(lx / p);
        v[i] = fmin(s->hi, fmax(s->lo, val));
    }
}

static double yield_of_values(const surrogate *g, const allocate_source *src, const double *v)
{
    double x[BUDGET_MAX_SOURCES];
    x_of_values(src, g->m, v, x);
    return surrogate_yield(g, src, x);
}

/* Loosen each source by LOOSEN_FACTOR while the surrogate holds, the
 * biggest saving first. */
static void loosen(const surrogate *g, const allocate_source *src, double k, double need,
                   double *v)
{
    for (int pass = 0; pass < LOOSEN_PASSES; pass++) {
        int moved = 0;
        for (;;) {
            int best = -1;
            double gain = 0;
            for (int i = 0; i < g->m; i++) {
                double t = fmin(v[i] * LOOSEN_FACTOR, src[i].hi);
                double save = cost_of(&src[i], v[i], k) - cost_of(&src[i], t, k);
                if (t <= v[i] || save <= gain)
                    continue;
                double old = v[i];
                v[i] = t;
                if (yield_of_values(g, src, v) >= need) {
                    best = i;
                    gain = save;
                }
                v[i] = old;
            }
            if (best < 0)
                break;
            v[best] = fmin(v[best] * LOOSEN_FACTOR, src[best].hi);
            moved = 1;
        }
        if (!moved)
            break;
    }
}

/* The loosest Lagrange set meeting need, then loosened; 0 when none. */
static int search(const surrogate *g, const allocate_source *src, double k, double need,
                  double *v)
{
    double lo = -LOG_LAMBDA_SPAN, hi = LOG_LAMBDA_SPAN;
    values_at(src, g->m, k, hi, v);
    if (yield_of_values(g, src, v) < need)
        return 0;
    for (int it = 0; it < LAMBDA_STEPS; it++) {
        double mid = 0.5 * (lo + hi);
        values_at(src, g->m, k, mid, v);
        if (yield_of_values(g, src, v) >= need)
            hi = mid;
        else
            lo = mid;
    }
    values_at(src, g->m, k, hi, v);
    loosen(g, src, k, need, v);
    return 1;
}

/* Set every source of cfg to v[i] (v NULL: 0). */
static void set_all(sunmc_config *cfg, const allocate_result *a, const double *v)
{
    for (int i = 0; i < a->n; i++)
        budget_set_tolerance(cfg, a->src[i].key, v ? v[i] : 0.0);
}

typedef struct {
    allocate_progress_fn fn;
    void *ctx;
    int i, n;
} meter;

static void tick(meter *mt, const char *what)
{
    if (mt->fn)
        mt->fn(what, ++mt->i, mt->n, mt->ctx);
}

/* Mean of x - y over units where both are finite. */
static double mean_increment(const double *x, const double *y, long n)
{
    double s = 0;
    long k = 0;
    for (long u = 0; u < n; u++)
        if (isfinite(x[u]) && isfinite(y[u])) {
            s += x[u] - y[u];
            k++;
        }
    return k > 0 ? s / (double)k : NAN;
}

/* The surrogate's runs (allocate.h) on run.seed; today's yield too. */
static int build_surrogate(const sunmc_config *c, allocate_result *a, int threads, meter *mt,
                           surrogate *g, char *err, size_t errlen)
{
    long n = a->units;
    double *all = malloc((size_t)n * sizeof *all), *probe = malloc((size_t)n * sizeof *probe);
    int rc = all && probe ? SUNMC_OK : sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    sunmc_config base = *c;
    set_all(&base, a, NULL);
    double y;
    stats_interval ci;
    tick(mt, "every tolerance 0 (design and noise)");
    if (rc == SUNMC_OK)
        rc = run_mc(&base, a, c->seed, threads, g->base, &y, &ci, err, errlen);
    tick(mt, "today's tolerances");
    if (rc == SUNMC_OK)
        rc = run_mc(c, a, c->seed, threads, all, &a->yield_today, &a->yield_today_ci, err, errlen);
    for (int i = 0; rc == SUNMC_OK && i < a->n; i++) {
        allocate_source *s = &a->src[i];
        double *d = g->d + (size_t)i * (size_t)n;
        sunmc_config t = base;
        char what[2 * CONFIG_STR_MAX];
        snprintf(what, sizeof what, "%s alone", s->name);
        tick(mt, what);
        budget_set_tolerance(&t, s->key, s->today);
        if ((rc = run_mc(&t, a, c->seed, threads, d, &y, &ci, err, errlen)))
            break;
        double f = fmin(ALLOCATE_PROBE, s->key->max / s->today);
        budget_set_tolerance(&t, s->key, s->today * f);
        snprintf(what, sizeof what, "%s alone at %gx", s->name, f);
        tick(mt, what);
        if ((rc = run_mc(&t, a, c->seed, threads, probe, &y, &ci, err, errlen)))
            break;
        double m1 = mean_increment(d, g->base, n), m2 = mean_increment(probe, g->base, n);
        s->ms_share = m1;
        s->power = m1 > 0 && m2 > m1 && f > 1 ? log(m2 / m1) / log(f) : POWER_DEFAULT;
        s->power = fmin(POWER_MAX, fmax(POWER_MIN, s->power));
        for (long u = 0; u < n; u++)
            d[u] -= g->base[u];
    }
    for (long u = 0; rc == SUNMC_OK && u < n; u++) {
        double r = all[u] - g->base[u];
        for (int i = 0; i < a->n; i++)
            r -= g->d[(size_t)i * (size_t)n + (size_t)u];
        g->inter[u] = r;
    }
    g->s_sum = 0;
    for (int i = 0; i < a->n; i++)
        g->s_sum += a->src[i].ms_share > 0 ? a->src[i].ms_share : 0;
    free(all);
    free(probe);
    return rc;
}

/* Search, then refine on run.seed + 1 until its yield reaches need. */
static int find_set(const sunmc_config *c, allocate_result *a, const surrogate *g, int threads,
                    meter *mt, double need, double *v, char *err, size_t errlen)
{
    double k = c->cost_exponent, ask = need;
    for (a->refinements = 0;; a->refinements++) {
        a->yield_needed = ask;
        if (!search(g, a->src, k, ask, v)) {
            a->status = ALLOCATE_NONE;
            a->surrogate_yield = yield_of_values(g, a->src, v); /* every source at its tightest */
            return SUNMC_OK;
        }
        a->surrogate_yield = yield_of_values(g, a->src, v);
        if (a->refinements == ALLOCATE_REFINE)
            return SUNMC_OK;
        sunmc_config t = *c;
        set_all(&t, a, v);
        stats_interval ci;
        tick(mt, "refinement");
        int rc = run_mc(&t, a, c->seed + 1, threads, NULL, &a->yield_refine, &ci, err, errlen);
        if (rc || a->yield_refine >= need)
            return rc;
        ask = fmin(1.0, ask + (need - a->yield_refine) + 1.0 / (double)a->units);
    }
}

int allocate_run(const sunmc_config *c, long units, int threads, allocate_progress_fn progress,
                 void *ctx, allocate_result *a, char *err, size_t errlen)
{
    memset(a, 0, sizeof *a);
    a->units = units;
    if (units < STUDY_MIN_UNITS)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "allocate needs at least %d units, not %ld",
                          STUDY_MIN_UNITS, units);
    int rc = collect_sources(c, a, err, errlen);
    if (rc)
        return rc;
    long pass = needed_pass(c, units);
    if (pass < 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%ld units cannot show a yield of at least %g at confidence %g (%s) even "
                          "if every unit passes: run more units",
                          units, c->yield_target, c->confidence, report_yield_interval_name(c));
    surrogate g = {units, a->n, 0, NULL, NULL, NULL, 0};
    double spec = c->spec_arcsec / c->family->arcsec_per_rms_unit;
    g.spec2 = spec * spec;
    g.base = malloc((size_t)units * sizeof *g.base);
    g.inter = malloc((size_t)units * sizeof *g.inter);
    g.d = malloc((size_t)a->n * (size_t)units * sizeof *g.d);
    meter mt = {progress, ctx, 0, 3 + 2 * a->n + ALLOCATE_REFINE};
    double v[BUDGET_MAX_SOURCES];
    rc = g.base && g.inter && g.d ? SUNMC_OK : sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    if (rc == SUNMC_OK)
        rc = build_surrogate(c, a, threads, &mt, &g, err, errlen);
    if (rc == SUNMC_OK)
        rc = find_set(c, a, &g, threads, &mt, (double)pass / (double)units, v, err, errlen);
    free(g.base);
    free(g.inter);
    free(g.d);
    if (rc || a->status == ALLOCATE_NONE)
        return rc;
    for (int i = 0; i < a->n; i++) {
        allocate_source *s = &a->src[i];
        s->allocated = v[i];
        s->cost_today = s->weight;
        s->cost_allocated = cost_of(s, v[i], c->cost_exponent);
        a->cost_today += s->cost_today;
        a->cost_allocated += s->cost_allocated;
    }
    sunmc_config t = *c;
    set_all(&t, a, v);
    a->confirm_seed = c->seed + 2;
    mt.n = mt.i + 1;
    tick(&mt, "confirmation (independent seed)");
    rc = run_mc(&t, a, a->confirm_seed, threads, NULL, &a->yield, &a->yield_ci, err, errlen);
    a->status = allocate_meets(c, a->yield_ci) ? ALLOCATE_CONFIRMED : ALLOCATE_UNCONFIRMED;
    return rc;
}

int allocate_meets(const sunmc_config *c, stats_interval yield_ci)
{
    return yield_ci.lo >= c->yield_target;
}

void allocate_apply(const allocate_result *a, sunmc_config *cfg)
{
    for (int i = 0; i < a->n; i++)
        budget_set_tolerance(cfg, a->src[i].key, a->src[i].allocated);
}
