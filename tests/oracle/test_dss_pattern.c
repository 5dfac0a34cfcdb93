/* test_dss_pattern.c - the detector's fixed pattern (PRNU, DSNU) and the
 * cover glass's ghost in the DSS centroid (issue 38, dss_pattern.h)
 * against what this file works out on its own: the windowed centroid of
 * the sampled Gaussian spot summed pixel by pixel with its own weights,
 * the first-order rms of a pattern of known variance, the ghost's pull
 * from the two spots' light integrated numerically over the window, the
 * Fresnel reflectance from Snell's law by angles; and the pattern's
 * identity: the same for repeats, another for another unit or seed. */
#include "test_util.h"

#include "config.h"
#include "dss_config.h"
#include "dss_pattern.h"
#include "dss_sensor.h"
#include "dss_unit.h"
#include "status.h"
#include "rng.h"
#include "units.h"

/* The design's spot: sigma = D / 4 = 60 / 5.5 / 4 px, window 2 * 7 + 1. */
static dss_pattern pattern_of(double prnu, double dsnu, uint32_t key)
{
    dss_pattern p;
    dss_pattern_init(&p, 60.0 / 5.5 / 4.0, 0.5);
    p.prnu = prnu;
    p.dsnu = dsnu;
    p.key = key;
    return p;
}

/* The windowed centroid error summed pixel by pixel: weights by exp(),
 * the pixel's gain and dark offset by dss_pattern_pixel, the pattern-free
 * centroid subtracted. */
static void brute_error(const dss_pattern *p, double x, double y, double e[2])
{
    int m = p->half_px;
    long i0 = lround(x - p->phase_px) - m, j0 = lround(y - p->phase_px) - m;
    double S = 0, Sx = 0, Sy = 0, W = 0, Wx = 0, Wy = 0;
    for (long j = j0; j <= j0 + 2 * m; j++)
        for (long i = i0; i <= i0 + 2 * m; i++) {
            double dx = p->phase_px + (double)i - x, dy = p->phase_px + (double)j - y;
            double w = exp(-(dx * dx + dy * dy) / (2 * p->sigma_px * p->sigma_px));
            double g, d;
            dss_pattern_pixel(p, (int32_t)i, (int32_t)j, &g, &d);
            double v = w * (1 + g) + d;
            S += v;
            Sx += dx * v;
            Sy += dy * v;
            W += w;
            Wx += dx * w;
            Wy += dy * w;
        }
    e[0] = Sx / S - Wx / W;
    e[1] = Sy / S - Wy / W;
}

static void test_window_of_the_spot(void **state)
{
    (void)state;
    dss_pattern p = pattern_of(0, 0, 0);
    assert_near(p.sigma_px, 60.0 / 5.5 / 4.0, 1e-15);
    assert_int_equal(p.half_px, 7); /* ceil(2.5 * 2.727) */
    /* the smallest and largest windows, and one past */
    assert_int_equal(dss_window_half_px(0.01), 1);
    assert_int_equal(dss_window_half_px(0.5), 2);
    assert_int_equal(dss_window_half_px(25.0), 63);
    assert_int_equal(dss_window_half_px(25.5), DSS_WINDOW_HALF_MAX);
    assert_int_equal(dss_window_half_px(30.0), DSS_WINDOW_HALF_MAX);
    dss_pattern_init(&p, 1000.0, 0.0);
    assert_int_equal(p.half_px, DSS_WINDOW_HALF_MAX);
    /* the design's spot: the disc, the Airy core at 650 nm and the sun's
     * disc in quadrature; its window */
    sunmc_config c = test_family_config("dss");
    dss_design d; /* copied bytewise: the config holds it in a byte blob */
    memcpy(&d, &dss_cfg(&c)->design, sizeof d);
    double D = d.pinhole_um / d.pixel_um;
    double airy = 0.42 * 650e-6 * d.h_mm / (d.pinhole_um * 1e-3) / (d.pixel_um * 1e-3);
    assert_near(dss_spot_sigma_px(&d), sqrt(D * D / 16 + airy * airy), 1e-12);
    d.sun_disc_deg = 0.533;
    double Ds = (d.h_mm - d.glass_thickness_mm + d.glass_thickness_mm / d.glass_index) *
                0.533 * M_PI / 180 / (d.pixel_um * 1e-3);
    assert_near(dss_spot_sun_px(&d), Ds, 1e-12);
    assert_near(dss_spot_sigma_px(&d), sqrt(D * D / 16 + airy * airy + Ds * Ds / 16), 1e-12);
    assert_int_equal(dss_window_half_px(dss_spot_sigma_px(&d)), 10);
    /* the sensor's pattern sums over that window, or the design's own */
    dss_deviations z = {0};
    dss_sensor s;
    dss_sensor_init(&s, &d, &z, 0);
    assert_int_equal(s.pattern.half_px, 10);
    d.centroid_window_px = 4;
    dss_sensor_init(&s, &d, &z, 0);
    assert_int_equal(s.pattern.half_px, 4);
}

