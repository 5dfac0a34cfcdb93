/* test_calibrate_models.c - issue 39: `calibrate` of a four-channel sensor
 * compares its models on the same folds and recommends one, and the
 * spline, hybrid and table models reach compensate:
 *  - a simulated unit (the physics exact, noise only): five models in the
 *    comparison and models.tsv, the physical one recommended, no word
 *    against the physics;
 *  - the same campaign with channel 1 warped by 30 % sin(alpha / 6 deg),
 *    which no geometry gives: the physical fit is refused, and the report
 *    says the physics does not describe the sensor and which model to use;
 *    calibrated with that model it is accepted;
 *  - a spline (a table) calibrated on +-20 deg compensates readings to +-30 deg:
 *    those beyond its field are '-', counted as outside the calibrated
 *    field, those inside are compensated;
 *  - with 4 repeats per point, the held-out mean of a point's readings
 *    is about half a single reading's error (noise over sqrt 4), and a
 *    polynomial that overfits shows it only held out;
 *  - an inverting sensor (aeroztark's layout) is compensated: its
 *    channels below the fitted darks are its signal (params.ini's
 *    design.polarity);
 *  - the comparison is the same at 1 and 2 threads;
 *  - a DSS's five models on folds of its b1 lines: the physical one
 *    recommended on a simulated unit, the hybrid's held-out error within
 *    10 % of it, the spline's and the table's far above (models.tsv). */
#include "test_util.h"

static char dir[512];

#define P "configs/psd.ini"
/* A small campaign of aeroztark's inverting sensor. */
#define AZ                                                                                   \
    "--set campaign.beta_deg=-10,-6,-2,2,6,10 --set campaign.repeats=1 "                      \
    "--set campaign.alpha_step_deg=2 --set campaign.alpha_max_deg=14"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    if (test_private_dir(dir, sizeof dir, "calmodels") != 0)
        return -1;
    const char *steps[] = {
        "simulate " P " --unit 3 --quiet --out $D/sp",
        "simulate " P " --unit 3 --quiet --set validation.alpha_max_deg=30 --out $D/sp30",
        "simulate " P " --unit 3 --quiet --set campaign.repeats=4 --out $D/sr",
        "simulate configs/psd_aeroztark.ini " AZ " --unit 3 --quiet --out $D/sa",
        "true; awk -F, 'BEGIN{OFS=\",\"} /^#/ || /^alpha/ {print; next} "
        "{$3 = $3 * (1 + 0.3 * sin($1 / 6)); print}' $D/sp/campaign.csv > $D/warp.csv"};
    return test_sunmc_steps(dir, steps, 5);
}

static void test_exact_physics_recommended(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " $D/sp/campaign.csv --out $D/cp", out,
                           sizeof out), 0);
    test_must_have(out, "model comparison");
    test_must_have(out, "used: physical; recommended: physical");
    assert_null(strstr(out, "does not describe"));
    char p[700];
    snprintf(p, sizeof p, "%s/cp/models.tsv", dir);
    assert_true(test_file_has(p, "rms_out_mean_arcsec\toutlier_folds\trms_out_all_arcsec\n"));
    const char *names[] = {"\nphysical\t", "\npolynomial\t", "\nspline\t", "\nhybrid\t",
                           "\ntable\t"};
    for (int k = 0; k < 5; k++)
        assert_true(test_file_has(p, names[k]));
}

static void test_physics_does_not_describe(void **state)
{
    static char out[65536];
    /* stdout only: the refusal on stderr would split its lines */
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "true; { %s calibrate --config " P " $D/warp.csv --out $D/cw 2>/dev/null; }",
             test_sunmc());
    assert_int_equal(sunmc(cmd, out, sizeof out), 1);
    test_must_have(out, "the physics does not describe this sensor");
    test_must_have(out, "recommended: hybrid");
    test_must_have(out, "calibrate with --set calibration.model=hybrid");
    assert_int_equal(sunmc("calibrate --config " P " --set calibration.model=hybrid "
                           "$D/warp.csv --out $D/ch", out, sizeof out), 0);
    test_must_have(out, "model psd_hybrid");
    test_must_have(out, "the correction's spline");
    char p[700];
    snprintf(p, sizeof p, "%s/ch/params.ini", dir);
    assert_true(test_file_has(p, "[correction]"));
    assert_true(test_file_has(p, "model = psd_hybrid"));
}

static void refuses_beyond_field(const char *model)
{
    static char out[65536];
    char cmd[512];
    snprintf(cmd, sizeof cmd, "calibrate --config " P " --set calibration.model=%s "
             "$D/sp/campaign.csv --quiet --out $D/c%s", model, model);
    assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "compensate $D/c%s/params.ini $D/sp30/validation.csv", model);
    assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    test_must_have(out, "outside the calibrated field (the model would extrapolate)");
    /* every row beyond the campaign's +-20 deg is '-', every row well inside compensated */
    int beyond = 0, inside = 0;
    for (const char *l = strchr(out, '\n'); l; l = strchr(l + 1, '\n')) {
        char *end;
        double a = strtod(l + 1, &end);
        if (end == l + 1 || *end != ',')
            continue;
        const char *eol = strchr(l + 1, '\n');
        size_t len = eol ? (size_t)(eol - l) : strlen(l);
        int dash = 0;
        for (size_t i = 0; i + 3 <= len; i++)
            dash |= strncmp(l + i, ",-,", 3) == 0;
        if (fabs(a) > 20.5) {
            beyond++;
            assert_true(dash);
        } else if (fabs(a) < 15) {
            inside++;
            assert_false(dash);
        }
    }
    assert_true(beyond > 10 && inside > 10);
}

