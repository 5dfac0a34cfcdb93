/* test_yield_interval.c - report.yield_interval (issue 28): the yield's
 * Clopper-Pearson interval and its one-sided lower bound in summary.tsv
 * equal GSL's beta quantiles computed here from the pass count; Wilson stays
 * the default; the method is named in the file and in Table 1. */
#include "test_tsv.h"
#include "test_util.h"

#include <gsl/gsl_cdf.h>

#define SPEC " --set report.spec_arcsec=27 --set validation.alpha_step_deg=2.3 --quiet"

static tsv *run(const char *method, char *out, size_t len)
{
    char cmd[4096], path[1024];
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 60 --set report.yield_interval=%s --out %s" SPEC,
             test_sunmc(), method, test_tmp(method));
    int rc = test_run(cmd, out, len);
    if (rc != 0)
        fail_msg("%s exited %d: %s", cmd, rc, out);
    snprintf(path, sizeof path, "%s/summary.tsv", test_tmp(method));
    tsv *t = tsv_load(path);
    assert_non_null(t);
    return t;
}

static void clopper_pearson_is_beta_quantiles(void **state)
{
    char out[16384];
    tsv *two = run("clopper_pearson", out, sizeof out);
    assert_non_null(strstr(out, "yield Clopper-Pearson"));
    tsv *one = run("clopper_pearson_lower", out, sizeof out);
    assert_non_null(strstr(out, "yield one-sided Clopper-Pearson lower bound"));
    tsv *wil = run("wilson", out, sizeof out);
    int interior = 0;
    for (int r = 0; r < two->nr; r++) {
        long n = (long)tsv_num(two, r, "units");
        long x = lround(tsv_num(two, r, "yield") * (double)n);
        double conf = tsv_num(two, r, "confidence"), a = 1 - conf;
        double lo2 = x == 0 ? 0 : gsl_cdf_beta_Pinv(a / 2, (double)x, (double)(n - x + 1));
        double hi2 = x == n ? 1 : gsl_cdf_beta_Pinv(1 - a / 2, (double)(x + 1), (double)(n - x));
        double lo1 = x == 0 ? 0 : gsl_cdf_beta_Pinv(a, (double)x, (double)(n - x + 1));
        assert_near(tsv_num(two, r, "yield_ci_lo"), lo2, 1e-5);
        assert_near(tsv_num(two, r, "yield_ci_hi"), hi2, 1e-5);
        assert_near(tsv_num(one, r, "yield_ci_lo"), lo1, 1e-5);
        assert_true(tsv_num(one, r, "yield_ci_hi") == 1.0);
        assert_true(lo1 > lo2 || x == 0); /* one-sided: a tighter lower bound */
        assert_string_equal(tsv_str(two, r, "yield_interval"), "clopper_pearson");
        assert_string_equal(tsv_str(one, r, "yield_interval"), "clopper_pearson_lower");
        assert_string_equal(tsv_str(wil, r, "yield_interval"), "wilson");
        /* Clopper-Pearson is wider than Wilson */
        assert_true(tsv_num(wil, r, "yield_ci_lo") >= lo2 - 1e-9);
        interior += x > 0 && x < n;
    }
    assert_true(interior > 0); /* some band's yield strictly between 0 and 100 % */
    tsv_free(two);
    tsv_free(one);
    tsv_free(wil);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(clopper_pearson_is_beta_quantiles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
