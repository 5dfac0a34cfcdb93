/* test_modelform.c - issue 38: what calibration leaves, named.  The
 * model-form part of a unit (modelform.h) is the after-RMS of the same unit
 * calibrated on a noise-free campaign and read without noise: checked
 * against a separate run of a config whose every noise key the test sets to
 * 0 itself (every family), against the identities of the split (no noise:
 * model form = after = systematic, shares 0, 0, 1), on the units it is due
 * (unit mod N = 0) and nowhere else, the same in any thread count and unit
 * range, and the streaming ratio against stats_ratio_t. */
#include "test_util.h"

#include "budget.h"
#include "config.h"
#include "family.h"
#include "modelform.h"
#include "montecarlo.h"
#include "report.h"
#include "stats.h"
#include "status.h"

#include <math.h>
#include <string.h>

#define UNITS 12

static void build(config_state *st, const char *path, const char *const *sets, int n)
{
    char err[SUNMC_ERRLEN];
    if (config_build(st, path, sets, n, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
}

static void run(const sunmc_config *c, long first, long end, int threads, unit_result *res)
{
    char err[SUNMC_ERRLEN];
    if (mc_run(c, first, end, threads, res, NULL, NULL, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
}

/* Each family's shipped config with small grids, and its noise keys as
 * the test knows them (not read from the family's table). */
static const struct {
    const char *config;
    const char *small[4];
    const char *noise_off[5];
} fams[] = {
    {"configs/ess_type_a.ini",
     {"campaign.alpha_step_deg=0.4", "validation.alpha_step_deg=0.9", NULL},
     {"noise.row_current_pct=0", "noise.encoder_arcsec=0", "calibration.roll_sigma_arcsec=0",
      NULL}},
    {"configs/dss.ini",
     {"campaign.b_step_deg=10", NULL},
     {"noise.centroid_px=0", "noise.encoder_arcsec=0", "calibration.sun_sigma_arcsec=0", NULL}},
    {"configs/psd.ini", {NULL}, {"noise.channel_pct=0", "noise.lamp_pct=0", NULL}},
};

/* The model-form part of a due unit equals the after-RMS of the same unit
 * of a config the test made noise-free itself; the other units have none. */
static void test_mf_is_the_noise_free_run(void **state)
{
    for (size_t f = 0; f < sizeof fams / sizeof fams[0]; f++) {
        const char *sets[16];
        int ns = 0;
        for (int i = 0; fams[f].small[i]; i++)
            sets[ns++] = fams[f].small[i];
        sets[ns++] = "report.model_form_every=5";
        config_state st, quiet;
        build(&st, fams[f].config, sets, ns);
        for (int i = 0; fams[f].noise_off[i]; i++)
            sets[ns++] = fams[f].noise_off[i];
        build(&quiet, fams[f].config, sets, ns);
        unit_result *a = calloc(UNITS, sizeof *a), *q = calloc(UNITS, sizeof *q);
        run(&st.cfg, 0, UNITS, 2, a);
        run(&quiet.cfg, 0, UNITS, 2, q);
        int na = st.cfg.family->n_angles(&st.cfg), nb = st.cfg.bands_deg.n, seen = 0;
        for (long u = 0; u < UNITS; u++)
            for (int an = 0; an < na; an++)
                for (int b = 0; b < nb; b++) {
                    double mf = a[u].rms_after_mf[an][b];
                    if (u % 5 != 0) {
                        assert_true(isnan(mf));
                        continue;
                    }
                    double want = q[u].rms_after[an][b];
                    if (!(fabs(mf - want) <= 1e-12 * fabs(want)))
                        fail_msg("%s unit %ld angle %d band %d: model form %.12g, the noise-free "
                                 "run %.12g",
                                 fams[f].config, u, an, b, mf, want);
                    /* noise-free: the systematic part of the quiet run too */
                    assert_true(fabs(q[u].rms_after_sys[an][b] - want) <= 1e-9 * fabs(want));
                    seen++;
                }
        assert_int_equal(seen, 3 * na * nb); /* units 0, 5, 10 */
        free(a);
        free(q);
        config_state_free(&st);
        config_state_free(&quiet);
    }
}

/* No noise at all: model form = after = systematic, so the after mean
 * square is model form alone (shares 0, 0, 1; the first two exactly 0). */
static void test_no_noise_is_all_model_form(void **state)
{
    const char *sets[8] = {"report.model_form_every=1", "noise.centroid_px=0",
                           "noise.encoder_arcsec=0", "campaign.b_step_deg=10"};
    config_state st;
    build(&st, "configs/dss.ini", sets, 4);
    unit_result *r = calloc(UNITS, sizeof *r);
    run(&st.cfg, 0, UNITS, 1, r);
    int nrow = report_n_rows(&st.cfg);
    summary_row *rows = calloc((size_t)nrow, sizeof *rows);
    assert_int_equal(report_summarize(&st.cfg, r, UNITS, rows), SUNMC_OK);
    for (int i = 0; i < nrow; i++) {
        assert_int_equal(rows[i].mf_units, UNITS);
        /* the noisy path with zero noise and the noise-free path round
         * differently at the last bits (the glass ghost's and the disc's
         * sums): 1e-9 of the mean square */
        assert_near(rows[i].share_noise, 0.0, 1e-9);
        assert_near(rows[i].share_estimation, 0.0, 1e-9);
        assert_near(rows[i].share_model_form, 1.0, 1e-9);
        assert_near(rows[i].rms_after_mf_mean, rows[i].rms_after_mean,
                    1e-9 * rows[i].rms_after_mean);
    }
    free(rows);
    free(r);
    config_state_free(&st);
}

/* With noise: the three shares sum to 1, each inside 0..1 here, and the
 * model-form share is the ratio of the units' mf^2 to after^2 sums. */
static void test_shares_add_up(void **state)
{
    const char *sets[] = {"report.model_form_every=2", "campaign.b_step_deg=10"};
    config_state st;
    build(&st, "configs/dss.ini", sets, 2);
    unit_result *r = calloc(UNITS, sizeof *r);
    run(&st.cfg, 0, UNITS, 2, r);
    int nrow = report_n_rows(&st.cfg);
    summary_row *rows = calloc((size_t)nrow, sizeof *rows);
    assert_int_equal(report_summarize(&st.cfg, r, UNITS, rows), SUNMC_OK);
    for (int i = 0; i < nrow; i++) {
        const summary_row *w = &rows[i];
        assert_int_equal(w->mf_units, UNITS / 2);
        assert_near(w->share_noise + w->share_estimation + w->share_model_form, 1.0, 1e-12);
        double m2 = 0, a2 = 0;
        for (long u = 0; u < UNITS; u += 2) {
            double mf = r[u].rms_after_mf[w->angle][w->band], af = r[u].rms_after[w->angle][w->band];
            m2 += mf * mf;
            a2 += af * af;
        }
        assert_near(w->share_model_form, m2 / a2, 1e-12);
        assert_true(w->share_noise > 0.5); /* the shipped DSS: noise dominates */
        assert_true(w->share_model_form_ci.lo <= w->share_model_form &&
                    w->share_model_form <= w->share_model_form_ci.hi);
    }
    free(rows);
    free(r);
    config_state_free(&st);
}

/* Off: every N = 0, and whenever the caller reads no systematic part. */
static void test_off(void **state)
{
    const char *sets[] = {"report.model_form_every=0", "campaign.b_step_deg=10"};
    config_state st;
    build(&st, "configs/dss.ini", sets, 2);
    assert_false(modelform_on(&st.cfg));
    assert_false(modelform_due(&st.cfg, 0));
    unit_result r[2];
    run(&st.cfg, 0, 2, 1, r);
    assert_true(isnan(r[0].rms_after_mf[2][0]));
    st.cfg.model_form_every = 1;
    assert_true(modelform_due(&st.cfg, 1));
    st.cfg.no_systematic = 1;
    assert_false(modelform_due(&st.cfg, 0));
    run(&st.cfg, 0, 2, 1, r);
    assert_true(isnan(r[0].rms_after_mf[2][0]));
    st.cfg.no_systematic = 0;
    st.cfg.model_form_every = 3; /* both sides of the modulus */
    assert_true(modelform_due(&st.cfg, 3));
    assert_false(modelform_due(&st.cfg, 2));
    assert_false(modelform_due(&st.cfg, 4));
    config_state_free(&st);
}

/* The same bits in any thread count and unit range. */
static void test_deterministic(void **state)
{
    const char *sets[] = {"report.model_form_every=3", "campaign.b_step_deg=10"};
    config_state st;
    build(&st, "configs/dss.ini", sets, 2);
    unit_result *a = calloc(UNITS, sizeof *a), *b = calloc(UNITS, sizeof *b);
    run(&st.cfg, 0, UNITS, 1, a);
    run(&st.cfg, 0, 5, 2, b);
    run(&st.cfg, 5, UNITS, 2, b + 5);
    for (long u = 0; u < UNITS; u++)
        assert_memory_equal(a[u].rms_after_mf, b[u].rms_after_mf, sizeof a[u].rms_after_mf);
    free(a);
    free(b);
    config_state_free(&st);
}

/* The streaming ratio equals stats_ratio_t on the same pairs. */
static void test_ratio_acc(void **state)
{
    double x[7] = {1.0, 2.5, -0.3, 4.0, 2.2, 0.7, 3.1}, a[7] = {2.0, 3.0, 1.5, 5.0, 2.5, 1.2, 4.4};
    for (size_t n = 0; n <= 7; n++) {
        stats_ratio_acc acc = {0};
        for (size_t i = 0; i < n; i++)
            stats_ratio_acc_add(&acc, x[i], a[i]);
        double r1, r2;
        stats_interval c1, c2;
        char err[SUNMC_ERRLEN];
        assert_int_equal(stats_ratio_t(x, a, n, 0.95, &r1, &c1, err, sizeof err), SUNMC_OK);
        assert_int_equal(stats_ratio_acc_t(&acc, 0.95, &r2, &c2, err, sizeof err), SUNMC_OK);
        if (n == 0) {
            assert_true(isnan(r1) && isnan(r2));
            continue;
        }
        assert_near(r2, r1, 1e-13);
        if (n < 2) {
            assert_true(isnan(c2.lo) && isnan(c2.hi));
            continue;
        }
        assert_near(c2.lo, c1.lo, 1e-12);
        assert_near(c2.hi, c1.hi, 1e-12);
    }
}

/* The budget's parts over every unit equal a run's shares with the pass on
 * every unit (the same units, the same config). */
static void test_budget_parts_match_the_run(void **state)
{
    const char *sets[] = {"campaign.b_step_deg=10", "report.budget_units=10",
                          "report.budget_steps=1"};
    config_state st;
    build(&st, "configs/dss.ini", sets, 3);
    budget_result *b = calloc(1, sizeof *b);
    char err[SUNMC_ERRLEN];
    assert_int_equal(budget_run(&st.cfg, UNITS, 2, 0, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->part_units, UNITS);
    st.cfg.model_form_every = 1;
    unit_result *r = calloc(UNITS, sizeof *r);
    run(&st.cfg, 0, UNITS, 2, r);
    int nrow = report_n_rows(&st.cfg);
    summary_row *rows = calloc((size_t)nrow, sizeof *rows);
    assert_int_equal(report_summarize(&st.cfg, r, UNITS, rows), SUNMC_OK);
    const summary_row *w = &rows[report_primary_row(&st.cfg, b->angle, b->band)];
    assert_near(b->part_after[BUDGET_PART_NOISE].v, w->share_noise, 1e-9);
    assert_near(b->part_after[BUDGET_PART_ESTIMATION].v, w->share_estimation, 1e-9);
    assert_near(b->part_after[BUDGET_PART_MODEL_FORM].v, w->share_model_form, 1e-9);
    free(rows);
    free(r);
    free(b);
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mf_is_the_noise_free_run),
        cmocka_unit_test(test_no_noise_is_all_model_form),
        cmocka_unit_test(test_shares_add_up),
        cmocka_unit_test(test_off),
        cmocka_unit_test(test_deterministic),
        cmocka_unit_test(test_ratio_acc),
        cmocka_unit_test(test_budget_parts_match_the_run),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
