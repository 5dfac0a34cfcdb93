/* test_ess_spline.c - issue 39: the ESS's spline, table and hybrid models
 * (ess_spline.c) on noise-free data the paper model generates:
 *  - hybrid: the physics exact, its correction is zero (every coefficient
 *    below 1e-6 arcsec) and its angles the paper model's;
 *  - hybrid: with an extra ripple of the code the paper model lacks (a
 *    fine period's first harmonic, 20 arcsec) the correction takes most of
 *    it up;
 *  - spline and table on one beta line (beta = 0, where the true angle is
 *    a function of the raw one alone): their error within the stated
 *    bound, the table's node count chosen by the folds, a raw angle
 *    beyond the calibrated field refused with NaN;
 *  - spline on three beta lines: the 1-D spline cannot follow the
 *    incidence (its error well above the hybrid's). */
#include "test_ess_grid.h"
#include "test_util.h"

#include "ess_calib.h"
#include "ess_labfit.h"
#include "ess_model.h"
#include "status.h"
#include "units.h"

#define THETA0_RAD (2.0 * RAD_PER_DEG)

static void truth_model(ess_model *m)
{
    ess_model_init(m, THETA0_RAD, 0);
    m->p[ESS_P_A] = 1.0004;
    m->p[ESS_P_B] = -2.0e-4;
    m->p[ESS_P_C] = 1.0e-4;
    m->p[ESS_P_KS] = 3.0e-4;
    m->p[ESS_P_KC] = -2.0e-4;
    m->p[ESS_P_INST_Y] = 100 * RAD_PER_ARCSEC;
    m->p[ESS_P_INST_Z] = -60 * RAD_PER_ARCSEC;
    m->p[ESS_P_SUN_Y] = 30 * RAD_PER_ARCSEC;
    ess_model_prepare(m);
}

static const double beta0[] = {0}, betas3[] = {-20, 0, 20};

/* Readings of truth on cw's grid, plus ripple * sin(w1 alpha_raw). */
static void read_grid(ess_calib_workspace *cw, const ess_model *truth, double ripple_rad)
{
    for (size_t i = 0; i < cw->n; i++) {
        double r = ess_model_predict(truth, cw->alpha_rad[i], cw->beta_rad[i], NULL);
        cw->raw_rad[i] = r + ripple_rad * sin(2 * M_PI * r / THETA0_RAD);
    }
}

/* Largest |compensated - truth| (arcsec) of m over cw's points. */
static double worst_arcsec(const ess_calib_workspace *cw, const ess_model *m)
{
    double e = 0;
    for (size_t i = 0; i < cw->n; i++) {
        double x;
        assert_int_equal(ess_angle_error(m, cw->alpha_rad[i], cw->beta_rad[i], cw->raw_rad[i],
                                         &x),
                         SUNMC_OK);
        e = fmax(e, fabs(x) * ARCSEC_PER_RAD);
    }
    return e;
}

static void test_hybrid_zero_on_exact_physics(void **state)
{
    ess_model truth, fit;
    truth_model(&truth);
    ess_calib_workspace *cw = test_ess_grid(ESS_MODEL_HYBRID, 0.2, betas3, 3);
    read_grid(cw, &truth, 0);
    fit_result fr;
    assert_int_equal(ess_calibrate(cw, THETA0_RAD, 0, 0.2, 100, &fit, &fr), SUNMC_OK);
    assert_int_equal(fit.kind, ESS_MODEL_HYBRID);
    for (int q = 0; q < fit.spline.n_coef; q++)
        assert_true(fabs(fit.spline.coef[0][q]) * ARCSEC_PER_RAD < 1e-6);
    assert_true(worst_arcsec(cw, &fit) < 1e-6);
    ess_calib_free(cw);
}

