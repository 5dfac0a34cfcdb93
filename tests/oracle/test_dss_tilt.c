/* test_dss_tilt.c - the detector plane tilted against the mask (issue 38,
 * dss_sensor.h "Detector tilt") against values this file works out on its
 * own: the untilted spot by the plate's lateral displacement (as
 * test_dss_closed_forms.c), then the exact intersection of the ray with the
 * tilted plane, solved here from the plane's normal and axes written out
 * with rotations of this file, and the closed form of a one-axis tilt by
 * the law of sines in the ray's plane.
 *
 * Conventions (rotation.h): passive Rx(a) = [1 0 0; 0 c s; 0 -s c],
 * Ry(a) = [c 0 -s; 0 1 0; s 0 c]; the detector's frame is D = Ry(ty) Rx(tx)
 * of the sensor frame, so its axes and normal in the sensor frame are
 * D^T e_x, D^T e_y, D^T e_z = Rx(-tx) Ry(-ty) e_i. */
#include "test_util.h"

#include "config.h"
#include "dss_config.h"
#include "dss_sensor.h"
#include "optics.h"
#include "status.h"
#include "units.h"

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
static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Untilted spot (mm) of sun u through a pinhole at (0, 0, H) and a plate
 * t, n: the plate displaces the ray by t (tan th - tan thg) along the
 * detector. */
static void ref_spot_mm(const double u[3], double H, double t, double n, double spot[3])
{
    double th = acos(u[2]), ph = atan2(u[1], u[0]);
    double thg = asin(sin(th) / n);
    double r = H * tan(th) - t * (tan(th) - tan(thg));
    spot[0] = -r * cos(ph);
    spot[1] = -r * sin(ph);
    spot[2] = 0.0;
}

/* The ray p0 - s u meets the plane through the origin with normal N where
 * N.(p0 - s u) = 0; the spot is that point on the plane's axes (px). */
static void ref_tilted_px(const double u[3], const double p0[3], double tx, double ty,
                          double pix_mm, double out[2])
{
    double e[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < 3; i++) {
        ry(-ty, e[i], e[i]);
        rx(-tx, e[i], e[i]);
    }
    double s = dot(e[2], p0) / dot(e[2], u);
    double p[3] = {p0[0] - s * u[0], p0[1] - s * u[1], p0[2] - s * u[2]};
    assert_near(dot(e[2], p), 0.0, 1e-15); /* on the plane */
    out[0] = dot(e[0], p) / pix_mm;
    out[1] = dot(e[1], p) / pix_mm;
}

typedef struct {
    sunmc_config c;
    double H, t, n, pix;
} setup;

static setup default_setup(void)
{
    setup s = {.c = test_family_config("dss")};
    const dss_design *d = &dss_cfg(&s.c)->design;
    s.H = d->h_mm;
    s.t = d->glass_thickness_mm;
    s.n = d->glass_index;
    s.pix = d->pixel_um * MM_PER_UM;
    return s;
}

/* One degree about X moves a spot at field angle 40 deg in the Y-Z plane
 * to y0 cos th / cos(th + a) (law of sines: the ray meets the tilted line
 * at angle 90 - th - a); about Y, in the X-Z plane, x0 cos th / cos(th - a). */
static void test_one_axis_closed_form(void **state)
{
    (void)state;
    setup e = default_setup();
    const double a = 1.0 * RAD_PER_DEG, th = 40.0 * RAD_PER_DEG;
    for (int axis = 0; axis < 2; axis++)
        for (int sign = -1; sign <= 1; sign += 2) {
            dss_deviations d = {0};
            if (axis == 0)
                d.detector_tilt_x_arcsec = sign * 3600.0;
            else
                d.detector_tilt_y_arcsec = sign * 3600.0;
            dss_sensor s;
            dss_sensor_init(&s, &dss_cfg(&e.c)->design, &d, 0);
            double u[3] = {0, 0, cos(th)}, p0[3], x = NAN, y = NAN;
            u[axis == 0 ? 1 : 0] = sin(th);
            ref_spot_mm(u, e.H, e.t, e.n, p0);
            assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_OK);
            double r0 = p0[axis == 0 ? 1 : 0] / e.pix; /* -(H - t) tan th - t tan thg */
            double want = axis == 0 ? r0 * cos(th) / cos(th + sign * a)
                                    : r0 * cos(th) / cos(th - sign * a);
            assert_near(axis == 0 ? y : x, want, 1e-9);
            assert_near(axis == 0 ? x : y, 0.0, 1e-12);
            /* the move itself: about 1.4 % of the spot's 470 px */
            assert_true(fabs(want - r0) > 5.0);
        }
}

/* Both angles, suns over the field: the exact ray-plane intersection. */
static void test_two_axes_intersection(void **state)
{
    (void)state;
    setup e = default_setup();
    const double tilts[][2] = {{360, 0}, {0, -360}, {360, 360}, {-1800, 900}, {7200, -3600}};
    for (size_t k = 0; k < sizeof tilts / sizeof tilts[0]; k++) {
        dss_deviations d = {.detector_tilt_x_arcsec = tilts[k][0],
                            .detector_tilt_y_arcsec = tilts[k][1]};
        dss_sensor s;
        dss_sensor_init(&s, &dss_cfg(&e.c)->design, &d, 0);
        int seen = 0;
        for (double al = -55; al <= 55; al += 5.5)
            for (double be = -55; be <= 55; be += 5.5) {
                double u[3] = {tan(al * RAD_PER_DEG), tan(be * RAD_PER_DEG), 1}, p0[3], want[2];
                double norm = sqrt(dot(u, u)), x = NAN, y = NAN;
                for (int i = 0; i < 3; i++)
                    u[i] /= norm;
                ref_spot_mm(u, e.H, e.t, e.n, p0);
                ref_tilted_px(u, p0, tilts[k][0] * RAD_PER_ARCSEC, tilts[k][1] * RAD_PER_ARCSEC,
                              e.pix, want);
                if (dss_sensor_spot(&s, u, NULL, &x, &y) != SUNMC_OK) {
                    /* off the detector: the tilted spot's disc leaves it */
                    double lim = 0.5 * dss_cfg(&e.c)->design.detector_px -
                                 0.5 * dss_spot_px(&dss_cfg(&e.c)->design);
                    assert_true(fabs(want[0]) > lim - 1e-6 || fabs(want[1]) > lim - 1e-6);
                    continue;
                }
                assert_near(x, want[0], 1e-9);
                assert_near(y, want[1], 1e-9);
                seen++;
            }
        assert_true(seen > 300); /* of 441 */
    }
}

