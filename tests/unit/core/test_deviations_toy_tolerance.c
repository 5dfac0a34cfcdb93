/* test_deviations_toy_tolerance.c - "adding a tolerance is one line plus its physics":
 * the toy family's bow (tests/toy_family.h: one line of TOY_DEVIATIONS,
 * its field, and + bow alpha^2 in toy_read_rad) reaches, with no other
 * code, the sampling (its own stream, units.tsv), the curve's mirror unit
 * (deviations_scale), the budget (a source of its own) and the lab
 * prediction (lab_predict.c), each checked against the closed form of a
 * reading error bow * alpha^2. */
#include "test_util.h"

#include "budget.h"
#include "report.h"
#include "dss_unit.h"
#include "lab.h"
#include "montecarlo.h"
#include "registry.h"
#include "status.h"
#include "toy_family.h"
#include "units.h"

#define BOW_ARCSEC 30.0

static char dir[] = "/tmp/sunmc_test_toy_tol_XXXXXX";
static char ini[300];

static int setup(void **state)
{
    if (sensor_family_register(&toy_family) != 0 || !mkdtemp(dir))
        return -1;
    snprintf(ini, sizeof ini, "%s/toy.ini", dir);
    return test_write_file(ini, "[sensor]\nfamily = toy\n");
}

static int teardown(void **state)
{
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd);
}

static void build(config_state *st, const char *const *sets, int n)
{
    test_build(st, ini, sets, n);
}

/* The column of the bow in unit_result.dev. */
static int bow_column(const sunmc_config *c)
{
    const char *names[UNIT_MAX_DEV];
    int n = c->family->dev_columns(c, names, UNIT_MAX_DEV);
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], "bow_arcsec") == 0)
            return i;
    fail_msg("no bow_arcsec column");
    return -1;
}

/* Sampling: drawn uniformly within +-30 from its own stream; the other
 * tolerances' draws are the same bits with or without it. */
static void sampling_draws_it(void **state)
{
    const char *with[] = {"tolerance.bow_arcsec=30"};
    config_state a, b;
    build(&a, NULL, 0);
    build(&b, with, 1);
    enum { N = 200 };
    unit_result *ra = calloc(N, sizeof *ra), *rb = calloc(N, sizeof *rb);
    char err[SUNMC_ERRLEN];
    assert_int_equal(mc_run(&a.cfg, 0, N, 1, ra, NULL, NULL, err, sizeof err), 0);
    assert_int_equal(mc_run(&b.cfg, 0, N, 1, rb, NULL, NULL, err, sizeof err), 0);
    int k = bow_column(&b.cfg);
    double lo = INFINITY, hi = -INFINITY, s = 0, s2 = 0;
    for (int u = 0; u < N; u++) {
        double v = rb[u].dev[k];
        lo = fmin(lo, v);
        hi = fmax(hi, v);
        s += v;
        s2 += v * v;
        assert_true(ra[u].dev[k] == 0);
        for (int j = 0; j < k; j++)
            assert_true(ra[u].dev[j] == rb[u].dev[j]);
    }
    assert_true(lo >= -BOW_ARCSEC && hi <= BOW_ARCSEC);
    assert_true(lo < -0.9 * BOW_ARCSEC && hi > 0.9 * BOW_ARCSEC);
    /* uniform on +-30: variance 300, the sample's within 20 % at N = 200 */
    double var = s2 / N - (s / N) * (s / N);
    assert_true(fabs(var / (BOW_ARCSEC * BOW_ARCSEC / 3) - 1) < 0.2);
    free(ra);
    free(rb);
    config_state_free(&a);
    config_state_free(&b);
}

/* Curve: the unit with a fixed bow errs by +bow a^2 before calibration,
 * its mirror (dev_sign -1) by -bow a^2. */
static void curve_mirrors_it(void **state)
{
    const char *sets[] = {"tolerance.bow_arcsec=30", "tolerance.bow_arcsec_dist=fixed",
                          "tolerance.scale_pct=0", "tolerance.offset_arcsec=0"};
    config_state st;
    build(&st, sets, 4);
    const sensor_family *f = st.cfg.family;
    char err[SUNMC_ERRLEN];
    void *cv = f->curve->alloc(&st.cfg, err, sizeof err);
    assert_non_null(cv);
    for (int s = -1; s <= 1; s += 2) {
        int ok;
        assert_int_equal(f->curve->prepare(&st.cfg, 0, s, cv, &ok), SUNMC_OK);
        double before[UNIT_MAX_ANGLES], after[UNIT_MAX_ANGLES], a = 37 * RAD_PER_DEG;
        assert_int_equal(f->curve->eval(&st.cfg, cv, 37, 0, before, after), SUNMC_OK);
        assert_near(before[0], s * BOW_ARCSEC * a * a, 1e-9);
    }
    f->curve->free(cv);
    config_state_free(&st);
}

/* RMS over the validation grid's |alpha| <= 40 of bow a^2 (arcsec). */
static double bow_rms(const sunmc_config *c)
{
    double s2 = 0;
    long n = toy_val_count(c);
    for (long i = 0; i < n; i++) {
        double a = toy_val_alpha_deg(c, i) * RAD_PER_DEG;
        s2 += pow(BOW_ARCSEC * a * a, 2);
    }
    return sqrt(s2 / (double)n);
}

