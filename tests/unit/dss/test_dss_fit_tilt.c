/* test_dss_fit_tilt.c - calibration.fit_detector_tilt (issue 38 item 3):
 * the physical model extended by the detector's tilt against the tilted
 * ray-traced sensor (spots, compensation back to the truth), its two
 * Jacobian columns against central differences, a noise-free unit with a
 * tilt fitted to that tilt and compensated to the floor, and the key off:
 * no tilt parameter fitted or named, the tilt left in the error. */
#include "test_util.h"

#include "config.h"
#include "dss_calib.h"
#include "dss_model.h"
#include "dss_unit.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <string.h>

static sunmc_config cfg(const char *const *extra, int n_extra)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    const char *sets[12] = {"sensor.family=dss"};
    for (int i = 0; i < n_extra; i++)
        sets[1 + i] = extra[i];
    assert_int_equal(config_build(&st, NULL, sets, 1 + n_extra, err, sizeof err), SUNMC_OK);
    sunmc_config c = st.cfg;
    config_state_free(&st);
    return c;
}

/* The noise-free lab of a unit with nothing but the modelled effects and
 * the tilt: no noise, no S-curve, no fixed pattern, no ghost. */
static const char *const quiet_on[] = {
    "noise.centroid_px=0",  "noise.encoder_arcsec=0", "noise.s_curve=off",
    "tolerance.prnu_pct=0", "tolerance.dsnu_pct=0",   "tolerance.glass_ghost=0",
    "calibration.fit_detector_tilt=on"};
#define N_QUIET (int)(sizeof quiet_on / sizeof *quiet_on)

static const double tilt_x_arcsec = 360.0, tilt_y_arcsec = -540.0;

static dss_deviations tilted_dev(void)
{
    dss_deviations d = {.dx_px = 0.17, .dy_px = -0.08, .dh_px = 0.06, .glass_thickness_um = 9.0,
                        .c1_arcsec = -7.0, .c2_arcsec = 8.0, .c3_arcsec = -6.0,
                        .glass_index = 0.004, .sun_b1_arcsec = 7.0, .sun_b2_arcsec = -5.0};
    d.detector_tilt_x_arcsec = tilt_x_arcsec;
    d.detector_tilt_y_arcsec = tilt_y_arcsec;
    return d;
}

/* The tilted model with the sensor's true parameters. */
static void true_model(const sunmc_config *c, const dss_sensor *s, const dss_deviations *d,
                       dss_model *m)
{
    dss_model_init(m, &dss_cfg(c)->design);
    assert_int_equal(m->tilt, 1);
    m->p[DSS_P_X0] = s->pinhole_mm[0];
    m->p[DSS_P_Y0] = s->pinhole_mm[1];
    m->p[DSS_P_H] = s->pinhole_mm[2];
    m->p[DSS_P_T] = s->glass_t_mm;
    m->p[DSS_P_N] = s->glass_n;
    m->p[DSS_P_C1] = d->c1_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_C2] = d->c2_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_C3] = d->c3_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_S1] = d->sun_b1_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_S2] = d->sun_b2_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_TX] = d->detector_tilt_x_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_TY] = d->detector_tilt_y_arcsec * RAD_PER_ARCSEC;
    dss_model_prepare(m);
}

/* The tilted model is the tilted sensor's spot, and compensating the
 * sensor's spot (on the tilted plane) gives the truth angles; a spot
 * compensated by the untilted model misses them by arcseconds. */
