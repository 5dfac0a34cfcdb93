/* budget.c - each source alone / removed, shares, ranks, inverse limits. */
#include "budget.h"
#include "montecarlo.h"
#include "report.h"
#include "status.h"

#include <math.h>
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

int budget_sources(const sunmc_config *c, budget_result *b, char *err, size_t errlen)
{
    memset(b, 0, sizeof *b);
    const sensor_family *fam = c->family;
    b->angle = fam->n_angles(c) - 1;
    b->band = 0;
    for (int i = 1; i < c->bands_deg.n; i++)
        if (c->bands_deg.hi[i] - c->bands_deg.lo[i] >=
            c->bands_deg.hi[b->band] - c->bands_deg.lo[b->band])
            b->band = i;
    for (const config_key *k = fam->keys; k && k->section; k++) {
        if (!config_is_tolerance(k, fam) || !(get_value(c, k) > 0))
            continue;
        if (b->n >= BUDGET_MAX_SOURCES)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "more than %d tolerance sources",
                              BUDGET_MAX_SOURCES);
        budget_source *s = &b->src[b->n++];
        snprintf(s->name, sizeof s->name, "%s", k->name);
        s->key = k;
        s->tolerance = get_value(c, k);
    }
    if (b->n == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "no tolerance is above 0: the budget has no error source");
    return SUNMC_OK;
}

int budget_monte_carlo(const sunmc_config *c, long units, int threads, int angle, int band,
                       budget_stats *out, char *err, size_t errlen)
{
    const sensor_family *fam = c->family;
    int nr = report_n_rows(c, fam);
    unit_result *res = calloc((size_t)units, sizeof *res);
    summary_row *rows = calloc((size_t)nr, sizeof *rows);
    int st = (res && rows) ? SUNMC_OK : SUNMC_ENOMEM;
    if (st == SUNMC_ENOMEM)
        sunmc_fail(err, errlen, st, "out of memory for %ld units", units);
    if (st == SUNMC_OK)
        st = mc_run(c, fam, 0, units, threads, res, NULL, NULL, err, errlen);
    if (st == SUNMC_OK && (st = report_summarize(c, fam, res, units, rows)) != SUNMC_OK)
        sunmc_fail(err, errlen, st, "out of memory summarising %ld units", units);
    if (st == SUNMC_OK) {
        const summary_row *r = &rows[angle * c->bands_deg.n + band];
        memset(out, 0, sizeof *out);
        out->before_mean = r->rms_before_mean;
        out->after_mean = r->rms_after_mean;
        out->yield = r->yield;
        out->fit_failures = r->fit_failures;
        double sb = 0, sa = 0;
        long k = 0;
        for (long u = 0; u < units; u++) {
            double bef = res[u].rms_before[angle][band], aft = res[u].rms_after[angle][band];
            if (res[u].fit_status != UNIT_FIT_OK || !isfinite(bef) || !isfinite(aft))
                continue;
            sb += bef * bef;
            sa += aft * aft;
            k++;
        }
        out->before_ms = k ? sb / (double)k : NAN;
        out->after_ms = k ? sa / (double)k : NAN;
    }
    free(res);
    free(rows);
    return st;
}

/* Yield with source s at value v (others as in c), budget_units units. */
static int yield_at(const sunmc_config *c, const budget_result *b, budget_source *s, double v,
                    int threads, double *yield, char *err, size_t errlen)
{
    sunmc_config t = *c;
    budget_set_tolerance(&t, s->key, v);
    budget_stats st;
    int rc = budget_monte_carlo(&t, c->budget_units, threads, b->angle, b->band, &st, err, errlen);
    s->limit_runs++;
    *yield = st.yield;
    return rc;
}

