/* test_dss_diffraction.c - the pinhole's diffraction, the centroid window
 * and the mask's thickness in the DSS spot (issue 38, dss_centroid.h
 * "Diffraction", dss_sensor.h) against what this file works out on its
 * own: the cut-off d / (lambda h), the whole spot's S-curve as the
 * geometric disc's times the circular pupil's MTF (written here), the
 * windowed centroid of the spot integrated numerically here (its line
 * spread function by the midpoint rule over its spectrum, the pixels by
 * their box), and the tube as a raised pinhole that closes at
 * tan(theta) = d / T. */
#include "test_util.h"

#include "config.h"
#include "dss_centroid.h"
#include "dss_config.h"
#include "dss_sensor.h"
#include "status.h"
#include "units.h"

#include <gsl/gsl_sf_bessel.h>

static dss_design design(void)
{
    sunmc_config c = test_family_config("dss");
    dss_design d; /* copied bytewise: the config holds it in a byte blob */
    memcpy(&d, &dss_cfg(&c)->design, sizeof d);
    return d;
}

static double ref_jinc(double z)
{
    return z == 0 ? 1.0 : 2.0 * gsl_sf_bessel_J1(z) / z;
}

/* The incoherent MTF of a circular pupil (Goodman, Introduction to Fourier
 * Optics, eq. 6-32). */
static double ref_mtf(double r)
{
    return r >= 1 ? 0.0 : 2.0 / M_PI * (acos(r) - r * sqrt(1 - r * r));
}

static void test_cutoff_and_whole_spot(void **state)
{
    (void)state;
    dss_design d = design();
    /* 60 um / (650 nm x 3 mm) = 30.8 / mm, times 5.5 um */
    assert_near(dss_spot_cutoff_px(&d), 0.060 / (650e-6 * 3.0) * 0.0055, 1e-15);
    assert_near(dss_spot_cutoff_px(&d), 0.1692, 1e-4);
    double amp[DSS_SCURVE_HARMONICS];
    dss_scurve_design(&d, amp);
    for (int k = 0; k < DSS_SCURVE_HARMONICS; k++)
        assert_true(amp[k] == 0.0); /* band-limited below the pixel frequency */
    /* no diffraction: the geometric disc, bit for bit */
    d.wavelength_nm = 0;
    double geo[DSS_SCURVE_HARMONICS];
    dss_scurve_design(&d, amp);
    dss_scurve_amplitudes(d.pinhole_um / d.pixel_um, geo);
    assert_memory_equal(amp, geo, sizeof amp);
    assert_near(dss_spot_cutoff_px(&d), 0.0, 0);
    /* a cut-off above the pixel frequency: harmonics k < nu_c survive, the
     * disc's times the MTF times the sun's disc */
    d = design();
    d.pinhole_um = 200;
    d.h_mm = 1;
    d.wavelength_nm = 100;
    d.sun_disc_deg = 0.533;
    double nuc = dss_spot_cutoff_px(&d), Ds = dss_spot_sun_px(&d);
    assert_near(nuc, 0.2 / (1e-4 * 1.0) * 0.0055, 1e-12); /* 11 */
    dss_scurve_design(&d, amp);
    dss_scurve_amplitudes(d.pinhole_um / d.pixel_um, geo);
    for (int k = 1; k <= DSS_SCURVE_HARMONICS; k++) {
        double want = geo[k - 1] * ref_mtf(k / nuc) * ref_jinc(M_PI * Ds * k);
        assert_near(amp[k - 1], want, 1e-15);
        if (k > 11)
            assert_true(amp[k - 1] == 0.0);
    }
    assert_true(amp[0] != 0.0);
}

/* The spot's line-spread function at x by the midpoint rule over its
 * spectrum (disc x MTF x sun) times the pixel box: a pixel's signal. */
static double ref_pixel(const dss_design *d, double x)
{
    const int N = 1500;
    double nuc = dss_spot_cutoff_px(d), D = d->pinhole_um / d->pixel_um, Ds = dss_spot_sun_px(d);
    double h = nuc / N, s = 0;
    for (int q = 0; q < N; q++) {
        double nu = (q + 0.5) * h;
        double F = ref_jinc(M_PI * D * nu) * ref_mtf(nu / nuc) * ref_jinc(M_PI * Ds * nu) *
                   sin(M_PI * nu) / (M_PI * nu);
        s += 2 * h * F * cos(2 * M_PI * nu * x);
    }
    return s;
}

