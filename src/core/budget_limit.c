/* budget_limit.c - the inverse limit of one source: bracket, bisection, and
 * the interval the tried values' yield intervals give (budget.h). */
#include "budget.h"
#include "status.h"

#include <math.h>

/* Note what the yield at value v says about the limit: an interval wholly
 * at or above the target puts the limit at v or beyond, one wholly below
 * puts it below v. */
static void note_tried(budget_source *s, double v, stats_interval y, double target)
{
    if (y.lo >= target && (isnan(s->limit_ci.lo) || v > s->limit_ci.lo))
        s->limit_ci.lo = v;
    if (y.hi < target && (isnan(s->limit_ci.hi) || v < s->limit_ci.hi))
        s->limit_ci.hi = v;
}

/* The most common cause of failing units in st. */
static int dominant_end(const budget_stats *st)
{
    long fit = st->fit_failures, cov = st->fail_coverage, spec = st->fail_spec;
    if (cov >= spec && cov >= fit && cov > 0)
        return BUDGET_END_COVERAGE;
    if (fit > spec)
        return BUDGET_END_FIT;
    return BUDGET_END_SPEC;
}

/* Yield with source s at value v (others as in c), budget_units units; at
 * today's value the all-sources run's first units (b->today) when it
 * holds them. */
static int yield_at(const sunmc_config *c, const budget_result *b, budget_source *s, double v,
                    int threads, double *yield, stats_interval *ci, char *err, size_t errlen)
{
    sunmc_config t = *c;
    budget_set_tolerance(&t, s->key, v);
    budget_stats st = b->today;
    int rc = SUNMC_OK;
    if (!(v == s->tolerance && b->today_units == c->budget_units)) {
        long reused = 0;
        rc = budget_monte_carlo_today(&t, b, &st, threads, &reused, err, errlen);
        s->limit_reused += reused;
        s->limit_units += budget_units_run(&t, c->budget_units);
    }
    s->limit_runs++;
    *yield = st.yield;
    if (ci)
        *ci = st.yield_ci;
    if (rc == SUNMC_OK)
        note_tried(s, v, st.yield_ci, c->yield_target);
    if (rc == SUNMC_OK && st.yield < c->yield_target &&
        (isnan(s->limit_end_at) || v < s->limit_end_at)) {
        s->limit_end_at = v;
        s->limit_end = dominant_end(&st);
    }
    return rc;
}

/* From today's value, grow the bracket while the yield holds: [*lo, *hi]
 * with the yield met at lo and not at hi, or the key's maximum reached. */
static int expand(const sunmc_config *c, const budget_result *b, budget_source *s, int threads,
                  double *lo, double *hi, char *err, size_t errlen)
{
    double kmax = s->key->max, y;
    *lo = s->tolerance;
    for (;;) {
        if (*lo >= kmax) {
            s->limit = kmax;
            s->limit_status = BUDGET_LIMIT_AT_MAX;
            s->limit_end = BUDGET_END_RANGE;
            return SUNMC_OK;
        }
        *hi = fmin(*lo * BUDGET_EXPAND, kmax);
        int rc = yield_at(c, b, s, *hi, threads, &y, NULL, err, errlen);
        if (rc || y < c->yield_target)
            return rc;
        *lo = *hi;
    }
}

int budget_inverse_limit(const sunmc_config *c, const budget_result *b, budget_source *s,
                         int threads, char *err, size_t errlen)
{
    double target = c->yield_target, y;
    s->limit_ci.lo = s->limit_ci.hi = NAN;
    s->limit_end_at = NAN;
    s->limit_end = BUDGET_END_SPEC;
    int rc = yield_at(c, b, s, s->tolerance, threads, &y, &s->yield_today_ci, err, errlen);
    if (rc)
        return rc;
    s->yield_today = y;
    double lo, hi;
    if (y >= target) {
        if ((rc = expand(c, b, s, threads, &lo, &hi, err, errlen)) ||
            s->limit_status == BUDGET_LIMIT_AT_MAX)
            return rc;
    } else {
        hi = s->tolerance;
        if ((rc = yield_at(c, b, s, 0.0, threads, &y, NULL, err, errlen)))
            return rc;
        if (y < target) {
            s->limit = 0;
            s->limit_status = BUDGET_LIMIT_UNMET;
            return SUNMC_OK;
        }
        lo = 0;
    }
    for (int i = 0; i < c->budget_steps; i++) {
        double mid = 0.5 * (lo + hi);
        if ((rc = yield_at(c, b, s, mid, threads, &y, NULL, err, errlen)))
            return rc;
        if (y >= target)
            lo = mid;
        else
            hi = mid;
    }
    s->limit = lo;
    s->limit_status = BUDGET_LIMIT_OK;
    return SUNMC_OK;
}