static int inverse_limit(const sunmc_config *c, const budget_result *b, budget_source *s,
                         int threads, char *err, size_t errlen)
{
    double target = c->yield_target, y;
    double kmax = s->key->max;
    int rc = yield_at(c, b, s, s->tolerance, threads, &y, err, errlen);
    if (rc)
        return rc;
    s->yield_today = y;
    double lo, hi;
    if (y >= target) {
        lo = s->tolerance;
        for (;;) {
            if (lo >= kmax) {
                s->limit = kmax;
                s->limit_status = BUDGET_LIMIT_AT_MAX;
                return SUNMC_OK;
            }
            hi = fmin(lo * BUDGET_EXPAND, kmax);
            if ((rc = yield_at(c, b, s, hi, threads, &y, err, errlen)))
                return rc;
            if (y < target)
                break;
            lo = hi;
        }
    } else {
        hi = s->tolerance;
        if ((rc = yield_at(c, b, s, 0.0, threads, &y, err, errlen)))
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
        if ((rc = yield_at(c, b, s, mid, threads, &y, err, errlen)))
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

static double share(double num, double den)
{
    return den > 0 ? num / den : NAN;
}

int budget_run(const sunmc_config *c, long units, int threads, int with_limits,
               budget_progress_fn progress, void *ctx, budget_result *b, char *err,
               size_t errlen)
{
    int rc = budget_sources(c, b, err, errlen);
    if (rc)
        return rc;
    b->units = units;
    int n_runs = 2 + 2 * b->n, run = 0;
    char what[2 * CONFIG_STR_MAX];

    sunmc_config none = *c;
    for (int i = 0; i < b->n; i++)
        budget_set_tolerance(&none, b->src[i].key, 0.0);
    if (progress)
        progress("all sources", ++run, n_runs, ctx);
    if ((rc = budget_monte_carlo(c, units, threads, b->angle, b->band, &b->all, err, errlen)))
        return rc;
    if (progress)
        progress("no source (design and noise)", ++run, n_runs, ctx);
    if ((rc = budget_monte_carlo(&none, units, threads, b->angle, b->band, &b->none, err, errlen)))
        return rc;

    for (int i = 0; i < b->n; i++) {
        budget_source *s = &b->src[i];
        sunmc_config t = none;
        budget_set_tolerance(&t, s->key, s->tolerance);
        snprintf(what, sizeof what, "%s alone", s->name);
        if (progress)
            progress(what, ++run, n_runs, ctx);
        if ((rc = budget_monte_carlo(&t, units, threads, b->angle, b->band, &s->alone, err,
                                     errlen)))
            return rc;
        t = *c;
        budget_set_tolerance(&t, s->key, 0.0);
        snprintf(what, sizeof what, "%s removed", s->name);
        if (progress)
            progress(what, ++run, n_runs, ctx);
        if ((rc = budget_monte_carlo(&t, units, threads, b->angle, b->band, &s->removed, err,
                                     errlen)))
            return rc;
        s->share_removed_before = share(b->all.before_ms - s->removed.before_ms, b->all.before_ms);
        s->share_removed_after = share(b->all.after_ms - s->removed.after_ms, b->all.after_ms);
        s->share_alone_before = share(s->alone.before_ms - b->none.before_ms,
                                      b->all.before_ms - b->none.before_ms);
        s->share_alone_after = share(s->alone.after_ms - b->none.after_ms,
                                     b->all.after_ms - b->none.after_ms);
    }

    /* Rank on the after-calibration share removed (NaN last), ties by the
     * share alone, then in key-table order: a stable insertion sort. */
    for (int i = 0; i < b->n; i++)
        b->order[i] = i;
    for (int i = 1; i < b->n; i++) {
        int x = b->order[i], j = i;
        const budget_source *sx = &b->src[x];
        while (j > 0) {
            const budget_source *sy = &b->src[b->order[j - 1]];
            double ax = isnan(sx->share_removed_after) ? -INFINITY : sx->share_removed_after;
            double ay = isnan(sy->share_removed_after) ? -INFINITY : sy->share_removed_after;
            int before = ax > ay || (ax == ay && sx->share_alone_after > sy->share_alone_after);
            if (!before)
                break;
            b->order[j] = b->order[j - 1];
            j--;
        }
        b->order[j] = x;
    }
    for (int i = 0; i < b->n; i++)
        b->src[b->order[i]].rank = i + 1;

    if (with_limits)
        for (int i = 0; i < b->n; i++) {
            snprintf(what, sizeof what, "%s inverse limit", b->src[i].name);
            if (progress)
                progress(what, i + 1, b->n, ctx);
            if ((rc = inverse_limit(c, b, &b->src[i], threads, err, errlen)))
                return rc;
        }
    return SUNMC_OK;
}