static void test_tilted_model_matches_sensor(void **state)
{
    (void)state;
    sunmc_config c = cfg(quiet_on, N_QUIET);
    dss_deviations d = tilted_dev();
    dss_sensor s;
    dss_sensor_init(&s, &dss_cfg(&c)->design, &d, 0);
    dss_model m, flat;
    true_model(&c, &s, &d, &m);
    flat = m;
    flat.tilt = 0;
    int n = 0;
    double worst_flat = 0;
    for (double b1 = -60; b1 <= 60; b1 += 3.7)
        for (double b2 = -60; b2 <= 60; b2 += 3.7) {
            double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG, x, y, sp[2], a, b, a0, b0;
            if (dss_sensor_read(&s, r1, r2, NULL, &x, &y) != SUNMC_OK)
                continue;
            n++;
            assert_int_equal(dss_model_spot(&m, r1, r2, sp, NULL), SUNMC_OK);
            assert_near(sp[0], x, 1e-9);
            assert_near(sp[1], y, 1e-9);
            assert_int_equal(dss_model_compensate(&m, x, y, &a, &b), SUNMC_OK);
            dss_sensor_truth(&s, r1, r2, &a0, &b0);
            assert_near(a * ARCSEC_PER_RAD, a0 * ARCSEC_PER_RAD, 1e-6);
            assert_near(b * ARCSEC_PER_RAD, b0 * ARCSEC_PER_RAD, 1e-6);
            assert_int_equal(dss_model_compensate(&flat, x, y, &a, &b), SUNMC_OK);
            worst_flat = fmax(worst_flat, fabs(a - a0) * ARCSEC_PER_RAD);
        }
    assert_true(n > 700);
    assert_true(worst_flat > 1.0);
}

/* The analytic Jacobian, the tilt's two columns and every other column
 * through the tilt, against central differences. */
static void test_tilted_jacobian(void **state)
{
    (void)state;
    sunmc_config c = cfg(quiet_on, N_QUIET);
    dss_deviations d = tilted_dev();
    dss_sensor s;
    dss_sensor_init(&s, &dss_cfg(&c)->design, &d, 0);
    dss_model m;
    true_model(&c, &s, &d, &m);
    const double steps[DSS_NP] = {1e-6, 1e-6, 1e-6, 1e-6, 1e-7, 1e-7,
                                  1e-7, 1e-6, 1e-7, 1e-7, 1e-7, 1e-7};
    double tilt_col = 0;
    for (double b1 = -50; b1 <= 50; b1 += 25)
        for (double b2 = -50; b2 <= 50; b2 += 25) {
            double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG, sp[2], J[2][DSS_NP];
            assert_int_equal(dss_model_spot(&m, r1, r2, sp, J), SUNMC_OK);
            for (int j = 0; j < DSS_NP; j++) {
                dss_model mp = m, mm = m;
                mp.p[j] += steps[j];
                mm.p[j] -= steps[j];
                dss_model_prepare(&mp);
                dss_model_prepare(&mm);
                double sp_p[2], sp_m[2];
                assert_int_equal(dss_model_spot(&mp, r1, r2, sp_p, NULL), SUNMC_OK);
                assert_int_equal(dss_model_spot(&mm, r1, r2, sp_m, NULL), SUNMC_OK);
                for (int a = 0; a < 2; a++) {
                    double num = (sp_p[a] - sp_m[a]) / (2 * steps[j]);
                    assert_near(J[a][j], num, 1e-5 * (1 + fabs(num)));
                    if (j >= DSS_P_TX)
                        tilt_col = fmax(tilt_col, fabs(num));
                }
            }
        }
    /* the columns are not trivially 0: a tilt moves a corner spot by
     * h tan^2 theta per radian, hundreds of px */
    assert_true(tilt_col > 100);
}

/* A noise-free campaign of a tilted unit fitted with the key on and off. */
typedef struct {
    double tilt_arcsec[2], residual_arcsec, worst_val_arcsec;
    int n_free;
} fit_out;

static fit_out fit_unit(const char *key)
{
    const char *sets[N_QUIET];
    memcpy(sets, quiet_on, sizeof sets);
    sets[N_QUIET - 1] = key;
    sunmc_config c = cfg(sets, N_QUIET);
    const dss_config *dc = dss_cfg(&c);
    dss_deviations d = {0};
    d.detector_tilt_x_arcsec = tilt_x_arcsec;
    d.detector_tilt_y_arcsec = tilt_y_arcsec;
    dss_unit u;
    dss_unit_build(&c, &d, &u);
    dss_calib_workspace *cw = dss_calib_alloc_config(dc, dss_campaign_size(&c));
    assert_non_null(cw);
    dss_unit_campaign(&c, &u, 0, cw->b1_rad, cw->b2_rad, cw->x_px, cw->y_px, cw->weight, NULL,
                      NULL);
    dss_calibration cal;
    fit_result fr;
    assert_int_equal(dss_calibrate(cw, c.max_iterations, &cal, &fr), SUNMC_OK);
    fit_out o = {{dss_param_value(&cal.phys, DSS_P_TX), dss_param_value(&cal.phys, DSS_P_TY)},
                 dss_calib_residual_rms(cw, &cal) * ARCSEC_PER_RAD, 0, cw->n_free};
    /* the validation: spots read off the unit, compensated, against the truth */
    for (double b1 = -58.7; b1 <= 60; b1 += 4.1)
        for (double b2 = -58.7; b2 <= 60; b2 += 4.1) {
            double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG, x, y, a, b, a0, b0;
            if (dss_sensor_read(&u.sensor, r1, r2, NULL, &x, &y) != SUNMC_OK)
                continue;
            assert_int_equal(dss_compensate(&cal, x, y, &a, &b), SUNMC_OK);
            dss_sensor_truth(&u.sensor, r1, r2, &a0, &b0);
            o.worst_val_arcsec = fmax(o.worst_val_arcsec, fabs(a - a0) * ARCSEC_PER_RAD);
            o.worst_val_arcsec = fmax(o.worst_val_arcsec, fabs(b - b0) * ARCSEC_PER_RAD);
        }
    dss_calib_free(cw);
    return o;
}

