/* test_campaign.c - a campaign's turntable time (closed forms counted by
 * hand), its span against the validation grid, and where both are reported
 * (Table 1, summary.tsv, calibrate). */
#include "test_util.h"

#include "campaign.h"
#include "config.h"
#include "registry.h"
#include "status.h"

/* Four positions by hand: (0,0) (1,0) (1,10) (3,10), two lines. */
static void cost_by_hand(void **state)
{
    config_state st;
    const char *sets[] = {"campaign.dwell_s=2", "campaign.point_settle_s=0.5",
                          "campaign.line_settle_s=7", "campaign.slew_deg_per_s=4",
                          "campaign.repeats=3"};
    test_build(&st, "configs/ess_type_a.ini", sets, 5);
    const double a0[] = {0, 1, 1, 3}, a1[] = {0, 0, 10, 10};
    campaign_info ci;
    campaign_cost(&st.cfg, a0, a1, 4, 1.0, &ci);
    assert_int_equal(ci.points, 4);
    assert_int_equal(ci.lines, 2);
    assert_int_equal(ci.readings, 12);
    /* moves: 1 (alpha), 10 (beta; both axes move at once, the longer counts), 2 */
    assert_near(ci.slew_deg, 13, 1e-12);
    double s = 13.0 / 4 + 2 * 7 + 2 * 0.5 + 12 * 2;
    assert_near(ci.hours, s / 3600, 1e-15);
    assert_near(ci.cal_lo[0], 0, 0);
    assert_near(ci.cal_hi[0], 3, 0);
    assert_near(ci.cal_hi[1], 10, 0);
    /* Radians in, degrees out. */
    const double r0[] = {0, M_PI / 180};
    campaign_cost(&st.cfg, r0, a1, 2, 180 / M_PI, &ci);
    assert_near(ci.slew_deg, 1, 1e-12);
    config_state_free(&st);
}

/* The shipped type A campaign, and a config without campaign or
 * validation keys (the key table's defaults, the same campaign): alpha
 * -61.95..61.95 in steps of 0.7, 123.9 / 0.7 + 1 = 178 alpha x 3 beta lines
 * = 534 points, back to -61.95 between lines (the beta moves of 30 are
 * shorter than that return, so they cost nothing more).  Travel 3 scans +
 * 2 returns of 123.9 = 619.5 deg; with the key table's 5 deg/s, 30 s,
 * 1 s and 1 s: 619.5 / 5 + 3 x 30 + (534 - 3) x 1 + 534 x 1 x 1
 * = 123.9 + 90 + 531 + 534 = 1278.9 s = 0.35525 h.  The alpha ends are the
 * validation's outermost angles (-62 + 0.05 and -61.95 + 0.13 x 953 =
 * 61.94) and lines at +-30 cover its beta +-25: no extrapolation. */
static void ess_campaign_of(const char *path)
{
    config_state st;
    const char *family[] = {"sensor.family=ess"};
    test_build(&st, path, path ? NULL : family, path ? 0 : 1);
    campaign_info ci;
    char err[SUNMC_ERRLEN];
    assert_int_equal(campaign_describe(&st.cfg, &ci, err, sizeof err), SUNMC_OK);
    assert_true(ci.known);
    assert_int_equal(ci.points, 178 * 3);
    assert_int_equal(ci.lines, 3);
    const sunmc_config *c = &st.cfg;
    double travel = 3 * 123.9 + 2 * 123.9; /* scans + returns (beta moves 30 < 123.9) */
    assert_near(ci.slew_deg, travel, 1e-9);
    double want = (travel / c->slew_deg_per_s + 3 * c->line_settle_s +
                   (178 * 3 - 3) * c->point_settle_s + 178 * 3 * c->cal_repeats * c->dwell_s) /
                  3600;
    assert_near(ci.hours, want, 1e-12);
    /* with the key table's 1 s, 1 s, 30 s and 5 deg/s: 1278.9 s */
    assert_near(ci.hours, (619.5 / 5 + 3 * 30 + 531 + 534) / 3600, 1e-12);
    assert_near(ci.cal_lo[0], -61.95, 1e-9);
    assert_near(ci.cal_hi[0], 61.95, 1e-9);
    assert_near(ci.outside_deg[0], 0, 0);
    assert_near(ci.outside_deg[1], 0, 0);
    assert_near(ci.extrapolation_deg, 0, 0);
    char text[512];
    campaign_extrapolation_text(&ci, c->family->grid->axis_names, text, sizeof text);
    assert_string_equal(text, "");
    config_state_free(&st);
}

