/* test_sensitivity.c - `sunmc sensitivity`: the random inputs of each
 * family, the pick-freeze draws (input i from B, every other from A), a
 * single input's indices (S1 = ST = 1 by the estimators' definitions), the
 * indices of type A within [0, 1] and ST >= S1 within their intervals, the
 * result independent of the thread count, and the command's errors and
 * output. */
#include "test_util.h"

#include "ess_sensor.h"
#include "montecarlo.h"
#include "sensitivity.h"
#include "status.h"

/* One band, 0:62 (the budget's row is band 0 of the one angle). */
static const char *const small_sets[] = {"campaign.alpha_step_deg=0.4", "campaign.beta_deg=0",
                                         "validation.alpha_step_deg=1.3",
                                         "report.bands_deg=0:62"};

static void inputs_of_each_family(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    sens_result *s = calloc(1, sizeof *s);
    test_build(&st, "configs/ess_type_a.ini", NULL, 0);
    assert_int_equal(sens_sources(&st.cfg, s, err, sizeof err), SUNMC_OK);
    assert_int_equal(s->n, 13 + 3); /* every tolerance (uniform), three noise streams */
    assert_string_equal(s->src[0].name, "dH_um");
    assert_int_equal(s->src[0].kind, SENS_TOLERANCE);
    assert_string_equal(s->src[13].name, "campaign_noise");
    assert_int_equal(s->src[13].stream, RNG_STREAM_CAL_NOISE);
    assert_non_null(strstr(s->src[13].keys, "noise.encoder_arcsec"));
    assert_string_equal(s->src[14].name, "validation_noise");
    assert_string_equal(s->src[15].name, "roll_measurement");
    config_state_free(&st);
    /* a fixed tolerance does not vary; a noise stream at 0 is no input */
    const char *sets[] = {"tolerance.dH_um_dist=fixed", "calibration.roll_sigma_arcsec=0"};
    test_build(&st, "configs/ess_type_a.ini", sets, 2);
    assert_int_equal(sens_sources(&st.cfg, s, err, sizeof err), SUNMC_OK);
    assert_int_equal(s->n, 12 + 2);
    assert_string_equal(s->src[0].name, "dd_um");
    config_state_free(&st);
    test_build(&st, "configs/dss.ini", NULL, 0);
    assert_int_equal(sens_sources(&st.cfg, s, err, sizeof err), SUNMC_OK);
    assert_string_equal(s->src[s->n - 2].name, "campaign_noise");
    assert_string_equal(s->src[s->n - 1].name, "validation_noise");
    assert_int_equal(s->angle, 2); /* DSS: the total angle */
    config_state_free(&st);
    free(s);
}

/* A_B^(i) draws input i from B's seed and every other input from A's. */
static void pick_freeze_draws(void **state)
{
    config_state st;
    test_build(&st, "configs/ess_type_a.ini", NULL, 0);
    sunmc_config a = st.cfg, b = st.cfg, ab = st.cfg;
    b.seed = a.seed ^ SENS_SEED_B_XOR;
    ab.pick.seed = b.seed;
    ab.pick.n = 1;
    ab.pick.stream[0] = RNG_STREAM_TOLERANCE + ess_deviation_list[1].stream; /* dd_um */
    for (long u = 0; u < 5; u++) {
        ess_deviations da, db, dab;
        ess_deviations_sample(&a, (uint64_t)a.seed, u, &da);
        ess_deviations_sample(&b, (uint64_t)b.seed, u, &db);
        ess_deviations_sample(&ab, (uint64_t)ab.seed, u, &dab);
        assert_true(dab.dd_um == db.dd_um && da.dd_um != db.dd_um);
        assert_true(dab.dH_um == da.dH_um && dab.gain_pct[2] == da.gain_pct[2]);
        assert_true(dab.roll_measured_arcsec - dab.install_x_arcsec ==
                    da.roll_measured_arcsec - da.install_x_arcsec);
    }
    /* the roll measurement's stream alone */
    ab.pick.stream[0] = RNG_STREAM_ALIGNMENT;
    ess_deviations da, db, dab;
    ess_deviations_sample(&a, (uint64_t)a.seed, 3, &da);
    ess_deviations_sample(&b, (uint64_t)b.seed, 3, &db);
    ess_deviations_sample(&ab, (uint64_t)ab.seed, 3, &dab);
    assert_true(dab.install_x_arcsec == da.install_x_arcsec);
    assert_near(dab.roll_measured_arcsec - dab.install_x_arcsec,
                db.roll_measured_arcsec - db.install_x_arcsec, 1e-12);
    config_state_free(&st);
}

