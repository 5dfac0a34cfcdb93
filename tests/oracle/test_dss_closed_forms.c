/* test_dss_closed_forms.c - the DSS physics against values this file works
 * out on its own: the spot through the cover glass by the textbook lateral
 * displacement of a plane-parallel plate (not Snell's vector form), with the
 * principal point and height deviations; the installation rotations from
 * rotation matrices written out here (c3 also as a closed form in the
 * tangents); the detector-edge check with the spot's size on both sides of
 * its boundary; the S-curve's amplitude (Bessel's integral for J1) and its
 * pixel phase for even and odd detectors (brute-force centroid of the
 * pixel-integrated disc); and the calibration model's spot and its exact
 * inverse.
 *
 * Conventions (dss_sensor.h, rotation.h): passive rotations
 * Rx(a) = [1 0 0; 0 c s; 0 -s c], Ry(a) = [c 0 -s; 0 1 0; s 0 c],
 * Rz(a) = [c s 0; -s c 0; 0 0 1]; mount M = Ry(c2) Rx(c1) Rz(c3); table
 * R(b) = Ry(b2) Rx(b1); sun in the sensor frame u = M R(b) M^T e_z; truth
 * alpha0 = -b2, beta0 = atan(tan b1 / cos b2); on-board alpha = atan(-x/h). */
#include "test_util.h"

#include "config.h"
#include "dss_config.h"
#include "dss_calib.h"
#include "dss_centroid.h"
#include "dss_model.h"
#include "dss_sensor.h"
#include "status.h"
#include "units.h"

static sunmc_config default_dss(void) { return test_family_config("dss"); }

/* ---- rotations written out ---- */

static void rx(double a, const double v[3], double o[3])
{
    double t[3] = {v[0], cos(a) * v[1] + sin(a) * v[2], -sin(a) * v[1] + cos(a) * v[2]};
    memcpy(o, t, sizeof t);
}
static void ry(double a, const double v[3], double o[3])
{
    double t[3] = {cos(a) * v[0] - sin(a) * v[2], v[1], sin(a) * v[0] + cos(a) * v[2]};
    memcpy(o, t, sizeof t);
}
static void rz(double a, const double v[3], double o[3])
{
    double t[3] = {cos(a) * v[0] + sin(a) * v[1], -sin(a) * v[0] + cos(a) * v[1], v[2]};
    memcpy(o, t, sizeof t);
}

/* u = M R(b) v_sun, M = Ry(c2) Rx(c1) Rz(c3), R(b) = Ry(b2) Rx(b1):
 * aligned (s == NULL): v_sun = M^T e_z = Rz(-c3) Rx(-c1) Ry(-c2) e_z;
 * as mounted: v_sun = R(s[0], s[1]) e_z. */
static void ref_sun_general(double c1, double c2, double c3, const double *s, double b1,
                            double b2, double u[3])
{
    double v[3] = {0, 0, 1};
    if (s) {
        rx(s[0], v, v);
        ry(s[1], v, v);
    } else {
        ry(-c2, v, v);
        rx(-c1, v, v);
        rz(-c3, v, v);
    }
    rx(b1, v, v);
    ry(b2, v, v);
    rz(c3, v, v);
    rx(c1, v, v);
    ry(c2, v, v);
    memcpy(u, v, sizeof v);
}

static void ref_sun(double c1, double c2, double c3, double b1, double b2, double u[3])
{
    ref_sun_general(c1, c2, c3, NULL, b1, b2, u);
}

/* Spot (mm) of sun u through a pinhole at (x0, y0, H) and a plate of
 * thickness t, index n on the detector: the plate displaces the ray
 * sideways by t sin(th - thg) / cos(thg), i.e. by t (tan th - tan thg)
 * along the detector. */
static void ref_spot_mm(const double u[3], double x0, double y0, double H, double t, double n,
                        double spot[2])
{
    double th = acos(u[2]), ph = atan2(u[1], u[0]);
    double thg = asin(sin(th) / n);
    double shift = t * sin(th - thg) / cos(thg) / cos(th);
    double r = H * tan(th) - shift;
    spot[0] = x0 - r * cos(ph);
    spot[1] = y0 - r * sin(ph);
}

