/* test_run_models.c - issue 39 item 4: the spline, table and hybrid
 * calibration models in the Monte Carlo (`run`, `design`):
 *  - each family's new models give byte-identical units.tsv and
 *    summary.tsv at 1 and 2 threads (the per-unit fit's choice of its
 *    smoothing and step by folds included);
 *  - on simulated DSS units, whose physics the physical model describes
 *    (its RMS after a few arcsec), the hybrid's correction buys nothing:
 *    its mean RMS after within 3 % of the physical model's;
 *  - `design` searches campaigns for the table model (the points it needs);
 *  - a mistyped model in a config file: FILE:LINE, exit 2, nothing written. */
#include "test_util.h"

static char dir[512];

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "runmodels");
}

/* `run` of config with model at 1 and 2 threads: the same bytes. */
static void same_at_threads(const char *config, const char *model, int units)
{
    static char out[65536];
    char cmd[2048];
    for (int t = 1; t <= 2; t++) {
        snprintf(cmd, sizeof cmd,
                 "true; OMP_NUM_THREADS=%d %s run %s --units %d --seed 1 --threads %d --quiet "
                 "--set calibration.model=%s --out $D/%s_%s_%d",
                 t, test_sunmc(), config, units, t, model, model, config + 8, t);
        if (sunmc(cmd, out, sizeof out) != 0)
            fail_msg("%s: %s", cmd, out);
    }
    const char *files[] = {"units.tsv", "summary.tsv"};
    for (int f = 0; f < 2; f++) {
        snprintf(cmd, sizeof cmd, "true; cmp $D/%s_%s_1/%s $D/%s_%s_2/%s", model, config + 8,
                 files[f], model, config + 8, files[f]);
        if (sunmc(cmd, out, sizeof out) != 0)
            fail_msg("%s %s: %s differs across threads: %s", config, model, files[f], out);
    }
}

static void test_threads_psd(void **state) { same_at_threads("configs/psd.ini", "table", 8); }

static void test_threads_ess(void **state)
{
    same_at_threads("configs/ess_type_a.ini", "hybrid", 6);
    same_at_threads("configs/ess_type_a.ini", "table", 6);
    /* readings beyond the campaign's +-61.95 deg are counted, no fit fails */
    char out[4096];
    assert_int_equal(sunmc("true; awk -F'\\t' 'NR == 1 {for (i = 1; i <= NF; i++) c[$i] = i; "
                           "next} NR == 2 {print $c[\"fit_failures\"], $c[\"gross_errors\"]}' "
                           "$D/hybrid_ess_type_a.ini_1/summary.tsv",
                           out, sizeof out), 0);
    long fails = -1, gross = -1;
    assert_int_equal(sscanf(out, "%ld %ld", &fails, &gross), 2);
    assert_int_equal(fails, 0);
    assert_true(gross > 0);
}

static void test_threads_dss(void **state)
{
    same_at_threads("configs/dss.ini", "hybrid", 3);
    same_at_threads("configs/dss.ini", "table", 3);
}

/* summary.tsv's mean RMS after of the total angle in its widest band. */
static double total_after(const char *run)
{
    char cmd[1024], out[4096];
    snprintf(cmd, sizeof cmd,
             "true; awk -F'\\t' 'NR == 1 {for (i = 1; i <= NF; i++) c[$i] = i; next} "
             "$c[\"angle\"] == \"total\" {v = $c[\"rms_after_mean\"]} END {print v}' "
             "$D/%s/summary.tsv",
             run);
    assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    return atof(out);
}

static void test_hybrid_buys_nothing_on_exact_physics(void **state)
{
    char out[65536];
    assert_int_equal(sunmc("run configs/dss.ini --units 6 --seed 1 --quiet "
                           "--set calibration.model=physical --out $D/dp",
                           out, sizeof out), 0);
    assert_int_equal(sunmc("run configs/dss.ini --units 6 --seed 1 --quiet "
                           "--set calibration.model=hybrid --out $D/dh",
                           out, sizeof out), 0);
    double p = total_after("dp"), h = total_after("dh");
    assert_true(p > 1.0 && p < 20.0);
    assert_true(fabs(h - p) < 0.03 * p);
}