/* One input only (dH, noise-free): A_B^(1) is B itself, so both indices
 * estimate Var(Y) / Var(Y) = 1: Jansen's ST = sum (fA - fB)^2 / (2 n V),
 * Saltelli's S1 = sum (fB - f0) (fB - fA) / (n V).  Their intervals must
 * hold 1. */
static void single_input(void **state)
{
    const char *sets[] = {"campaign.alpha_step_deg=0.4", "campaign.beta_deg=0",
                          "validation.alpha_step_deg=1.3", "noise.row_current_pct=0",
                          "noise.encoder_arcsec=0", "calibration.roll_sigma_arcsec=0",
                          "tolerance.dd_um=0", "tolerance.dphi_deg=0",
                          "tolerance.slit_width_um=0", "tolerance.harmonic_phase_deg=0",
                          "tolerance.gain_pct=0", "tolerance.etch_um=0",
                          "tolerance.install_x_arcsec=0", "tolerance.install_y_arcsec=0",
                          "tolerance.install_z_arcsec=0", "tolerance.sun_x_arcsec=0",
                          "tolerance.sun_y_arcsec=0", "tolerance.dial_tilt_deg=0"};
    config_state st;
    test_build(&st, "configs/ess_type_a.ini", sets, (int)(sizeof sets / sizeof sets[0]));
    sens_result *s = calloc(1, sizeof *s);
    char err[SUNMC_ERRLEN];
    assert_int_equal(sens_run(&st.cfg, 100, 1, NULL, NULL, s, err, sizeof err), SUNMC_OK);
    assert_int_equal(s->n, 1);
    const stats_sobol_index *x = &s->src[0].before;
    print_message("dH alone: S1 %.4f [%.4f, %.4f], ST %.4f [%.4f, %.4f]\n", x->s1, x->s1_lo,
                  x->s1_hi, x->st, x->st_lo, x->st_hi);
    assert_true(x->s1_lo <= 1.0 && 1.0 <= x->s1_hi);
    assert_true(x->st_lo <= 1.0 && 1.0 <= x->st_hi);
    assert_near(x->s1, 1.0, 0.3);
    assert_near(x->st, 1.0, 0.3);
    free(s);
    config_state_free(&st);
}

/* Type A, small: indices in [0, 1] within their intervals and ST >= S1
 * within theirs -- for at least 90 % of the 4 x 16 x 2 intervals (a 95 %
 * interval misses its bound now and then: an input of no effect has its S1
 * interval just below 0 one time in 40), and every miss by less than 0.01;
 * the same bytes on 1 and 2 threads. */
static int misses(double lo, double hi, double lo_bound, double hi_bound, double *worst)
{
    double over = fmax(lo - hi_bound, lo_bound - hi);
    *worst = fmax(*worst, over);
    return over > 0;
}