static void ref_table_truth(double b1, double b2, double *a0, double *b0)
{
    *a0 = -b2;
    *b0 = atan(tan(b1) / cos(b2));
}

/* ---- the spot through the glass, with the intrinsic deviations ---- */

static void test_spot_through_glass(void **state)
{
    sunmc_config c = default_dss();
    const dss_deviations devs[] = {
        {0},
        {.dh_px = 0.2},
        {.dx_px = 0.1, .dy_px = -0.07},
        {.glass_thickness_um = 10, .glass_index = 0.005},
        {.dh_px = -0.3, .dx_px = -0.2, .dy_px = 0.15, .glass_thickness_um = -8,
         .glass_index = -0.004},
    };
    const double pix = dss_cfg(&c)->design.pixel_um * MM_PER_UM;
    for (size_t k = 0; k < sizeof devs / sizeof devs[0]; k++) {
        const dss_deviations *d = &devs[k];
        dss_sensor s;
        dss_sensor_init(&s, &dss_cfg(&c)->design, d, 0);
        double H = dss_cfg(&c)->design.h_mm + d->dh_px * pix;
        double t = dss_cfg(&c)->design.glass_thickness_mm + d->glass_thickness_um * MM_PER_UM;
        double n = dss_cfg(&c)->design.glass_index + d->glass_index;
        int seen = 0;
        for (double b1 = -55; b1 <= 55; b1 += 5.5)
            for (double b2 = -55; b2 <= 55; b2 += 5.5) {
                double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG;
                double u[3] = {-sin(r2) * cos(r1), sin(r1), cos(r1) * cos(r2)}, want[2], x, y;
                ref_spot_mm(u, d->dx_px * pix, d->dy_px * pix, H, t, n, want);
                int st = dss_sensor_read(&s, r1, r2, NULL, &x, &y);
                if (st != SUNMC_OK) /* off the detector: checked separately */
                    continue;
                assert_near(x, want[0] / pix, 1e-9);
                assert_near(y, want[1] / pix, 1e-9);
                seen++;
            }
        assert_true(seen > 300); /* of 441: only the far corners are off the detector */
    }
}

/* The on-board formula with the glass ignored (eq. 9-10): the pinhole
 * inverts the image. */
static void test_onboard_formula(void **state)
{
    const dss_onboard o = {.h_mm = 3.0, .pixel_mm = 5.5e-3, .glass_t_mm = 0, .glass_n = 1.52};
    for (double x = -900; x <= 900; x += 137.1) {
        double a, b;
        assert_int_equal(dss_onboard_angles(&o, x, -0.5 * x + 11, &a, &b), SUNMC_OK);
        assert_near(a, atan(-x * 5.5e-3 / 3.0), 1e-15);
        assert_near(b, atan((0.5 * x - 11) * 5.5e-3 / 3.0), 1e-15);
    }
}

/* The corrected on-board formula (the default) is the exact inverse of the
 * nominal geometry: the spot of sun (alpha, beta) through the nominal glass
 * by the textbook plate displacement reads back (alpha, beta) to 1e-9";
 * with the glass ignored the error is of the order of degrees at 60 deg. */
static void test_onboard_corrected(void **state)
{
    sunmc_config c = default_dss();
    dss_design *d = &dss_cfg(&c)->design;
    assert_int_equal(d->onboard_refraction, DSS_ONBOARD_CORRECTED);
    dss_onboard o, paper;
    dss_onboard_init(&o, d);
    d->onboard_refraction = DSS_ONBOARD_IGNORED;
    dss_onboard_init(&paper, d);
    const double pix = d->pixel_um * MM_PER_UM;
    double worst_paper = 0;
    for (double a = -60; a <= 60; a += 7.5)
        for (double b = -60; b <= 60; b += 7.5) {
            double ar = a * RAD_PER_DEG, br = b * RAD_PER_DEG;
            double nrm = sqrt(1 + tan(ar) * tan(ar) + tan(br) * tan(br));
            double u[3] = {tan(ar) / nrm, tan(br) / nrm, 1 / nrm}, sp[2], ga, gb;
            ref_spot_mm(u, 0, 0, d->h_mm, d->glass_thickness_mm, d->glass_index, sp);
            assert_int_equal(dss_onboard_angles(&o, sp[0] / pix, sp[1] / pix, &ga, &gb),
                             SUNMC_OK);
            assert_near((ga - ar) * ARCSEC_PER_RAD, 0.0, 1e-9);
            assert_near((gb - br) * ARCSEC_PER_RAD, 0.0, 1e-9);
            assert_int_equal(dss_onboard_angles(&paper, sp[0] / pix, sp[1] / pix, &ga, &gb),
                             SUNMC_OK);
            worst_paper = fmax(worst_paper, fabs(ga - ar) * ARCSEC_PER_RAD);
        }
    assert_true(worst_paper > 3600);
    double ga, gb; /* the centre, where r = 0 */
    assert_int_equal(dss_onboard_angles(&o, 0, 0, &ga, &gb), SUNMC_OK);
    assert_true(ga == 0 && gb == 0);
}