/* The pattern's error is the windowed centroid's, pixel by pixel. */
static void test_pattern_against_pixel_sum(void **state)
{
    (void)state;
    const double pos[][2] = {{0.3, -0.2}, {412.77, -96.5}, {-1003.49, 7.01}, {0.5, 0.5}};
    const double mix[][2] = {{0.01, 0}, {0, 0.001}, {0.02, 0.003}};
    for (size_t k = 0; k < 3; k++)
        for (size_t q = 0; q < 4; q++) {
            dss_pattern p = pattern_of(mix[k][0], mix[k][1], 12345u + (uint32_t)k);
            double ex, ey, want[2];
            dss_pattern_error(&p, pos[q][0], pos[q][1], &ex, &ey);
            brute_error(&p, pos[q][0], pos[q][1], want);
            assert_near(ex, want[0], 1e-9); /* weights rounded to 2^-23 */
            assert_near(ey, want[1], 1e-9);
            assert_true(fabs(ex) + fabs(ey) > 1e-6); /* a pattern is there */
        }
    /* no pattern: nothing, bit for bit */
    dss_pattern p = pattern_of(0, 0, 99);
    double ex = 1, ey = 1;
    dss_pattern_error(&p, 10.3, -4.2, &ex, &ey);
    assert_true(ex == 0.0 && ey == 0.0);
}

/* Over many positions the error's rms is the first-order closed form
 * sqrt(prnu^2 sum x^2 w^2 + dsnu^2 sum x^2) / sum w (pixel values of unit
 * variance), to the sampling's 3 %; PRNU 1 % alone gives 0.2 % of a pixel
 * (sigma_p / sqrt(8 pi) for a wide Gaussian). */
static void test_pattern_rms_closed_form(void **state)
{
    (void)state;
    const double mix[][2] = {{0.01, 0}, {0, 0.001}};
    for (int k = 0; k < 2; k++) {
        dss_pattern p = pattern_of(mix[k][0], mix[k][1], 777u);
        double s2 = 0;
        long n = 0;
        for (int a = 0; a < 60; a++)
            for (int b = 0; b < 60; b++) {
                double ex, ey;
                /* 17.3 px apart: windows that share no pixel */
                dss_pattern_error(&p, 17.3 * a - 500.0 + 0.37 * b, 17.3 * b - 500.0, &ex, &ey);
                s2 += ex * ex + ey * ey;
                n += 2;
            }
        double rms = sqrt(s2 / (double)n);
        /* the closed form at a spot centred on a pixel corner's average: the
         * sums over the window at phase 0.25 */
        double sw = 0, sxw2 = 0, sx2 = 0, x0 = 0.25, y0 = 0.4;
        int m = p.half_px;
        for (int j = -m; j <= m; j++)
            for (int i = -m; i <= m; i++) {
                double dx = i - x0, dy = j - y0;
                double w = exp(-(dx * dx + dy * dy) / (2 * p.sigma_px * p.sigma_px));
                sw += w;
                sxw2 += dx * dx * w * w;
                sx2 += dx * dx;
            }
        double want = sqrt(mix[k][0] * mix[k][0] * sxw2 + mix[k][1] * mix[k][1] * sx2) / sw;
        assert_near(rms / want, 1.0, 0.03);
        if (k == 0)
            assert_near(rms, 0.01 / sqrt(8 * M_PI), 0.0003);
    }
}

/* A unit's pattern: the same spot for repeats and rebuilds, another for
 * another unit or another seed; deterministic in (seed, unit). */
