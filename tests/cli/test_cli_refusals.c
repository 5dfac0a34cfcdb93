/* test_cli_refusals.c - issue 9's reproducers: sunmc refuses what it cannot stand
 * behind (exit 2 before any work, naming the keys) and flags what is
 * doubtful.  Each test names the reproducer it guards. */
#include "test_util.h"

#include "family.h"
#include "memory.h"
#include "registry.h"
#include "report.h"
#include "sweep.h"
#include "tolerance.h"

#include <sys/time.h>

#define MAX_SETS 12

/* Build family fam's config with sets; returns the status, message in err. */
static int build(const char *fam, const char *const *sets, int n, char *err)
{
    char famset[64];
    snprintf(famset, sizeof famset, "sensor.family=%s", fam);
    const char *all[MAX_SETS + 1] = {famset};
    for (int i = 0; i < n && i < MAX_SETS; i++)
        all[i + 1] = sets[i];
    config_state st;
    err[0] = '\0';
    int s = config_build(&st, NULL, all, n + 1, err, SUNMC_ERRLEN);
    if (s == SUNMC_OK)
        config_state_free(&st);
    return s;
}

#define SETS(...) ((const char *const[]){__VA_ARGS__}), \
                  (int)(sizeof((const char *const[]){__VA_ARGS__}) / sizeof(const char *))

static void ok(const char *fam, const char *const *sets, int n)
{
    char err[SUNMC_ERRLEN];
    if (build(fam, sets, n, err) != SUNMC_OK)
        fail_msg("refused: %s", err);
}

/* Refused as bad input, the message holding every needle ("|" between). */
static void refused(const char *fam, const char *const *sets, int n, const char *needles)
{
    char err[SUNMC_ERRLEN], want[512];
    int s = build(fam, sets, n, err);
    if (s != SUNMC_EINPUT)
        fail_msg("expected SUNMC_EINPUT for '%s', got %d '%s'", needles, s, err);
    snprintf(want, sizeof want, "%s", needles);
    for (char *p = strtok(want, "|"); p; p = strtok(NULL, "|"))
        if (!strstr(err, p))
            fail_msg("'%s' does not say '%s'", err, p);
}

/* ---- the reach of each distribution ---- */

static void test_tolerance_range(void **state)
{
    double lo, hi;
    tolerance t = {2.0, DIST_UNIFORM};
    tolerance_range(&t, 3, &lo, &hi);
    assert_near(lo, -2, 0);
    assert_near(hi, 2, 0);
    t.dist = DIST_TRUNCNORMAL;
    tolerance_range(&t, 3, &lo, &hi);
    assert_near(lo, -6, 0);
    assert_near(hi, 6, 0);
    t.dist = DIST_NORMAL;
    tolerance_range(&t, 3, &lo, &hi);
    assert_near(lo, -2 * TOLERANCE_NORMAL_REACH_SIGMAS, 0);
    t.dist = DIST_FIXED;
    tolerance_range(&t, 3, &lo, &hi);
    assert_near(lo, 2, 0);
    assert_near(hi, 2, 0);
}

/* ---- physical consistency across keys ---- */

/* ESS: the slit must stay above the dial, H + dH > 0: H = 0.5 mm takes a
 * dH just below 500 um, not 500 um (a draw could touch the dial). */
static void test_ess_height_stays_positive(void **state)
{
    ok("ess", SETS("design.H_mm=0.5", "tolerance.dH_um=499.999"));
    refused("ess", SETS("design.H_mm=0.5", "tolerance.dH_um=500"),
            "tolerance.dH_um = 500|design.H_mm = 0.5|slit-to-dial height H + dH <= 0");
    /* truncnormal reaches truncation_sigmas sigma, normal 6 sigma */
    ok("ess", SETS("design.H_mm=0.5", "tolerance.dH_um=166", "tolerance.dH_um_dist=truncnormal"));
    refused("ess",
            SETS("design.H_mm=0.5", "tolerance.dH_um=167", "tolerance.dH_um_dist=truncnormal"),
            "truncnormal, +-3 sigma = +-501");
    refused("ess", SETS("design.H_mm=0.5", "tolerance.dH_um=100", "tolerance.dH_um_dist=normal"),
            "normal, unbounded|bound the draws (truncnormal)");
    /* a fixed deviation moves one way only */
    ok("ess", SETS("design.H_mm=0.5", "tolerance.dH_um=1000", "tolerance.dH_um_dist=fixed"));
}

