/* test_onboard.c - issue 42 item 2: the on-board arithmetic in the
 * accuracy.  `compensate --onboard` against the compiled export (the ESS
 * unit's validation readings through the exported C, built with the
 * system's cc: float and the table form, each reading's angle within
 * 1e-9 deg, i.e. the same float bits); the table's error against the
 * double model falls as step^2 (half the step, about a quarter); the
 * Monte Carlo key calibration.onboard: float moves the mean after-RMS by
 * less than its interval, a coarse table by more, budget lists the
 * ONBOARD_ row; the PSD's float error against its double model is
 * bounded and its budget part near 0; and the refusals (FILE:LINE, exit
 * 2; steps at and one past the table's node limit; the PSD's spline and
 * hybrid have no float path). */
#include "test_util.h"

#include <math.h>

static char dir[512];

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    (void)state;
    if (test_private_dir(dir, sizeof dir, "onboard") != 0)
        return -1;
    static const char *const steps[] = {
        "simulate configs/ess_type_a.ini --unit 3 --quiet --out $D/se",
        "calibrate --config configs/ess_type_a.ini $D/se/campaign.csv --quiet --out $D/ce",
        "simulate configs/dss.ini --unit 3 --quiet --out $D/sd",
        "calibrate --config configs/dss.ini $D/sd/campaign.csv --quiet --out $D/cd",
        "calibrate --config configs/dss.ini --set calibration.model=polynomial "
        "$D/sd/campaign.csv --quiet --out $D/cl",
        /* the PSD's validation made a grid of 900 readings (the compiled
         * export's comparison wants more than 500) */
        "simulate configs/psd.ini --unit 3 --quiet --set validation.alpha_step_deg=0.4 --set "
        "validation.beta_deg=-19,-14,-9,-4,1,6,11,16,19 --out $D/sp",
        "calibrate --config configs/psd.ini $D/sp/campaign.csv --quiet --out $D/cp",
        "calibrate --config configs/psd.ini --set calibration.model=polynomial "
        "$D/sp/campaign.csv --quiet --out $D/cq",
        "calibrate --config configs/psd.ini --set calibration.model=spline "
        "$D/sp/campaign.csv --quiet --out $D/cs"};
    return test_sunmc_steps(dir, steps, (int)(sizeof steps / sizeof *steps));
}

/* A program that runs the exported function on the readings of stdin (one
 * per line, N_RAW values) and prints its angles (%.17g) or '-'. */
static const char runner[] =
    "#include <stdio.h>\n"
    "int main(void)\n{\n    double r[N_RAW];\n    sunmc_real raw[N_RAW], a[N_ANG];\n"
    "    int k;\n    for (;;) {\n        for (k = 0; k < N_RAW; k++)\n"
    "            if (scanf(\" %lf ,\", &r[k]) != 1)\n                return 0;\n"
    "        for (k = 0; k < N_RAW; k++)\n            raw[k] = (sunmc_real)r[k];\n"
    "        if (CAL(raw, a) != 0) {\n            puts(\"-\");\n            continue;\n        }\n"
    "        for (k = 0; k < N_ANG; k++)\n"
    "            printf(\"%s%.17g\", k ? \",\" : \"\", (double)a[k]);\n"
    "        putchar('\\n');\n    }\n}\n";

/* The largest |difference| (deg) between the compiled export (export
 * options xopt, cc flags) and compensate --onboard onb on the unit's
 * validation readings (raw columns rawcols of validation.csv: awk
 * fields; angle columns angcols of compensate's output); *mismatch counts
 * readings where one gives an angle and the other none. */
