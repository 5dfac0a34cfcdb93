/* test_dss_disc.c - the DSS spot as the pinhole's image of the sun's disc
 * (dss_sensor.h, Sun disc) against a numerical integration over the disc
 * done here: every point of a limb-darkened disc of apparent diameter D is
 * ray-traced through the glass by the point-sun sensor and the images are
 * averaged with the disc's brightness.  The integration runs over
 * chi = asin(rho / R) (mu = cos chi), where the brightness is smooth:
 * rho drho = R^2 sin chi cos chi dchi.  Then the closed form of a uniform
 * disc without glass, (R^2 / 4) tan theta (second-order Taylor of tan over
 * the disc, <a^2> = R^2 / 4), ~1.1 arcsec tan theta; the calibration model's
 * spot and inverse with the disc; the on-board formula's error with and
 * without the disc. */
#include "test_util.h"

#include "config.h"
#include "dss_config.h"
#include "dss_labfit.h"
#include "dss_calib.h"
#include "dss_model.h"
#include "params_io.h"
#include "dss_sensor.h"
#include "status.h"
#include "units.h"

#define N_CHI 200
#define N_PSI 72

static dss_design design_of(double disc_deg, double u_ld, double t_mm)
{
    sunmc_config c = test_family_config("dss");
    dss_design d = dss_cfg(&c)->design;
    d.sun_disc_deg = disc_deg;
    d.limb_darkening = u_ld;
    d.glass_thickness_mm = t_mm;
    return d;
}

/* The sun's centre at field angle th, azimuth ph, in the sensor frame and
 * the radial and tangential unit vectors there. */