/* ESS: a slit of negative width, a photocell of no gain. */
static void test_ess_width_and_gain(void **state)
{
    ok("ess", SETS("design.slit_width_um=5", "tolerance.slit_width_um=5"));
    refused("ess", SETS("design.slit_width_um=5", "tolerance.slit_width_um=5.001"),
            "tolerance.slit_width_um|design.slit_width_um = 5|slit width < 0");
    ok("ess", SETS("tolerance.gain_pct=33.3", "tolerance.gain_pct_dist=truncnormal"));
    refused("ess", SETS("tolerance.gain_pct=34", "tolerance.gain_pct_dist=truncnormal"),
            "tolerance.gain_pct|photocell gain");
}

/* DSS (the reproducer): a +-10 um glass tolerance on a 0 mm design
 * drew negative thicknesses and counted the failed fits as yield loss. */
static void test_dss_glass_thickness(void **state)
{
    refused("dss", SETS("design.glass_thickness_mm=0"),
            "tolerance.glass_thickness_um = 10|design.glass_thickness_mm = 0|thickness < 0");
    ok("dss", SETS("design.glass_thickness_mm=0", "tolerance.glass_thickness_um=0"));
    ok("dss", SETS("design.glass_thickness_mm=0.01"));
    refused("dss", SETS("design.glass_thickness_mm=0.0099"), "draws reach -0.0001 mm");
}

/* DSS: pinhole above the detector, glass below the pinhole, index >= 1. */
static void test_dss_height_gap_index(void **state)
{
    /* h = 0.2 mm, 5.5 um pixels: dh reaches at most 0.2 / 0.0055 = 36.36 px */
    ok("dss", SETS("design.h_mm=0.2", "design.glass_thickness_mm=0", "tolerance.glass_thickness_um=0",
                   "tolerance.dh_px=36.36"));
    refused("dss",
            SETS("design.h_mm=0.2", "design.glass_thickness_mm=0",
                 "tolerance.glass_thickness_um=0", "tolerance.dh_px=36.37"),
            "tolerance.dh_px = 36.37|design.h_mm = 0.2|pinhole height h + dh <= 0");
    /* gap: h - 0.2 px * 5.5 um - (t + 10 um) must stay > 0 */
    ok("dss", SETS("design.h_mm=1", "design.glass_thickness_mm=0.9888"));
    refused("dss", SETS("design.h_mm=1", "design.glass_thickness_mm=0.989"),
            "tolerance.dh_px = 0.2 and tolerance.glass_thickness_um = 10|at or above the pinhole");
    ok("dss", SETS("design.glass_index=1.0051"));
    refused("dss", SETS("design.glass_index=1.0049"),
            "tolerance.glass_index = 0.005|design.glass_index = 1.0049|index < 1");
}

/* ---- bands against the validation grid and the field of view ---- */

static void test_bands_hold_points(void **state)
{
    /* the reproducers: rows of NaN and a yield of 0 */
    refused("ess", SETS("report.bands_deg=62:90"),
            "band 62:90 lies outside the field of view +-62 deg|design.fov_deg");
    refused("ess", SETS("validation.alpha_step_deg=90"),
            "band 30:60 holds no point of the validation grid|validation.alpha_step_deg");
    ok("ess", SETS("report.bands_deg=0:30,30:61.9"));
    /* |alpha| of the grid reaches 61.95: a band from 61.95 holds nothing */
    refused("ess", SETS("report.bands_deg=61.95:62"), "|alpha| reaches 61.95 deg");
    ok("ess", SETS("report.bands_deg=61.9:62"));
    /* DSS bands are on the field angle, which reaches past the per-axis
     * field of view in the corners: atan(sqrt(2) tan 60) = 67.79 deg */
    ok("dss", SETS("report.bands_deg=0:60,60:67"));
    refused("dss", SETS("report.bands_deg=0:60,67.8:80"),
            "band 67.8:80 lies outside the field of view +-67.79");
    refused("dss", SETS("validation.b_min_deg=-10", "validation.b_max_deg=10"),
            "band 20:40 holds no point");
}

/* ---- memory, before any work ---- */