/* ---- installation rotations ---- */

/* Without glass, the on-board angles of a mounted unit are those of u:
 * tan alpha_m = u_x / u_z (the spot is -h u_xy / u_z). */
static void test_installation_rotations(void **state)
{
    sunmc_config c = default_dss();
    dss_cfg(&c)->design.glass_thickness_mm = 0;
    const double sets[][5] = {{10, 0, 0, 0, 0},        {0, 10, 0, 0, 0},   {0, 0, 10, 0, 0},
                              {3600, -1800, 900, 0, 0}, {-7, 12, -20, 0, 0}, {0, 0, 0, 10, 0},
                              {0, 0, 0, 0, 10},         {-7, 12, -20, 30, -45}};
    for (int mount = DSS_MOUNT_ALIGNED; mount <= DSS_MOUNT_AS_MOUNTED; mount++)
    for (size_t k = 0; k < sizeof sets / sizeof sets[0]; k++) {
        dss_cfg(&c)->design.mount = mount;
        dss_deviations d = {0};
        d.c1_arcsec = sets[k][0];
        d.c2_arcsec = sets[k][1];
        d.c3_arcsec = sets[k][2];
        d.sun_b1_arcsec = sets[k][3];
        d.sun_b2_arcsec = sets[k][4];
        double sun[2] = {d.sun_b1_arcsec * RAD_PER_ARCSEC, d.sun_b2_arcsec * RAD_PER_ARCSEC};
        dss_sensor s;
        dss_sensor_init(&s, &dss_cfg(&c)->design, &d, 0);
        for (double b1 = -40; b1 <= 40; b1 += 8)
            for (double b2 = -40; b2 <= 40; b2 += 8) {
                double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG, u[3], got[3], x, y, am, bm;
                ref_sun_general(d.c1_arcsec * RAD_PER_ARCSEC, d.c2_arcsec * RAD_PER_ARCSEC,
                                d.c3_arcsec * RAD_PER_ARCSEC,
                                mount == DSS_MOUNT_ALIGNED ? NULL : sun, r1, r2, u);
                dss_sensor_sun(&s, r1, r2, got);
                for (int i = 0; i < 3; i++)
                    assert_near(got[i], u[i], 1e-14);
                assert_int_equal(dss_sensor_read(&s, r1, r2, NULL, &x, &y), SUNMC_OK);
                dss_sensor_angles(&s, x, y, &am, &bm);
                assert_near(am * ARCSEC_PER_RAD, atan(u[0] / u[2]) * ARCSEC_PER_RAD, 1e-6);
                assert_near(bm * ARCSEC_PER_RAD, atan(u[1] / u[2]) * ARCSEC_PER_RAD, 1e-6);
            }
    }
}

/* c3 alone turns the tangents: tan alpha_m = cos c3 tan a + sin c3 tan b,
 * tan beta_m = -sin c3 tan a + cos c3 tan b, exactly. */