/* A fixed window of 2 m + 1 pixels: its S-curve against the centroid
 * computed here, away from the jump at +-0.5 px where the window moves on
 * (the 64 harmonics ring there). */
static void test_window_scurve_numerical(void **state)
{
    (void)state;
    dss_design d = design();
    d.sun_disc_deg = 0.533;
    const int ms[] = {6, 10, 20};
    for (int i = 0; i < 3; i++) {
        d.centroid_window_px = ms[i];
        double amp[DSS_SCURVE_HARMONICS], peak = 0;
        dss_scurve_design(&d, amp);
        for (double x0 = -0.3; x0 <= 0.3; x0 += 0.05) {
            double S = 0, S1 = 0;
            for (int n = -ms[i]; n <= ms[i]; n++) {
                double s = ref_pixel(&d, n - x0);
                S += s;
                S1 += n * s;
            }
            double want = S1 / S - x0;
            /* 64 harmonics of a curve with a jump: 0.002 px 0.2 px away */
            assert_near(dss_scurve_bias(amp, x0), want, 2.5e-3);
            peak = fmax(peak, fabs(want));
        }
        /* the window cuts the x^-2 tails: tenths to hundredths of a pixel */
        assert_true(peak > 0.005 && peak < 0.3);
    }
    /* the harmonics themselves: the sine transform of the centroid at 128
     * phases (j + 0.5) / 128 - 0.5, computed here */
    d.centroid_window_px = 10;
    double amp[DSS_SCURVE_HARMONICS], bias[128];
    dss_scurve_design(&d, amp);
    for (int j = 0; j < 128; j++) {
        double x0 = (j + 0.5) / 128 - 0.5, S = 0, S1 = 0;
        for (int n = -10; n <= 10; n++) {
            double s = ref_pixel(&d, n - x0);
            S += s;
            S1 += n * s;
        }
        bias[j] = S1 / S - x0;
    }
    for (int k = 1; k <= DSS_SCURVE_HARMONICS; k += 7) {
        double a = 0;
        for (int j = 0; j < 128; j++)
            a += bias[j] * sin(2 * M_PI * k * ((j + 0.5) / 128 - 0.5)) * 2 / 128;
        assert_near(amp[k - 1], a, 2e-5);
    }
}

/* The mask's thickness T: the pinhole raised by T / 2, closed at
 * tan(theta) = d / T. */
static void test_mask_tube(void **state)
{
    (void)state;
    dss_design d = design();
    dss_design dt = d;
    dt.mask_thickness_um = 60; /* = the pinhole: closed at 45 deg */
    dss_deviations z = {0}, raised = {.dh_px = 0.5 * 60 / d.pixel_um};
    dss_sensor s, r;
    dss_sensor_init(&s, &dt, &z, 0);
    dss_sensor_init(&r, &d, &raised, 0);
    const double ths[] = {0.0, 10.0, 30.0, 44.9};
    for (int k = 0; k < 4; k++) {
        double th = ths[k] * RAD_PER_DEG, u[3] = {sin(th) * 0.6, sin(th) * 0.8, cos(th)};
        double x, y, xr, yr;
        assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_OK);
        assert_int_equal(dss_sensor_spot(&r, u, NULL, &xr, &yr), SUNMC_OK);
        assert_near(x, xr, 1e-9);
        assert_near(y, yr, 1e-9);
    }
    for (double th_deg = 45.1; th_deg < 46; th_deg += 0.4) {
        double th = th_deg * RAD_PER_DEG, u[3] = {sin(th), 0, cos(th)}, x, y;
        assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_EDOM);
        assert_int_equal(dss_sensor_spot(&r, u, NULL, &x, &y), SUNMC_OK); /* on the detector */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cutoff_and_whole_spot),
        cmocka_unit_test(test_window_scurve_numerical),
        cmocka_unit_test(test_mask_tube),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
