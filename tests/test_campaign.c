/* test_campaign.c - a campaign's turntable time (closed forms counted by
 * hand), its span against the validation grid, and where both are reported
 * (Table 1, summary.tsv, calibrate). */
#include "test_util.h"

#include "campaign.h"
#include "config.h"
#include "registry.h"
#include "status.h"

static void build(config_state *st, const char *path, const char *const *sets, int n)
{
    char err[SUNMC_ERRLEN];
    if (config_build(st, path, sets, n, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
}

/* Four positions by hand: (0,0) (1,0) (1,10) (3,10), two lines. */
static void cost_by_hand(void **state)
{
    config_state st;
    const char *sets[] = {"campaign.dwell_s=2", "campaign.point_settle_s=0.5",
                          "campaign.line_settle_s=7", "campaign.slew_deg_per_s=4",
                          "campaign.repeats=3"};
    build(&st, "configs/ess_type_a.ini", sets, 5);
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

/* The shipped type A campaign: 621 alpha x 3 beta lines, -62..62 each,
 * back to -62 between lines; validation beta +-25 lies 5 deg beyond. */
static void ess_default_campaign(void **state)
{
    config_state st;
    build(&st, "configs/ess_type_a.ini", NULL, 0);
    campaign_info ci;
    char err[SUNMC_ERRLEN];
    assert_int_equal(campaign_describe(&st.cfg, &ci, err, sizeof err), SUNMC_OK);
    assert_true(ci.known);
    assert_int_equal(ci.points, 621 * 3);
    assert_int_equal(ci.lines, 3);
    const sunmc_config *c = &st.cfg;
    double travel = 3 * 124.0 + 2 * 124.0; /* scans + returns (beta moves 20 < 124) */
    double want = (travel / c->slew_deg_per_s + 3 * c->line_settle_s +
                   (621 * 3 - 3) * c->point_settle_s + 621 * 3 * c->cal_repeats * c->dwell_s) /
                  3600;
    assert_near(ci.hours, want, 1e-12);
    assert_near(ci.outside_deg[0], 0, 0);
    assert_near(ci.outside_deg[1], 5, 1e-12);
    assert_near(ci.extrapolation_deg, 5, 1e-12);
    char text[512];
    campaign_extrapolation_text(&ci, c->family->table_axis_names, text, sizeof text);
    assert_non_null(strstr(text, "validation beta reaches -25..25 deg"));
    assert_non_null(strstr(text, "-20..20"));
    config_state_free(&st);
    /* Lines at +-30 cover the validation: no extrapolation, no text. */
    const char *wide[] = {"campaign.beta_deg=-30,0,30"};
    build(&st, "configs/ess_type_a.ini", wide, 1);
    assert_int_equal(campaign_describe(&st.cfg, &ci, err, sizeof err), SUNMC_OK);
    assert_near(ci.extrapolation_deg, 0, 0);
    campaign_extrapolation_text(&ci, st.cfg.family->table_axis_names, text, sizeof text);
    assert_string_equal(text, "");
    config_state_free(&st);
    /* Validation alpha beyond the campaign's alpha range: on axis 0. */
    const char *narrow[] = {"campaign.alpha_min_deg=-50", "campaign.alpha_max_deg=50"};
    build(&st, "configs/ess_type_a.ini", narrow, 2);
    assert_int_equal(campaign_describe(&st.cfg, &ci, err, sizeof err), SUNMC_OK);
    assert_true(ci.outside_deg[0] > 11.9 && ci.outside_deg[0] <= 12);
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
    build(&st, "configs/dss.ini", sets, 7);
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

/* run: Table 1 states points and hours and warns; summary.tsv has them. */
static void run_reports_campaign(void **state)
{
    char out[16384], cmd[2048];
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 2 --set validation.alpha_step_deg=1.3 "
             "--quiet --out %s",
             test_sunmc(), test_tmp("run"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "campaign: 1863 points on 3 lines, 1 reading each: 1.09 "
                                "turntable hours"));
    assert_non_null(strstr(out, "WARNING: validation beta reaches -25..25 deg"));
    snprintf(cmd, sizeof cmd, "head -2 %s | cut -f38-40", test_tmp("run/summary.tsv"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_string_equal(out, "campaign_points\tcampaign_hours\textrapolation_deg\n"
                             "1863\t1.09361\t5\n");
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 2 --set validation.alpha_step_deg=1.3 "
             "--set campaign.beta_deg=-25,25 --quiet",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_null(strstr(out, "WARNING"));
    assert_non_null(strstr(out, "1242 points on 2 lines"));
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
        cmocka_unit_test(dss_campaign),         cmocka_unit_test(run_reports_campaign),
        cmocka_unit_test(calibrate_reports_campaign),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
