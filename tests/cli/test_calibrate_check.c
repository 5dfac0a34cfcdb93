/* test_calibrate_check.c - lab data a calibration must not be run on (issue 9's
 * garbage campaigns: radians, a flipped sign, swapped columns, one alpha,
 * all outputs 0, every DSS spot at the centre) and fits refused although
 * they converged (gross-error rows, rank, residual against the noise);
 * weights that count by their ratios only. */
#include "test_util.h"

#include "calreport.h"
#include "lab.h"

#include <unistd.h>

static int sunmc(const char *args, char *out, size_t len)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s %s", test_sunmc(), args);
    return test_run(cmd, out, len);
}

/* Unit 1 of config simulated into a private directory, once per family. */
static const char *simulated(const char *name, const char *config)
{
    static char dirs[2][512];
    char *d = dirs[strcmp(name, "ess") == 0 ? 0 : 1];
    if (!d[0]) {
        char args[1024], out[8192];
        snprintf(d, 512, "%s", test_tmp(name));
        snprintf(args, sizeof args, "simulate %s --unit 1 --quiet --out %s", config, d);
        assert_int_equal(sunmc(args, out, sizeof out), 0);
    }
    return d;
}

/* The family's campaign with its data rows rewritten by an awk statement
 * (header and comments copied) into DIR/file, then calibrated with opts;
 * the exit status, output in out. */
static int calibrate_garbled(const char *name, const char *config, const char *awk,
                             const char *file, const char *opts, char *out, size_t len)
{
    const char *d = simulated(name, config);
    char cmd[8192];
    snprintf(cmd, sizeof cmd,
             "awk -F, 'BEGIN {OFS=\",\"} /^#/ {print; next} !h {h=1; print; next} {%s; print}' "
             "%s/campaign.csv > %s/%s && %s calibrate --config %s %s %s/%s --out %s/%s.cal",
             awk, d, d, file, test_sunmc(), config, opts ? opts : "", d, file, d, file);
    return test_run(cmd, out, len);
}

#define ESS "configs/ess_type_a.ini"
#define DSS "configs/dss.ini"
#define RAD "3.14159265358979/180"

static void expect(int st, const char *out, int want, const char *needle)
{
    if (st != want || !strstr(out, needle))
        fail_msg("expected exit %d and '%s', got %d:\n%s", want, needle, st, out);
}

/* The reproducer: an ESS campaign in radians was fitted, exit 0,
 * "held-out 1.81 arcsec". */
static void test_radians(void **state)
{
    char out[16384];
    int st = calibrate_garbled("ess", ESS, "$1 = $1 * " RAD "; $2 = $2 * " RAD "; $3 = $3 * " RAD,
                               "rad.csv", NULL, out, sizeof out);
    expect(st, out, 2, "the angles look like radians");
    assert_non_null(strstr(out, "column 'alpha_deg' spans"));
    st = calibrate_garbled("dss", DSS, "$1 = $1 * " RAD "; $2 = $2 * " RAD, "rad.csv", NULL, out,
                           sizeof out);
    expect(st, out, 2, "look like radians");
}

/* The reproducers: the output's sign flipped (1,848 of 1,863 rows
 * silently dropped, exit 0), alpha and beta swapped (30 rows used, exit 0). */
static void test_sign_and_swaps(void **state)
{
    char out[16384];
    int st = calibrate_garbled("ess", ESS, "$3 = -$3", "sign.csv", NULL, out, sizeof out);
    expect(st, out, 2, "with every output's sign flipped");
    assert_non_null(strstr(out, "rows are inconsistent with their table angles"));
    st = calibrate_garbled("ess", ESS, "t = $1; $1 = $2; $2 = t", "swap.csv", NULL, out,
                           sizeof out);
    expect(st, out, 2, "with the two table-angle columns swapped");
    st = calibrate_garbled("dss", DSS, "t = $3; $3 = $4; $4 = t", "swapxy.csv", NULL, out,
                           sizeof out);
    expect(st, out, 2, "rows are inconsistent with their table angles");
    st = calibrate_garbled("dss", DSS, "$3 = -$3; $4 = -$4", "signxy.csv", NULL, out, sizeof out);
    expect(st, out, 2, "with every output's sign flipped");
}

/* The reproducers: all rows at one alpha ("fit: converged",
 * condition 2.7e18), all outputs 0, every DSS spot at (0, 0). */
static void test_degenerate(void **state)
{
    char out[16384];
    int st = calibrate_garbled("ess", ESS, "$1 = 10; $3 = 10.01", "one.csv", NULL, out, sizeof out);
    expect(st, out, 2, "column 'alpha_deg' takes 1 distinct value (every row at 10)");
    st = calibrate_garbled("ess", ESS, "$3 = 0", "zero.csv", NULL, out, sizeof out);
    expect(st, out, 2, "rows are inconsistent with their table angles");
    st = calibrate_garbled("dss", DSS, "$3 = 0; $4 = 0", "centre.csv", NULL, out, sizeof out);
    expect(st, out, 2, "rows are inconsistent with their table angles");
    /* the data as simulated pass */
    st = calibrate_garbled("ess", ESS, "", "asis.csv", NULL, out, sizeof out);
    expect(st, out, 0, "fit: converged");
    st = calibrate_garbled("dss", DSS, "", "asis.csv", NULL, out, sizeof out);
    expect(st, out, 0, "fit: converged");
}

