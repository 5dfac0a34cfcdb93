/* test_psd_physics.c - the four-channel sensor's physics against closed
 * forms derived here, independently of psd_sensor.c:
 *  - duo-lateral PSD: a spot wholly on the area reads x = 2 cx / L with
 *    cx = x0 - u_x q (q = h / u_z without glass; with a glass of thickness
 *    t and index n, q = (h - t)/u_z + t / sqrt(n^2 - s^2), Snell's law);
 *  - quadrant photodiode, no gap, a uniform disc of radius R centred at
 *    (e, 0): the share right of the axis is the disc's area with x > 0,
 *    so x = (A_right - A_left) / (pi R^2) = (2/pi) (asin t + t sqrt(1 - t^2)),
 *    t = e / R (the area of a circular segment), saturating at 1 for e >= R;
 *  - the disc in a rectangle: whole disc pi R^2, a centred quadrant pi R^2/4,
 *    a half disc's centroid 4 R / (3 pi);
 *  - dark and gain on the ratios: a dark d added to both channels of a
 *    duo pair turns x into x S / (S + 2 d) (S = i1 + i2); a gain 1 + e on
 *    channel 2 turns it into ((1 + e) i2 - i1) / ((1 + e) i2 + i1);
 *  - the lab's lamp: light L turns the raw ratio into
 *    (sum c_k d_k + L N) / (sum d_k + L S) and leaves the dark-corrected one;
 *  - the physical fit's first stage recovers a noiseless unit exactly;
 *  - tetra-lateral: the corner currents' ratios are the pincushioned
 *    X' = X (1 + k Y^2), Y' = Y (1 + k X^2). */
#include "test_util.h"

#include "psd_model.h"
#include "psd_sensor.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

static psd_design base_design(int detector, int lateral)
{
    psd_design d;
    memset(&d, 0, sizeof d);
    d.detector = detector;
    d.lateral = lateral;
    d.h_mm = 4;
    d.active_mm = 9;
    d.aperture_um = 500;
    d.gap_um = 0;
    d.pincushion = 0;
    d.glass_index = 1.5;
    d.fov_deg = 45;
    d.polarity = PSD_POSITIVE;
    d.signal_fs = 1;
    d.dark_fs = 0;
    return d;
}

static void unit_vec(double a_deg, double b_deg, double u[3])
{
    double tx = tan(a_deg * RAD_PER_DEG), ty = tan(b_deg * RAD_PER_DEG), n = sqrt(1 + tx * tx + ty * ty);
    u[0] = tx / n;
    u[1] = ty / n;
    u[2] = 1 / n;
}

static void duo_lateral_response(void **state)
{
    psd_design d = base_design(PSD_LATERAL, PSD_DUO);
    psd_deviations dev;
    memset(&dev, 0, sizeof dev);
    dev.dx_um[0] = 30;
    dev.dy_um[0] = -20;
    psd_sensor s;
    psd_sensor_build(&d, &dev, &s);
    for (double a = -30; a <= 30; a += 7.5)
        for (double b = -25; b <= 25; b += 12.5) {
            double u[3], m[4], x, y;
            unit_vec(a, b, u);
            assert_int_equal(psd_sensor_read(&s, u, m), SUNMC_OK);
            psd_ratios(d.detector, d.lateral, m, &x, &y);
            double q = d.h_mm / u[2];
            assert_near(x, 2 * (0.030 - u[0] * q) / d.active_mm, 1e-12);
            assert_near(y, 2 * (-0.020 - u[1] * q) / d.active_mm, 1e-12);
            /* each face collects the whole light: u_z */
            assert_near(m[0] + m[1], u[2], 1e-12);
            assert_near(m[2] + m[3], u[2], 1e-12);
        }
    /* with a cover glass: Snell's law's q */
    d.glass_thickness_mm = 1;
    psd_sensor_nominal(&d, &s);
    double u[3], m[4], x, y;
    unit_vec(20, 10, u);
    assert_int_equal(psd_sensor_read(&s, u, m), SUNMC_OK);
    psd_ratios(d.detector, d.lateral, m, &x, &y);
    double s2 = u[0] * u[0] + u[1] * u[1];
    double q = (d.h_mm - 1) / u[2] + 1 / sqrt(1.5 * 1.5 - s2);
    assert_near(x, -2 * u[0] * q / d.active_mm, 1e-12);
}

