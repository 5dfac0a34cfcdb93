/* test_design.c - the candidate space, the aliased step marked and never
 * chosen, best.ini that run takes as it is, and the refusals. */
#include "test_util.h"

#include "design.h"
#include "registry.h"

static void build(config_state *st, const char *const *sets, int n)
{
    test_build(st, "configs/ess_type_a.ini", sets, n);
}

/* 2 steps x (1 line + 2..3 lines x 2 extents) x 1 repeat + the input. */
static void space_counts(void **state)
{
    config_state st;
    const char *sets[] = {"campaign.search_steps_deg=0.3,0.6", "campaign.search_max_lines=3",
                          "campaign.search_beta_step_deg=15", "campaign.search_beta_max_deg=30",
                          "campaign.search_repeats=1", "campaign.search_max_extrapolation_deg=90"};
    build(&st, sets, 6);
    design_result d;
    char err[SUNMC_ERRLEN];
    assert_int_equal(design_space(&st.cfg, &d, err, sizeof err), SUNMC_OK);
    assert_int_equal(d.n, 1 + 2 * (1 + 2 * 2));
    assert_true(d.cand[0].is_input);
    assert_string_equal(d.cand[0].step, "0.7");
    assert_string_equal(d.cand[0].lines, "-30, 0, 30");
    int found = 0;
    for (int i = 0; i < d.n; i++)
        found += strcmp(d.cand[i].step, "0.3") == 0 && strcmp(d.cand[i].lines, "-15, 0, 15") == 0;
    assert_int_equal(found, 1);
    design_free(&d);
    config_state_free(&st);
    /* At most 0.5 deg beyond the span: the lines must reach the validation's
     * +-25 deg, so only the +-30 sets of 2 and 3 lines stay (and the input). */
    build(&st, sets, 5);
    assert_int_equal(design_space(&st.cfg, &d, err, sizeof err), SUNMC_OK);
    assert_int_equal(d.n, 1 + 2 * 2);
    assert_int_equal(d.n_extrapolating, 2 * (1 + 2));
    design_free(&d);
    config_state_free(&st);
}


/* The input campaign at 0.2 deg costs more than any searched candidate, so
 * the choice is among the steps searched: 0.5 aliases, 0.3 is chosen. */
#define SPACE                                                                                     \
    "--set campaign.alpha_step_deg=0.2 --space steps_deg=0.5,0.3 --space max_lines=3 --space beta_step_deg=30 "                     \
    "--space beta_max_deg=30 --space repeats=1 --space screen_units=12 --space max_units=24 "     \
    "--space shortlist=1 --set run.block_units=12 --set validation.alpha_step_deg=1.3 "          \
    "--set report.yield_target=0.5 --quiet"

static void design_command(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd, "%s design configs/ess_type_a.ini " SPACE " --out %s", test_sunmc(),
             test_tmp("d"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "campaign design"));
    const char *tsv = test_tmp("d/design.tsv");
    assert_true(test_file_has(tsv, "rank\tcandidate\tcampaign.alpha_step_deg\tcampaign.beta_deg\t"));
    /* 0.5 deg is the fine-code period: aliased, marked, never best. */
    snprintf(cmd, sizeof cmd, "awk -F'\\t' '$3==\"0.5\" && ($19!=\"aliased\" || $21!=0)' %s", tsv);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_string_equal(out, "");
    snprintf(cmd, sizeof cmd, "awk -F'\\t' '$21==1 {print $3, $19}' %s", tsv);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_string_equal(out, "0.3 pass\n");
    const char *best = test_tmp("d/best.ini");
    assert_true(test_file_has(best, "alpha_step_deg = 0.3  # sunmc design"));
    snprintf(cmd, sizeof cmd, "%s run %s --units 2 --seed 9 --quiet", test_sunmc(), best);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "points on"));
}

static void design_refusals(void **state)
{
    char out[8192], cmd[4096];
    const char *bad[] = {"--space nonsense=1", "--space max_lines=8", "--vary design.H_mm=3"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(cmd, sizeof cmd, "%s design configs/ess_type_a.ini %s --out %s --quiet",
                 test_sunmc(), bad[i], test_tmp("bad"));
        if (test_run(cmd, out, sizeof out) != 2)
            fail_msg("'%s' was not refused: %s", bad[i], out);
    }
    snprintf(cmd, sizeof cmd, "test -e %s", test_tmp("bad"));
    assert_int_not_equal(system(cmd), 0);
    /* Nothing can reach a 100 % lower bound: exit 1, design.tsv but no best.ini. */
    snprintf(cmd, sizeof cmd,
             "%s design configs/ess_type_a.ini " SPACE " --set report.yield_target=1 --out %s",
             test_sunmc(), test_tmp("none"));
    assert_int_equal(test_run(cmd, out, sizeof out), 1);
    assert_non_null(strstr(out, "WARNING: no candidate met the target"));
    assert_true(test_file_has(test_tmp("none/design.tsv"), "rank"));
    snprintf(cmd, sizeof cmd, "test -e %s", test_tmp("none/best.ini"));
    assert_int_not_equal(system(cmd), 0);
}

/* The extended ESS model's alias check decides design's verdict too: 0.8
 * deg samples the fine period's 1st harmonic as its 4th (aliased, never
 * chosen), 0.7 deg resolves every fitted harmonic.  The input is the
 * former shipped campaign, 0.8 deg over -62..62 (over the shipped
 * -61.95..61.95 a 0.8 scan ends 0.69 deg short of the validation, beyond
 * campaign.search_max_extrapolation_deg, and would not be tried). */