/* Key on: the fit finds the tilt and compensation reaches the floor of a
 * noise-free unit (0 to 1e-6 arcsec).  Key off: 10 parameters as before,
 * the tilt stays in the residuals and in the validation error. */
static void test_fit_recovers_tilt(void **state)
{
    (void)state;
    fit_out on = fit_unit("calibration.fit_detector_tilt=on");
    assert_int_equal(on.n_free, 12);
    assert_near(on.tilt_arcsec[0], tilt_x_arcsec, 1e-3);
    assert_near(on.tilt_arcsec[1], tilt_y_arcsec, 1e-3);
    assert_true(on.residual_arcsec < 1e-6);
    assert_true(on.worst_val_arcsec < 1e-5);
    fit_out off = fit_unit("calibration.fit_detector_tilt=off");
    assert_int_equal(off.n_free, 10);
    assert_near(off.tilt_arcsec[0], 0, 0);
    assert_near(off.tilt_arcsec[1], 0, 0);
    assert_true(off.residual_arcsec > 0.1);
    assert_true(off.worst_val_arcsec > 1.0);
}

/* units.tsv names the tilt's columns only with the key on, before the fit
 * quality columns, and the values follow the names. */
static void test_par_columns(void **state)
{
    (void)state;
    const char *names[UNIT_MAX_PAR];
    const char *off_set[] = {"calibration.fit_detector_tilt=off"};
    const char *on_set[] = {"calibration.fit_detector_tilt=on"};
    sunmc_config off = cfg(off_set, 1), on = cfg(on_set, 1);
    assert_int_equal(dss_par_names(&off, names, UNIT_MAX_PAR), 13);
    for (int i = 0; i < 13; i++)
        assert_null(strstr(names[i], "tilt"));
    assert_string_equal(names[10], "corr_max_abs");
    assert_int_equal(dss_par_names(&on, names, UNIT_MAX_PAR), 15);
    assert_string_equal(names[10], "fit_detector_tilt_x_arcsec");
    assert_string_equal(names[11], "fit_detector_tilt_y_arcsec");
    assert_string_equal(names[12], "corr_max_abs");
    assert_string_equal(names[14], "log10_rcond");
    dss_calibration cal = {.kind = DSS_MODEL_PHYSICAL};
    dss_model_init(&cal.phys, &dss_cfg(&on)->design);
    dss_param_set(&cal.phys, DSS_P_TY, 12.5);
    double v[UNIT_MAX_PAR];
    assert_int_equal(dss_par_values(&on, &cal, 0.5, 4, 10, 1e-3, v, UNIT_MAX_PAR), 15);
    assert_near(v[11], 12.5, 1e-9);
    assert_near(v[12], 0.5, 0);
    assert_near(v[13], 410, 0);
    assert_near(v[14], -3, 1e-12);
    assert_int_equal(dss_par_values(&off, &cal, 0.5, 4, 7, 1e-3, v, UNIT_MAX_PAR), 13);
    assert_near(v[10], 0.5, 0);
    assert_near(v[11], 407, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tilted_model_matches_sensor),
        cmocka_unit_test(test_tilted_jacobian),
        cmocka_unit_test(test_fit_recovers_tilt),
        cmocka_unit_test(test_par_columns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