static void test_memory_limits(void **state)
{
    sunmc_config c = test_family_config("ess");
    char err[SUNMC_ERRLEN];
    double per_unit = (double)sizeof(unit_result);
    double ws = memory_run_bytes(&c, 0, 2, 1);
    assert_true(ws > 0);
    /* held whole (budget): a unit_result per unit */
    assert_near(memory_run_bytes(&c, 1000, 2, 1), ws + 1000 * per_unit, 1e-6);
    /* streamed: a block of unit_results, and per unit the RMS after of each
     * of the 3 bands (8 bytes each, arrays grown by half) */
    assert_near(memory_run_bytes(&c, 100000, 2, 0),
                ws + (double)c.block_units * per_unit + 1.5 * 100000 * 3 * 8, 1e-6);
    /* exactly enough passes, one byte less is refused with the need */
    double need = memory_run_bytes(&c, 1000, 2, 1);
    assert_int_equal(memory_check_run(&c, 0, 1000, 2, 1, need, err, sizeof err), SUNMC_OK);
    assert_int_equal(memory_check_run(&c, 0, 1000, 2, 1, need - 1, err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "--units 1000: 1000 units need"));
    assert_non_null(strstr(err, "of memory"));
    assert_int_equal(memory_check_run(&c, 5, 1005, 2, 1, need - 1, err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "--units 5:1005"));
    char t[32];
    memory_text(1.28e11, t, sizeof t);
    assert_string_equal(t, "128 GB");
    memory_text(999, t, sizeof t);
    assert_string_equal(t, "999 bytes");
    /* a campaign grid too large for a thread's workspace is a config error */
    refused("dss", SETS("campaign.b_step_deg=0.01"), "GB per thread|coarser step");
    refused("dss", SETS("validation.b_step_deg=0.01"), "GB per thread|coarser step");
    ok("dss", SETS("campaign.b_step_deg=0.1"));
}

static double now_s(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (double)tv.tv_sec + 1e-6 * (double)tv.tv_usec;
}

/* The reproducers: "--units 100000000" (the documented maximum)
 * and "--units 0:200000000" said "out of memory"; a 0.01 deg DSS campaign
 * exhausted the memory.  Now: exit 2 at once, with what they would need.
 * Streamed, 10^8 units need 3.6 GB: the test limits the process to 1 GB
 * (ulimit -v; not under AddressSanitizer, which reserves terabytes of
 * address space). */
static void test_cli_limits_up_front(void **state)
{
    char out[4096], cmd[1024];
    int asan = strstr(test_sunmc(), "asan") != NULL;
    const char *args[] = {
        "run configs/ess_type_a.ini --units 100000000",
        "run configs/ess_type_a.ini --units 0:200000000",
        "budget configs/dss.ini --units 100000000",
        "run configs/dss.ini --units 2 --set campaign.b_step_deg=0.01",
    };
    const char *needle[] = {"100000000 units need", "END <= 100000000",
                            "100000000 units need", "GB per thread"};
    for (int i = asan ? 3 : 0; i < 4; i++) {
        snprintf(cmd, sizeof cmd, "%s%s %s --quiet", asan ? "" : "ulimit -v 1000000; ",
                 test_sunmc(), args[i]);
        double t0 = now_s();
        int st = test_run(cmd, out, sizeof out);
        double dt = now_s() - t0;
        if (st != 2 || !strstr(out, needle[i]) || strstr(out, "out of memory"))
            fail_msg("%s: exit %d, '%s'", args[i], st, out);
        if (dt > 2.0)
            fail_msg("%s refused after %.2f s", args[i], dt);
    }
}

/* ---- the Monte Carlo report: never silent ---- */

static int sunmc(const char *args, char *out, size_t len)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s %s", test_sunmc(), args);
    return test_run(cmd, out, len);
}

/* The reproducer: yield 0.9995 printed "100.0%". */
static void test_yield_digits(void **state)
{
    /* 1999/2000: printf's "%.1f" of 99.95 (stored a hair above) is "100.0" */
    char t[32];
    snprintf(t, sizeof t, "%.*f", report_percent_decimals(1999.0 / 2000, 1), 100 * 1999.0 / 2000);
    assert_string_equal(t, "99.95");
    snprintf(t, sizeof t, "%.*f", report_percent_decimals(19999.0 / 20000, 1),
             100 * 19999.0 / 20000);
    assert_string_equal(t, "99.995");
    assert_int_equal(report_percent_decimals(0.99951, 1), 2);  /* 99.95, not 100.0 */
    assert_int_equal(report_percent_decimals(0.9994, 1), 1);   /* 99.9 */
    assert_int_equal(report_percent_decimals(1.0, 1), 1);      /* 100.0 */
    assert_int_equal(report_percent_decimals(0.0, 1), 1);      /* 0.0 */
    assert_int_equal(report_percent_decimals(0.0004, 1), 2);   /* 0.04 */
    assert_int_equal(report_percent_decimals(1e-9, 1), 6);     /* at most 6 */
    assert_int_equal(report_percent_decimals(0.5, 0), 0);
}