static void test_c3_closed_form(void **state)
{
    sunmc_config c = default_dss();
    dss_cfg(&c)->design.glass_thickness_mm = 0;
    const double c3s[] = {10, -10, 7200};
    for (size_t k = 0; k < 3; k++) {
        dss_deviations d = {0};
        d.c3_arcsec = c3s[k];
        dss_sensor s;
        dss_sensor_init(&s, &dss_cfg(&c)->design, &d, 0);
        double g = c3s[k] * RAD_PER_ARCSEC;
        for (double b1 = -40; b1 <= 40; b1 += 10)
            for (double b2 = -40; b2 <= 40; b2 += 10) {
                double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG, a0, b0, x, y, am, bm;
                ref_table_truth(r1, r2, &a0, &b0);
                assert_int_equal(dss_sensor_read(&s, r1, r2, NULL, &x, &y), SUNMC_OK);
                dss_sensor_angles(&s, x, y, &am, &bm);
                double ta = cos(g) * tan(a0) + sin(g) * tan(b0);
                double tb = -sin(g) * tan(a0) + cos(g) * tan(b0);
                assert_near(am * ARCSEC_PER_RAD, atan(ta) * ARCSEC_PER_RAD, 1e-6);
                assert_near(bm * ARCSEC_PER_RAD, atan(tb) * ARCSEC_PER_RAD, 1e-6);
            }
    }
}

/* ---- the detector edge ---- */

/* A spot is seen while its whole disc is on the detector: |centre| <=
 * (detector_px pixel - pinhole) / 2 on both axes.  Checked just inside and
 * just outside, on both axes and both sides, for a small and a large
 * pinhole. */
static void test_detector_edge(void **state)
{
    const double pinholes_um[] = {60, 500};
    for (size_t k = 0; k < 2; k++) {
        sunmc_config c = default_dss();
        dss_cfg(&c)->design.glass_thickness_mm = 0;
        dss_cfg(&c)->design.pinhole_um = pinholes_um[k];
        dss_deviations d = {0};
        dss_sensor s;
        dss_sensor_init(&s, &dss_cfg(&c)->design, &d, 0);
        const double h = dss_cfg(&c)->design.h_mm, pix = dss_cfg(&c)->design.pixel_um * MM_PER_UM;
        const double lim = 0.5 * (dss_cfg(&c)->design.detector_px * dss_cfg(&c)->design.pixel_um - pinholes_um[k]) * MM_PER_UM;
        for (int axis = 0; axis < 2; axis++)
            for (int sign = -1; sign <= 1; sign += 2)
                for (int outside = 0; outside < 2; outside++) {
                    double X = sign * lim * (outside ? 1 + 1e-9 : 1 - 1e-9);
                    /* the spot is -h tan(theta) along the sun's azimuth */
                    double th = atan(fabs(X) / h), u[3] = {0, 0, cos(th)};
                    u[axis] = -(X > 0 ? 1 : -1) * sin(th);
                    u[1 - axis] = 0;
                    double x = NAN, y = NAN;
                    int st = dss_sensor_spot(&s, u, NULL, &x, &y);
                    if (outside) {
                        assert_int_equal(st, SUNMC_EDOM);
                    } else {
                        assert_int_equal(st, SUNMC_OK);
                        assert_near(axis == 0 ? x : y, X / pix, 1e-6);
                        assert_near(axis == 0 ? y : x, 0.0, 1e-9);
                    }
                }
    }
    /* 5.5 mm from the centre: on the detector for a 60 um pinhole, off it
     * for a 500 um one (the disc would stick out). */
    sunmc_config c = default_dss();
    dss_cfg(&c)->design.glass_thickness_mm = 0;
    const double th = atan(5.5 / dss_cfg(&c)->design.h_mm), u[3] = {-sin(th), 0, cos(th)};
    dss_deviations d = {0};
    dss_sensor s;
    double x, y;
    dss_sensor_init(&s, &dss_cfg(&c)->design, &d, 0);
    assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_OK);
    dss_cfg(&c)->design.pinhole_um = 500;
    dss_sensor_init(&s, &dss_cfg(&c)->design, &d, 0);
    assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_EDOM);
}

/* ---- S-curve ---- */

/* Simpson's rule for Bessel's integral J1(z) = (1/pi) int_0^pi cos(t - z sin t) dt. */
static double bessel_j1(double z)
{
    const int n = 4000;
    double h = M_PI / n, s = cos(0.0) + cos(M_PI - z * sin(M_PI));
    for (int i = 1; i < n; i++) {
        double t = i * h;
        s += (i % 2 ? 4.0 : 2.0) * cos(t - z * sin(t));
    }
    return s * h / 3.0 / M_PI;
}

