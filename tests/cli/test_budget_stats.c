/* test_budget_stats.c - the budget's numbers against a recomputation here:
 * the per-unit squares of each run (all, floor, alone) from the unit results
 * of the same Monte Carlo, the shares by their definition (budget.h) and
 * their delta-method intervals written out here, the sum to 100 %, the ranks
 * from the shares, and each
 * inverse limit checked by running at it (the yield meets the target) and
 * just past it, one bisection resolution further (it does not); a source
 * that fails even at 0 is unmet, and yields are computed here from the units.
 * Also the DSS budget row: the total angle in the widest band. */
#include "test_util.h"

#include "budget.h"
#include "montecarlo.h"
#include "status.h"

#include <gsl/gsl_cdf.h>

static void build(config_state *st, const char *path, const char *const *sets, int n)
{
    test_build(st, path, sets, n);
    /* the inverse limits checked here bisect into tolerances whose pilot
     * cannot be fitted; the plain fit keeps the expected values exact */
    st->cfg.cal_priors = CONFIG_PRIORS_OFF;
}

/* Mean squares, means and yield of config c over units [0, n) in one report
 * row, from the unit results. */
#define UNITS 12

typedef struct {
    double before_mean, after_mean, yield;
    double sq[2][UNITS]; /* per-unit RMS^2 before, after (NaN: no fit) */
} recomputed;

static recomputed recompute(const sunmc_config *c, long n, int angle, int band)
{
    const sensor_family *fam = c->family;
    unit_result *res = calloc((size_t)n, sizeof *res);
    char err[SUNMC_ERRLEN];
    assert_int_equal(mc_run(c, 0, n, 1, res, NULL, NULL, err, sizeof err), SUNMC_OK);
    recomputed r;
    memset(&r, 0, sizeof r);
    long k = 0, pass = 0;
    double spec = c->spec_arcsec / fam->arcsec_per_rms_unit;
    for (long u = 0; u < n; u++) {
        double b = res[u].rms_before[angle][band], a = res[u].rms_after[angle][band];
        int ok = res[u].fit_status == UNIT_FIT_OK && !isnan(a) && !isnan(b);
        if (u < UNITS) {
            r.sq[0][u] = ok ? b * b : NAN;
            r.sq[1][u] = ok ? a * a : NAN;
        }
        if (!ok)
            continue;
        r.before_mean += b;
        r.after_mean += a;
        pass += test_rms_spec_pass(&res[u], angle, c->bands_deg.n, spec);
        k++;
    }
    assert_true(k > 0);
    r.before_mean /= (double)k;
    r.after_mean /= (double)k;
    r.yield = (double)pass / (double)n;
    free(res);
    return r;
}

static void expect_stats(const budget_stats *s, const recomputed *r, const char *what)
{
    const double tol = 1e-12;
    if (!(fabs(s->before_mean - r->before_mean) <= tol * r->before_mean &&
          fabs(s->after_mean - r->after_mean) <= tol * r->after_mean &&
          fabs(s->yield - r->yield) <= 1e-15))
        fail_msg("%s: mean %g %g yield %g; recomputed %g %g, %g", what, s->before_mean,
                 s->after_mean, s->yield, r->before_mean, r->after_mean, r->yield);
}

/* The share sum(x) / sum(a) over the units with a value in every run, and
 * its interval written out: R +- t sd(x - R a) / (sqrt(n) mean(a)). */
static void expect_share(const budget_share *got, const double *x, const double *a,
                         const unsigned char *paired, double conf, const char *what)
{
    double sx = 0, sa = 0;
    int n = 0;
    for (int u = 0; u < UNITS; u++)
        if (paired[u]) {
            sx += x[u];
            sa += a[u];
            n++;
        }
    double r = sx / sa, ss = 0;
    for (int u = 0; u < UNITS; u++)
        if (paired[u])
            ss += (x[u] - r * a[u]) * (x[u] - r * a[u]);
    double half = gsl_cdf_tdist_Pinv(0.5 + 0.5 * conf, n - 1) * sqrt(ss / (n - 1)) /
                  sqrt((double)n) / (sa / n);
    if (!(fabs(got->v - r) <= 1e-9 && fabs(got->ci.lo - (r - half)) <= 1e-9 &&
          fabs(got->ci.hi - (r + half)) <= 1e-9))
        fail_msg("%s: share %g [%g, %g], recomputed %g [%g, %g]", what, got->v, got->ci.lo,
                 got->ci.hi, r, r - half, r + half);
    assert_int_equal(got->significant, r - half > 0 || r + half < 0);
}
#define SMALL_SETS                                                                                \
    "campaign.alpha_step_deg=0.4", "validation.alpha_step_deg=0.7", "report.spec_arcsec=33",      \
        "report.yield_target=0.5", "report.budget_units=12", "report.budget_steps=4",            \
        "tolerance.dphi_deg=0", "tolerance.slit_width_um=0", "tolerance.harmonic_phase_deg=0",    \
        "tolerance.sun_x_arcsec=0", "tolerance.sun_y_arcsec=0", "tolerance.install_z_arcsec=0",   \
        "tolerance.install_x_arcsec=0", "tolerance.install_y_arcsec=0", "tolerance.dd_um=0",      \
        "tolerance.dial_tilt_deg=0"