static void test_pattern_per_unit(void **state)
{
    (void)state;
    sunmc_config c = test_family_config("dss");
    double u[3] = {sin(0.2), 0.1, 0}, xs[4], ys[4];
    u[2] = sqrt(1 - u[0] * u[0] - u[1] * u[1]);
    const long units[4] = {3, 3, 4, 3};
    const uint64_t seeds[4] = {1, 1, 1, 2};
    for (int k = 0; k < 4; k++) {
        dss_deviations d;
        dss_deviations_sample(&c, seeds[k], units[k], &d);
        /* uniform below the datasheet's bounds; the ghost fixed */
        assert_true(fabs(d.prnu_pct) <= 1.0 && d.prnu_pct != 0.0);
        assert_true(fabs(d.dsnu_pct) <= 0.1 && d.dsnu_pct != 0.0);
        assert_near(d.glass_ghost, 1.0, 0);
        memset(&d, 0, sizeof d);
        d.prnu_pct = 1.0;
        d.dsnu_pct = 0.1;
        dss_unit un;
        dss_unit_build(&c, &d, &un);
        dss_unit_set_pattern(&c, seeds[k], units[k], &un);
        assert_int_equal(dss_sensor_spot(&un.sensor, u, NULL, &xs[k], &ys[k]), SUNMC_OK);
    }
    assert_true(xs[0] == xs[1] && ys[0] == ys[1]);
    assert_true(xs[2] != xs[0] && ys[2] != ys[0]);
    assert_true(xs[3] != xs[0] && ys[3] != ys[0]);
    assert_int_equal(dss_pattern_key(&c, 1, 3), dss_pattern_key(&c, 1, 3));
    /* the key is seeded as prnu_pct's stream: its line of the list */
    int found = 0;
    for (int e = 0; e < DSS_N_TOL; e++)
        if (strcmp(dss_deviation_list[e].name, "prnu_pct") == 0) {
            assert_int_equal(dss_deviation_list[e].stream, DSS_PRNU_STREAM);
            found = 1;
        }
    assert_true(found);
    /* a pick-freeze of that stream freezes the pattern; of another, not */
    sunmc_config cp = c;
    cp.pick.n = 1;
    cp.pick.seed = 99;
    cp.pick.stream[0] = RNG_STREAM_TOLERANCE + DSS_PRNU_STREAM;
    assert_int_equal(dss_pattern_key(&cp, 1, 3), dss_pattern_key(&c, 99, 3));
    cp.pick.stream[0] = RNG_STREAM_TOLERANCE + 17;
    assert_int_equal(dss_pattern_key(&cp, 1, 3), dss_pattern_key(&c, 1, 3));
    assert_true(dss_pattern_key(&c, 1, 3) != dss_pattern_key(&c, 1, 4));
    /* the readings repeat: dss_sensor_read gives the same spot as _spot */
    dss_deviations d = {.prnu_pct = 1.0, .dsnu_pct = 0.1};
    dss_unit un;
    dss_unit_build(&c, &d, &un);
    dss_unit_set_pattern(&c, 1, 3, &un);
    double x1, y1, x2, y2, a1, b1;
    assert_int_equal(dss_sensor_read(&un.sensor, 0.1, -0.2, NULL, &x1, &y1), SUNMC_OK);
    assert_int_equal(dss_sensor_read(&un.sensor, 0.1, -0.2, NULL, &x2, &y2), SUNMC_OK);
    assert_true(x1 == x2 && y1 == y2);
    double uu[3];
    dss_sensor_sun(&un.sensor, 0.1, -0.2, uu);
    assert_int_equal(dss_sensor_spot(&un.sensor, uu, NULL, &a1, &b1), SUNMC_OK);
    assert_near(a1, x1, 1e-9);
    assert_near(b1, y1, 1e-9);
}

/* Fresnel's reflectances from the angles (Snell), both polarisations
 * reflected twice, averaged. */
static double ref_ghost(double th, double n)
{
    double tt = asin(sin(th) / n);
    double rs = th == 0 ? (1 - n) / (1 + n) : -sin(th - tt) / sin(th + tt);
    double rp = th == 0 ? (n - 1) / (n + 1) : tan(th - tt) / tan(th + tt);
    return 0.5 * (pow(rs, 4) + pow(rp, 4));
}

static void test_ghost_intensity(void **state)
{
    (void)state;
    assert_near(dss_ghost_intensity(1.0, 1.52), pow(0.52 / 2.52, 4), 1e-15);
    assert_near(dss_ghost_intensity(1.0, 1.52), 0.00181, 0.00001); /* 0.18 % */
    for (double th = 5; th < 89; th += 7)
        assert_near(dss_ghost_intensity(cos(th * RAD_PER_DEG), 1.52) /
                        ref_ghost(th * RAD_PER_DEG, 1.52), 1.0, 1e-12);
}

/* Mass and first moment about x of a Gaussian spot at c in [lo, hi] by
 * the midpoint rule. */
static void num_share(double lo, double hi, double c, double x, double s, double *m, double *f)
{
    const int N = 20000;
    double h = (hi - lo) / N;
    *m = *f = 0;
    for (int k = 0; k < N; k++) {
        double t = lo + (k + 0.5) * h, g = exp(-0.5 * (t - c) * (t - c) / (s * s));
        *m += g * h;
        *f += (t - x) * g * h;
    }
    *m /= s * sqrt(2 * M_PI);
    *f /= s * sqrt(2 * M_PI);
}