/* Amplitude k: (-1)^k F(k) / (pi k), F(k) = 2 J1(pi D k) / (pi D k). */
static void test_scurve_amplitudes(void **state)
{
    const double sizes[] = {2.5, 4.0, 60.0 / 5.5, 23.7};
    for (size_t i = 0; i < 4; i++) {
        double amp[DSS_SCURVE_HARMONICS];
        dss_scurve_amplitudes(sizes[i], amp);
        for (int k = 1; k <= 8; k++) {
            double z = M_PI * sizes[i] * k;
            double want = (k % 2 ? -1.0 : 1.0) * 2 * bessel_j1(z) / z / (M_PI * k);
            assert_near(amp[k - 1], want, 1e-12);
        }
    }
}

/* Bias of the centroid of a disc spot of diameter D px centred at x0. */
static double brute_bias(double D, double x0) { return test_disc_centroid(D, x0) - x0; }

/* The sensor's measured spot with the S-curve on: pixel centres sit at the
 * detector centre + 1/2 for an even number of pixels, at the centre for an
 * odd one; the bias is that of a disc of the pinhole's diameter in pixels,
 * on each axis; noise is added after. */
static void test_scurve_pixel_phase(void **state)
{
    const int detectors[] = {2048, 2047};
    const double pinholes_um[] = {13.75, 60};
    const double spots_px[][2] = {{0.25, 0.1},  {0.5, -0.25}, {0.75, 0.6},  {1.1, -3.3},
                                  {-0.3, 0.45}, {100.37, 7.8}, {-200.2, -0.9}};
    for (int di = 0; di < 2; di++)
        for (int pi = 0; pi < 2; pi++) {
            sunmc_config c = default_dss();
            dss_cfg(&c)->design.glass_thickness_mm = 0;
            dss_cfg(&c)->design.wavelength_nm = 0; /* the geometric disc's S-curve */
            dss_cfg(&c)->design.detector_px = detectors[di];
            dss_cfg(&c)->design.pinhole_um = pinholes_um[pi];
            dss_deviations d = {0};
            dss_sensor s, s0;
            dss_sensor_init(&s, &dss_cfg(&c)->design, &d, 1);
            dss_sensor_init(&s0, &dss_cfg(&c)->design, &d, 0);
            const double D = pinholes_um[pi] / dss_cfg(&c)->design.pixel_um;
            const double phase = detectors[di] % 2 == 0 ? 0.5 : 0.0;
            const double tol = D < 5 ? 3e-5 : 5e-6;
            const double h = dss_cfg(&c)->design.h_mm, pix = dss_cfg(&c)->design.pixel_um * MM_PER_UM;
            double peak = 0;
            for (size_t k = 0; k < sizeof spots_px / sizeof spots_px[0]; k++) {
                double X = spots_px[k][0], Y = spots_px[k][1];
                /* a sun whose spot lands at (X, Y) px */
                double u[3] = {-X * pix / h, -Y * pix / h, 1};
                double nrm = sqrt(u[0] * u[0] + u[1] * u[1] + 1);
                for (int i = 0; i < 3; i++)
                    u[i] /= nrm;
                double x0, y0, x, y;
                assert_int_equal(dss_sensor_spot(&s0, u, NULL, &x0, &y0), SUNMC_OK);
                assert_near(x0, X, 1e-9);
                assert_near(y0, Y, 1e-9);
                assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_OK);
                double bx = brute_bias(D, X - phase), by = brute_bias(D, Y - phase);
                assert_near(x, X + bx, tol);
                assert_near(y, Y + by, tol);
                peak = fmax(peak, fabs(bx));
                const double noise[2] = {0.031, -0.017};
                assert_int_equal(dss_sensor_spot(&s, u, noise, &x, &y), SUNMC_OK);
                assert_near(x, X + bx + noise[0], tol);
                assert_near(y, Y + by + noise[1], tol);
            }
            assert_true(peak > 20 * tol); /* the comparison sees the S-curve */
        }
}

/* ---- the calibration model and its inverse ---- */

typedef struct {
    double x0, y0, H, t, c1, c2, c3, n;
} ref_params;

