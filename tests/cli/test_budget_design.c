/* test_budget_design.c - the budget's shares under a sampling design when
 * some units have no fit (issue 43).  The shares are over the units with a
 * fit in every run; their intervals come from the block totals of
 * z_u = x_u - R a_u, a unit's block being ITS run.sampling_block block
 * (u / B), not its place among the paired units: recomputed here from the
 * unit results of the same Monte Carlo (calibration.max_iterations = 5
 * leaves a few ESS units unfitted). */
#include "test_util.h"

#include "budget.h"
#include "montecarlo.h"
#include "report.h"
#include "status.h"

#include <gsl/gsl_cdf.h>

#define UNITS 24
#define BLOCK 4

/* Per-unit RMS^2 before and after (NaN: no fit) of config c, band. */
static void squares(const sunmc_config *c, int angle, int band, double sq[2][UNITS])
{
    unit_result *res = calloc(UNITS, sizeof *res);
    char err[SUNMC_ERRLEN];
    assert_int_equal(mc_run(c, 0, UNITS, 1, res, NULL, NULL, err, sizeof err), SUNMC_OK);
    for (long u = 0; u < UNITS; u++) {
        double b = res[u].rms_before[angle][band], a = res[u].rms_after[angle][band];
        int ok = res[u].fit_status == UNIT_FIT_OK && !isnan(a) && !isnan(b);
        sq[0][u] = ok ? b * b : NAN;
        sq[1][u] = ok ? a * a : NAN;
    }
    free(res);
}

/* sum x / sum a over the paired units, its interval from the totals of
 * z = x - R a per design block u / BLOCK. */
static void expect_share(const budget_share *got, const double *x, const double *a,
                         const unsigned char *paired, double conf, const char *what)
{
    double sx = 0, sa = 0;
    for (int u = 0; u < UNITS; u++)
        if (paired[u]) {
            sx += x[u];
            sa += a[u];
        }
    double R = sx / sa, tot[UNITS / BLOCK] = {0};
    int used[UNITS / BLOCK] = {0}, nb = 0;
    for (int u = 0; u < UNITS; u++)
        if (paired[u]) {
            tot[u / BLOCK] += x[u] - R * a[u];
            used[u / BLOCK] = 1;
        }
    double zz = 0;
    for (int b = 0; b < UNITS / BLOCK; b++) {
        zz += tot[b] * tot[b];
        nb += used[b];
    }
    double v = (double)nb / (double)(nb - 1) * zz / (sa * sa);
    double h = gsl_cdf_tdist_Pinv(0.5 * (1 + conf), nb - 1) * sqrt(v);
    if (!(fabs(got->v - R) <= 1e-9 && fabs(got->ci.lo - (R - h)) <= 1e-9 &&
          fabs(got->ci.hi - (R + h)) <= 1e-9))
        fail_msg("%s: share %g [%g, %g], recomputed %g [%g, %g]", what, got->v, got->ci.lo,
                 got->ci.hi, R, R - h, R + h);
}

static void shares_by_unit_blocks(void **state)
{
    const char *sets[] = {"campaign.alpha_step_deg=0.4", "validation.alpha_step_deg=0.7",
                          "report.budget_units=10", "report.budget_steps=1",
                          "run.sampling=lhs", "run.sampling_block=4",
                          "calibration.max_iterations=5"};
    config_state st;
    test_build(&st, "configs/ess_type_a.ini", sets, (int)(sizeof sets / sizeof sets[0]));
    st.cfg.cal_priors = CONFIG_PRIORS_OFF;
    const sunmc_config *c = &st.cfg;
    assert_int_equal(c->sampling_block, BLOCK);
    budget_result *b = calloc(1, sizeof *b);
    char err[SUNMC_ERRLEN];
    assert_int_equal(budget_run(c, UNITS, 1, 1, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    static double sq[BUDGET_MAX_SOURCES + 2][2][UNITS];
    squares(c, b->angle, b->band, sq[0]);
    sunmc_config floor = *c;
    for (int i = 0; i < b->n; i++)
        budget_set_tolerance(&floor, b->src[i].key, 0.0);
    squares(&floor, b->angle, b->band, sq[1]);
    for (int i = 0; i < b->n; i++) {
        sunmc_config t = floor;
        budget_set_tolerance(&t, b->src[i].key, b->src[i].tolerance);
        squares(&t, b->angle, b->band, sq[2 + i]);
    }
    unsigned char paired[UNITS];
    long np = 0;
    for (int u = 0; u < UNITS; u++) {
        paired[u] = 1;
        for (int r = 0; r < 2 + b->n; r++)
            paired[u] = paired[u] && !isnan(sq[r][0][u]) && !isnan(sq[r][1][u]);
        np += paired[u];
    }
    assert_int_equal(b->paired_units, np);
    /* the case of this test: units lost, but enough left */
    if (!(np < UNITS && np >= STUDY_MIN_UNITS))
        fail_msg("%ld of %d units paired", np, UNITS);
    for (int w = 0; w < 2; w++) {
        double x[UNITS];
        expect_share(w ? &b->floor_after : &b->floor_before, sq[1][w], sq[0][w], paired,
                     c->confidence, "floor");
        for (int i = 0; i < b->n; i++) {
            for (int u = 0; u < UNITS; u++)
                x[u] = sq[2 + i][w][u] - sq[1][w][u];
            expect_share(w ? &b->src[i].share_after : &b->src[i].share_before, x, sq[0][w],
                         paired, c->confidence, b->src[i].name);
        }
    }
    free(b);
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(shares_by_unit_blocks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
