/* test_budget.c - sources, the alone run against a closed form, shares of a
 * single source, inverse-limit end states, and the budget command's errors. */
#include "test_util.h"

#include "ess_config.h"

#include "budget.h"
#include "report.h"
#include "config.h"
#include "family.h"
#include "montecarlo.h"
#include "sensitivity.h"
#include "status.h"
#include "units.h"

#include <string.h>

/* Small, noiseless, ideal-fine-code ESS: the error of dH alone is then
 * exactly atan((1 + dH/H) tan a) - a (the slit image lands at (H+dH) tan a on
 * a dial etched by eta = H tan). */
static const char *const ideal_sets[] = {
    "design.harmonics=given", "design.a3_ratio=0", "design.a5_ratio=0",
    "noise.row_current_pct=0", "noise.encoder_arcsec=0", "calibration.roll_sigma_arcsec=0",
    "campaign.alpha_step_deg=0.3", "campaign.beta_deg=0", "validation.alpha_step_deg=1.3",
    "tolerance.dd_um=0", "tolerance.dphi_deg=0", "tolerance.slit_width_um=0",
    "tolerance.harmonic_phase_deg=0", "tolerance.gain_pct=0", "tolerance.etch_um=0",
    "tolerance.install_x_arcsec=0", "tolerance.install_y_arcsec=0",
    "tolerance.install_z_arcsec=0", "tolerance.sun_x_arcsec=0", "tolerance.sun_y_arcsec=0",
    "tolerance.dial_tilt_deg=0", "tolerance.dH_um=2", "tolerance.dH_um_dist=fixed"};
#define N_IDEAL (sizeof ideal_sets / sizeof ideal_sets[0])

static void sources_of_type_a(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", NULL, 0, err, sizeof err), 0);
    budget_result *b = calloc(1, sizeof *b);
    assert_int_equal(budget_sources(&st.cfg, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->n, 13 + 3); /* the tolerances, then the noise keys */
    assert_string_equal(b->src[0].name, "dH_um");
    assert_near(b->src[0].tolerance, 2, 0);
    assert_int_equal(b->src[0].kind, BUDGET_TOLERANCE);
    const char *noise[3] = {"noise.row_current_pct", "noise.encoder_arcsec",
                            "calibration.roll_sigma_arcsec"};
    for (int i = 0; i < 3; i++) {
        assert_string_equal(b->src[13 + i].name, noise[i]);
        assert_int_equal(b->src[13 + i].kind, BUDGET_NOISE);
    }
    assert_near(b->src[13].tolerance, 1.5, 0);
    assert_int_equal(b->band, 2); /* 0:62 is the widest band */
    assert_int_equal(b->angle, 0);
    free(b);
    config_state_free(&st);
}

static void no_source_is_an_error(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", ideal_sets, N_IDEAL, err,
                                  sizeof err),
                     0);
    budget_result *b = calloc(1, sizeof *b);
    budget_set_tolerance(&st.cfg, config_find("tolerance", "dH_um"), 0.0);
    assert_int_equal(budget_sources(&st.cfg, b, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "no tolerance or noise"));
    free(b);
    config_state_free(&st);
}

static void alone_matches_closed_form(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", ideal_sets, N_IDEAL, err,
                                  sizeof err),
                     0);
    const sunmc_config *c = &st.cfg;
    const ess_config *ec = ess_cfg(c);
    budget_result *b = calloc(1, sizeof *b);
    assert_int_equal(budget_run(c, STUDY_MIN_UNITS, 1, 0, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->n, 1);
    /* Closed form over the validation grid, band 0:62. */
    double q = 1.0 + 2.0 * MM_PER_UM / ec->design.H_mm, s2 = 0;
    long n = 0;
    long na = grid_count(ec->val_alpha_min_deg, ec->val_alpha_max_deg, ec->val_alpha_step_deg,
                         ec->val_alpha_offset_deg);
    for (int k = 0; k < ec->val_beta_deg.n; k++)
        for (long j = 0; j < na; j++) {
            double a = (ec->val_alpha_min_deg + ec->val_alpha_offset_deg +
                        (double)j * ec->val_alpha_step_deg) *
                       RAD_PER_DEG;
            double e = atan(q * tan(a)) - a;
            s2 += e * e;
            n++;
        }
    double rms_deg = sqrt(s2 / (double)n) * DEG_PER_RAD;
    assert_near(b->src[0].alone.before_mean, rms_deg, 1e-6);
    assert_near(b->all.before_mean, rms_deg, 1e-6);
    /* One source, no noise: alone is all, the floor (the ideal nominal
     * design) has no error, the share is 100 %, nothing interacts. */
    assert_near(b->src[0].share_before.v, 1.0, 1e-9);
    assert_near(b->floor.before_mean, 0.0, 1e-6);
    assert_near(b->floor_before.v, 0.0, 1e-9);
    assert_near(b->interaction_before.v, 0.0, 1e-9);
    assert_int_equal(b->paired_units, STUDY_MIN_UNITS);
    /* Calibration removes a pure height error. */
    assert_true(b->all.after_mean < 0.01 * rms_deg);
    assert_int_equal(b->src[0].rank, 1);
    free(b);
    config_state_free(&st);
}