static void centre_frame(double th, double ph, double u0[3], double e1[3], double e2[3])
{
    double v0[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
    double v1[3] = {cos(th) * cos(ph), cos(th) * sin(ph), -sin(th)};
    double v2[3] = {-sin(ph), cos(ph), 0};
    memcpy(u0, v0, sizeof v0);
    memcpy(e1, v1, sizeof v1);
    memcpy(e2, v2, sizeof v2);
}

/* The brightness-weighted centroid of the images of the disc's points. */
static void disc_centroid(const dss_sensor *point, double disc_deg, double u_ld, double th,
                          double ph, double out[2])
{
    double R = 0.5 * disc_deg * RAD_PER_DEG, u0[3], e1[3], e2[3];
    centre_frame(th, ph, u0, e1, e2);
    double sw = 0, sx = 0, sy = 0;
    for (int i = 0; i < N_CHI; i++) {
        double chi = (i + 0.5) * (M_PI / 2) / N_CHI;
        double rho = R * sin(chi); /* angular radius of the point */
        double w = (1.0 - u_ld * (1.0 - cos(chi))) * sin(chi) * cos(chi);
        for (int j = 0; j < N_PSI; j++) {
            double psi = (j + 0.5) * 2 * M_PI / N_PSI;
            double v[3];
            for (int k = 0; k < 3; k++)
                v[k] = cos(rho) * u0[k] + sin(rho) * (cos(psi) * e1[k] + sin(psi) * e2[k]);
            double x, y;
            assert_int_equal(dss_sensor_spot(point, v, NULL, &x, &y), SUNMC_OK);
            sw += w;
            sx += w * x;
            sy += w * y;
        }
    }
    out[0] = sx / sw;
    out[1] = sy / sw;
}

/* The bias the sensor models, against the integration: glass and limb
 * darkening as the defaults, field angles 0-60 deg at an oblique azimuth. */
static void test_disc_bias_matches_integration(void **state)
{
    (void)state;
    static const dss_deviations none;
    const double ths[] = {0, 10, 30, 45, 60}, ph = 0.4;
    for (int g = 0; g < 2; g++) {
        double t = g ? 0.4 : 0.0, u_ld = g ? 0.6 : 0.0;
        dss_design dd = design_of(0.533, u_ld, t), dp = design_of(0, u_ld, t);
        dss_sensor disc, point;
        dss_sensor_init(&disc, &dd, &none, 0);
        dss_sensor_init(&point, &dp, &none, 0);
        for (size_t i = 0; i < sizeof ths / sizeof *ths; i++) {
            double th = ths[i] * RAD_PER_DEG, u0[3], e1[3], e2[3];
            centre_frame(th, ph, u0, e1, e2);
            double xd, yd, x0, y0, ref[2];
            assert_int_equal(dss_sensor_spot(&disc, u0, NULL, &xd, &yd), SUNMC_OK);
            assert_int_equal(dss_sensor_spot(&point, u0, NULL, &x0, &y0), SUNMC_OK);
            disc_centroid(&point, 0.533, u_ld, th, ph, ref);
            double bx = ref[0] - x0, by = ref[1] - y0;
            /* 1% of the bias (the next order is R^2 ~ 1e-5 of it; the rest is
             * the quadrature) or 1e-7 px at the centre */
            double tol = 0.01 * hypot(bx, by) + 1e-7;
            assert_near(xd - x0, bx, tol);
            assert_near(yd - y0, by, tol);
            if (ths[i] >= 30)
                assert_true(hypot(bx, by) > 1e-3); /* px: a bias worth modelling */
        }
    }
}

/* A uniform disc without glass: the angle of the centroid is the centre's
 * plus (R^2 / 4) tan theta, ~1.1 arcsec tan theta for D = 0.533 deg. */
static void test_disc_bias_closed_form(void **state)
{
    (void)state;
    static const dss_deviations none;
    dss_design d = design_of(0.533, 0.0, 0.0), p = design_of(0, 0.0, 0.0);
    dss_sensor disc, point;
    dss_sensor_init(&disc, &d, &none, 0);
    dss_sensor_init(&point, &p, &none, 0);
    double R = 0.5 * 0.533 * RAD_PER_DEG;
    assert_near(R * R / 4 * ARCSEC_PER_RAD, 1.1, 0.02);
    for (double th_deg = 5; th_deg <= 60; th_deg += 11) {
        double th = th_deg * RAD_PER_DEG, u0[3], e1[3], e2[3];
        centre_frame(th, 0.0, u0, e1, e2);
        double xd, yd, x0, y0;
        assert_int_equal(dss_sensor_spot(&disc, u0, NULL, &xd, &yd), SUNMC_OK);
        assert_int_equal(dss_sensor_spot(&point, u0, NULL, &x0, &y0), SUNMC_OK);
        double h_px = d.h_mm / (d.pixel_um * MM_PER_UM);
        double bias = atan(-xd / h_px) - atan(-x0 / h_px);
        assert_near(bias * ARCSEC_PER_RAD, R * R / 4 * tan(th) * ARCSEC_PER_RAD,
                    1e-3 * tan(th) + 1e-6);
    }
}

/* The calibration model knows the disc: the nominal model's spot is the
 * nominal sensor's, its inverse gives the truth; the on-board formula
 * (which does not) errs by the bias, and by nothing with a point sun. */
static void test_disc_model_and_onboard(void **state)
{
    (void)state;
    static const dss_deviations none;
    for (int with = 0; with < 2; with++) {
        dss_design d = design_of(with ? 0.533 : 0.0, 0.6, 0.4);
        d.mount = DSS_MOUNT_ALIGNED;
        dss_sensor s;
        dss_model m;
        dss_sensor_init(&s, &d, &none, 0);
        dss_model_init(&m, &d);
        double worst_ob = 0;
        int n = 0;
        for (double b = -60; b <= 60; b += 7.5) {
            double b1 = b * RAD_PER_DEG, b2 = -0.6 * b * RAD_PER_DEG, u[3], x, y, mx[2];
            dss_sensor_sun(&s, b1, b2, u);
            if (dss_sensor_spot(&s, u, NULL, &x, &y) != SUNMC_OK)
                continue; /* off the detector */
            n++;
            assert_int_equal(dss_model_spot(&m, b1, b2, mx, NULL), SUNMC_OK);
            assert_near(mx[0], x, 1e-9);
            assert_near(mx[1], y, 1e-9);
            double a0, be0, a, be, ao, bo;
            dss_sensor_truth(&s, b1, b2, &a0, &be0);
            assert_int_equal(dss_model_compensate(&m, x, y, &a, &be), SUNMC_OK);
            assert_near((a - a0) * ARCSEC_PER_RAD, 0, 1e-5);
            assert_near((be - be0) * ARCSEC_PER_RAD, 0, 1e-5);
            assert_int_equal(dss_sensor_angles(&s, x, y, &ao, &bo), SUNMC_OK);
            double e = hypot(ao - a0, bo - be0) * ARCSEC_PER_RAD;
            worst_ob = e > worst_ob ? e : worst_ob;
        }
        assert_true(n >= 13);
        if (with) /* ~1 arcsec tan(theta) at the corner (theta ~ 64 deg) */
            assert_true(worst_ob > 1.0 && worst_ob < 3.5);
        else
            assert_true(worst_ob < 1e-6);
    }
}

/* params.ini carries the disc to compensate; a coefficient outside its
 * range (a disc above 2 deg, or negative) is refused, naming the key. */
static void test_disc_params_round_trip(void **state)
{
    (void)state;
    dss_design d = design_of(0.533, 0.6, 0.4);
    dss_calibration cal = {.kind = DSS_MODEL_PHYSICAL};
    dss_model_init(&cal.phys, &d);
    assert_true(cal.phys.disc_c_rad2 > 1e-6);
    static params_file p;
    params_init(&p);
    assert_int_equal(params_set_text(&p, "calibration", "model", DSS_CALFIT_MODEL_PHYSICAL, NULL),
                     SUNMC_OK);
    assert_int_equal(dss_params_fill(&p, &cal, NULL), SUNMC_OK);
    static dss_calibration back;
    char err[SUNMC_ERRLEN];
    assert_int_equal(dss_params_load(&p, &back, err, sizeof err), SUNMC_OK);
    assert_near(back.phys.disc_c_rad2, cal.phys.disc_c_rad2, 1e-15 * cal.phys.disc_c_rad2);
    const double bad[] = {-1e-9, DSS_DISC_C_MAX_RAD2 * 1.01};
    for (int i = 0; i < 2; i++) {
        for (int k = 0; k < p.n; k++)
            if (strcmp(p.e[k].key, "sun_disc_c_rad2") == 0)
                snprintf(p.e[k].value, sizeof p.e[k].value, "%.17g", bad[i]);
        assert_int_equal(dss_params_load(&p, &back, err, sizeof err), SUNMC_EINPUT);
        assert_non_null(strstr(err, "sun_disc_c_rad2"));
    }
    /* at the limit it is taken */
    for (int k = 0; k < p.n; k++)
        if (strcmp(p.e[k].key, "sun_disc_c_rad2") == 0)
            snprintf(p.e[k].value, sizeof p.e[k].value, "%.17g", DSS_DISC_C_MAX_RAD2);
    assert_int_equal(dss_params_load(&p, &back, err, sizeof err), SUNMC_OK);
    /* a point sun writes no key (older params.ini read as a point sun) */
    dss_design d0 = design_of(0, 0.6, 0.4);
    dss_model_init(&cal.phys, &d0);
    params_init(&p);
    assert_int_equal(params_set_text(&p, "calibration", "model", DSS_CALFIT_MODEL_PHYSICAL, NULL),
                     SUNMC_OK);
    assert_int_equal(dss_params_fill(&p, &cal, NULL), SUNMC_OK);
    assert_int_equal(dss_params_load(&p, &back, err, sizeof err), SUNMC_OK);
    assert_true(back.phys.disc_c_rad2 == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_disc_bias_matches_integration),
        cmocka_unit_test(test_disc_bias_closed_form),
        cmocka_unit_test(test_disc_model_and_onboard),
        cmocka_unit_test(test_disc_params_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