/* The reproducer: tolerance.dH_um=500 left units without a usable
 * reading out of a band's statistics, silently.  20 units = 5 with
 * readings in 30:60 + 15 fitted without one (on the former 0.8-deg
 * campaign one of them failed its fit: 14). */
static void test_band_without_readings_marked(void **state)
{
    char out[16384], args[512];
    const char *o = test_tmp("dh500");
    snprintf(args, sizeof args,
             "run configs/ess_type_a.ini --units 20 --quiet --set tolerance.dH_um=500 --out %s", o);
    assert_int_equal(sunmc(args, out, sizeof out), 0);
    assert_non_null(strstr(out, "alpha  30:60*"));
    assert_non_null(strstr(out, "* alpha 30:60: statistics over 5 of 20 units: 15 units with a "
                                "fit have no usable reading in this band"));
    /* summary.tsv counts them in its no_reading_units column */
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "awk -F'\t' 'NR==1 {for (i = 1; i <= NF; i++) if ($i == \"no_reading_units\") k = i; "
             "print $k} $4==\"30:60\" {print $k}' %s/summary.tsv", o);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_string_equal(out, "no_reading_units\n15\n");
}

/* The reproducers: a 1 deg campaign step (improvement 0.72x, every
 * unit aliased) and a campaign over alpha 0..8 only (0.2x) said so only in
 * a quiet count. */
static void test_worse_and_alias_warned(void **state)
{
    char out[16384];
    assert_int_equal(sunmc("run configs/ess_type_a.ini --units 20 --quiet "
                           "--set campaign.alpha_step_deg=1", out, sizeof out), 0);
    assert_non_null(strstr(out, "WARNING: calibration makes the units worse"));
    assert_non_null(strstr(out, "WARNING: 20 of 20 units (100%) could not resolve the fine-code"));
    assert_non_null(strstr(out, "Change the campaign step"));
    assert_int_equal(sunmc("run configs/ess_type_a.ini --units 20 --quiet "
                           "--set campaign.alpha_min_deg=0 --set campaign.alpha_max_deg=8",
                           out, sizeof out), 0);
    assert_non_null(strstr(out, "WARNING: calibration makes the units worse"));
    assert_null(strstr(out, "could not resolve"));
    /* the shipped config gives neither warning */
    assert_int_equal(sunmc("run configs/ess_type_a.ini --units 20 --quiet", out, sizeof out), 0);
    assert_null(strstr(out, "WARNING: calibration makes"));
    assert_null(strstr(out, "could not resolve"));
    assert_null(strstr(out, "* |"));
}

/* The reproducer: the DSS budget with tiny unit counts printed nan%
 * and shares from -100 % to 132 % without a word.  Now every share has its
 * interval and "~" marks those inside the noise; none prints as nan. */
static void test_budget_noise_warned(void **state)
{
    char out[16384];
    assert_int_equal(sunmc("budget configs/dss.ini --units 10 --quiet --set report.budget_units=10 "
                           "--set report.budget_steps=1", out, sizeof out), 0);
    assert_null(strstr(out, "nan"));
    assert_non_null(strstr(out, "]~"));
    assert_non_null(strstr(out, "~ = the interval\nincludes 0: inside the Monte Carlo noise"));
}

/* ---- compensate: params.ini within physical ranges ---- */

/* A calibration of family fam (simulate + calibrate) into dir; returns the
 * params.ini path. */