static double export_vs_onboard(const char *cal, const char *sim, const char *xopt,
                                const char *flags, const char *onb, const char *rawcols,
                                int n_raw, const char *angcols, int n_ang, long *mismatch)
{
    char cmd[4096], out[16384];
    char runner_path[600];
    snprintf(runner_path, sizeof runner_path, "%s/runner.c", dir);
    assert_int_equal(test_write_file(runner_path, runner), 0);
    snprintf(cmd, sizeof cmd,
             "export $D/%s/params.ini --out $D/x %s > /dev/null && h=$(ls $D/x/sunmc_*_cal.h) "
             "&& n=$(basename $h .h) && cc -std=c99 -Wall -Wextra -Werror -pedantic -O1 %s "
             "-DCAL=$n -DN_RAW=%d -DN_ANG=%d -include $h -o $D/x/run $D/runner.c $D/x/$n.c -lm "
             "&& grep -v '^#' $D/%s/validation.csv | tail -n +2 | awk -F, '{print %s}' > "
             "$D/x/raw.txt && $D/x/run < $D/x/raw.txt > $D/x/got.txt && %s compensate "
             "$D/%s/params.ini $D/%s/validation.csv --onboard %s 2>/dev/null | grep -v '^#' | "
             "tail -n +2 | awk -F, '{print %s}' > $D/x/want.txt && paste -d, $D/x/got.txt "
             "$D/x/want.txt | awk -F, -v h=%d '{g=$1; w=$(h+1); if ((g == \"-\") != (w == "
             "\"-\")) m++; else if (g != \"-\") for (k = 1; k <= h; k++) {d = $k - $(h+k); "
             "if (d < 0) d = -d; if (d > x) x = d}} END {printf \"%%.6g %%d %%d\\n\", x, m, NR}'",
             cal, xopt, flags, n_raw, n_ang, sim, rawcols, test_sunmc(), cal, sim, onb, angcols,
             n_ang);
    assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    double worst = NAN;
    long rows = 0;
    assert_int_equal(sscanf(out, "%lf %ld %ld", &worst, mismatch, &rows), 3);
    assert_true(rows > 500);
    char rm[600];
    snprintf(rm, sizeof rm, "rm -rf %s/x", dir);
    assert_int_equal(system(rm), 0);
    return worst;
}

/* Float: compensate --onboard float gives the compiled -DSUNMC_FLOAT
 * export's bits (a float ulp at 60 deg is 3.8e-6 deg; 1e-9 is none): the
 * ESS paper model, the DSS and the PSD physical model and polynomial. */
static void test_float_matches_compiled_export(void **state)
{
    (void)state;
    long mismatch = -1;
    double d = export_vs_onboard("ce", "se", "--precision float", "-DSUNMC_FLOAT", "float", "$3",
                                 1, "$5", 1, &mismatch);
    assert_int_equal(mismatch, 0);
    assert_true(d <= 1e-9);
    static const char *const dss[] = {"cd", "cl"};
    for (int k = 0; k < 2; k++) {
        d = export_vs_onboard(dss[k], "sd", "--precision float", "-DSUNMC_FLOAT", "float",
                              "$3 \",\" $4", 2, "$(NF-1) \",\" $NF", 2, &mismatch);
        assert_int_equal(mismatch, 0);
        assert_true(d <= 1e-9);
    }
    static const char *const psd[] = {"cp", "cq"};
    for (int k = 0; k < 2; k++) {
        d = export_vs_onboard(psd[k], "sp", "--precision float", "-DSUNMC_FLOAT", "float",
                              "$3 \",\" $4 \",\" $5 \",\" $6", 4, "$7 \",\" $8", 2, &mismatch);
        assert_int_equal(mismatch, 0);
        assert_true(d <= 1e-9);
    }
}

/* The largest |float - double| (arcsec) of compensate of params cal on the
 * PSD unit's validation grid; *rows the readings with an angle in both,
 * *mismatch those with an angle in one only. */
static double psd_float_error(const char *cal, long *rows, long *mismatch)
{
    char cmd[2048], out[4096];
    snprintf(cmd, sizeof cmd,
             "compensate $D/%s/params.ini $D/sp/validation.csv 2>/dev/null | grep -v '^#' | "
             "tail -n +2 | cut -d, -f7,8 > $D/d.txt && %s compensate $D/%s/params.ini "
             "$D/sp/validation.csv --onboard float 2>/dev/null | grep -v '^#' | tail -n +2 | "
             "cut -d, -f7,8 > $D/f.txt && paste -d, $D/d.txt $D/f.txt | awk -F, '{if (($1 == "
             "\"-\") != ($3 == \"-\")) m++; else if ($1 != \"-\") {n++; for (k = 1; k <= 2; "
             "k++) {d = $k - $(k+2); if (d < 0) d = -d; if (d > x) x = d}}} END {printf "
             "\"%%.6g %%d %%d\\n\", 3600 * x, n, m}'",
             cal, test_sunmc(), cal);
    assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    double worst = NAN;
    assert_int_equal(sscanf(out, "%lf %ld %ld", &worst, rows, mismatch), 3);
    return worst;
}

/* The PSD's float error against its double model: a few float ulps of
 * the ratios (6e-8 relative) through the Newton inversion or the
 * polynomial, a few hundredths of an arcsec on the grid; bound 0.36
 * arcsec (1e-4 deg), ten times what is seen, far below the unit's 200
 * arcsec; not zero (the arithmetic is float). */
