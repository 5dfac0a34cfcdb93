/* test_dss_spline.c - issue 39: the pinhole DSS's spline, table and hybrid
 * models (dss_spline.c) on a unit's noise-free campaign:
 *  - hybrid on exact physics (no noise, no fixed pattern: the physical
 *    model describes the unit): its correction is zero, every coefficient
 *    below 1e-3 arcsec, and its angles the physical model's to 1e-6";
 *  - hybrid on a physics that misses a term (the glass index held at its
 *    nominal value while the unit's is 0.02 off): the correction takes up
 *    more than half of the physical model's error;
 *  - spline and table: their angles on the campaign's own spots within
 *    their stated errors, the table's worse than the spline's (its nodes
 *    17 per axis), a spot beyond the calibrated field refused (EDOM);
 *  - the same fit twice gives the same bytes. */
#include "test_util.h"

#include "config.h"
#include "dss_calib.h"
#include "dss_model.h"
#include "dss_unit.h"
#include "status.h"
#include "units.h"

static sunmc_config config_of(const char *const *extra, int n_extra)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    const char *sets[12] = {"sensor.family=dss", "noise.centroid_px=0", "noise.encoder_arcsec=0",
                            "noise.s_curve=off", "tolerance.prnu_pct=0", "tolerance.dsnu_pct=0",
                            "tolerance.glass_ghost=0"};
    for (int i = 0; i < n_extra; i++)
        sets[7 + i] = extra[i];
    if (config_build(&st, NULL, sets, 7 + n_extra, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    sunmc_config c = st.cfg;
    config_state_free(&st);
    return c;
}

static const dss_deviations test_dev = {0.17, -0.08, 0.06, 9.0, -7.0, 8.0, -6.0, 0.004, 7.0, -5.0};

static dss_calib_workspace *campaign(const sunmc_config *c, const dss_deviations *dev)
{
    const dss_config *dc = dss_cfg(c);
    dss_unit u;
    dss_unit_build(c, dev, &u);
    dss_calib_workspace *cw = dss_calib_alloc_fix(&dc->design, dss_campaign_size(c), dc->cal_model,
                                                  dc->poly_order, dc->fit_glass_index, 0);
    assert_non_null(cw);
    size_t seen = dss_unit_campaign(c, &u, 0, cw->b1_rad, cw->b2_rad, cw->x_px, cw->y_px,
                                    cw->weight, NULL, NULL);
    assert_true(seen > 400);
    return cw;
}

/* Largest angle error (arcsec) of cal over cw's spots against its truth. */
static double worst_arcsec(const dss_calib_workspace *cw, const dss_calibration *cal)
{
    double e = 0;
    for (size_t i = 0; i < cw->n; i++) {
        double a, b, a0, b0;
        if (!(cw->weight[i] > 0))
            continue;
        assert_int_equal(dss_compensate(cal, cw->x_px[i], cw->y_px[i], &a, &b), SUNMC_OK);
        dss_calib_truth(cal, cw->b1_rad[i], cw->b2_rad[i], &a0, &b0);
        e = fmax(e, fmax(fabs(a - a0), fabs(b - b0)) * ARCSEC_PER_RAD);
    }
    return e;
}

static void test_hybrid_zero_on_exact_physics(void **state)
{
    const char *sets[] = {"calibration.model=hybrid"};
    sunmc_config c = config_of(sets, 1);
    dss_calib_workspace *cw = campaign(&c, &test_dev);
    dss_calibration cal, again;
    fit_result fr;
    assert_int_equal(dss_calibrate(cw, c.max_iterations, &cal, &fr), SUNMC_OK);
    assert_int_equal(cal.kind, DSS_MODEL_HYBRID);
    for (int j = 0; j < 2; j++)
        for (int q = 0; q < cal.spline.n_coef; q++)
            assert_true(fabs(cal.spline.coef[j][q]) * ARCSEC_PER_RAD < 1e-3);
    dss_calibration phys = cal;
    phys.kind = DSS_MODEL_PHYSICAL;
    for (size_t i = 0; i < cw->n; i++) {
        double a, b, ap, bp;
        if (!(cw->weight[i] > 0))
            continue;
        assert_int_equal(dss_compensate(&cal, cw->x_px[i], cw->y_px[i], &a, &b), SUNMC_OK);
        assert_int_equal(dss_compensate(&phys, cw->x_px[i], cw->y_px[i], &ap, &bp), SUNMC_OK);
        assert_true(fabs(a - ap) * ARCSEC_PER_RAD < 1e-3 && fabs(b - bp) * ARCSEC_PER_RAD < 1e-3);
    }
    assert_true(worst_arcsec(cw, &cal) < 1e-3);
    assert_int_equal(dss_calibrate(cw, c.max_iterations, &again, &fr), SUNMC_OK);
    assert_memory_equal(&cal.spline, &again.spline, sizeof cal.spline);
    dss_calib_free(cw);
}

/* The glass index held at its nominal value while the unit's is off by
 * 0.02: the physics misses it, the correction takes most of it up. */
static void test_hybrid_corrects_missing_term(void **state)
{
    dss_deviations dev = test_dev;
    dev.glass_index = 0.02;
    const char *phys_sets[] = {"calibration.model=physical", "calibration.fit_glass_index=off"};
    const char *hyb_sets[] = {"calibration.model=hybrid", "calibration.fit_glass_index=off"};
    sunmc_config cp = config_of(phys_sets, 2), ch = config_of(hyb_sets, 2);
    dss_calib_workspace *wp = campaign(&cp, &dev), *wh = campaign(&ch, &dev);
    dss_calibration kp, kh;
    fit_result fr;
    assert_int_equal(dss_calibrate(wp, cp.max_iterations, &kp, &fr), SUNMC_OK);
    assert_int_equal(dss_calibrate(wh, ch.max_iterations, &kh, &fr), SUNMC_OK);
    double ep = worst_arcsec(wp, &kp), eh = worst_arcsec(wh, &kh);
    assert_true(ep > 5.0);
    assert_true(eh < 0.5 * ep);
    dss_calib_free(wp);
    dss_calib_free(wh);
}

static void test_spline_and_table(void **state)
{
    const char *ss[] = {"calibration.model=spline"}, *ts[] = {"calibration.model=table"};
    sunmc_config cs = config_of(ss, 1), ct = config_of(ts, 1);
    dss_calib_workspace *ws = campaign(&cs, &test_dev), *wt = campaign(&ct, &test_dev);
    dss_calibration ks, kt;
    fit_result fr;
    assert_int_equal(dss_calibrate(ws, cs.max_iterations, &ks, &fr), SUNMC_OK);
    assert_int_equal(dss_calibrate(wt, ct.max_iterations, &kt, &fr), SUNMC_OK);
    assert_int_equal(kt.table.nodes, LAB_TABLE_MAX_NODES2);
    double es = worst_arcsec(ws, &ks), et = worst_arcsec(wt, &kt);
    /* 10 breakpoints over a 2048 px detector: a cubic's error of the pinhole's atan */
    assert_true(es < 300.0);
    assert_true(et > es && et < 6000.0);
    double a, b;
    assert_int_equal(dss_compensate(&ks, ks.spline.hi[0] + 1.0, 0.0, &a, &b), SUNMC_EDOM);
    assert_true(isnan(a) && isnan(b));
    assert_int_equal(dss_compensate(&kt, 0.0, kt.table.lo[1] - 1.0, &a, &b), SUNMC_EDOM);
    dss_calib_free(ws);
    dss_calib_free(wt);
}

/* Fewer usable spots than the spline needs: refused, not fitted. */
static void test_too_few_rows(void **state)
{
    const char *ss[] = {"calibration.model=spline"};
    sunmc_config cs = config_of(ss, 1);
    dss_calib_workspace *ws = campaign(&cs, &test_dev);
    int kept = 0;
    for (size_t i = 0; i < ws->n; i++)
        if (ws->weight[i] > 0 && kept++ >= DSS_SPLINE_MIN_ROWS - 1)
            ws->weight[i] = 0;
    dss_calibration k;
    fit_result fr;
    assert_int_equal(dss_calibrate(ws, cs.max_iterations, &k, &fr), SUNMC_EINPUT);
    dss_calib_free(ws);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hybrid_zero_on_exact_physics),
        cmocka_unit_test(test_hybrid_corrects_missing_term),
        cmocka_unit_test(test_spline_and_table),
        cmocka_unit_test(test_too_few_rows),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