static void test_design_table(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("design configs/psd.ini --set calibration.model=table "
                           "--space steps_deg=5,10 --space max_lines=3 --space beta_step_deg=10 "
                           "--space beta_max_deg=20 --space repeats=1 --space screen_units=10 "
                           "--space max_units=10 --space shortlist=1 --set run.block_units=10 "
                           "--set report.yield_target=0.5 --quiet --out $D/design",
                           out, sizeof out), 0);
    char p[700];
    snprintf(p, sizeof p, "%s/design/best.ini", dir);
    assert_true(test_file_has(p, "model = table"));
    snprintf(p, sizeof p, "%s/design/design.tsv", dir);
    assert_true(test_file_has(p, "\tpoints\t"));
}

static void test_mistyped_model(void **state)
{
    static char out[16384];
    const char *families[] = {"psd", "dss", "ess_type_a"};
    /* the ESS config has no [calibration]: one is added at its end */
    const char *edits[] = {"s/^model *=.*/model = tabel/", "s/^model *=.*/model = tabel/",
                           "$a [calibration]\\nmodel = tabel"};
    for (int f = 0; f < 3; f++) {
        char cmd[1024];
        snprintf(cmd, sizeof cmd,
                 "true; sed '%s' configs/%s.ini > $D/bad_%s.ini && "
                 "grep -n '^model = tabel' $D/bad_%s.ini | cut -d: -f1",
                 edits[f], families[f], families[f], families[f]);
        assert_int_equal(sunmc(cmd, out, sizeof out), 0);
        int line = atoi(out);
        assert_true(line > 0);
        snprintf(cmd, sizeof cmd, "run $D/bad_%s.ini --units 2 --out $D/never_%s", families[f],
                 families[f]);
        assert_int_equal(sunmc(cmd, out, sizeof out), 2);
        char where[128];
        snprintf(where, sizeof where, "bad_%s.ini:%d:", families[f], line);
        if (!strstr(out, where) || !strstr(out, "table"))
            fail_msg("%s: %s", where, out);
        snprintf(cmd, sizeof cmd, "true; test ! -e $D/never_%s", families[f]);
        assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    }
}

/* An empirical model has no field before its fit nor a float path: the
 * Monte Carlo's on-board forms are refused for it, naming the way out,
 * before anything is written (the merge of issues 39 and 42). */
static void test_onboard_refused_for_empirical(void **state)
{
    static char out[8192];
    const char *cases[] = {"configs/dss.ini --set calibration.model=spline "
                           "--set calibration.onboard=float",
                           "configs/ess_type_a.ini --set calibration.model=hybrid "
                           "--set calibration.onboard=table:0.05",
                           "configs/psd.ini --set calibration.model=table "
                           "--set calibration.onboard=table:0.05"};
    for (int i = 0; i < 3; i++) {
        char cmd[512];
        snprintf(cmd, sizeof cmd, "run %s --units 4 --quiet --out $D/onb%d", cases[i], i);
        assert_int_equal(sunmc(cmd, out, sizeof out), 2);
        assert_non_null(strstr(out, "calibration.model is an empirical model"));
        assert_non_null(strstr(out, "--form table:STEP"));
        snprintf(cmd, sizeof cmd, "true; test ! -e $D/onb%d", i);
        assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_threads_psd),
        cmocka_unit_test(test_threads_dss),
        cmocka_unit_test(test_threads_ess),
        cmocka_unit_test(test_hybrid_buys_nothing_on_exact_physics),
        cmocka_unit_test(test_design_table),
        cmocka_unit_test(test_mistyped_model),
        cmocka_unit_test(test_onboard_refused_for_empirical),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