static void test_psd_float_error_bounded(void **state)
{
    (void)state;
    static const char *const psd[] = {"cp", "cq"};
    for (int k = 0; k < 2; k++) {
        long rows = 0, mismatch = -1;
        double e = psd_float_error(psd[k], &rows, &mismatch);
        assert_int_equal(mismatch, 0);
        assert_true(rows > 200);
        assert_true(e > 0 && e < 0.36);
    }
}

/* The table form, ESS (linear) and DSS (bilinear), double: the compiled
 * export's lookup to 1e-9 deg. */
static void test_table_matches_compiled_export(void **state)
{
    (void)state;
    long mismatch = -1;
    double d = export_vs_onboard("ce", "se", "--form table:0.05", "-DSUNMC_DOUBLE", "table:0.05",
                                 "$3", 1, "$5", 1, &mismatch);
    assert_int_equal(mismatch, 0);
    assert_true(d <= 1e-9);
    d = export_vs_onboard("cd", "sd", "--form table:16", "-DSUNMC_DOUBLE", "table:16",
                          "$3 \",\" $4", 2, "$(NF-1) \",\" $NF", 2, &mismatch);
    assert_int_equal(mismatch, 0);
    assert_true(d <= 1e-9);
}

/* The largest |table - double| (deg) of compensate on the ESS unit's
 * validation readings. */
static double table_error(const char *step)
{
    char cmd[2048], out[4096];
    snprintf(cmd, sizeof cmd,
             "compensate $D/ce/params.ini $D/se/validation.csv 2>/dev/null | grep -v '^#' | "
             "tail -n +2 | cut -d, -f5 > $D/d.txt && %s compensate $D/ce/params.ini "
             "$D/se/validation.csv --onboard table:%s 2>/dev/null | grep -v '^#' | tail -n +2 | "
             "cut -d, -f5 > $D/t.txt && paste -d, $D/d.txt $D/t.txt | awk -F, '{d = $1 - $2; if "
             "(d < 0) d = -d; if (d > x) x = d} END {printf \"%%.6g\\n\", x}'",
             test_sunmc(), step);
    assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    return atof(out);
}

/* Linear interpolation's error is step^2 / 8 times the curvature: half
 * the step, a quarter of the error (3 to 5 allows for where the nodes
 * fall); the double model's table at a fine step is within 1e-5 deg. */
static void test_table_error_step_squared(void **state)
{
    (void)state;
    double e1 = table_error("0.04"), e2 = table_error("0.02"), e3 = table_error("0.01");
    assert_true(e1 > 0 && e2 > 0 && e3 > 0);
    assert_true(e1 / e2 > 3.0 && e1 / e2 < 5.0);
    assert_true(e2 / e3 > 3.0 && e2 / e3 < 5.0);
}

/* mean RMS after and its interval (summary.tsv's last row, the widest band) of `run` with
 * calibration.onboard = onb. */
static void mean_after(const char *cfg, const char *onb, double *mean, double *lo, double *hi,
                       double *sys)
{
    char cmd[1024], out[16384];
    snprintf(cmd, sizeof cmd,
             "run %s --units 40 --set calibration.onboard=%s --quiet --out "
             "$D/r_%c > /dev/null && rm -rf $D/r_%c.old && mv $D/r_%c $D/r_%c.old && awk -F'\\t' 'NR == 1 {for (k = 1; k <= NF; k++) c[$k] = "
             "k} END {print $c[\"rms_after_mean\"], $c[\"rms_after_mean_ci_lo\"], "
             "$c[\"rms_after_mean_ci_hi\"], $c[\"rms_after_sys_mean\"]}' $D/r_%c.old/summary.tsv",
             cfg, onb, onb[1], onb[1], onb[1], onb[1], onb[1]);
    assert_int_equal(sunmc(cmd, out, sizeof out), 0);
    const char *p = out + strlen(out);
    while (p > out && p[-1] == '\n')
        p--;
    while (p > out && p[-1] != '\n')
        p--;
    assert_int_equal(sscanf(p, "%lf %lf %lf %lf", mean, lo, hi, sys), 4);
}

/* The check: float differs from double by less than the interval
 * of the mean after-RMS; a coarse table by more (ESS: 0.1 deg, the fine
 * code's period 0.5 deg in 5 cells; DSS: 16 px). */
