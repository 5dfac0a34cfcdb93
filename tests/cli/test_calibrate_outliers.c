/* test_calibrate_outliers.c - issue 39: a repeat campaign unlike the
 * others (fold_outliers.h).  A simulated PSD unit's beta = 10 deg line
 * read six times, each read a sweep after its "# source:" line, the folds
 * of the cross-validation being the sweeps:
 *  - as read: nothing judged unlike the others;
 *  - sweep 4's table angles 3 % too large (a table that lost its scale,
 *    as kenscl's beta sweep of 19.11.2021 16.55 is off beyond 40 deg): by
 *    default the sweep is named and dropped from the calibration, its
 *    rows weighted 0, the estimate of the first pass said beside it, and
 *    the drift report still compares it (its table's -3 % found);
 *  - calibration.outlier_campaigns = keep: the sweep stays in the fit,
 *    named, and left out of the estimate only: the estimate is the pooled
 *    RMS of the other five folds (from crossval.tsv, in closed form), the
 *    models' comparison the same;
 *  - beta lines as folds (across the field): never judged, however far an
 *    edge line's error is above the others'. */
#include "test_util.h"
#include "test_tsv.h"

#include <math.h>

static char dir[512];

#define P "configs/psd.ini --set calibration.model=spline"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    if (test_private_dir(dir, sizeof dir, "caloutl") != 0)
        return -1;
    const char *steps[] = {
        "simulate " P " --unit 3 --quiet --set campaign.repeats=6 --set campaign.beta_deg=-10,10 "
        "--set campaign.alpha_step_deg=1 --out $D/s",
        "true; awk -F, '/^#/{next} /^alpha/{print; next} $2==10{k=(n++)%6; r[k]=r[k] $0 \"\\n\"} "
        "END{for (k=0;k<6;k++) {print \"# source: sweep \" k; printf \"%s\", r[k]}}' "
        "$D/s/campaign.csv > $D/ok.csv",
        "true; awk -F, 'BEGIN{OFS=\",\"} /^# source: sweep 4/{d=1; print; next} /^#/{d=0; print; "
        "next} /^alpha/{print; next} {if (d) $1=$1*1.03; print}' $D/ok.csv > $D/bad.csv",
        /* nine beta lines, the -15 deg line's alpha 3 % off: a fold far out */
        "simulate " P " --unit 3 --quiet --set campaign.beta_deg=-20,-15,-10,-5,0,5,10,15,20 "
        "--set campaign.alpha_step_deg=2 --out $D/l",
        "true; awk -F, 'BEGIN{OFS=\",\"} /^#/||/^alpha/{print; next} {if ($2==-15) "
        "$1=$1*1.03; print}' $D/l/campaign.csv > $D/lines.csv",
        /* one alpha sweep on the axis (beta = 0): the spline and table per axis */
        "simulate " P " --unit 3 --quiet --set campaign.beta_deg=-10,0 --set campaign.repeats=2 "
        "--set campaign.alpha_step_deg=1 --out $D/a",
        "true; awk -F, '/^#/||/^alpha/{print; next} $2==0{print}' $D/a/campaign.csv > $D/axis.csv"};
    return test_sunmc_steps(dir, steps, 7);
}

/* The value of params.ini's key at path (NaN: no such line). */
static double params_value(const char *path, const char *key)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[512];
    double v = NAN;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, key, strlen(key)) == 0 && line[strlen(key)] == ' ' && strchr(line, '='))
            v = atof(strchr(line, '=') + 1);
    fclose(f);
    return v;
}

static void test_clean_sweeps_quiet(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " $D/ok.csv --out $D/c0", out, sizeof out), 0);
    test_must_have(out, "held out sweep 5");
    assert_null(strstr(out, "unlike the others"));
    assert_null(strstr(out, "dropped from the calibration"));
    char p[700];
    snprintf(p, sizeof p, "%s/c0/crossval.tsv", dir);
    tsv *t = tsv_load(p);
    assert_non_null(t);
    assert_int_equal(t->nr, 6);
    for (int r = 0; r < 6; r++)
        assert_int_equal((int)tsv_num(t, r, "outlier"), 0);
    tsv_free(t);
}

static void test_outlier_dropped(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " $D/bad.csv --out $D/c1", out, sizeof out), 0);
    const char *w = strstr(out, "dropped from the calibration: 1 repeat campaign");
    assert_non_null(w);
    test_must_have(w, "the spline model (the best held out) left above 2 times");
    test_must_have(w, " on sweep 4 (");
    test_must_have(out, "data: 246 rows, 205 used (41 of campaigns unlike the others set aside)");
    char p[700];
    snprintf(p, sizeof p, "%s/c1/crossval.tsv", dir);
    tsv *t = tsv_load(p);
    assert_non_null(t);
    assert_int_equal(t->nr, 5);
    for (int r = 0; r < 5; r++)
        assert_string_not_equal(tsv_str(t, r, "held_out"), "sweep_4");
    tsv_free(t);
    snprintf(p, sizeof p, "%s/c1/residuals.tsv", dir);
    t = tsv_load(p);
    assert_non_null(t);
    int zero = 0;
    for (int r = 0; r < t->nr; r++)
        zero += tsv_num(t, r, "weight") == 0;
    assert_int_equal(zero, 41);
    tsv_free(t);
    /* the dropped sweep still in the drift report: its table's 3 % */
    snprintf(p, sizeof p, "%s/c1/campaigns.tsv", dir);
    t = tsv_load(p);
    assert_non_null(t);
    assert_int_equal(t->nr, 6);
    assert_string_equal(tsv_str(t, 4, "name"), "sweep 4");
    assert_int_equal((int)tsv_num(t, 4, "rows"), 41);
    double k = tsv_num(t, 4, "scale_change_pct");
    if (!(k < -2.5 && k > -3.5))
        fail_msg("sweep 4's scale change %g %%, want about -3", k);
    tsv_free(t);
    /* the first pass's estimate, with the sweep, is the larger */
    double was = atof(strstr(w, "the estimate was ") + strlen("the estimate was "));
    snprintf(p, sizeof p, "%s/c1/params.ini", dir);
    assert_true(was > 1.5 * params_value(p, "crossval_rms_arcsec"));
}