/* The whole budget of c, checked against recomputations. */
static void check_budget(const sunmc_config *c, budget_result *b)
{
    char err[SUNMC_ERRLEN];
    assert_int_equal(budget_run(c, UNITS, 1, 1, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->angle, 0);
    assert_int_equal(b->band, 2); /* 0:62 is the widest */
    static recomputed run[BUDGET_MAX_SOURCES + 2];
    run[0] = recompute(c, UNITS, b->angle, b->band);
    expect_stats(&b->all, &run[0], "all");
    sunmc_config floor = *c;
    for (int i = 0; i < b->n; i++)
        budget_set_tolerance(&floor, b->src[i].key, 0.0);
    run[1] = recompute(&floor, UNITS, b->angle, b->band);
    expect_stats(&b->floor, &run[1], "floor");
    for (int i = 0; i < b->n; i++) {
        sunmc_config t = floor;
        budget_set_tolerance(&t, b->src[i].key, b->src[i].tolerance);
        run[2 + i] = recompute(&t, UNITS, b->angle, b->band);
        expect_stats(&b->src[i].alone, &run[2 + i], b->src[i].name);
    }
    unsigned char paired[UNITS];
    long np = 0;
    for (int u = 0; u < UNITS; u++) {
        paired[u] = 1;
        for (int r = 0; r < 2 + b->n; r++)
            paired[u] = paired[u] && !isnan(run[r].sq[0][u]) && !isnan(run[r].sq[1][u]);
        np += paired[u];
    }
    assert_int_equal(b->paired_units, np);
    for (int w = 0; w < 2; w++) {
        double x[UNITS], rest[UNITS];
        const double *all = run[0].sq[w], *fl = run[1].sq[w];
        expect_share(w ? &b->floor_after : &b->floor_before, fl, all, paired, c->confidence,
                     "floor");
        double sum = w ? b->floor_after.v : b->floor_before.v;
        for (int u = 0; u < UNITS; u++)
            rest[u] = all[u] - fl[u];
        for (int i = 0; i < b->n; i++) {
            for (int u = 0; u < UNITS; u++) {
                x[u] = run[2 + i].sq[w][u] - fl[u];
                rest[u] -= x[u];
            }
            const budget_share *s = w ? &b->src[i].share_after : &b->src[i].share_before;
            expect_share(s, x, all, paired, c->confidence, b->src[i].name);
            sum += s->v;
        }
        const budget_share *in = w ? &b->interaction_after : &b->interaction_before;
        expect_share(in, rest, all, paired, c->confidence, "interaction");
        assert_near(sum + in->v, 1.0, 1e-12); /* floor + sources + interaction = 100 % */
    }
    /* ranks: 1 = the largest after-calibration share outside the noise,
     * then before; sources whose shares are all inside the noise last */
    for (int i = 0; i < b->n; i++) {
        const budget_source *s = &b->src[b->order[i]];
        assert_int_equal(s->rank, i + 1);
        double ka = s->share_after.significant && fabs(s->share_after.v) >= 5e-5 ? s->share_after.v : 0;
        double kb = s->share_before.significant && fabs(s->share_before.v) >= 5e-5 ? s->share_before.v : 0;
        assert_int_equal(s->in_noise, ka == 0 && kb == 0);
        if (i > 0) {
            const budget_source *p = &b->src[b->order[i - 1]];
            double pa = p->share_after.significant && fabs(p->share_after.v) >= 5e-5 ? p->share_after.v : 0;
            double pb = p->share_before.significant && fabs(p->share_before.v) >= 5e-5 ? p->share_before.v : 0;
            assert_true(s->in_noise > p->in_noise ||
                        (s->in_noise == p->in_noise && (ka < pa || (ka == pa && kb <= pb))));
        }
    }
}

/* Yield with source s at value v, over the budget's units, computed here. */
static double yield_at(const sunmc_config *c, const budget_result *b, const budget_source *s,
                       double v)
{
    sunmc_config t = *c;
    budget_set_tolerance(&t, s->key, v);
    return recompute(&t, c->budget_units, b->angle, b->band).yield;
}

/* At the limit the yield meets the target; one bisection resolution past
 * it, it does not.  The resolution: bisection over [0, today] when today
 * fails, else over [lo, BUDGET_EXPAND lo] with lo <= limit. */
static void check_limit(const sunmc_config *c, const budget_result *b, const budget_source *s)
{
    assert_int_equal(s->limit_status, BUDGET_LIMIT_OK);
    double today = yield_at(c, b, s, s->tolerance);
    assert_near(s->yield_today, today, 1e-15);
    double step = today >= c->yield_target
                      ? (BUDGET_EXPAND - 1) * s->limit / ldexp(1.0, c->budget_steps)
                      : s->tolerance / ldexp(1.0, c->budget_steps);
    double at = yield_at(c, b, s, s->limit), past = yield_at(c, b, s, s->limit + step);
    if (!(at >= c->yield_target))
        fail_msg("%s: yield %g at its limit %g, below the target %g", s->name, at, s->limit,
                 c->yield_target);
    if (!(past < c->yield_target))
        fail_msg("%s: yield %g at %g, past its limit %g, still meets the target %g", s->name,
                 past, s->limit + step, s->limit, c->yield_target);
    assert_true(s->limit > 0);
    /* the interval from the tried values' yield intervals holds the limit */
    if (!isnan(s->limit_ci.lo))
        assert_true(s->limit_ci.lo <= s->limit);
    if (!isnan(s->limit_ci.hi))
        assert_true(s->limit < s->limit_ci.hi);
}

/* The budget of a config with gain_pct and etch_um at the given values
 * (dH_um = 2 besides), checked against recomputations; then gain_pct's
 * limit (and etch_um's status) checked. */
static void gain_budget(const char *gain, const char *etch, int n_sources, int today_meets)
{
    const char *sets[] = {SMALL_SETS, gain, etch, "tolerance.dH_um=2"};
    config_state st;
    build(&st, "configs/ess_type_a.ini", sets, (int)(sizeof sets / sizeof sets[0]));
    budget_result *b = calloc(1, sizeof *b);
    check_budget(&st.cfg, b);
    assert_int_equal(b->n, n_sources);
    int seen_gain = 0;
    for (int i = 0; i < b->n; i++) {
        const budget_source *s = &b->src[i];
        if (strcmp(s->name, "gain_pct") == 0) {
            seen_gain = 1;
            assert_int_equal(s->yield_today >= st.cfg.yield_target, today_meets);
            check_limit(&st.cfg, b, s);
            assert_int_equal(s->limit > s->tolerance, today_meets);
        } else if (strcmp(s->name, "etch_um") == 0) {
            /* the others alone keep the yield below the target */
            assert_int_equal(s->limit_status, BUDGET_LIMIT_UNMET);
            assert_true(yield_at(&st.cfg, b, s, 0.0) < st.cfg.yield_target);
        }
    }
    assert_true(seen_gain);
    free(b);
    config_state_free(&st);
}

/* (3 + 3, 2 + 3 sources: the tolerances and the three noise keys.) */
/* Today's gain tolerance fails the target: the limit is below it; etch_um
 * fails it even at 0. */
static void limit_below_today(void **state)
{
    (void)state;
    gain_budget("tolerance.gain_pct=3", "tolerance.etch_um=0.5", 3 + 3, 0);
}

/* Today's gain tolerance meets the target: the limit is above it. */
static void limit_above_today(void **state)
{
    (void)state;
    gain_budget("tolerance.gain_pct=1", "tolerance.etch_um=0", 2 + 3, 1);
}

/* DSS: the budget is read on the total angle in the widest band. */
static void dss_budget_row(void **state)
{
    (void)state;
    const char *sets[] = {"campaign.b_step_deg=10", "validation.b_step_deg=10",
                          "report.bands_deg=0:20, 0:50, 20:40", "tolerance.c1_arcsec=0",
                          "tolerance.c2_arcsec=0", "tolerance.c3_arcsec=0",
                          "tolerance.glass_index=0", "tolerance.glass_thickness_um=0"};
    config_state st;
    build(&st, "configs/dss.ini", sets, 8);
    budget_result *b = calloc(1, sizeof *b);
    char err[SUNMC_ERRLEN];
    assert_int_equal(budget_run(&st.cfg, 10, 1, 0, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->angle, 2);
    assert_int_equal(b->band, 1);
    recomputed all = recompute(&st.cfg, 10, 2, 1);
    expect_stats(&b->all, &all, "all");
    free(b);
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(limit_below_today),
        cmocka_unit_test(limit_above_today),
        cmocka_unit_test(dss_budget_row),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