static void mc_check(const char *cfg, const char *coarse)
{
    double m0, lo0, hi0, m1, lo1, hi1, m2, lo2, hi2, s0, s1, s2;
    mean_after(cfg, "double", &m0, &lo0, &hi0, &s0);
    mean_after(cfg, "float", &m1, &lo1, &hi1, &s1);
    mean_after(cfg, coarse, &m2, &lo2, &hi2, &s2);
    assert_true(hi0 > lo0 && m0 > 0 && s0 > 0 && s0 < m0);
    assert_true(fabs(m1 - m0) < 0.5 * (hi0 - lo0));
    /* the systematic part (the noise-free readings) through float too */
    assert_true(fabs(s1 - s0) < 1e-3 * s0);
    assert_true(m2 - m0 > 0.5 * (hi0 - lo0));
}

static void test_mc_float_within_interval(void **state)
{
    (void)state;
    mc_check("configs/ess_type_a.ini", "table:0.1");
    mc_check("configs/dss.ini", "table:16");
    /* the PSD: a coarse table is 0.25 in the ratios */
    mc_check("configs/psd.ini", "table:0.25");
}

/* The same units for any thread count: each thread's table is built from
 * the unit's own model. */
static void test_mc_onboard_threads(void **state)
{
    (void)state;
    char out[16384], cmd[2048];
    snprintf(cmd, sizeof cmd,
             "run configs/dss.ini --units 12 --threads 1 --quiet --set calibration.onboard=table:8 "
             "--out $D/t1 > /dev/null && %s run configs/dss.ini --units 12 --threads 2 --quiet "
             "--set calibration.onboard=table:8 --out $D/t2 > /dev/null && cmp $D/t1/summary.tsv "
             "$D/t2/summary.tsv && cmp $D/t1/units.tsv $D/t2/units.tsv",
             test_sunmc());
    assert_int_equal(sunmc(cmd, out, sizeof out), 0);
}

/* budget lists the on-board arithmetic as a part of the mean square after
 * (budget.tsv's after_part rows), only when it is not double. */
static void test_budget_onboard_row(void **state)
{
    (void)state;
    char out[65536];
    assert_int_equal(sunmc("budget configs/ess_type_a.ini --units 12 --set "
                           "calibration.onboard=table:0.1 --out $D/b",
                           out, sizeof out),
                     0);
    assert_non_null(strstr(out, "on-board arithmetic (ONBOARD_TABLE"));
    char path[600];
    snprintf(path, sizeof path, "%s/b/budget.tsv", dir);
    assert_true(test_file_has(path, "\tafter_part\tONBOARD_TABLE\t"));
    /* the four parts (share_after, column 13) sum to the on-board mean
     * square; the table's part is a real share, not the whole */
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "awk -F'\\t' '$2 == \"after_part\" {s += $13} $3 == \"ONBOARD_TABLE\" {o = $13} "
             "END {print s, o}' %s/b/budget.tsv",
             dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    double sum = NAN, part = NAN;
    assert_int_equal(sscanf(out, "%lf %lf", &sum, &part), 2);
    assert_true(fabs(sum - 1.0) < 0.02);
    assert_true(part > 0.05 && part < 0.9);
    assert_int_equal(sunmc("budget configs/ess_type_a.ini --units 12 --quiet --out $D/b0",
                           out, sizeof out),
                     0);
    snprintf(path, sizeof path, "%s/b0/budget.tsv", dir);
    assert_false(test_file_has(path, "ONBOARD"));
}

/* budget of the PSD through float: the ONBOARD_FLOAT row is there and its
 * share of the mean square after is near 0 (below 0.1 %). */
static void test_budget_psd_float(void **state)
{
    (void)state;
    char out[65536];
    assert_int_equal(sunmc("budget configs/psd.ini --units 10 --set calibration.onboard=float "
                           "--out $D/bp",
                           out, sizeof out),
                     0);
    assert_non_null(strstr(out, "on-board arithmetic (ONBOARD_FLOAT"));
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "awk -F'\\t' '$2 == \"after_part\" && $3 == \"ONBOARD_FLOAT\" {print $13; n++} "
             "END {if (n != 1) print \"none\"}' %s/bp/budget.tsv",
             dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    double part = NAN;
    assert_int_equal(sscanf(out, "%lf", &part), 1);
    assert_true(fabs(part) < 1e-3);
}