/* A spot leaving the area: the ratio stops at the centroid of what is left,
 * below the spot's own position, and never passes the edge (1). */
static void lateral_clips_at_the_edge(void **state)
{
    psd_design d = base_design(PSD_LATERAL, PSD_DUO);
    psd_sensor s;
    psd_sensor_nominal(&d, &s);
    double prev = 0;
    for (double a = -40; a >= -60; a -= 0.5) {
        double u[3], m[4], x, y;
        unit_vec(a, 0, u);
        if (psd_sensor_read(&s, u, m) != SUNMC_OK)
            break;
        psd_ratios(d.detector, d.lateral, m, &x, &y);
        double free_x = -2 * u[0] * d.h_mm / u[2] / d.active_mm;
        assert_true(x <= free_x + 1e-12);
        assert_true(x <= 1.0 + 1e-12);
        assert_true(x >= prev - 1e-12); /* monotonic up to the edge */
        prev = x;
    }
    assert_true(prev > 0.9);
}

static void quadrant_uniform_disc(void **state)
{
    psd_design d = base_design(PSD_QUADRANT, PSD_DUO);
    psd_sensor s;
    psd_sensor_nominal(&d, &s);
    double R = s.R_mm;
    assert_near(R, 0.25 + 4 * tan(PSD_SUN_HALF_ANGLE_DEG * RAD_PER_DEG), 1e-15);
    for (double t = -1.2; t <= 1.2; t += 0.05) {
        double spot[2] = {t * R, 0}, i[4], x, y;
        psd_sensor_currents(&s, spot, 1.0, i);
        psd_ratios(d.detector, d.lateral, i, &x, &y);
        double tc = fmax(-1, fmin(1, t));
        double want = 2 / M_PI * (asin(tc) + tc * sqrt(1 - tc * tc));
        /* near |t| = 1 the segment's area moves as sqrt(1 - t^2): rounding
         * of t (1e-16) moves it by 1e-8 */
        assert_near(x, want, fabs(fabs(t) - 1) < 1e-6 ? 1e-7 : 1e-12);
        assert_near(y, 0, 1e-12);
        assert_near(i[0] + i[1] + i[2] + i[3], 1, 1e-12);
    }
    /* a gap takes its strips' light: a centred disc with gap g = 2 w keeps
     * pi R^2 - 2 strip + g^2 of its area, strip = 2 (w sqrt(R^2 - w^2) +
     * R^2 asin(w / R)) the disc's area within |x| < w, g^2 their overlap */
    d.gap_um = 100;
    psd_sensor_nominal(&d, &s);
    double spot[2] = {0, 0}, i[4], g = 0.1, w = g / 2;
    double strip = 2 * (w * sqrt(R * R - w * w) + R * R * asin(w / R));
    psd_sensor_currents(&s, spot, 1.0, i);
    assert_near(i[0] + i[1] + i[2] + i[3], (M_PI * R * R - 2 * strip + g * g) / (M_PI * R * R),
                1e-12);
}

static void disc_in_rectangles(void **state)
{
    double R = 1.3, a, mx, my;
    psd_disc_rect(R, -5, 5, -5, 5, &a, &mx, &my);
    assert_near(a, M_PI * R * R, 1e-13);
    assert_near(mx, 0, 1e-13);
    psd_disc_rect(R, 0, 5, 0, 5, &a, &mx, &my);
    assert_near(a, M_PI * R * R / 4, 1e-13);
    psd_disc_rect(R, 0, 5, -5, 5, &a, &mx, &my);
    assert_near(mx / a, 4 * R / (3 * M_PI), 1e-13);
    assert_near(my / a, 0, 1e-13);
    psd_disc_rect(R, -5, 5, 0.4, 5, &a, &mx, &my);
    double t = 0.4 / R; /* segment above y = 0.4: R^2 (acos t - t sqrt(1 - t^2)) */
    assert_near(a, R * R * (acos(t) - t * sqrt(1 - t * t)), 1e-13);
    /* its centroid: 2 (R^2 - c^2)^(3/2) / (3 A) */
    assert_near(my / a, 2 * pow(R * R - 0.16, 1.5) / (3 * a), 1e-13);
    /* an off-centre corner x > 0.2, y > -0.3 against a midpoint sum over a
     * 4000 x 4000 grid (error ~ the disc's perimeter x cell / 2) */
    psd_disc_rect(R, 0.2, 5, -0.3, 5, &a, &mx, &my);
    long N = 4000;
    double cell = 2 * R / (double)N, sa = 0, sx = 0, sy = 0;
    for (long i = 0; i < N; i++)
        for (long j = 0; j < N; j++) {
            double x = -R + (i + 0.5) * cell, y = -R + (j + 0.5) * cell;
            if (x * x + y * y <= R * R && x > 0.2 && y > -0.3) {
                sa += cell * cell;
                sx += x * cell * cell;
                sy += y * cell * cell;
            }
        }
    assert_near(a, sa, 2e-3);
    assert_near(mx, sx, 2e-3);
    assert_near(my, sy, 2e-3);
}