static const ref_params params[] = {
    {0.0, 0.0, 3.0, 0.4, 0, 0, 0, 1.52},
    {5.5e-4, -3.3e-4, 3.0011, 0.41, 4.8e-5, -3.9e-5, 2.4e-5, 1.523},
    {-0.02, 0.015, 2.8, 0.6, 0.01, 0.02, -0.03, 1.7},
    {0.001, 0.002, 3.2, 0.0, -2e-4, 1e-4, 3e-4, 1.5},
};

static void to_model(const ref_params *r, double pixel_mm, dss_model *m)
{
    memset(m, 0, sizeof *m);
    m->p[DSS_P_X0] = r->x0;
    m->p[DSS_P_Y0] = r->y0;
    m->p[DSS_P_H] = r->H;
    m->p[DSS_P_T] = r->t;
    m->p[DSS_P_C1] = r->c1;
    m->p[DSS_P_C2] = r->c2;
    m->p[DSS_P_C3] = r->c3;
    m->p[DSS_P_N] = r->n;
    m->pixel_mm = pixel_mm;
    dss_model_prepare(m);
}

/* The model's spot is the written-out chain; compensating that spot gives
 * the truth back to 1e-10 rad: aligned, the table's angles (eq. 3-4); as
 * mounted, the angles of the sun w = R(b) v_sun in the table-top frame. */
static void test_model_and_inverse(void **state)
{
    const double pix = 5.5e-3, sun[2] = {3e-4, -2.2e-4};
    for (size_t k = 0; k < 2 * sizeof params / sizeof params[0]; k++) {
        const ref_params *r = &params[k / 2];
        int mounted = k % 2;
        dss_model m;
        to_model(r, pix, &m);
        if (mounted) {
            m.mount = DSS_MOUNT_AS_MOUNTED;
            m.p[DSS_P_S1] = sun[0];
            m.p[DSS_P_S2] = sun[1];
            dss_model_prepare(&m);
        }
        dss_calibration cal;
        memset(&cal, 0, sizeof cal);
        cal.kind = DSS_MODEL_PHYSICAL;
        cal.phys = m;
        for (double b1 = -58; b1 <= 58; b1 += 4.7)
            for (double b2 = -58; b2 <= 58; b2 += 4.7) {
                double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG, u[3], want[2], got[2];
                ref_sun_general(r->c1, r->c2, r->c3, mounted ? sun : NULL, r1, r2, u);
                ref_spot_mm(u, r->x0, r->y0, r->H, r->t, r->n, want);
                assert_int_equal(dss_model_spot(&m, r1, r2, got, NULL), SUNMC_OK);
                assert_near(got[0], want[0] / pix, 1e-9);
                assert_near(got[1], want[1] / pix, 1e-9);
                double a, b, a0, b0;
                ref_table_truth(r1, r2, &a0, &b0);
                if (mounted) {
                    double w[3] = {0, 0, 1};
                    rx(sun[0], w, w);
                    ry(sun[1], w, w);
                    rx(r1, w, w);
                    ry(r2, w, w);
                    a0 = atan(w[0] / w[2]);
                    b0 = atan(w[1] / w[2]);
                }
                assert_int_equal(dss_model_compensate(&m, want[0] / pix, want[1] / pix, &a, &b),
                                 SUNMC_OK);
                assert_near(a, a0, 1e-10);
                assert_near(b, b0, 1e-10);
                assert_int_equal(dss_compensate(&cal, want[0] / pix, want[1] / pix, &a, &b),
                                 SUNMC_OK);
                assert_near(a, a0, 1e-10);
                assert_near(b, b0, 1e-10);
            }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spot_through_glass),
        cmocka_unit_test(test_onboard_formula),
        cmocka_unit_test(test_onboard_corrected),
        cmocka_unit_test(test_installation_rotations),
        cmocka_unit_test(test_c3_closed_form),
        cmocka_unit_test(test_detector_edge),
        cmocka_unit_test(test_scurve_amplitudes),
        cmocka_unit_test(test_scurve_pixel_phase),
        cmocka_unit_test(test_model_and_inverse),
    };
    return cmocka_run_group_tests_name("dss_closed_forms", tests, NULL, NULL);
}