/* Budget: a source of its own, whose before-RMS alone is the closed form. */
static void budget_ranks_it(void **state)
{
    const char *sets[] = {"tolerance.bow_arcsec=30", "tolerance.bow_arcsec_dist=fixed"};
    config_state st;
    build(&st, sets, 2);
    budget_result *b = calloc(1, sizeof *b);
    char err[SUNMC_ERRLEN];
    assert_int_equal(budget_run(&st.cfg, STUDY_MIN_UNITS, 1, 0, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->n, 3);
    assert_string_equal(b->src[2].name, "bow_arcsec");
    assert_near(b->src[2].alone.before_mean, bow_rms(&st.cfg), 1e-9);
    free(b);
    config_state_free(&st);
}

/* Lab prediction: the nominal unit reads alpha; the spread allowed grows
 * by exactly the bow's reach times a^2, and a scale of 2 % adds 2 % of
 * |alpha| (each alone: the envelope is exact for one tolerance). */
static void lab_prediction_sees_it(void **state)
{
    const char *none[] = {"tolerance.scale_pct=0", "tolerance.offset_arcsec=0"};
    const char *bow[] = {"tolerance.scale_pct=0", "tolerance.offset_arcsec=0",
                         "tolerance.bow_arcsec=30"};
    const char *scale[] = {"tolerance.scale_pct=2", "tolerance.offset_arcsec=0"};
    const char *const *sets[] = {none, bow, scale};
    double in[1] = {-33}, a = in[0] * RAD_PER_DEG, margin = 0;
    for (int k = 0; k < 3; k++) {
        config_state st;
        build(&st, sets[k], 2 + (k == 1));
        char err[SUNMC_ERRLEN];
        lab_predictor *p = lab_predict_alloc(st.cfg.family->lab, &st.cfg, err, sizeof err);
        assert_non_null(p);
        double out[LAB_MAX_COLUMNS], allowed[LAB_MAX_COLUMNS];
        assert_int_equal(lab_predict(p, in, out, allowed), SUNMC_OK);
        assert_near(out[0], in[0], 1e-12);
        if (k == 0)
            margin = allowed[0];
        double want = k == 0 ? margin
                    : k == 1 ? margin + BOW_ARCSEC * a * a / ARCSEC_PER_DEG
                             : margin + 0.02 * fabs(in[0]);
        assert_near(allowed[0], want, 1e-12);
        lab_predict_free(p);
        config_state_free(&st);
    }
    assert_true(margin > 0);
}

/* A built-in family (the DSS) with one tolerance, the glass index, whose
 * spot moves unequally at its two ends: the envelope is the larger of the
 * two changes, read here from the units built directly. */
static void built_in_envelope_both_ends(void **state)
{
    const sensor_family *f = sensor_family_find("dss");
    assert_non_null(f);
    char sets_buf[24][80];
    const char *sets[24];
    int n = 0;
    for (int e = 0; e < f->n_deviations; e++) {
        snprintf(sets_buf[n], sizeof sets_buf[n], "tolerance.%s=%s", f->deviations[e].name,
                 strcmp(f->deviations[e].name, "glass_index") == 0 ? "0.3" : "0");
        sets[n] = sets_buf[n];
        n++;
    }
    config_state st;
    char err[SUNMC_ERRLEN];
    if (config_build(&st, "configs/dss.ini", sets, n, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    lab_predictor *p = lab_predict_alloc(f->lab, &st.cfg, err, sizeof err);
    assert_non_null(p);
    double in[2] = {40, -35}, out[LAB_MAX_COLUMNS], allowed[LAB_MAX_COLUMNS];
    assert_int_equal(lab_predict(p, in, out, allowed), SUNMC_OK);
    double spot[3][2];
    for (int k = 0; k < 3; k++) {
        dss_deviations dev;
        memset(&dev, 0, sizeof dev);
        dev.glass_index = (k - 1) * 0.3;
        dss_unit u;
        dss_unit_build(&st.cfg, &dev, &u);
        assert_int_equal(dss_sensor_read(&u.sensor, in[0] * RAD_PER_DEG, in[1] * RAD_PER_DEG,
                                         NULL, &spot[k][0], &spot[k][1]),
                         SUNMC_OK);
    }
    for (int j = 0; j < 2; j++) {
        double lo = fabs(spot[0][j] - spot[1][j]), hi = fabs(spot[2][j] - spot[1][j]);
        assert_true(fabs(lo - hi) > 1e-3); /* the two ends differ */
        assert_near(out[j], spot[1][j], 1e-12);
        assert_near(allowed[j] - fmax(lo, hi), f->lab->cal_predict_margin[j], 1e-9);
    }
    lab_predict_free(p);
    config_state_free(&st);
}

/* A family without a lab prediction is told so. */
static void lab_prediction_refused_without_hooks(void **state)
{
    config_state st;
    build(&st, NULL, 0);
    family_lab none = {0};
    char err[SUNMC_ERRLEN] = "";
    assert_null(lab_predict_alloc(&none, &st.cfg, err, sizeof err));
    assert_non_null(strstr(err, "toy family has no lab prediction"));
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sampling_draws_it),
        cmocka_unit_test(curve_mirrors_it),
        cmocka_unit_test(budget_ranks_it),
        cmocka_unit_test(lab_prediction_sees_it),
        cmocka_unit_test(built_in_envelope_both_ends),
        cmocka_unit_test(lab_prediction_refused_without_hooks),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