static void design_extended_model_aliases(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd,
             "%s design configs/ess_type_a.ini --space steps_deg=0.7,0.8 --space max_lines=3 "
             "--space beta_max_deg=30 --space beta_step_deg=30 --space screen_units=10 "
             "--space max_units=20 --space repeats=1 --set calibration.model=extended "
             "--set campaign.alpha_step_deg=0.8 --set campaign.alpha_min_deg=-62 "
             "--set campaign.alpha_max_deg=62 "
             "--set validation.alpha_step_deg=1.3 --set report.yield_target=0.5 --out %s --quiet",
             test_sunmc(), test_tmp("dext"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    const char *tsv = test_tmp("dext/design.tsv");
    /* step, alias_units = units, verdict, best */
    snprintf(cmd, sizeof cmd, "awk -F'\\t' 'NR > 1 {print $3, $17 == $10, $19, $21}' %s | sort",
             tsv);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_string_equal(out, "0.7 0 pass 0\n0.7 0 pass 1\n0.8 1 aliased 0\n0.8 1 aliased 0\n");
}

/* Four lines over +-40 deg are evenly spaced at 80/3 deg: the table is
 * set to -40, -13.33, 13.33, 40 (0.01 deg, what a lab sets), not
 * 13.33333333, in design.tsv's beta column and label. */
static void design_lines_lab_resolution(void **state)
{
    char cmd[2048], out[8192];
    snprintf(cmd, sizeof cmd,
             "%s design configs/ess_type_a.ini --space steps_deg=0.7 --set "
             "campaign.search_beta_max_deg=40 --set campaign.search_beta_step_deg=40 --set "
             "campaign.search_repeats=1 --set campaign.search_screen_units=10 --units 10 --set "
             "validation.alpha_step_deg=2.3 --quiet --out %s",
             test_sunmc(), test_tmp("dlines"));
    assert_int_equal(test_run(cmd, out, sizeof out), 1); /* 10 units settle nothing */
    const char *tsv = test_tmp("dlines/design.tsv");
    assert_true(test_file_has(tsv, "\t-40, -13.33, 13.33, 40\t"));
    assert_true(test_file_has(tsv, "\t-40, -20, 0, 20, 40\t"));
    assert_false(test_file_has(tsv, "13.333"));
}

/* One design of the small space above, reusing the readings or not, in
 * `threads` threads. */
static void design_of(design_result *d, int no_reuse, int threads)
{
    config_state st;
    const char *sets[] = {"campaign.alpha_step_deg=0.2", "campaign.search_steps_deg=0.5, 0.3",
                          "campaign.search_max_lines=3", "campaign.search_beta_step_deg=15",
                          "campaign.search_beta_max_deg=30", "campaign.search_repeats=1, 2",
                          "campaign.search_screen_units=12", "campaign.search_max_units=36",
                          "campaign.search_shortlist=2", "run.block_units=24",
                          "validation.alpha_step_deg=1.3", "report.yield_target=0.9"};
    build(&st, sets, sizeof sets / sizeof sets[0]);
    char err[SUNMC_ERRLEN];
    assert_int_equal(design_space(&st.cfg, d, err, sizeof err), SUNMC_OK);
    d->no_reuse = no_reuse;
    if (design_run(d, threads, NULL, NULL, err, sizeof err) != SUNMC_OK)
        fail_msg("design: %s", err);
    config_state_free(&st);
}

/* Reading each unit's validation once for every candidate changes
 * nothing: the same verdicts, statistics, Pareto set and choice as reading
 * it afresh for each, in 1 and 2 threads.  The store holds a block (24
 * units): the screen's 12 units and the settle's block of 24 are each read
 * once, the rest of the unit runs reuse the readings. */
static void design_reuse_changes_nothing(void **state)
{
    design_result fresh, reuse;
    design_of(&fresh, 1, 1);
    assert_int_equal(fresh.units_reused, 0);
    for (int threads = 1; threads <= 2; threads++) {
        design_of(&reuse, 0, threads);
        assert_int_equal(reuse.n, fresh.n);
        assert_int_equal(reuse.best, fresh.best);
        assert_true(reuse.best >= 0);
        assert_int_equal(reuse.units_run, fresh.units_run);
        long most = 0;
        for (int i = 0; i < reuse.n; i++) {
            const design_candidate *a = &fresh.cand[i], *b = &reuse.cand[i];
            assert_int_equal(a->verdict, b->verdict);
            assert_int_equal(a->pareto, b->pareto);
            assert_int_equal(a->units, b->units);
            assert_int_equal(a->alias_units, b->alias_units);
            assert_int_equal(a->fit_failures, b->fit_failures);
            assert_memory_equal(&a->yield, &b->yield, sizeof a->yield);
            assert_memory_equal(&a->yield_ci, &b->yield_ci, sizeof a->yield_ci);
            assert_memory_equal(&a->after_mean, &b->after_mean, sizeof a->after_mean);
            assert_memory_equal(&a->after_ci, &b->after_ci, sizeof a->after_ci);
            most = b->units > most ? b->units : most;
        }
        assert_true(most > 12); /* something settled */
        assert_int_equal(reuse.units_run - reuse.units_reused, most);
        design_free(&reuse);
    }
    design_free(&fresh);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(space_counts),
        cmocka_unit_test(design_command),
        cmocka_unit_test(design_refusals),
        cmocka_unit_test(design_extended_model_aliases),
        cmocka_unit_test(design_lines_lab_resolution),
        cmocka_unit_test(design_reuse_changes_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
