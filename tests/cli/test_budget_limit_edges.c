/* test_budget_limit_edges.c - the inverse-limit search when the yield today
 * equals the target exactly (issue 29), on the toy family (one angle, a
 * line fit): the spec is set to the 95th smallest after-calibration RMS of
 * 100 units, so exactly 95 of 100 pass; the limit must then be at or above
 * today's tolerance.  One unit fewer (94 of 100) and it must be below. */
#include "test_util.h"

#include "toy_family.h"

#include "budget.h"
#include "config.h"
#include "family.h"
#include "montecarlo.h"
#include "registry.h"
#include "status.h"

#include <stdlib.h>

static char dir[] = "/tmp/sunmc_test_limit_XXXXXX";
static char ini[300];

static int setup(void **state)
{
    if (sensor_family_register(&toy_family) != 0 || !mkdtemp(dir))
        return -1;
    snprintf(ini, sizeof ini, "%s/toy.ini", dir);
    return test_write_file(ini, "[sensor]\nfamily = toy\n[tolerance]\nscale_pct = 2\n"
                                "offset_arcsec = 0\n[noise]\nreading_arcsec = 5\n"
                                "[report]\nyield_target = 0.95\nbudget_units = 100\n"
                                "budget_steps = 3\n");
}

static int teardown(void **state)
{
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The limit of the scale source with the spec at the k-th smallest after
 * RMS (k of 100 units pass); yield today in *today. */
static budget_source limit_with_passing(long k, double *today)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    if (config_build(&st, ini, NULL, 0, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    sunmc_config *c = &st.cfg;
    budget_result *b = calloc(1, sizeof *b);
    assert_int_equal(budget_sources(c, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->n, 1); /* scale_pct (the toy lists no noise source) */
    assert_string_equal(b->src[0].name, "scale_pct");
    long n = c->budget_units;
    assert_int_equal(n, 100);
    unit_result *res = calloc((size_t)n, sizeof *res);
    double *aft = calloc((size_t)n, sizeof *aft);
    assert_int_equal(mc_run(c, 0, n, 1, res, NULL, NULL, err, sizeof err), SUNMC_OK);
    for (long u = 0; u < n; u++) {
        assert_int_equal(res[u].fit_status, UNIT_FIT_OK);
        aft[u] = res[u].rms_after[b->angle][b->band];
    }
    qsort(aft, (size_t)n, sizeof *aft, cmp_double);
    assert_true(aft[k - 1] < aft[k]); /* no tie at the edge */
    assert_near(c->family->arcsec_per_rms_unit, 1.0, 0);
    c->spec_arcsec = aft[k - 1];
    /* the spec in the budget's band alone: k units pass (verdict.h) */
    snprintf(c->spec_bands, sizeof c->spec_bands, "%g:%g", c->bands_deg.lo[b->band],
             c->bands_deg.hi[b->band]);
    budget_source s = b->src[0];
    assert_int_equal(budget_inverse_limit(c, b, &s, 1, err, sizeof err), SUNMC_OK);
    *today = s.yield_today;
    free(aft);
    free(res);
    free(b);
    config_state_free(&st);
    return s;
}

static void yield_exactly_at_target(void **state)
{
    double today;
    budget_source s = limit_with_passing(95, &today);
    assert_true(today == 0.95); /* 95 of 100, exactly the target */
    if (!(s.limit >= s.tolerance) || s.limit_status == BUDGET_LIMIT_UNMET)
        fail_msg("yield today = target: limit %g (status %d) below today's %g", s.limit,
                 s.limit_status, s.tolerance);
    s = limit_with_passing(94, &today);
    assert_true(today == 0.94);
    if (!(s.limit < s.tolerance))
        fail_msg("yield today below target: limit %g not below today's %g", s.limit,
                 s.tolerance);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(yield_exactly_at_target),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