static void type_a_indices_and_threads(void **state)
{
    config_state st;
    test_build(&st, "configs/ess_type_a.ini", small_sets, 4);
    sens_result *s1 = calloc(1, sizeof *s1), *s2 = calloc(1, sizeof *s2);
    char err[SUNMC_ERRLEN];
    assert_int_equal(sens_run(&st.cfg, 48, 1, NULL, NULL, s1, err, sizeof err), SUNMC_OK);
    assert_int_equal(sens_run(&st.cfg, 48, 2, NULL, NULL, s2, err, sizeof err), SUNMC_OK);
    assert_memory_equal(s1, s2, sizeof *s1);
    assert_int_equal(s1->n, 16);
    /* campaign_noise and roll_measurement finished from A's readings */
    assert_int_equal(s1->reused_units, 2 * 48);
    /* Two inputs' total index after calibration recomputed here from three
     * Monte Carlos: A (run.seed), B (the other seed), A with the input's
     * stream from B; Jansen's formula over the variance of A and B. */
    const int check[2] = {0, 13}; /* dH_um, campaign_noise */
    for (int k = 0; k < 2; k++) {
        const sens_source *src = &s1->src[check[k]];
        sunmc_config a = st.cfg, b = st.cfg, ab = st.cfg;
        b.seed = a.seed ^ SENS_SEED_B_XOR;
        ab.pick.seed = b.seed;
        ab.pick.n = 1;
        ab.pick.stream[0] = src->stream;
        const sunmc_config *cs[3] = {&a, &b, &ab};
        static unit_result res[3][48];
        for (int r = 0; r < 3; r++)
            assert_int_equal(mc_run(cs[r], 0, 48, 1, res[r], NULL, NULL, err,
                                    sizeof err),
                             SUNMC_OK);
        double m = 0, v = 0, sq = 0;
        for (int u = 0; u < 48; u++)
            m += res[0][u].rms_after[0][0] + res[1][u].rms_after[0][0];
        m /= 96;
        for (int u = 0; u < 48; u++) {
            double fa = res[0][u].rms_after[0][0], fb = res[1][u].rms_after[0][0];
            double fab = res[2][u].rms_after[0][0];
            v += (fa - m) * (fa - m) + (fb - m) * (fb - m);
            sq += (fa - fab) * (fa - fab);
        }
        v /= 96;
        assert_near(src->after.st, 0.5 * sq / 48 / v, 1e-9);
    }
    int miss = 0, total = 0;
    double worst = 0;
    for (int i = 0; i < s1->n; i++)
        for (int w = 0; w < 2; w++) {
            const stats_sobol_index *x = w ? &s1->src[i].after : &s1->src[i].before;
            assert_true(x->s1_lo <= x->s1 && x->s1 <= x->s1_hi);
            assert_true(x->st_lo <= x->st && x->st <= x->st_hi);
            assert_true(x->st >= 0.0); /* Jansen's ST is a mean of squares */
            /* and above 0 after calibration for every input: redrawing one
             * input's stream alone moves some unit's result, so each
             * purpose draws from a stream of its own (were the validation
             * noise drawn from the campaign's stream, its ST would be 0) */
            if (w && !(x->st > 0.0))
                fail_msg("input %s: redrawing its stream alone changed no unit (ST = %g)",
                         s1->src[i].name, x->st);
            miss += misses(x->s1_lo, x->s1_hi, 0.0, 1.0, &worst);
            miss += misses(x->st_lo, x->st_hi, 0.0, 1.0, &worst);
            miss += misses(x->s1_lo, x->s1_lo, -INFINITY, x->st_hi, &worst); /* ST >= S1 */
            total += 3;
        }
    print_message("intervals missing [0, 1] or ST >= S1: %d of %d, worst by %.2g\n", miss, total,
                  worst);
    assert_true(miss <= total / 10);
    assert_true(worst < 0.01);
    free(s1);
    free(s2);
    config_state_free(&st);
}