static void inverse_limit_end_states(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    const char *sets[N_IDEAL + 4];
    memcpy(sets, ideal_sets, sizeof ideal_sets);
    sets[N_IDEAL] = "report.budget_units=10";
    sets[N_IDEAL + 1] = "report.budget_steps=2";
    sets[N_IDEAL + 2] = "tolerance.sun_x_arcsec=60";
    sets[N_IDEAL + 3] = "report.spec_arcsec=0";
    /* spec 0: no unit can pass, whatever the tolerance. */
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", sets, N_IDEAL + 4, err, sizeof err),
                     0);
    budget_result *b = calloc(1, sizeof *b);
    assert_int_equal(budget_run(&st.cfg, STUDY_MIN_UNITS, 1, 1, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    for (int i = 0; i < b->n; i++)
        assert_int_equal(b->src[i].limit_status, BUDGET_LIMIT_UNMET);
    config_state_free(&st);
    /* A generous spec: the sun tilt toward X is invisible to an alpha
     * sensor, its limit is the key's maximum. */
    sets[N_IDEAL + 3] = "report.spec_arcsec=36000";
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", sets, N_IDEAL + 4, err, sizeof err),
                     0);
    assert_int_equal(budget_run(&st.cfg, STUDY_MIN_UNITS, 1, 1, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    int found = 0;
    for (int i = 0; i < b->n; i++)
        if (strcmp(b->src[i].name, "sun_x_arcsec") == 0) {
            found = 1;
            assert_int_equal(b->src[i].limit_status, BUDGET_LIMIT_AT_MAX);
            assert_near(b->src[i].limit, config_find("tolerance", "sun_x_arcsec")->max, 0);
        }
    assert_true(found);
    free(b);
    config_state_free(&st);
}

/* The inverse limits' yield at today's value is the all-sources run's
 * first report.budget_units units (issue 27): the same yield and interval
 * a run of those units gives, and one budget_units run fewer per source;
 * with budget_units above the units (the limit: no head to take) every
 * source runs its own. */
static void today_from_all_sources_run(void **state)
{
    const char *sets[] = {"validation.alpha_step_deg=2.3", "campaign.beta_deg=0",
                          "report.budget_steps=1", "report.budget_units=10",
                          "tolerance.install_y_arcsec=0", "tolerance.install_z_arcsec=0",
                          "tolerance.sun_x_arcsec=0", "tolerance.sun_y_arcsec=0",
                          "tolerance.install_x_arcsec=0", "tolerance.etch_um=0"};
    size_t ns = sizeof sets / sizeof sets[0];
    config_state st;
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", sets, ns, err, sizeof err), 0);
    budget_result *b = calloc(1, sizeof *b);
    assert_int_equal(budget_run(&st.cfg, 12, 2, 1, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->today_units, 10);
    budget_stats alone;
    assert_int_equal(budget_monte_carlo(&st.cfg, 10, 1, b->angle, b->band, &alone, NULL, NULL, err,
                                        sizeof err),
                     SUNMC_OK);
    long searched = 0;
    for (int i = 0; i < b->n; i++) {
        assert_near(b->src[i].yield_today, alone.yield, 0);
        assert_near(b->src[i].yield_today_ci.lo, alone.yield_ci.lo, 0);
        assert_near(b->src[i].yield_today_ci.hi, alone.yield_ci.hi, 0);
        assert_int_equal(b->src[i].limit_units, 10L * (b->src[i].limit_runs - 1));
        searched += b->src[i].limit_units;
    }
    /* the floor (no random input) is one unit run, copied; the parts after
     * calibration run the all-sources units again, each twice (modelform.h) */
    assert_int_equal(budget_unit_runs(b), (2L + b->n) * 12 + 1 + searched + 2L * 12);
    /* Finished from stored readings: the encoder and roll noise alone read
     * the floor's validation (1 unit stored by the floor's run, then 12),
     * no tolerance reads the row-current noise alone's (12); each search
     * of the encoder and roll noise reads the all-sources run's units. */
    long expect = 1 + 12 + 12;
    for (int i = 0; i < b->n; i++) {
        const char *nm = b->src[i].name;
        int campaign = strcmp(nm, "noise.encoder_arcsec") == 0 ||
                       strcmp(nm, "calibration.roll_sigma_arcsec") == 0;
        assert_int_equal(b->src[i].limit_reused, campaign ? b->src[i].limit_units : 0);
        expect += b->src[i].limit_reused;
        if (!campaign)
            continue;
        /* and give the bits of a run that reads its own */
        sunmc_config t = st.cfg;
        for (int j = 0; j < b->n; j++)
            budget_set_tolerance(&t, b->src[j].key, j == i ? b->src[j].tolerance : 0.0);
        budget_stats own;
        assert_int_equal(budget_monte_carlo(&t, 12, 2, b->angle, b->band, &own, NULL, NULL, err,
                                            sizeof err),
                         SUNMC_OK);
        assert_memory_equal(&own, &b->src[i].alone, sizeof own);
    }
    assert_int_equal(budget_reused_units(b), expect);
    config_state_free(&st);
    /* 13 units per search run, more than the 12 of the budget's runs */
    sets[3] = "report.budget_units=13";
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", sets, ns, err, sizeof err), 0);
    assert_int_equal(budget_run(&st.cfg, 12, 2, 1, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->today_units, 0);
    for (int i = 0; i < b->n; i++)
        assert_int_equal(b->src[i].limit_units, 13L * b->src[i].limit_runs);
    free(b);
    config_state_free(&st);
}

/* The searches run a source to a thread: their results are the same in
 * 1 and 2 threads, source by source (every field of every source). */
static void limits_independent_of_threads(void **state)
{
    const char *sets[] = {"validation.alpha_step_deg=2.3", "campaign.beta_deg=0",
                          "report.budget_steps=2", "report.budget_units=10",
                          "tolerance.install_y_arcsec=0", "tolerance.install_z_arcsec=0"};
    config_state st;
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", sets, 6, err, sizeof err), 0);
    budget_result *b1 = calloc(1, sizeof *b1), *b2 = calloc(1, sizeof *b2);
    assert_int_equal(budget_run(&st.cfg, 12, 1, 1, NULL, NULL, b1, err, sizeof err), SUNMC_OK);
    assert_int_equal(budget_run(&st.cfg, 12, 2, 1, NULL, NULL, b2, err, sizeof err), SUNMC_OK);
    assert_int_equal(b1->n, b2->n);
    long runs = 0;
    for (int i = 0; i < b1->n; i++) {
        assert_memory_equal(&b1->src[i], &b2->src[i], sizeof b1->src[i]);
        runs += b1->src[i].limit_runs;
    }
    assert_true(runs > b1->n); /* searches were made */
    assert_int_equal(budget_unit_runs(b1), budget_unit_runs(b2));
    free(b1);
    free(b2);
    config_state_free(&st);
}

/* The floor run computes one unit and copies it (budget_units_run): right
 * only when every unit of the floor config is the same unit.  Each shipped
 * family's floor (every budget source 0) run in full over 5 units: every
 * unit's RMS and fitted parameters equal unit 0's, and the config has no
 * random input while today's has. */
static void floor_units_are_one_unit(void **state)
{
    const char *cfgs[] = {"configs/ess_type_a.ini", "configs/dss.ini", "configs/psd.ini"};
    const char *sets[] = {"validation.alpha_step_deg=2.3"};
    for (size_t f = 0; f < sizeof cfgs / sizeof cfgs[0]; f++) {
        config_state st;
        char err[SUNMC_ERRLEN];
        assert_int_equal(config_build(&st, cfgs[f], sets, f == 0, err, sizeof err), 0);
        budget_result *b = calloc(1, sizeof *b);
        assert_int_equal(budget_sources(&st.cfg, b, err, sizeof err), SUNMC_OK);
        sunmc_config floor = st.cfg;
        assert_true(sens_random_inputs(&floor) > 0);
        assert_int_equal(budget_units_run(&floor, 7), 7);
        for (int i = 0; i < b->n; i++)
            budget_set_tolerance(&floor, b->src[i].key, 0.0);
        assert_int_equal(sens_random_inputs(&floor), 0);
        assert_int_equal(budget_units_run(&floor, 7), 1);
        assert_int_equal(budget_units_run(&floor, 1), 1);
        unit_result res[5];
        assert_int_equal(mc_run(&floor, 0, 5, 1, res, NULL, NULL, err, sizeof err), SUNMC_OK);
        for (int u = 1; u < 5; u++) {
            assert_int_equal(res[u].fit_status, res[0].fit_status);
            assert_memory_equal(res[u].rms_before, res[0].rms_before, sizeof res[0].rms_before);
            assert_memory_equal(res[u].rms_after, res[0].rms_after, sizeof res[0].rms_after);
            for (int k = 0; k < UNIT_MAX_PAR; k++)
                assert_true(res[u].par[k] == res[0].par[k]); /* -0 == 0 */
        }
        budget_stats copied;
        assert_int_equal(budget_monte_carlo(&floor, 5, 1, b->angle, b->band, &copied, NULL,
                                            NULL, err, sizeof err),
                         SUNMC_OK);
        assert_near(copied.after_mean, res[0].rms_after[b->angle][b->band], 0);
        free(b);
        config_state_free(&st);
    }
}

static void cli(void **state)
{
    char out[16384], cmd[4096];
    const char *dir = test_tmp("budget");
    const char *bad[] = {"", "configs/ess_type_a.ini --units 2:5",
                         "configs/ess_type_a.ini --set report.yield_target=2",
                         "configs/ess_type_a.ini --set report.budget_units=x",
                         "configs/ess_type_a.ini --bogus"};
    test_refused("budget", bad, sizeof bad / sizeof bad[0], dir);
    /* A small real budget: table, budget.tsv with the floor, 12 + 3 ranked
     * rows and the interaction, whose shares sum to 100 %. */
    snprintf(cmd, sizeof cmd,
             "%s budget configs/ess_type_a.ini --units 10 --set report.budget_units=10 "
             "--set report.budget_steps=1 --set validation.alpha_step_deg=2.3 "
             "--set campaign.beta_deg=0 --out %s --quiet",
             test_sunmc(), dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "inverse limit"));
    assert_non_null(strstr(out, "FLOOR"));
    assert_non_null(strstr(out, "INTERACTION"));
    assert_non_null(strstr(out, " unit runs (each inverse limit's yield at today's value"));
    snprintf(cmd, sizeof cmd, "test $(awk -F'\\t' 'NR>1 && $1>0' %s/budget.tsv | wc -l) -eq 16",
             dir);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd,
             "awk -F'\\t' 'NR==2 && $3==\"FLOOR\" {ok=1} $3==\"INTERACTION\" {ok2=NR} "
             "$2==\"after_part\" {np++; sp+=$13; next} "
             "NR>1 {sb+=$9; sa+=$13} END {exit !(ok && ok2==NR-3 && np==3 && sb>0.999999 && "
             "sb<1.000001 && sa>0.999999 && sa<1.000001 && sp>0.999999 && sp<1.000001)}' "
             "%s/budget.tsv",
             dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sources_of_type_a),
        cmocka_unit_test(no_source_is_an_error),
        cmocka_unit_test(alone_matches_closed_form),
        cmocka_unit_test(inverse_limit_end_states),
        cmocka_unit_test(today_from_all_sources_run),
        cmocka_unit_test(floor_units_are_one_unit),
        cmocka_unit_test(limits_independent_of_threads),
        cmocka_unit_test(cli),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