/* The pooled RMS of crossval.tsv's folds with outlier 0, weighted by their points. */
static double pooled_kept(const tsv *t)
{
    double s2 = 0, n = 0;
    for (int r = 0; r < t->nr; r++)
        if (tsv_num(t, r, "outlier") == 0) {
            double m = tsv_num(t, r, "points"), e = tsv_num(t, r, "rms_out_arcsec");
            s2 += m * e * e;
            n += m;
        }
    return sqrt(s2 / n);
}

static void test_outlier_kept(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " --set calibration.outlier_campaigns=keep "
                           "$D/bad.csv --out $D/c2",
                           out, sizeof out),
                     0);
    test_must_have(out, "1 of 6 held-out repeat campaigns is unlike the others");
    test_must_have(out, "sweep 4 (");
    test_must_have(out, "(unlike the others: not in the estimate)");
    test_must_have(out, "data: 246 rows, 246 used,");
    assert_null(strstr(out, "dropped from the calibration"));
    char p[700];
    snprintf(p, sizeof p, "%s/c2/crossval.tsv", dir);
    tsv *t = tsv_load(p);
    assert_non_null(t);
    assert_int_equal(t->nr, 6);
    assert_int_equal((int)tsv_num(t, 4, "outlier"), 1);
    double kept = pooled_kept(t);
    tsv_free(t);
    snprintf(p, sizeof p, "%s/c2/params.ini", dir);
    double est = params_value(p, "crossval_rms_arcsec");
    /* points weight each fold; a few rows outside a refit's field go unscored */
    assert_true(fabs(est - kept) < 2e-3 * kept);
    /* the comparison's spline: the same fold left out, the pool with it larger */
    snprintf(p, sizeof p, "%s/c2/models.tsv", dir);
    t = tsv_load(p);
    assert_non_null(t);
    for (int r = 0; r < t->nr; r++)
        if (strcmp(tsv_str(t, r, "model"), "spline") == 0) {
            assert_int_equal((int)tsv_num(t, r, "outlier_folds"), 1);
            assert_true(tsv_num(t, r, "rms_out_all_arcsec") > 1.5 * tsv_num(t, r, "rms_out_arcsec"));
            assert_true(fabs(tsv_num(t, r, "rms_out_arcsec") - kept) < 2e-3 * kept);
            /* the means leave the same fold's points out: no worse than a reading */
            assert_true(tsv_num(t, r, "rms_out_mean_arcsec") < tsv_num(t, r, "rms_out_arcsec"));
        }
    tsv_free(t);
}

static void test_lines_never_judged(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " $D/lines.csv --out $D/c3", out, sizeof out),
                     0);
    test_must_have(out, "held out beta = -15 deg");
    assert_null(strstr(out, "unlike the others"));
    char p[700];
    snprintf(p, sizeof p, "%s/c3/crossval.tsv", dir);
    tsv *t = tsv_load(p);
    assert_non_null(t);
    double worst = 0, other = 0;
    for (int r = 0; r < t->nr; r++) {
        assert_int_equal((int)tsv_num(t, r, "outlier"), 0);
        double e = tsv_num(t, r, "rms_out_arcsec");
        if (strcmp(tsv_str(t, r, "held_out"), "beta_=_-15_deg") == 0)
            worst = e;
        else
            other = fmax(other, e);
    }
    tsv_free(t);
    assert_true(worst > 2.0 * other); /* far out, and still not judged */
}

/* Single-axis rows: the spline takes the other ratio's cross term, the
 * table (one line per axis) does not and still calibrates. */
static void test_axis_spline_and_table(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " $D/axis.csv --out $D/c4", out, sizeof out), 0);
    test_must_have(out, "one per axis: single-axis sweeps");
    char p[700];
    snprintf(p, sizeof p, "%s/c4/params.ini", dir);
    assert_true(test_file_has(p, "\ncross "));
    assert_int_equal(sunmc("calibrate --config " P " --set calibration.model=table $D/axis.csv "
                           "--out $D/c5",
                           out, sizeof out),
                     0);
    test_must_have(out, "the look-up table:");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clean_sweeps_quiet),
        cmocka_unit_test(test_outlier_dropped),
        cmocka_unit_test(test_outlier_kept),
        cmocka_unit_test(test_lines_never_judged),
        cmocka_unit_test(test_axis_spline_and_table),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