static const char *calibrated(const char *fam, const char *config)
{
    static char params[2][512];
    char args[2048], out[8192];
    const char *sim = test_tmp(fam);
    snprintf(args, sizeof args, "simulate %s --unit 1 --quiet --out %s/sim", config, sim);
    assert_int_equal(sunmc(args, out, sizeof out), 0);
    snprintf(args, sizeof args, "calibrate --sensor %s --config %s %s/sim/campaign.csv --out %s/cal",
             fam, config, sim, sim);
    if (sunmc(args, out, sizeof out) != 0)
        fail_msg("%s: %s", args, out);
    char *p = params[strcmp(fam, "ess") == 0 ? 0 : 1];
    snprintf(p, 512, "%s/cal/params.ini", sim);
    return p;
}

/* Replace the line of params.ini that starts with `key ` by "key = value"
 * into a copy; compensate the family's validation.csv with it. */
static int compensate_with(const char *params, const char *key, const char *value, char *out,
                           size_t len)
{
    char cmd[4096], copy[600];
    snprintf(copy, sizeof copy, "%s.bad", params);
    snprintf(cmd, sizeof cmd, "(sed 's/^%s .*/%s = %s/' %s > %s && %s compensate %s "
             "$(dirname %s)/../sim/validation.csv > /dev/null)",
             key, key, value, params, copy, test_sunmc(), copy, params);
    return test_run(cmd, out, len);
}

/* The reproducers: compensate accepted pixel 0, height 1e308 or 0,
 * index 0, a = 0 and wrote constant or NaN columns with exit 0. */