static void ess_default_campaign(void **state)
{
    ess_campaign_of("configs/ess_type_a.ini");
    ess_campaign_of(NULL);
    config_state st;
    campaign_info ci;
    char err[SUNMC_ERRLEN], text[512];
    /* Lines at +-20: validation beta +-25 lies 5 deg beyond, on axis 1. */
    const char *close[] = {"campaign.beta_deg=-20,0,20"};
    test_build(&st, "configs/ess_type_a.ini", close, 1);
    assert_int_equal(campaign_describe(&st.cfg, &ci, err, sizeof err), SUNMC_OK);
    assert_near(ci.outside_deg[0], 0, 0);
    assert_near(ci.outside_deg[1], 5, 1e-12);
    assert_near(ci.extrapolation_deg, 5, 1e-12);
    campaign_extrapolation_text(&ci, st.cfg.family->grid->axis_names, text, sizeof text);
    assert_non_null(strstr(text, "validation beta reaches -25..25 deg"));
    assert_non_null(strstr(text, "-20..20"));
    config_state_free(&st);
    /* Validation alpha beyond the campaign's alpha range: on axis 0.  The
     * 0.7 scan from -50 stops at -50 + 142 x 0.7 = 49.4; the validation
     * reaches 61.94 (and -61.95, 11.95 below -50): 12.54 beyond. */
    const char *narrow[] = {"campaign.alpha_min_deg=-50", "campaign.alpha_max_deg=50"};
    test_build(&st, "configs/ess_type_a.ini", narrow, 2);
    assert_int_equal(campaign_describe(&st.cfg, &ci, err, sizeof err), SUNMC_OK);
    assert_near(ci.cal_hi[0], 49.4, 1e-9);
    assert_near(ci.outside_deg[0], 61.94 - 49.4, 1e-9);
    config_state_free(&st);
}

/* DSS: a b grid of n x n, one line per b1 value. */
static void dss_campaign(void **state)
{
    config_state st;
    /* every report band must hold validation points: one band over the
     * +-10 deg grid (field angles up to 14 deg) */
    const char *sets[] = {"campaign.b_min_deg=-10", "campaign.b_max_deg=10",
                          "campaign.b_step_deg=5", "validation.b_min_deg=-10",
                          "validation.b_max_deg=10", "validation.b_offset_deg=0",
                          "report.bands_deg=0:15"};
    test_build(&st, "configs/dss.ini", sets, 7);
    campaign_info ci;
    char err[SUNMC_ERRLEN];
    assert_int_equal(campaign_describe(&st.cfg, &ci, err, sizeof err), SUNMC_OK);
    assert_int_equal(ci.points, 25);
    assert_int_equal(ci.lines, 5);
    /* 4 steps of 5 per line, 4 returns of 20 (b1 moves 5 at once) */
    assert_near(ci.slew_deg, 5 * 20 + 4 * 20, 1e-9);
    assert_near(ci.extrapolation_deg, 0, 0);
    config_state_free(&st);
}

/* DSS, a config without campaign or validation keys: the key table's
 * -60..60 step 5 grid (that of configs/dss.ini), 120 / 5 + 1 = 25 b2
 * positions on each of 25 b1 lines = 625 points; travel: 25 scans of
 * 24 x 5 = 120 deg and 24 returns of 120 (b1 moves 5 at once) = 5880 deg
 * at 5 deg/s = 1176 s, 25 line settles of 30 s, 600 point settles and 625
 * readings of 1 s: 3151 s.  Validation -60 + 1.3 + 4.1 k, k = 0..28, is
 * -58.7..56.1 on both axes: inside, no extrapolation. */
static void dss_default_campaign(void **state)
{
    config_state st;
    const char *family[] = {"sensor.family=dss"};
    test_build(&st, NULL, family, 1);
    campaign_info ci;
    char err[SUNMC_ERRLEN];
    assert_int_equal(campaign_describe(&st.cfg, &ci, err, sizeof err), SUNMC_OK);
    assert_true(ci.known);
    assert_int_equal(ci.points, 625);
    assert_int_equal(ci.lines, 25);
    assert_near(ci.slew_deg, 25 * 120.0 + 24 * 120.0, 1e-9);
    assert_near(ci.hours, (5880.0 / 5 + 25 * 30 + 600 + 625) / 3600, 1e-12);
    for (int a = 0; a < CAMPAIGN_AXES; a++) {
        assert_near(ci.val_lo[a], -58.7, 1e-9);
        assert_near(ci.val_hi[a], 56.1, 1e-9);
        assert_near(ci.outside_deg[a], 0, 0);
    }
    assert_near(ci.extrapolation_deg, 0, 0);
    config_state_free(&st);
}

/* The campaign and validation keys a shipped config sets are the key
 * table's defaults: a config that leaves them out gets the campaign the
 * shipped one was designed with (and the shipped outputs do not depend on
 * the defaults: it sets at least min_set of them itself). */
static void expect_shipped_defaults(const char *path, const char *family, int min_set)
{
    config_state def, shipped;
    char set[64];
    snprintf(set, sizeof set, "sensor.family=%s", family);
    const char *sets[] = {set};
    test_build(&def, NULL, sets, 1);
    test_build(&shipped, path, NULL, 0);
    static const config_key *keys[CONFIG_KEYS_MAX];
    static const sensor_family *owners[CONFIG_KEYS_MAX];
    size_t n = config_list_keys(def.cfg.family, keys, owners, CONFIG_KEYS_MAX);
    int in_file = 0;
    for (size_t i = 0; i < n; i++) {
        const config_key *k = keys[i];
        if (strcmp(k->section, "campaign") != 0 && strcmp(k->section, "validation") != 0)
            continue;
        char d[1024], v[1024];
        config_format_value(k, &def.cfg, d, sizeof d);
        config_format_value(k, &shipped.cfg, v, sizeof v);
        if (strcmp(d, v) != 0)
            fail_msg("%s.%s: default %s, %s sets %s", k->section, k->name, d, path, v);
        in_file += strcmp(config_origin_of(&shipped, k), "default") != 0;
    }
    assert_true(in_file >= min_set);
    config_state_free(&def);
    config_state_free(&shipped);
}