static void dark_and_gain_on_the_ratios(void **state)
{
    psd_design d = base_design(PSD_LATERAL, PSD_DUO);
    psd_sensor s;
    psd_sensor_nominal(&d, &s);
    double u[3], m0[4], x0, y0;
    unit_vec(12, -7, u);
    assert_int_equal(psd_sensor_read(&s, u, m0), SUNMC_OK);
    psd_ratios(d.detector, d.lateral, m0, &x0, &y0);
    double S = m0[0] + m0[1];
    psd_deviations dev;
    memset(&dev, 0, sizeof dev);
    dev.dark_pct[0] = dev.dark_pct[1] = 3; /* d = 0.03 of full scale */
    psd_sensor_build(&d, &dev, &s);
    double m[4], x, y;
    assert_int_equal(psd_sensor_read(&s, u, m), SUNMC_OK);
    psd_ratios(d.detector, d.lateral, m, &x, &y);
    assert_near(x, x0 * S / (S + 2 * 0.03), 1e-12);
    assert_near(y, y0, 1e-12);
    memset(&dev, 0, sizeof dev);
    dev.gain_pct[1] = 4;
    psd_sensor_build(&d, &dev, &s);
    assert_int_equal(psd_sensor_read(&s, u, m), SUNMC_OK);
    psd_ratios(d.detector, d.lateral, m, &x, &y);
    assert_near(x, (1.04 * m0[1] - m0[0]) / (1.04 * m0[1] + m0[0]), 1e-12);
    /* the physical model's dark and gain correction undoes both */
    dev.dark_pct[0] = 2;
    dev.dark_pct[1] = 1.5; /* on the channel with a gain: dark before gain */
    dev.dark_pct[3] = -1;
    psd_sensor_build(&d, &dev, &s);
    assert_int_equal(psd_sensor_read(&s, u, m), SUNMC_OK);
    psd_phys ph;
    double p[PSD_NP] = {0};
    p[PSD_P_G2] = 1.04;
    p[PSD_P_G3] = p[PSD_P_G4] = 1;
    p[PSD_P_D1] = 0.02;
    p[PSD_P_D2] = 0.015;
    p[PSD_P_D4] = -0.01;
    psd_phys_set(&ph, &d, p);
    assert_int_equal(psd_phys_observed(&ph, m, &x, &y), SUNMC_OK);
    assert_near(x, x0, 1e-12);
    assert_near(y, y0, 1e-12);
}

/* The lab's lamp (noise.lamp_pct): light L on channels with darks d_k and
 * signals S_k: the raw ratio is (sum_k c_k d_k + L N) / (sum_k d_k + L S)
 * with N = sum_k c_k S_k (c_k the corner signs), S = sum_k S_k; the
 * dark-corrected ratios are those of L = 1. */