static void test_hybrid_takes_up_ripple(void **state)
{
    ess_model truth, paper, hybrid;
    truth_model(&truth);
    ess_calib_workspace *cp = test_ess_grid(ESS_MODEL_PAPER, 0.05, betas3, 3);
    ess_calib_workspace *ch = test_ess_grid(ESS_MODEL_HYBRID, 0.05, betas3, 3);
    read_grid(cp, &truth, 20 * RAD_PER_ARCSEC);
    read_grid(ch, &truth, 20 * RAD_PER_ARCSEC);
    fit_result fr;
    assert_int_equal(ess_calibrate(cp, THETA0_RAD, 0, 0.2, 100, &paper, &fr), SUNMC_OK);
    assert_int_equal(ess_calibrate(ch, THETA0_RAD, 0, 0.2, 100, &hybrid, &fr), SUNMC_OK);
    double ep = worst_arcsec(cp, &paper), eh = worst_arcsec(ch, &hybrid);
    assert_true(ep > 15.0);
    assert_true(eh < 0.5 * ep);
    ess_calib_free(cp);
    ess_calib_free(ch);
}

static void test_spline_and_table_one_line(void **state)
{
    ess_model truth, fs, ft;
    truth_model(&truth);
    truth.p[ESS_P_KS] = truth.p[ESS_P_KC] = 0; /* smooth: the spline's order shows */
    ess_model_prepare(&truth);
    ess_calib_workspace *cs = test_ess_grid(ESS_MODEL_SPLINE, 0.2, beta0, 1);
    ess_calib_workspace *ct = test_ess_grid(ESS_MODEL_TABLE, 0.2, beta0, 1);
    read_grid(cs, &truth, 0);
    read_grid(ct, &truth, 0);
    fit_result fr;
    assert_int_equal(ess_calibrate(cs, THETA0_RAD, 0, 0.2, 100, &fs, &fr), SUNMC_OK);
    assert_int_equal(ess_calibrate(ct, THETA0_RAD, 0, 0.2, 100, &ft, &fr), SUNMC_OK);
    /* against the truth the nominal model assigns (the unit's mounting is
     * in the spline): a cubic's error, and the table's linear one at its
     * chosen step (257 nodes over 124 deg: h^2 f''/8, f'' of order 1e-3) */
    double es = worst_arcsec(cs, &fs), et = worst_arcsec(ct, &ft);
    assert_true(es < 1e-3);
    assert_true(et > es && et < 0.1);
    assert_true(ft.table.nodes >= 3 && ft.table.nodes <= LAB_TABLE_MAX_NODES1);
    double a[2], raw[2] = {fs.spline.hi[0] + 1e-6, fs.spline.lo[0]};
    int st[2];
    assert_int_equal(ess_model_compensate_batch(&fs, 2, raw, a, st), SUNMC_EDOM);
    assert_int_equal(st[0], SUNMC_EDOM);
    assert_true(isnan(a[0]));
    assert_int_equal(st[1], SUNMC_OK);
    assert_int_equal(ess_model_compensate(&ft, ft.table.lo[0] - 1e-6, &a[0]), SUNMC_EDOM);
    ess_calib_free(cs);
    ess_calib_free(ct);
}

static void test_spline_cannot_follow_incidence(void **state)
{
    ess_model truth, fs, fh;
    truth_model(&truth);
    ess_calib_workspace *cs = test_ess_grid(ESS_MODEL_SPLINE, 0.2, betas3, 3);
    ess_calib_workspace *ch = test_ess_grid(ESS_MODEL_HYBRID, 0.2, betas3, 3);
    read_grid(cs, &truth, 0);
    read_grid(ch, &truth, 0);
    fit_result fr;
    assert_int_equal(ess_calibrate(cs, THETA0_RAD, 0, 0.2, 100, &fs, &fr), SUNMC_OK);
    assert_int_equal(ess_calibrate(ch, THETA0_RAD, 0, 0.2, 100, &fh, &fr), SUNMC_OK);
    assert_true(worst_arcsec(cs, &fs) > 100.0 * (worst_arcsec(ch, &fh) + 1e-3));
    ess_calib_free(cs);
    ess_calib_free(ch);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hybrid_zero_on_exact_physics),
        cmocka_unit_test(test_hybrid_takes_up_ripple),
        cmocka_unit_test(test_spline_and_table_one_line),
        cmocka_unit_test(test_spline_cannot_follow_incidence),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