/* Refusals: exit 2, FILE:LINE for a config's key, nothing written. */
static void test_onboard_refused(void **state)
{
    (void)state;
    char out[16384], cfg[600];
    snprintf(cfg, sizeof cfg, "%s/bad.ini", dir);
    assert_int_equal(test_write_file(cfg, "[sensor]\nfamily = ess\n[calibration]\n"
                                          "onboard = tabel:0.1\n"),
                     0);
    assert_int_equal(sunmc("run $D/bad.ini --units 2 --out $D/no", out, sizeof out), 2);
    assert_non_null(strstr(out, "bad.ini:4"));
    assert_non_null(strstr(out, "calibration.onboard"));
    static const char *const bad[] = {
        "configs/ess_type_a.ini --units 2 --set calibration.onboard=table:0",
        "configs/ess_type_a.ini --units 2 --set calibration.onboard=table:-1",
        "configs/ess_type_a.ini --units 2 --set calibration.onboard=table:",
        "configs/ess_type_a.ini --units 2 --set calibration.onboard=table:nan",
        "configs/ess_type_a.ini --units 2 --set calibration.onboard=Float",
        /* one past the node limit: 178 deg in 1000000 cells, 1000001 nodes */
        "configs/ess_type_a.ini --units 2 --set calibration.onboard=table:0.000178",
        /* the PSD's float path: the physical model and the polynomial */
        "configs/psd.ini --units 2 --set calibration.model=spline --set "
        "calibration.onboard=float",
        "configs/psd.ini --units 2 --set calibration.model=hybrid --set "
        "calibration.onboard=float",
        /* the DSS's detector, 2048 px, in more than 10^6 nodes */
        "configs/dss.ini --units 2 --set calibration.onboard=table:2",
        /* the export has no detector tilt: neither has its on-board form */
        "configs/dss.ini --units 2 --set calibration.fit_detector_tilt=on --set "
        "calibration.onboard=float"};
    char no[600];
    snprintf(no, sizeof no, "%s/none", dir);
    test_refused("run", bad, sizeof bad / sizeof *bad, no);
    /* compensate: the option's errors, the same limits */
    static const char *const cbad[] = {"table:0", "table:x", "double2",
                                       "table:0.000178"};
    for (size_t i = 0; i < sizeof cbad / sizeof *cbad; i++) {
        char cmd[1024];
        snprintf(cmd, sizeof cmd,
                 "compensate $D/ce/params.ini $D/se/validation.csv --onboard %s > $D/o.csv "
                 "2> $D/e.txt; rc=$?; cat $D/e.txt; exit $rc",
                 cbad[i]);
        assert_int_equal(sunmc(cmd, out, sizeof out), 2);
        assert_non_null(strstr(out, "--onboard"));
    }
    assert_int_equal(sunmc("compensate $D/cs/params.ini $D/sp/validation.csv --onboard float "
                           "> $D/o.csv 2> $D/e.txt; rc=$?; cat $D/e.txt; exit $rc",
                           out, sizeof out),
                     2);
    assert_non_null(strstr(out, "spline model has no float path"));
    assert_non_null(strstr(out, "--onboard"));
}

/* The largest table: 178 deg in 999999 cells (1000000 nodes) is taken;
 * the largest step, one cell over the range, too. */
static void test_onboard_table_limits(void **state)
{
    (void)state;
    char out[16384];
    assert_int_equal(sunmc("compensate $D/ce/params.ini $D/se/validation.csv --onboard "
                           "table:0.00017800027 > $D/o.csv",
                           out, sizeof out),
                     0);
    assert_int_equal(sunmc("compensate $D/ce/params.ini $D/se/validation.csv --onboard "
                           "table:178 > $D/o.csv",
                           out, sizeof out),
                     0);
    assert_int_equal(sunmc("compensate $D/ce/params.ini $D/se/validation.csv --onboard "
                           "table:1e300 > $D/o.csv",
                           out, sizeof out),
                     0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_float_matches_compiled_export),
        cmocka_unit_test(test_table_matches_compiled_export),
        cmocka_unit_test(test_table_error_step_squared),
        cmocka_unit_test(test_mc_float_within_interval),
        cmocka_unit_test(test_mc_onboard_threads),
        cmocka_unit_test(test_budget_onboard_row),
        cmocka_unit_test(test_budget_psd_float),
        cmocka_unit_test(test_psd_float_error_bounded),
        cmocka_unit_test(test_onboard_refused),
        cmocka_unit_test(test_onboard_table_limits),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