/* The detector's edge is judged in the tilted axes: a spot just inside
 * the edge along the tilted Y is seen, just outside is not. */
static void test_edge_in_tilted_axes(void **state)
{
    (void)state;
    setup e = default_setup();
    dss_deviations d = {.detector_tilt_x_arcsec = 3600};
    dss_sensor s;
    dss_sensor_init(&s, &dss_cfg(&e.c)->design, &d, 0);
    const double lim = 0.5 * dss_cfg(&e.c)->design.detector_px -
                       0.5 * dss_spot_px(&dss_cfg(&e.c)->design);
    /* bisect the field angle whose tilted spot sits at -lim */
    double lo = 0.5, hi = 1.3;
    for (int i = 0; i < 200; i++) {
        double mid = 0.5 * (lo + hi), u[3] = {0, sin(mid), cos(mid)}, p0[3], w[2];
        ref_spot_mm(u, e.H, e.t, e.n, p0);
        ref_tilted_px(u, p0, 3600 * RAD_PER_ARCSEC, 0, e.pix, w);
        if (-w[1] < lim)
            lo = mid;
        else
            hi = mid;
    }
    double x, y, u_in[3] = {0, sin(lo - 1e-7), cos(lo - 1e-7)};
    double u_out[3] = {0, sin(hi + 1e-7), cos(hi + 1e-7)};
    assert_int_equal(dss_sensor_spot(&s, u_in, NULL, &x, &y), SUNMC_OK);
    assert_true(y < -lim + 0.01);
    assert_int_equal(dss_sensor_spot(&s, u_out, NULL, &x, &y), SUNMC_EDOM);
    /* untilted, the same sun is still on the detector (the tilt pushed it off) */
    dss_deviations d0 = {0};
    dss_sensor_init(&s, &dss_cfg(&e.c)->design, &d0, 0);
    assert_int_equal(dss_sensor_spot(&s, u_out, NULL, &x, &y), SUNMC_OK);
}

/* A sun in front of the mask but behind the tilted plane (field angle 85
 * deg, tilt 10 deg, the key's maximum, toward it) is not seen: its ray
 * meets the plane's extension behind the pinhole, which with a low pinhole
 * (0.3 mm, no glass) would land on the detector at -y0, 3.4 mm out. */
static void test_sun_behind_tilted_plane(void **state)
{
    (void)state;
    setup e = default_setup();
    dss_design g = dss_cfg(&e.c)->design;
    g.h_mm = 0.3;
    g.glass_thickness_mm = 0.0;
    const double th = 85.0 * RAD_PER_DEG, u[3] = {0, sin(th), cos(th)};
    dss_deviations d = {0};
    dss_sensor s;
    double x, y;
    dss_sensor_init(&s, &g, &d, 0);
    assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_OK); /* untilted: seen */
    assert_near(y * s.pixel_mm, -0.3 * tan(th), 1e-9);
    d.detector_tilt_x_arcsec = 36000;
    dss_sensor_init(&s, &g, &d, 0);
    assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_EDOM);
    d.detector_tilt_x_arcsec = -36000; /* tilted away: in front, nearer the centre, seen */
    dss_sensor_init(&s, &g, &d, 0);
    assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_OK);
    assert_near(y * s.pixel_mm, -0.3 * tan(th) * cos(th) / cos(th - 10.0 * RAD_PER_DEG), 1e-9);
}

/* Zero tilt is the untilted trace to the bit (optics_trace, the scalar
 * ray trace the sensor's spot is documented to equal). */
static void test_zero_tilt_bitwise(void **state)
{
    (void)state;
    setup e = default_setup();
    dss_deviations d = {.dh_px = 0.2, .dx_px = -0.1, .dy_px = 0.07, .glass_thickness_um = 5};
    dss_sensor s;
    dss_sensor_init(&s, &dss_cfg(&e.c)->design, &d, 0);
    for (double al = -50; al <= 50; al += 7.3)
        for (double be = -50; be <= 50; be += 7.3) {
            double u[3] = {tan(al * RAD_PER_DEG), tan(be * RAD_PER_DEG), 1}, sp[2], x, y;
            double norm = sqrt(dot(u, u));
            for (int i = 0; i < 3; i++)
                u[i] /= norm;
            assert_int_equal(dss_sensor_spot(&s, u, NULL, &x, &y), SUNMC_OK);
            assert_int_equal(optics_trace(u, s.pinhole_mm, 0.0, s.glass_t_mm, s.glass_n, sp),
                             SUNMC_OK);
            assert_true(x == sp[0] / s.pixel_mm);
            assert_true(y == sp[1] / s.pixel_mm);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_one_axis_closed_form),
        cmocka_unit_test(test_two_axes_intersection),
        cmocka_unit_test(test_edge_in_tilted_axes),
        cmocka_unit_test(test_sun_behind_tilted_plane),
        cmocka_unit_test(test_zero_tilt_bitwise),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