/* The ghost's pull against the two spots' light integrated over the window. */
static void test_ghost_pull_numerical(void **state)
{
    (void)state;
    dss_pattern p = pattern_of(0, 0, 0);
    const double cases[][4] = {{0.2, -0.3, 3.0, -1.0},  {10.4, 5.0, 7.5, 0.0},
                               {-3.3, 0.45, -6.0, 4.0}, {0.0, 0.0, 12.0, 9.0}};
    const double a = 0.0018;
    for (size_t k = 0; k < 4; k++) {
        double x = cases[k][0], y = cases[k][1], dx = cases[k][2], dy = cases[k][3];
        double ex, ey;
        dss_ghost_pull(&p, a, x, y, dx, dy, &ex, &ey);
        double half = p.half_px + 0.5, nx = 0.5 + round(x - 0.5), ny = 0.5 + round(y - 0.5);
        double Mx, Sx, My, Sy, Gx, Tx, Gy, Ty;
        num_share(nx - half, nx + half, x, x, p.sigma_px, &Mx, &Sx);
        num_share(ny - half, ny + half, y, y, p.sigma_px, &My, &Sy);
        num_share(nx - half, nx + half, x + dx, x, p.sigma_px, &Gx, &Tx);
        num_share(ny - half, ny + half, y + dy, y, p.sigma_px, &Gy, &Ty);
        double wx = (Sx * My + a * Tx * Gy) / (Mx * My + a * Gx * Gy) - Sx / Mx;
        double wy = (Sy * Mx + a * Ty * Gx) / (Mx * My + a * Gx * Gy) - Sy / My;
        assert_near(ex, wx, 1e-9);
        assert_near(ey, wy, 1e-9);
    }
    /* a ghost inside the window pulls toward itself, a little under the
     * a dx / (1 + a) of an unbounded window (its tail is cut); far outside,
     * nothing */
    double ex, ey;
    dss_ghost_pull(&p, a, 0.5, 0.5, 2.0, 0.0, &ex, &ey);
    assert_true(ex < a * 2.0 / (1 + a) && ex > 0.85 * a * 2.0 / (1 + a));
    assert_true(ex > 0 && ey == 0.0);
    dss_ghost_pull(&p, a, 0.5, 0.5, 60.0, 0.0, &ex, &ey);
    assert_true(ex == 0.0 && ey == 0.0);
}

/* Through the sensor: the ghost lies 2 t tan(theta_r) outward, and its
 * pull is the difference of the spot with and without it. */
static void test_ghost_in_sensor(void **state)
{
    (void)state;
    sunmc_config c = test_family_config("dss");
    const dss_design *dd = &dss_cfg(&c)->design;
    double pix = dd->pixel_um * MM_PER_UM, t = dd->glass_thickness_mm, n = dd->glass_index;
    dss_deviations d0 = {0}, d1 = {.glass_ghost = 1.0};
    dss_sensor s0, s1;
    dss_sensor_init(&s0, dd, &d0, 0);
    dss_sensor_init(&s1, dd, &d1, 0);
    const double ths[] = {0.5, 1.0, 2.0, 20.0, 45.0};
    for (size_t k = 0; k < 5; k++) {
        double th = ths[k] * RAD_PER_DEG, ph = 0.7;
        double u[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)}, x0, y0, x1, y1;
        assert_int_equal(dss_sensor_spot(&s0, u, NULL, &x0, &y0), SUNMC_OK);
        assert_int_equal(dss_sensor_spot(&s1, u, NULL, &x1, &y1), SUNMC_OK);
        double D = 2 * t * tan(asin(sin(th) / n)) / pix, ex, ey;
        dss_ghost_pull(&s1.pattern, ref_ghost(th, n), x0, y0, -D * cos(ph), -D * sin(ph), &ex,
                       &ey);
        assert_near(x1 - x0, ex, 1e-12);
        assert_near(y1 - y0, ey, 1e-12);
        if (ths[k] <= 2.0)
            assert_true(fabs(x1 - x0) > 1e-4); /* inside the window: pulled outward */
        else if (ths[k] <= 20.0)
            assert_true(fabs(x1 - x0) < 1e-6); /* 34 px out: its tail only */
        else
            assert_true(x1 == x0 && y1 == y0); /* 76 px out, 8 sigma beyond the window */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_window_of_the_spot),
        cmocka_unit_test(test_pattern_against_pixel_sum),
        cmocka_unit_test(test_pattern_rms_closed_form),
        cmocka_unit_test(test_pattern_per_unit),
        cmocka_unit_test(test_ghost_intensity),
        cmocka_unit_test(test_ghost_pull_numerical),
        cmocka_unit_test(test_ghost_in_sensor),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