static void test_compensate_ranges(void **state)
{
    char out[4096];
    const char *ess = calibrated("ess", "configs/ess_type_a.ini");
    const char *dss = calibrated("dss", "configs/dss.ini");
    const struct {
        const char *params, *key, *value, *needle; /* needle NULL: accepted */
    } cases[] = {
        {ess, "a", "0", "parameters.a = 0 is out of range: allowed 0.1 to 10"},
        {ess, "a", "1e308", "parameters.a = 1e308 is out of range"},
        {ess, "a", "1.001", NULL},
        {ess, "b", "2.5", "parameters.b = 2.5 is out of range"},
        {ess, "theta0_deg", "0", "design.theta0_deg = 0 is out of range: allowed 0.1 to 10 deg"},
        {ess, "ks_deg", "0.08", "the fine-code amplitude"},
        {ess, "ks_deg", "0.01", NULL},
        {ess, "fit_install_y_arcsec", "40000", "fit_install_y_arcsec = 40000 is out of range"},
        {dss, "pixel_um", "0", "design.pixel_um = 0 is out of range"},
        {dss, "h_mm", "0", "design.h_mm = 0 is out of range"},
        {dss, "h_mm", "1e308", "design.h_mm = 1e308 is out of range"},
        {dss, "h_mm", "3.01", NULL},
        {dss, "glass_index", "0", "design.glass_index = 0 is out of range: allowed 1 to 3"},
        {dss, "glass_thickness_mm", "-5", "design.glass_thickness_mm = -5 is out of range"},
        {dss, "fit_c1_arcsec", "1e6", "parameters.fit_c1_arcsec = 1e6 is out of range"},
        {dss, "fit_glass_index", "-0.6", "parameters.fit_glass_index = -0.6 is out of range"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int st = compensate_with(cases[i].params, cases[i].key, cases[i].value, out, sizeof out);
        if (!cases[i].needle) {
            if (st != 0)
                fail_msg("%s = %s refused: %s", cases[i].key, cases[i].value, out);
            continue;
        }
        if (st != 2 || !strstr(out, cases[i].needle) || !strstr(out, ".ini.bad:"))
            fail_msg("%s = %s: exit %d, '%s'", cases[i].key, cases[i].value, st, out);
    }
}

/* ---- smaller items ---- */

/* The reproducer: `sunmc config /dev/zero` never returned. */
static void test_ini_nul_bytes(void **state)
{
    char out[4096];
    double t0 = now_s();
    assert_int_equal(sunmc("config /dev/zero", out, sizeof out), 2);
    assert_true(now_s() - t0 < 2.0);
    assert_non_null(strstr(out, "/dev/zero:1: a NUL byte"));
    const char *p = test_tmp("nul.ini");
    FILE *f = fopen(p, "wb");
    assert_non_null(f);
    fwrite("[sensor]\nfamily = ess\n\0[run]\nunits = 3\n", 1, 39, f);
    fclose(f);
    char args[600];
    snprintf(args, sizeof args, "config %s", p);
    assert_int_equal(sunmc(args, out, sizeof out), 2);
    assert_non_null(strstr(out, "nul.ini:3: a NUL byte"));
    /* a byte-order mark is skipped */
    assert_int_equal(test_write_file(p, "\xEF\xBB\xBF[sensor]\nfamily = dss\n"), 0);
    assert_int_equal(sunmc(args, out, sizeof out), 0);
    assert_non_null(strstr(out, "family = dss"));
}

/* The reproducers: "1,,2" became "1, 2"; UTF-8 in sensor.product
 * was called a control character; a 200-digit --seed ran with seed 0. */
static void test_values(void **state)
{
    refused("ess", SETS("campaign.beta_deg=1,,2"),
            "campaign.beta_deg: item 2 of the list is empty");
    refused("ess", SETS("campaign.beta_deg=1,2,"), "item 3 of the list is empty");
    refused("ess", SETS("campaign.beta_deg=,1"), "item 1 of the list is empty");
    refused("ess", SETS("report.bands_deg=0:30,,30:60"), "report.bands_deg: item 2");
    ok("ess", SETS("campaign.beta_deg= 1 , 2 "));
    ok("ess", SETS("sensor.product=Sonnensensor Typ \xC3\x84 \xC2\xB5 \xE2\x80\x93 \xF0\x9F\x8C\x9E"));
    refused("ess", SETS("sensor.product=a\xFF"), "sensor.product is not valid UTF-8 (byte 2)");
    refused("ess", SETS("sensor.product=a\xC3"), "not valid UTF-8");
    refused("ess", SETS("sensor.product=\xC0\xAF"), "not valid UTF-8"); /* overlong '/' */
    refused("ess", SETS("sensor.product=\xED\xA0\x80"), "not valid UTF-8"); /* surrogate */
    refused("ess", SETS("sensor.product=a\tb"), "tab or control character");
    refused("ess", SETS("run.seed=99999999999999999999"),
            "run.seed = '99999999999999999999...' (20 digits) is out of range: allowed 0 to "
            "2147483647");
    char out[4096], args[600];
    snprintf(args, sizeof args, "run configs/ess_type_a.ini --units 2 --seed %0200d", 1);
    assert_int_equal(sunmc(args, out, sizeof out), 2);
    assert_non_null(strstr(out, "--seed is too long for a whole number"));
}

/* The reproducer: sweep values were applied rounded to 10 digits. */
static void test_sweep_full_precision(void **state)
{
    sweep_axis ax;
    char err[SUNMC_ERRLEN];
    const sensor_family *ess = sensor_family_find("ess");
    assert_int_equal(sweep_axis_parse("design.H_mm=4.12345678901234,5", ess, &ax, err, sizeof err),
                     SUNMC_OK);
    assert_string_equal(ax.text[0], "4.12345678901234");
    assert_true(ax.v[0] == 4.12345678901234);
    assert_int_equal(sweep_axis_parse("design.H_mm=0.1000000000000001", ess, &ax, err, sizeof err),
                     SUNMC_OK);
    assert_true(strtod(ax.text[0], NULL) == 0.1000000000000001);
    /* a range's values are the decimals it names, not the sums' rounding */
    assert_int_equal(sweep_axis_parse("design.H_mm=3:4:0.1", ess, &ax, err, sizeof err), SUNMC_OK);
    assert_int_equal(ax.n, 11);
    assert_string_equal(ax.text[3], "3.3");
    assert_true(ax.v[3] == 3.3);
    assert_string_equal(ax.text[10], "4");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tolerance_range),
        cmocka_unit_test(test_ess_height_stays_positive),
        cmocka_unit_test(test_ess_width_and_gain),
        cmocka_unit_test(test_dss_glass_thickness),
        cmocka_unit_test(test_dss_height_gap_index),
        cmocka_unit_test(test_bands_hold_points),
        cmocka_unit_test(test_memory_limits),
        cmocka_unit_test(test_cli_limits_up_front),
        cmocka_unit_test(test_yield_digits),
        cmocka_unit_test(test_band_without_readings_marked),
        cmocka_unit_test(test_worse_and_alias_warned),
        cmocka_unit_test(test_budget_noise_warned),
        cmocka_unit_test(test_compensate_ranges),
        cmocka_unit_test(test_ini_nul_bytes),
        cmocka_unit_test(test_values),
        cmocka_unit_test(test_sweep_full_precision),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
