/* test_lab_weights.c - issue 36, rule 3: a lab file's weights are relative
 * precisions, not a lever.  One heavy row leaves the reported residual and
 * the standard errors where they were; weights that cannot be precisions
 * (all zero, non-finite, more than 1e6 times the median) are refused with
 * FILE:LINE, exit 2, nothing written.  PSD and DSS campaigns (the ESS's
 * heavy-row refusal is in test_calibrate_trust). */
#include "test_util.h"

static char dir[512];

#define P "configs/psd.ini"
#define D "configs/dss.ini"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    if (test_private_dir(dir, sizeof dir, "labweights") != 0)
        return -1;
    const char *steps[] = {"simulate " P " --unit 1 --quiet --out $D/p",
                           "simulate " D " --unit 3 --quiet --out $D/d"};
    return test_sunmc_steps(dir, steps, (int)(2));
}

/* $D/NAME.csv: SRC's campaign with the weight (last column) of its ROW-th
 * row of weight > 0 set to W (ROW 0: every such row; -1: none). */
static void reweight(const char *src, const char *name, int row, const char *w)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd,
             "grep -v '^#' %s/%s/campaign.csv | awk -F, 'BEGIN { OFS = \",\" } NR == 1 { print; "
             "next } $NF > 0 { k++; if (%d == 0 || k == %d) $NF = \"%s\" } { print }' > %s/%s.csv",
             dir, src, row, row, w, dir, name);
    assert_int_equal(system(cmd), 0);
}

/* The residual and the first standard error calibrate prints for NAME. */
static void calibrate(const char *config, const char *name, double *sigma, double *se)
{
    char args[1024], out[65536];
    snprintf(args, sizeof args, "calibrate --config %s $D/%s.csv", config, name);
    int rc = sunmc(args, out, sizeof out);
    if (rc != 0)
        fail_msg("%s: exit %d: %s", name, rc, out);
    const char *r = strstr(out, "residual standard deviation: ");
    const char *p = strstr(out, "+- ");
    assert_non_null(r);
    assert_non_null(p);
    *sigma = atof(r + strlen("residual standard deviation: "));
    *se = atof(p + 3);
}

/* The reproducers: one row of weight 100 made calibrate report
 * 1522" (PSD, bands 133-153") and 33.9" (DSS, 3.33" unweighted), and grew
 * the standard errors 9x; weight 1e4 refused the fit.  Now the residual
 * and the standard errors stay within 25 % of the unweighted fit's. */
static void one_heavy_row(const char *src, const char *config)
{
    double s0, e0;
    reweight(src, "w1", -1, "1");
    calibrate(config, "w1", &s0, &e0);
    const char *heavy[] = {"100", "1e4", "1e6"};
    for (int i = 0; i < 3; i++) {
        double s, e;
        reweight(src, "wh", 2, heavy[i]);
        calibrate(config, "wh", &s, &e);
        if (!(fabs(s / s0 - 1) < 0.25 && fabs(e / e0 - 1) < 0.25))
            fail_msg("%s weight %s: residual %g (unweighted %g), standard error %g (%g)", src,
                     heavy[i], s, s0, e, e0);
    }
}

static void test_heavy_row_psd(void **state) { one_heavy_row("p", P); }
static void test_heavy_row_dss(void **state) { one_heavy_row("d", D); }

/* Uniform weights of any size are the unweighted fit, exactly. */
static void test_uniform_weights_are_unweighted(void **state)
{
    double s0, e0, s, e;
    reweight("p", "u1", -1, "1");
    calibrate(P, "u1", &s0, &e0);
    reweight("p", "u7", 0, "7e-3");
    calibrate(P, "u7", &s, &e);
    assert_near(s, s0, 1e-3);
    assert_near(e, e0, 1e-3 * e0);
}

/* `sunmc calibrate` of NAME must exit 2 naming FILE:LINE and the cause,
 * and write nothing. */
static void refused(const char *config, const char *name, const char *line, const char *why)
{
    char args[1024], out[65536], cmd[1024];
    snprintf(args, sizeof args, "calibrate --config %s $D/%s.csv --out $D/out_%s", config, name,
             name);
    int rc = sunmc(args, out, sizeof out);
    char at[256];
    snprintf(at, sizeof at, "%s.csv:%s: column 'weight'", name, line);
    if (rc != 2 || !strstr(out, at) || !strstr(out, why))
        fail_msg("%s: exit %d, expected 2 with '%s' and '%s': %s", name, rc, at, why, out);
    snprintf(cmd, sizeof cmd, "test -e %s/out_%s", dir, name);
    assert_int_not_equal(system(cmd), 0);
}

/* All weights 0 was exit 1 "the residual nan arcsec"; one weight 1e30 was
 * blamed on "a saturated or clipped spot" with +- nan on stdout. */
static void test_weights_refused(void **state)
{
    reweight("p", "zero", 0, "0");
    refused(P, "zero", "2", "is 0 in every row");
    reweight("d", "dzero", 0, "0");
    refused(D, "dzero", "2", "is 0 in every row");
    reweight("p", "huge", 5, "1e30");
    refused(P, "huge", "6", "more than 1e+06 times the median");
    reweight("d", "dhuge", 5, "1e30");
    refused(D, "dhuge", "12", "more than 1e+06 times the median");
    reweight("p", "inf", 5, "inf");
    char args[1024], out[65536];
    snprintf(args, sizeof args, "calibrate --config " P " $D/inf.csv --out $D/out_inf");
    assert_int_equal(sunmc(args, out, sizeof out), 2);
}

/* The limit on both sides: 1e6 times the median is taken, one past it
 * refused. */
static void test_weight_ratio_limit(void **state)
{
    double s, e;
    reweight("p", "at", 4, "1e6");
    calibrate(P, "at", &s, &e);
    reweight("p", "past", 4, "1.000001e6");
    refused(P, "past", "5", "more than 1e+06 times the median weight 1");
}

/* calibrate's residuals.tsv: a weight-0 "no spot" row of a DSS file gets
 * no angle (it gave a near-boresight one from its (0, 0)); a read row one. */
static void test_no_spot_rows_have_no_angle(void **state)
{
    char out[65536], p[700];
    assert_int_equal(sunmc("calibrate --config " D " $D/d/campaign.csv --quiet --out $D/dres", out,
                           sizeof out),
                     0);
    snprintf(p, sizeof p, "%s/dres/residuals.tsv", dir);
    FILE *f = fopen(p, "r");
    assert_non_null(f);
    char line[1024];
    int zero = 0, read = 0;
    assert_non_null(fgets(line, sizeof line, f));
    while (fgets(line, sizeof line, f)) {
        char *fld[10], *save = NULL;
        int n = 0;
        for (char *t = strtok_r(line, "\t\n", &save); t && n < 10; t = strtok_r(NULL, "\t\n", &save))
            fld[n++] = t;
        assert_int_equal(n, 10);
        if (atof(fld[5]) == 0) {
            zero++;
            for (int k = 6; k < 10; k++)
                assert_string_equal(fld[k], "-");
        } else {
            read++;
            assert_true(strcmp(fld[6], "-") != 0 && strcmp(fld[8], "-") != 0);
        }
    }
    fclose(f);
    assert_true(zero > 0 && read > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_heavy_row_psd),
        cmocka_unit_test(test_heavy_row_dss),
        cmocka_unit_test(test_uniform_weights_are_unweighted),
        cmocka_unit_test(test_weights_refused),
        cmocka_unit_test(test_weight_ratio_limit),
        cmocka_unit_test(test_no_spot_rows_have_no_angle),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