static void errors_and_output(void **state)
{
    char out[1 << 15], cmd[4096];
    const char *dir = test_tmp("sens");
    const char *bad[] = {"", "configs/ess_type_a.ini --units 2:5",
                         "configs/ess_type_a.ini --units 1",
                         "configs/ess_type_a.ini --set tolerance.dH_um=x",
                         "configs/ess_type_a.ini --bogus"};
    test_refused("sensitivity", bad, sizeof bad / sizeof bad[0], dir);
    /* no random input at all */
    config_state st;
    const char *none[] = {"noise.row_current_pct=0", "noise.encoder_arcsec=0",
                          "calibration.roll_sigma_arcsec=0", "tolerance.dH_um_dist=fixed",
                          "tolerance.dd_um=0", "tolerance.dphi_deg=0", "tolerance.slit_width_um=0",
                          "tolerance.harmonic_phase_deg=0", "tolerance.gain_pct=0",
                          "tolerance.etch_um=0", "tolerance.install_x_arcsec=0",
                          "tolerance.install_y_arcsec=0", "tolerance.install_z_arcsec=0",
                          "tolerance.sun_x_arcsec=0", "tolerance.sun_y_arcsec=0",
                          "tolerance.dial_tilt_deg=0"};
    test_build(&st, "configs/ess_type_a.ini", none, (int)(sizeof none / sizeof none[0]));
    sens_result *s = calloc(1, sizeof *s);
    char err[SUNMC_ERRLEN];
    assert_int_equal(sens_run(&st.cfg, 10, 1, NULL, NULL, s, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "no random input varies"));
    free(s);
    config_state_free(&st);
    /* a small real one: table, sensitivity.tsv with both RMS, every input */
    snprintf(cmd, sizeof cmd,
             "%s sensitivity configs/ess_type_a.ini --units 12 --set validation.alpha_step_deg=2.3 "
             "--set campaign.beta_deg=0 --out %s --quiet",
             test_sunmc(), dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "Sobol indices"));
    snprintf(cmd, sizeof cmd,
             "awk -F'\\t' 'NR==1 && $1==\"rms\" && $2==\"source\" && $5==\"S1\" && $6==\"S1_ci_lo\" "
             "&& $7==\"S1_ci_hi\" && $8==\"ST\" && $9==\"ST_ci_lo\" && $10==\"ST_ci_hi\" {h=1} "
             "$1==\"before\" {b++} $1==\"after\" {a++} END {exit !(h && a==16 && b==16)}' "
             "%s/sensitivity.tsv",
             dir);
    assert_int_equal(system(cmd), 0);
}

/* The widest half-width of stat over s's inputs, from the definitions. */
static double widest_of(const sens_result *s, int stat)
{
    double w = 0;
    for (int i = 0; i < s->n; i++) {
        int after = stat == SENS_UNTIL_ST || stat == SENS_UNTIL_S1;
        const stats_sobol_index *x = after ? &s->src[i].after : &s->src[i].before;
        double h = stat == SENS_UNTIL_ST || stat == SENS_UNTIL_ST_BEFORE ? (x->st_hi - x->st_lo) / 2
                                                                         : (x->s1_hi - x->s1_lo) / 2;
        w = fmax(w, h);
    }
    return w;
}

/* --until: blocks of 16 units; a target met at the first check stops there,
 * one never met runs every unit (the last block partial); either way the
 * result is the same bytes as a fixed run of the units taken; the check is
 * "half-width <= target", on both sides of it; each statistic is its own
 * intervals' widest half-width. */