static double sigma_of(const char *out)
{
    const char *p = strstr(out, "residual standard deviation: ");
    return p ? strtod(p + strlen("residual standard deviation: "), NULL) : NAN;
}

/* The reproducer: uniform weights 1e300 gave a residual sigma of
 * 2e151 and +-inf correlations.  Weights count by their ratios only. */
static void test_weights_ratio_only(void **state)
{
    char out[16384];
    int st = calibrate_garbled("ess", ESS, "$4 = 1", "w1.csv", NULL, out, sizeof out);
    expect(st, out, 0, "fit: converged");
    double s1 = sigma_of(out);
    const char *big[] = {"$4 = 1e300", "$4 = 1e-300"};
    for (int i = 0; i < 2; i++) {
        st = calibrate_garbled("ess", ESS, big[i], "wbig.csv", NULL, out, sizeof out);
        expect(st, out, 0, "fit: converged");
        assert_near(sigma_of(out), s1, 1e-6 * s1);
        assert_null(strstr(out, "+inf"));
        assert_null(strstr(out, "-inf"));
    }
}

/* A fit far above the config's noise is refused (exit 1, the report
 * printed, nothing written); the ratio is a key. */
static void test_residual_against_noise(void **state)
{
    char out[16384], dir[600];
    /* the default 1.5 % row noise (residual ~22") fitted with a config that
     * claims 0.01 %: the limit is 10 x max(0.1", 1") */
    int st = calibrate_garbled("ess", ESS, "", "quiet.csv", "--set noise.row_current_pct=0.01",
                               out, sizeof out);
    expect(st, out, 1, "fit: REFUSED after");
    assert_non_null(strstr(out, "times the reading noise of the config"));
    assert_non_null(strstr(out, "the fit is refused"));
    snprintf(dir, sizeof dir, "%s/quiet.csv.cal", simulated("ess", ESS));
    assert_int_equal(access(dir, F_OK), -1);
    st = calibrate_garbled("ess", ESS, "", "quiet2.csv",
                           "--set noise.row_current_pct=0.01 "
                           "--set calibration.max_residual_ratio=100",
                           out, sizeof out);
    expect(st, out, 0, "fit: converged");
}

/* ---- lab_check_fit and calreport_print on made-up reports ---- */

static void test_check_fit_limits(void **state)
{
    sunmc_config c = test_family_config("ess");
    double w[100];
    for (int i = 0; i < 100; i++)
        w[i] = i < 10 ? 0 : 1; /* 10 rows weighted 0 by the user: not gross errors */
    lab_columns d = {.path = "x.csv", .n = 100, .n_cols = 1, .v = {w}};
    family_lab lab = {0};
    calreport r;
    calreport_init(&r, "ess", "m");
    r.fit_ok = 1;
    r.cov_ok = 1;
    r.cond_jacobian = 1e12;
    r.sigma_arcsec = 10; /* no noise hook: 10 x the 1" floor */
    r.n_used = 90 - 4;   /* 4 of 90 dropped: 4.4 % */
    lab_check_fit(&lab, &c, &d, &r);
    assert_int_equal(r.fit_ok, 1);
    assert_string_equal(r.refused, "");
    r.n_used = 90 - 5; /* 5.6 % */
    lab_check_fit(&lab, &c, &d, &r);
    assert_int_equal(r.fit_ok, 0);
    assert_non_null(strstr(r.refused, "5 of 90 rows were dropped as gross errors"));
    /* no covariance alone (a linear model's report) is not a refusal */
    calreport_init(&r, "ess", "m");
    r.fit_ok = 1;
    r.n_used = 90;
    r.cond_jacobian = 10;
    r.sigma_arcsec = 1;
    lab_check_fit(&lab, &c, &d, &r);
    assert_int_equal(r.fit_ok, 1);
    const struct {
        int cov_ok;
        double cond, sigma;
        const char *needle;
    } cases[] = {{1, 1.01e12, 1, "condition number 1.01e+12"},
                 {1, NAN, 1, "rank-deficient"},
                 {1, 10, 10.01, "the residual 10.01 arcsec"},
                 {1, 10, NAN, "the residual nan"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        calreport_init(&r, "ess", "m");
        r.fit_ok = 1;
        r.n_used = 90;
        r.cov_ok = cases[i].cov_ok;
        r.cond_jacobian = cases[i].cond;
        r.sigma_arcsec = cases[i].sigma;
        lab_check_fit(&lab, &c, &d, &r);
        if (r.fit_ok || !strstr(r.refused, cases[i].needle))
            fail_msg("case %zu: fit_ok %d, '%s'", i, r.fit_ok, r.refused);
    }
}

/* The reproducer: without a covariance the correlation matrix
 * printed +0.000 everywhere, diagonal included. */
static void test_no_covariance_printed(void **state)
{
    calreport r;
    calreport_init(&r, "ess", "m");
    r.np = 2;
    snprintf(r.name[0], sizeof r.name[0], "a");
    snprintf(r.name[1], sizeof r.name[1], "b");
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    calreport_print(f, &r);
    fclose(f);
    assert_non_null(strstr(buf, "correlation matrix: not available"));
    assert_null(strstr(buf, "+0.000 "));
    assert_null(strstr(buf, "+0.000\n"));
    free(buf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_radians),
        cmocka_unit_test(test_sign_and_swaps),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_weights_ratio_only),
        cmocka_unit_test(test_residual_against_noise),
        cmocka_unit_test(test_check_fit_limits),
        cmocka_unit_test(test_no_covariance_printed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
