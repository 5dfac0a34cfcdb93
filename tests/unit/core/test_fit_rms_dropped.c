/* test_fit_rms_dropped.c - the fit residual RMS of units.tsv (fit_rms_*)
 * at its edges (issue 29): with points of weight 0 holding wild readings it
 * is the RMS over the kept points only, recomputed here point by point with
 * the scalar model and an angle-between formula of the test's own; for the
 * DSS polynomial model on noise-free data it is 0, and after a known
 * perturbation of the kept readings it equals the recomputed RMS. */
#include "test_ess_grid.h"
#include "test_util.h"

#include "config.h"
#include "dss_calib.h"
#include "dss_config.h"
#include "dss_onboard.h"
#include "dss_poly.h"
#include "ess_calib.h"
#include "ess_model.h"
#include "status.h"
#include "units.h"

#define THETA0_RAD (2.0 * RAD_PER_DEG)

static void ess_fit_rms_skips_dropped_points(void **state)
{
    ess_model m;
    ess_model_init(&m, THETA0_RAD, 20 * RAD_PER_ARCSEC);
    m.p[ESS_P_A] = 1.0004;
    m.p[ESS_P_B] = -2.0e-4;
    m.p[ESS_P_KS] = 3.0e-4;
    ess_model_prepare(&m);
    const double betas[] = {-20, 0, 20};
    ess_calib_workspace *cw = test_ess_grid(ESS_MODEL_PAPER, 0.7, betas, 3);
    double sum = 0;
    long kept = 0;
    for (size_t i = 0; i < cw->n; i++) {
        double pred = ess_model_predict(&m, cw->alpha_rad[i], cw->beta_rad[i], NULL);
        double resid = 1e-5 * (double)((long)(i % 7) - 3); /* rad, known */
        if (i % 11 == 5) {
            cw->weight[i] = 0; /* a gross error: wild reading, weight 0 */
            resid = 0.3;
        }
        cw->raw_rad[i] = pred - resid;
        if (cw->weight[i] > 0) {
            double r = ess_model_predict(&m, cw->alpha_rad[i], cw->beta_rad[i], NULL) -
                       cw->raw_rad[i];
            sum += r * r;
            kept++;
        }
    }
    assert_true(kept > 0 && (size_t)kept < cw->n);
    double want = sqrt(sum / (double)kept);
    assert_true(want > 1e-6);
    cw->table.n = cw->n; /* the turntable matrices, as ess_calibrate fills them */
    ess_table_fill(&cw->table, cw->alpha_rad, cw->beta_rad);
    assert_near(ess_calib_residual_rms(cw, &m), want, 1e-9 * want);
    /* every point dropped: no number, not 0 */
    for (size_t i = 0; i < cw->n; i++)
        cw->weight[i] = 0;
    assert_true(isnan(ess_calib_residual_rms(cw, &m)));
    ess_calib_free(cw);
}

/* Angle (rad) between the directions of (tan a, tan b, 1) and (tan a0, tan b0, 1). */
static double direction_angle(double a, double b, double a0, double b0)
{
    double u[3] = {tan(a), tan(b), 1}, v[3] = {tan(a0), tan(b0), 1};
    double dot = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    double nu = sqrt(u[0] * u[0] + u[1] * u[1] + 1), nv = sqrt(v[0] * v[0] + v[1] * v[1] + 1);
    double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                   u[0] * v[1] - u[1] * v[0]};
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / (nu * nv), dot / (nu * nv));
}

static void dss_poly_fit_rms(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    const char *sets[] = {"sensor.family=dss", "calibration.model=polynomial",
                          "calibration.poly_order=2"};
    assert_int_equal(config_build(&st, NULL, sets, 3, err, sizeof err), SUNMC_OK);
    const dss_config *dc = dss_cfg(&st.cfg);
    dss_calib_workspace *cw = dss_calib_alloc(&dc->design, 400, DSS_MODEL_POLYNOMIAL, 2, 0);
    assert_non_null(cw);
    dss_poly truth;
    dss_onboard ob;
    dss_onboard_init(&ob, &dc->design);
    dss_poly_init(&truth, 2, &ob, dc->design.fov_deg * RAD_PER_DEG);
    const double ca[6] = {1e-4, -2e-4, 3e-5, 5e-5, -4e-5, 2e-5};
    const double cb[6] = {-3e-4, 1e-5, 2e-4, -1e-5, 6e-5, -7e-5};
    memcpy(truth.ca, ca, sizeof ca);
    memcpy(truth.cb, cb, sizeof cb);
    /* Noise-free readings of a table whose truth (eq. 3-4: alpha = -b2,
     * tan b1 = tan beta cos b2) is the polynomial's output; 3 dropped. */
    size_t i = 0;
    for (int k1 = 0; k1 < 20; k1++)
        for (int k2 = 0; k2 < 20; k2++, i++) {
            cw->x_px[i] = -900 + 95.0 * k1;
            cw->y_px[i] = -880 + 93.0 * k2;
            double a, b;
            assert_int_equal(dss_poly_compensate(&truth, cw->x_px[i], cw->y_px[i], &a, &b),
                             SUNMC_OK);
            cw->b2_rad[i] = -a;
            cw->b1_rad[i] = atan(tan(b) * cos(cw->b2_rad[i]));
            cw->weight[i] = i % 97 == 13 ? 0 : 1;
        }
    dss_calibration cal;
    fit_result fr;
    assert_int_equal(dss_calibrate(cw, 100, &cal, &fr), SUNMC_OK);
    /* noise-free: the polynomial explains every kept point */
    assert_true(dss_calib_residual_rms(cw, &cal) * ARCSEC_PER_RAD < 1e-6);
    /* now readings moved by known amounts, the dropped ones wildly */
    double sum = 0;
    long kept = 0;
    for (i = 0; i < cw->n; i++) {
        cw->x_px[i] += cw->weight[i] > 0 ? 0.05 * (double)((long)(i % 5) - 2) : 300;
        cw->y_px[i] += cw->weight[i] > 0 ? 0.03 * (double)((long)(i % 3) - 1) : -300;
        if (!(cw->weight[i] > 0))
            continue;
        double a, b;
        assert_int_equal(dss_poly_compensate(&cal.poly, cw->x_px[i], cw->y_px[i], &a, &b),
                         SUNMC_OK);
        double a0 = -cw->b2_rad[i], b0 = atan(tan(cw->b1_rad[i]) / cos(cw->b2_rad[i]));
        double e = direction_angle(a, b, a0, b0);
        sum += e * e;
        kept++;
    }
    assert_int_equal(kept, 400 - 4);
    double want = sqrt(sum / (double)kept);
    assert_true(want * ARCSEC_PER_RAD > 0.1);
    assert_near(dss_calib_residual_rms(cw, &cal), want, 1e-6 * want);
    dss_calib_free(cw);
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ess_fit_rms_skips_dropped_points),
        cmocka_unit_test(dss_poly_fit_rms),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
