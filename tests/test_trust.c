/* test_trust.c - issue 9's reproducers: sunmc refuses what it cannot stand
 * behind (exit 2 before any work, naming the keys) and flags what is
 * doubtful.  Each test names the reproducer it guards. */
#include "test_util.h"

#include "family.h"
#include "memory.h"
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
    refused("dss", SETS("campaign.b_step_deg=0.01"), "GB per thread|coarser campaign step");
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
    const char *needle[] = {"100000000 units need", "200000000 units need",
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
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