static void lamp_on_raw_and_corrected_ratios(void **state)
{
    psd_design d = base_design(PSD_LATERAL, PSD_TETRA);
    psd_deviations dev;
    memset(&dev, 0, sizeof dev);
    const double dark[4] = {0.02, 0.015, 0.03, -0.01}, cx[4] = {-1, 1, 1, -1};
    for (int k = 0; k < 4; k++)
        dev.dark_pct[k] = dark[k] * 100;
    dev.gain_pct[1] = 60;
    psd_sensor s;
    psd_sensor_build(&d, &dev, &s);
    double u[3], m1[4], mL[4], x1, y1, x, y, L = 1.37;
    unit_vec(11, -6, u);
    assert_int_equal(psd_sensor_read_lit(&s, u, 1.0, m1), SUNMC_OK);
    assert_int_equal(psd_sensor_read_lit(&s, u, L, mL), SUNMC_OK);
    double N = 0, S = 0, Nd = 0, Sd = 0;
    for (int k = 0; k < 4; k++) {
        N += cx[k] * (m1[k] - dark[k]);
        S += m1[k] - dark[k];
        Nd += cx[k] * dark[k];
        Sd += dark[k];
        assert_near(mL[k] - dark[k], L * (m1[k] - dark[k]), 1e-15);
    }
    psd_ratios(d.detector, d.lateral, mL, &x, &y);
    assert_near(x, (Nd + L * N) / (Sd + L * S), 1e-14);
    psd_phys ph;
    double p[PSD_NP] = {0};
    p[PSD_P_G2] = 1.6;
    p[PSD_P_G3] = p[PSD_P_G4] = 1;
    for (int k = 0; k < 4; k++)
        p[PSD_P_D1 + k] = dark[k];
    psd_phys_set(&ph, &d, p);
    assert_int_equal(psd_phys_observed(&ph, m1, &x1, &y1), SUNMC_OK);
    assert_int_equal(psd_phys_observed(&ph, mL, &x, &y), SUNMC_OK);
    assert_near(x, x1, 1e-14);
    assert_near(y, y1, 1e-14);
}

/* The physical fit's first stage (psd_phys_fit_channels) on noiseless
 * readings whose light changes from row to row: it finds the unit exactly
 * (every dark, unequal gains, the height) from a start with the height off
 * by a factor 3 and the darks 0.1 of full scale off, where the ratios'
 * fit from the same start does not find it. */
static void channel_fit_finds_the_unit(void **state)
{
    enum { NA = 11, NB = 4, N = NA * NB };
    psd_design d = base_design(PSD_LATERAL, PSD_TETRA);
    d.signal_fs = 0.1;
    psd_deviations dev;
    memset(&dev, 0, sizeof dev);
    const double dark[4] = {0.32, 0.31, 0.335, 0.29}, gain[4] = {1, 1.6, 1.05, 1.55};
    for (int k = 0; k < 4; k++) {
        dev.dark_pct[k] = dark[k] * 100;
        dev.gain_pct[k] = (gain[k] - 1) * 100;
    }
    dev.dh_um[0] = -800;
    dev.dy_um[0] = -300;
    psd_sensor s;
    psd_sensor_build(&d, &dev, &s);
    static double m[4][N], ut[3 * N], scratch[8 * N];
    for (int r = 0; r < N; r++) {
        double a = -20 + 4 * (r % NA), b = -15 + 10 * (r / NA), mm[4];
        unit_vec(a, b, ut + 3 * r);
        assert_int_equal(psd_sensor_read_lit(&s, ut + 3 * r, 1 + 0.3 * sin(r), mm), SUNMC_OK);
        for (int k = 0; k < 4; k++)
            m[k][r] = mm[k];
    }
    psd_design nominal = d;
    nominal.h_mm = 4 * 3.0; /* the truth: 3.2 mm */
    psd_rows rows = {.n = N, .m = {m[0], m[1], m[2], m[3]}, .ut = ut, .design = &nominal,
                     .scratch = scratch};
    double p[PSD_NP], q[PSD_NP];
    psd_phys_start(&rows, p);
    for (int k = 0; k < 4; k++)
        p[PSD_P_D1 + k] = dark[k] + (k % 2 ? 0.1 : -0.1);
    memcpy(q, p, sizeof q);
    fit_workspace *fw = fit_workspace_alloc(PSD_RESIDUALS_PER_ROW * N, psd_phys_free_channels(0));
    fit_result res;
    assert_int_equal(psd_phys_fit_channels(fw, &rows, 0, p, &res), SUNMC_OK);
    for (int k = 0; k < 4; k++) {
        assert_near(p[PSD_P_D1 + k], dark[k], 1e-8);
        if (k > 0)
            assert_near(p[PSD_P_G2 + k - 1], gain[k], 1e-7);
    }
    assert_near(nominal.h_mm + p[PSD_P_DH], 3.2, 1e-7);
    assert_near(p[PSD_P_DY], -0.3, 1e-7);
    fit_workspace_free(fw);
    /* the ratios' fit alone (no first stage) from the same start */
    int fr[PSD_NP];
    fw = fit_workspace_alloc(2 * N, psd_phys_free(&nominal, 0, fr));
    rows.fw_channels = NULL;
    psd_phys_fit(fw, &rows, 0, q, &res);
    assert_false(fabs(nominal.h_mm + q[PSD_P_DH] - 3.2) < 1e-3);
    fit_workspace_free(fw);
}