static void test_spline_refuses_beyond_field(void **state) { refuses_beyond_field("spline"); }
static void test_table_refuses_beyond_field(void **state) { refuses_beyond_field("table"); }

/* Row `model` of models.tsv: held-out and in-sample RMS, rows per point
 * and the held-out RMS of the points' means. */
static void models_row(const char *tsv, const char *model, double v[4])
{
    char key[64];
    snprintf(key, sizeof key, "\n%s\t", model);
    const char *r = strstr(tsv, key);
    assert_non_null(r);
    int np, ok, al, used, rec;
    long n;
    assert_int_equal(sscanf(r + strlen(key), "%d\t%d\t%d\t%ld\t%lf\t%lf\t%d\t%d\t%lf\t%lf", &np,
                            &ok, &al, &n, &v[0], &v[1], &used, &rec, &v[2], &v[3]),
                     10);
    assert_int_equal(ok, 1);
}

static void test_mean_of_repeats(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " --set campaign.repeats=4 "
                           "$D/sr/campaign.csv --quiet --out $D/cr && cat $D/cr/models.tsv",
                           out, sizeof out), 0);
    double ph[4], po[4];
    models_row(out, "physical", ph);
    models_row(out, "polynomial", po);
    assert_true(ph[2] == 4.0);
    assert_true(ph[3] > 0.35 * ph[1] && ph[3] < 0.65 * ph[1]);
    assert_true(po[1] > 3.0 * po[0]);
}

static void test_inverting_sensor_compensated(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config configs/psd_aeroztark.ini " AZ
                           " $D/sa/campaign.csv --quiet --out $D/ca",
                           out, sizeof out), 0);
    assert_int_equal(sunmc("compensate $D/ca/params.ini $D/sa/validation.csv", out, sizeof out),
                     0);
    assert_null(strstr(out, "not compensated"));
    test_must_have(out, "compensated_alpha_deg");
}

static void test_threads_same(void **state)
{
    static char a[65536], b[65536];
    char cmd[1024];
    for (int t = 1; t <= 2; t++) {
        snprintf(cmd, sizeof cmd,
                 "true; OMP_NUM_THREADS=%d %s calibrate --config " P " $D/sp/campaign.csv "
                 "--quiet --out $D/t%d && cat $D/t%d/models.tsv",
                 t, test_sunmc(), t, t);
        assert_int_equal(sunmc(cmd, t == 1 ? a : b, sizeof a), 0);
    }
    assert_non_null(strstr(a, "\nhybrid\t"));
    assert_string_equal(a, b);
}

/* A DSS models.tsv row: held-out RMS, used and recommended. */
static double dss_row(const char *tsv, const char *model, int *used, int *rec)
{
    char key[64];
    snprintf(key, sizeof key, "\n%s\t", model);
    const char *r = strstr(tsv, key);
    assert_non_null(r);
    int np, ok, al;
    long n;
    double in, held;
    assert_int_equal(sscanf(r + strlen(key), "%d\t%d\t%d\t%ld\t%lf\t%lf\t%d\t%d", &np, &ok,
                            &al, &n, &in, &held, used, rec),
                     8);
    assert_int_equal(ok, 1);
    assert_true(n > 400);
    return held;
}

static void test_dss_compares_five(void **state)
{
    static char out[65536];
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "true; %s simulate configs/dss.ini --unit 3 --quiet --out $D/sd && %s calibrate "
             "--config configs/dss.ini $D/sd/campaign.csv --quiet --out $D/cd 2>/dev/null && "
             "cat $D/cd/models.tsv",
             test_sunmc(), test_sunmc());
    assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    int u[5], r[5];
    const char *names[5] = {"physical", "polynomial", "spline", "hybrid", "table"};
    double h[5];
    for (int m = 0; m < 5; m++)
        h[m] = dss_row(out, names[m], &u[m], &r[m]);
    assert_true(h[0] > 1.0 && h[0] < 20.0);
    assert_true(fabs(h[3] - h[0]) < 0.1 * h[0]);
    assert_true(h[2] > 3.0 * h[0] && h[4] > 3.0 * h[0]);
    assert_int_equal(u[0] + r[0], 2);
    assert_int_equal(u[1] + u[2] + u[3] + u[4] + r[1] + r[2] + r[3] + r[4], 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_physics_recommended),
        cmocka_unit_test(test_physics_does_not_describe),
        cmocka_unit_test(test_spline_refuses_beyond_field),
        cmocka_unit_test(test_table_refuses_beyond_field),
        cmocka_unit_test(test_mean_of_repeats),
        cmocka_unit_test(test_inverting_sensor_compensated),
        cmocka_unit_test(test_threads_same),
        cmocka_unit_test(test_dss_compares_five),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