static void until_stops_as_a_fixed_run(void **state)
{
    config_state st;
    test_build(&st, "configs/ess_type_a.ini", small_sets, 4);
    sens_result *s = calloc(1, sizeof *s), *f = calloc(1, sizeof *f);
    char err[SUNMC_ERRLEN];
    sens_until u = {SENS_UNTIL_ST, 10.0, 16, 0, 0};
    assert_int_equal(sens_run_until(&st.cfg, 40, &u, 2, NULL, NULL, s, err, sizeof err), SUNMC_OK);
    assert_int_equal(u.met, 1);
    assert_int_equal(s->units, 16);
    assert_int_equal(sens_run(&st.cfg, 16, 1, NULL, NULL, f, err, sizeof err), SUNMC_OK);
    assert_memory_equal(s, f, sizeof *s);
    assert_true(u.reached == widest_of(f, SENS_UNTIL_ST));
    double r16 = u.reached;
    /* never met: all 40 (16 + 16 + 8) */
    for (int stat = 0; stat < SENS_UNTIL_STATS; stat++) {
        sens_until v = {stat, 1e-9, 16, 0, 0};
        memset(s, 0, sizeof *s);
        assert_int_equal(sens_run_until(&st.cfg, 40, &v, 1, NULL, NULL, s, err, sizeof err),
                         SUNMC_OK);
        assert_int_equal(v.met, 0);
        assert_int_equal(s->units, 40);
        if (stat == 0) {
            memset(f, 0, sizeof *f);
            assert_int_equal(sens_run(&st.cfg, 40, 1, NULL, NULL, f, err, sizeof err), SUNMC_OK);
            assert_memory_equal(s, f, sizeof *s);
        }
        assert_true(v.reached == widest_of(s, stat));
        assert_true(v.reached > 0 && isfinite(v.reached));
    }
    /* the target exactly at the first check's half-width: met there; just
     * below it: not */
    sens_until at = {SENS_UNTIL_ST, r16, 16, 0, 0};
    assert_int_equal(sens_run_until(&st.cfg, 40, &at, 1, NULL, NULL, s, err, sizeof err), SUNMC_OK);
    assert_int_equal(s->units, 16);
    sens_until below = {SENS_UNTIL_ST, nextafter(r16, 0.0), 16, 0, 0};
    assert_int_equal(sens_run_until(&st.cfg, 40, &below, 1, NULL, NULL, s, err, sizeof err),
                     SUNMC_OK);
    assert_true(s->units > 16);
    /* refused: no half-width, no block, no such statistic */
    sens_until bad[] = {{SENS_UNTIL_ST, 0.0, 16, 0, 0}, {SENS_UNTIL_ST, 0.1, 0, 0, 0},
                        {SENS_UNTIL_STATS, 0.1, 16, 0, 0}, {-1, 0.1, 16, 0, 0}};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++)
        assert_int_equal(sens_run_until(&st.cfg, 40, &bad[k], 1, NULL, NULL, s, err, sizeof err),
                         SUNMC_EINPUT);
    free(s);
    free(f);
    config_state_free(&st);
}

/* --until on the command line: refused forms exit 2 writing nothing; a run
 * says whether it met the target, and config.ini notes it. */
static void until_cli(void **state)
{
    char out[1 << 15], cmd[4096];
    const char *dir = test_tmp("sens_until");
    const char *bad[] = {"configs/ess_type_a.ini --until st", "configs/ess_type_a.ini --until st:0",
                         "configs/ess_type_a.ini --until st:-0.1",
                         "configs/ess_type_a.ini --until sT:0.1",
                         "configs/ess_type_a.ini --until st:0.1x",
                         "configs/ess_type_a.ini --until :0.1"};
    test_refused("sensitivity", bad, sizeof bad / sizeof bad[0], dir);
    snprintf(cmd, sizeof cmd, "%s sensitivity configs/ess_type_a.ini --until st_bfore:0.1 --units 4",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "(did you mean st_before?)"));
    snprintf(cmd, sizeof cmd,
             "%s sensitivity configs/ess_type_a.ini --units 24 --set run.block_units=8 "
             "--set validation.alpha_step_deg=2.3 --set campaign.beta_deg=0 --until st:5 "
             "--out %s --quiet",
             test_sunmc(), dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "--until st:5: met after 16 units (widest half-width "));
    snprintf(cmd, sizeof cmd, "grep -q '^# --until st:5: met after 16 units' %s/config.ini && "
             "awk -F'\t' 'NR == 2 { exit !($16 == 16) }' %s/sensitivity.tsv", dir, dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(inputs_of_each_family),
        cmocka_unit_test(pick_freeze_draws),
        cmocka_unit_test(single_input),
        cmocka_unit_test(type_a_indices_and_threads),
        cmocka_unit_test(errors_and_output),
        cmocka_unit_test(until_stops_as_a_fixed_run),
        cmocka_unit_test(until_cli),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