static void tetra_pincushion(void **state)
{
    psd_design d = base_design(PSD_LATERAL, PSD_TETRA);
    d.pincushion = 0.05;
    psd_sensor s;
    psd_sensor_nominal(&d, &s);
    double spot[2] = {1.2, -2.0}, i[4], x, y;
    psd_sensor_currents(&s, spot, 0.9, i);
    psd_ratios(d.detector, d.lateral, i, &x, &y);
    double X = 1.2 / 4.5, Y = -2.0 / 4.5;
    assert_near(x, X * (1 + 0.05 * Y * Y), 1e-12);
    assert_near(y, Y * (1 + 0.05 * X * X), 1e-12);
    assert_near(i[0] + i[1] + i[2] + i[3], 0.9, 1e-12);
}

/* The physical model inverts its own prediction, and the ADC rounds to its
 * code. */
static void inversion_and_adc(void **state)
{
    for (int det = 0; det < 2; det++) {
        psd_design d = base_design(det, PSD_TETRA);
        d.pincushion = 0.04;
        psd_phys ph;
        double p[PSD_NP] = {0.02, -0.01, 0.05, 0.001, -0.002, 0.01, 1, 1, 1, 0, 0, 0, 0};
        psd_phys_set(&ph, &d, p);
        double lim = det == PSD_QUADRANT ? 2.5 : 25; /* the quadrant reads within its spot */
        for (double a = -lim; a <= lim; a += lim / 4)
            for (double b = -lim; b <= lim; b += lim / 2) {
                double u[3], x, y, back[3];
                unit_vec(a, b, u);
                assert_int_equal(psd_phys_predicted(&ph, u, &x, &y), SUNMC_OK);
                assert_int_equal(psd_phys_invert(&ph, x, y, back), SUNMC_OK);
                assert_near(back[0], u[0], 1e-10);
                assert_near(back[1], u[1], 1e-10);
            }
    }
    assert_near(psd_adc(0.5, 12), 2048.0 / 4095, 1e-15);
    assert_near(psd_adc(-0.1, 12), 0, 0);
    assert_near(psd_adc(1.7, 12), 1, 0);
}

/* The table conventions: projected, alpha_outer, beta_outer (psd_config.h). */
static void table_conventions(void **state)
{
    psd_config pc;
    memset(&pc, 0, sizeof pc);
    double a = 20 * RAD_PER_DEG, b = 15 * RAD_PER_DEG, u[3];
    pc.table_order = PSD_TABLE_PROJECTED;
    psd_table_sun(&pc, a, b, u);
    assert_near(u[0] / u[2], tan(a), 1e-15);
    assert_near(u[1] / u[2], tan(b), 1e-15);
    pc.table_order = PSD_TABLE_BETA_OUTER; /* (sin a cos b, sin b, cos a cos b) */
    psd_table_sun(&pc, a, b, u);
    assert_near(u[0], sin(a) * cos(b), 1e-15);
    assert_near(u[1], sin(b), 1e-15);
    pc.table_order = PSD_TABLE_ALPHA_OUTER; /* (sin a, cos a sin b, cos a cos b) */
    psd_table_sun(&pc, a, b, u);
    assert_near(u[0], sin(a), 1e-15);
    assert_near(u[1], cos(a) * sin(b), 1e-15);
    pc.table_alpha_sign = pc.table_beta_sign = 1;
    psd_table_sun(&pc, a, b, u);
    assert_near(u[0], -sin(a), 1e-15);
    assert_near(u[1], -cos(a) * sin(b), 1e-15);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(duo_lateral_response),
        cmocka_unit_test(lateral_clips_at_the_edge),
        cmocka_unit_test(quadrant_uniform_disc),
        cmocka_unit_test(disc_in_rectangles),
        cmocka_unit_test(dark_and_gain_on_the_ratios),
        cmocka_unit_test(lamp_on_raw_and_corrected_ratios),
        cmocka_unit_test(channel_fit_finds_the_unit),
        cmocka_unit_test(tetra_pincushion),
        cmocka_unit_test(inversion_and_adc),
        cmocka_unit_test(table_conventions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