static void defaults_are_shipped_campaign(void **state)
{
    /* ESS: alpha min, max, step, beta of each; validation step, offset, beta */
    expect_shipped_defaults("configs/ess_type_a.ini", "ess", 7);
    expect_shipped_defaults("configs/ess_type_b.ini", "ess", 7);
    /* DSS: b min, max, step of each; validation offset */
    expect_shipped_defaults("configs/dss.ini", "dss", 7);
}

/* Runs 2 units of config (type A unless NULL) with extra --set options into
 * DIR: Table 1 in out, and summary.tsv's campaign columns must read want. */
static void run_campaign(const char *config, const char *sets, const char *dir,
                         const char *want, char *out, size_t len)
{
    char cmd[2048], cols[256];
    snprintf(cmd, sizeof cmd,
             "%s run %s --units 2 --set validation.alpha_step_deg=1.3 %s --quiet --out %s",
             test_sunmc(), config ? config : "configs/ess_type_a.ini", sets, test_tmp(dir));
    assert_int_equal(test_run(cmd, out, len), 0);
    snprintf(cmd, sizeof cmd, "head -2 %s/summary.tsv | cut -f38-40", test_tmp(dir));
    assert_int_equal(test_run(cmd, cols, sizeof cols), 0);
    assert_string_equal(cols, want);
}

/* run: Table 1 states points and hours and warns; summary.tsv has them.
 * The shipped campaign (534 points, 1278.9 s = 0.35525 h, see above) covers
 * its validation; lines at +-20 do not, by 5 deg.  Two lines at +-25: 356
 * points, 2 scans + 1 return of 123.9 deg at 5 deg/s (74.34 s), 2 line
 * settles of 30 s, 354 point settles and 356 readings of 1 s: 844.34 s
 * = 0.234539 h. */
static void run_reports_campaign(void **state)
{
    char out[16384];
    const char *head = "campaign_points\tcampaign_hours\textrapolation_deg\n";
    char want[128];
    snprintf(want, sizeof want, "%s534\t0.35525\t0\n", head);
    run_campaign(NULL, "", "run", want, out, sizeof out);
    assert_non_null(strstr(out, "campaign: 534 points on 3 lines, 1 reading each: 0.36 "
                                "turntable hours"));
    assert_null(strstr(out, "WARNING"));
    /* A config with no campaign or validation keys: the same campaign, the
     * same cost, no extrapolation and no warning. */
    const char *bare = test_tmp("bare.ini");
    assert_int_equal(test_write_file(bare, "[sensor]\nfamily = ess\n"), 0);
    run_campaign(bare, "", "runbare", want, out, sizeof out);
    assert_non_null(strstr(out, "campaign: 534 points on 3 lines, 1 reading each: 0.36 "
                                "turntable hours"));
    assert_null(strstr(out, "WARNING"));
    snprintf(want, sizeof want, "%s534\t0.35525\t5\n", head);
    run_campaign(NULL, "--set campaign.beta_deg=-20,0,20", "run20", want, out, sizeof out);
    assert_non_null(strstr(out, "WARNING: validation beta reaches -25..25 deg"));
    snprintf(want, sizeof want, "%s356\t0.234539\t0\n", head);
    run_campaign(NULL, "--set campaign.beta_deg=-25,25", "run25", want, out, sizeof out);
    assert_null(strstr(out, "WARNING"));
    assert_non_null(strstr(out, "356 points on 2 lines"));
}

/* calibrate: the campaign of the data, in file order. */
static void calibrate_reports_campaign(void **state)
{
    char out[65536], cmd[2048];
    snprintf(cmd, sizeof cmd,
             "%s simulate configs/ess_type_a.ini --unit 1 --quiet --set campaign.alpha_step_deg=1.3 "
             "--out %s > /dev/null && %s calibrate --sensor ess --config configs/ess_type_a.ini "
             "%s",
             test_sunmc(), test_tmp("sim"), test_sunmc(), test_tmp("sim/campaign.csv"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    /* -62 + 95 x 1.3 = 61.5: 96 alpha x 3 beta */
    assert_non_null(strstr(out, "campaign: 288 points on 3 lines, 288 readings"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cost_by_hand),         cmocka_unit_test(ess_default_campaign),
        cmocka_unit_test(dss_campaign),         cmocka_unit_test(dss_default_campaign),
        cmocka_unit_test(defaults_are_shipped_campaign), cmocka_unit_test(run_reports_campaign),
        cmocka_unit_test(calibrate_reports_campaign),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
