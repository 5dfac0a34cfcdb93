/* test_ess_paper_findings.c - the physical ESS model against closed forms and the
 * ESS paper's stated findings (sec. 3). */
#include "test_util.h"

#include "config.h"
#include "ess_sensor.h"
#include "ess_unit.h"
#include "status.h"
#include "units.h"

/* A config with the ESS defaults (type A) and every deviation nominal. */
static sunmc_config base_config(void) { return test_family_config("ess"); }

/* Build a sensor with the harmonics given as a3, a5 and deviations dev. */
static void build(const sunmc_config *c, const ess_deviations *dev, ess_sensor *s)
{
    ess_sensor_init(s, &ess_cfg(c)->design, dev);
}

static double output_deg(const ess_sensor *s, double alpha_deg, double beta_deg)
{
    double a = alpha_deg * RAD_PER_DEG, b = beta_deg * RAD_PER_DEG;
    double sv[3] = {sin(b), cos(b) * sin(a), cos(b) * cos(a)};
    double out;
    assert_int_equal(ess_sensor_output(s, sv, NULL, &out), SUNMC_OK);
    return out * DEG_PER_RAD;
}

static sunmc_config no_harmonics(void)
{
    sunmc_config c = base_config();
    ess_config *ec = ess_cfg(&c);
    ec->design.harmonics = 1; /* given */
    ec->design.a3_ratio = 0;
    ec->design.a5_ratio = 0;
    return c;
}

/* dH alone: alpha' = atan((H + dH)/H tan alpha), to 1e-9. */
static void test_dH_closed_form(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    dev.dH_um = 2.0;
    ess_sensor s;
    build(&c, &dev, &s);
    double H = ess_cfg(&c)->design.H_mm;
    for (double a = -62; a <= 62; a += 0.37) {
        double expect = atan((H + dev.dH_um * MM_PER_UM) / H * tan(a * RAD_PER_DEG)) * DEG_PER_RAD;
        assert_near(output_deg(&s, a, 0), expect, 1e-9);
        assert_near(output_deg(&s, a, 17), expect, 1e-9); /* no tilt: beta does not matter */
    }
}

/* dd alone: alpha' = atan(tan alpha - dd/H). */
static void test_dd_closed_form(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    dev.dd_um = 1.0;
    ess_sensor s;
    build(&c, &dev, &s);
    double H = ess_cfg(&c)->design.H_mm;
    for (double a = -62; a <= 62; a += 0.53) {
        double expect = atan(tan(a * RAD_PER_DEG) - dev.dd_um * MM_PER_UM / H) * DEG_PER_RAD;
        assert_near(output_deg(&s, a, 5), expect, 1e-9);
    }
}

/* Tilt alone, one row: eta = H tan a - (x + H tan b / cos a) tan dphi
 * (independent derivation from the slit line and the ray). */
static void test_tilt_geometry(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    dev.dphi_deg = 0.3;
    ess_sensor s;
    build(&c, &dev, &s);
    double H = ess_cfg(&c)->design.H_mm, x = 1.7, tp = tan(0.3 * RAD_PER_DEG);
    for (double a = -50; a <= 50; a += 10)
        for (double b = -30; b <= 30; b += 15) {
            double ar = a * RAD_PER_DEG, br = b * RAD_PER_DEG;
            double u = tan(br) / cos(ar), v = tan(ar);
            assert_near(ess_slit_eta_mm(&s, x, u, v), H * tan(ar) - (x + H * tan(br) / cos(ar)) * tp,
                        1e-12);
        }
}

/* The tilt's pivot (design.tilt_pivot_mm = p): a row at x reads
 * eta = H tan a - (x - p + H tan b / cos a) tan dphi.  With the four fine
 * rows at one x0 the reading is atan(eta / H) (independent derivation, as
 * for dd); at the pivot itself and b = 0 the tilt does nothing. */
static void test_tilt_pivot_closed_form(void **state)
{
    const double pivots[] = {0.0, 1.5, 1.8, -2.0};
    for (size_t k = 0; k < sizeof pivots / sizeof pivots[0]; k++) {
        sunmc_config c = no_harmonics();
        ess_config *ec = ess_cfg(&c);
        double x0 = 1.8, p = pivots[k], H = ec->design.H_mm, tp = tan(0.3 * RAD_PER_DEG);
        for (int m = 0; m < 4; m++)
            ec->design.fine_rows_x_mm.v[m] = x0;
        ec->design.tilt_pivot_mm = p;
        ess_deviations dev = {0};
        dev.dphi_deg = 0.3;
        ess_sensor s;
        build(&c, &dev, &s);
        for (double a = -60; a <= 60; a += 7.5)
            for (double b = -30; b <= 30; b += 15) {
                double ar = a * RAD_PER_DEG, u = tan(b * RAD_PER_DEG) / cos(ar);
                double expect = atan(tan(ar) - (x0 - p + H * u) * tp / H) * DEG_PER_RAD;
                assert_near(output_deg(&s, a, b), expect, 1e-9);
                if (p == x0 && b == 0)
                    assert_near(output_deg(&s, a, b), a, 1e-9);
            }
    }
}

/* A third harmonic alone gives eq. 7's error (with eq. 8's sign):
 * eps = -theta0/(2 pi) atan(r sin 4x / (1 + r cos 4x)), x = 2 pi alpha/theta0. */
static void test_third_harmonic_eq7(void **state)
{
    sunmc_config c = no_harmonics();
    ess_config *ec = ess_cfg(&c);
    double r = -0.12;
    ec->design.a3_ratio = r;
    ess_deviations dev = {0};
    ess_sensor s;
    build(&c, &dev, &s);
    double th0 = ec->design.theta0_deg;
    for (double a = -60; a <= 60; a += 0.0731) {
        double x = 2 * M_PI * a / th0;
        double eps = -th0 / (2 * M_PI) * atan(r * sin(4 * x) / (1 + r * cos(4 * x)));
        assert_near(output_deg(&s, a, 0) - a, eps, 1e-9);
    }
}

/* Derived harmonics: a duty-0.5 dial, no slit, no sun gives the square wave
 * a3/a1 = -1/3; the sun's disc multiplies by 2J1(z)/z (z = pi n S/theta0). */
static void test_derived_harmonics(void **state)
{
    sunmc_config c = base_config();
    ess_config *ec = ess_cfg(&c);
    ec->design.slit_width_um = 0;
    ec->design.sun_diameter_deg = 0;
    ess_deviations dev = {0};
    ess_sensor s;
    build(&c, &dev, &s);
    double h[ESS_HARMONICS];
    ess_finecode_harmonics(&s, 0.3, h);
    assert_near(h[0], 1.0, 1e-12);
    assert_near(h[1], -1.0 / 3.0, 1e-12);
    assert_near(h[2], 1.0 / 5.0, 1e-12);
    ec->design.sun_diameter_deg = 0.53;
    build(&c, &dev, &s);
    ess_finecode_harmonics(&s, 0.0, h);
    /* 2 J1(z)/z at z1 = 0.8325, z3 = 2.4975; J1 from its power series
     * sum (-1)^k (z/2)^(2k+1) / (k! (k+1)!): 0.3812241, 0.4976949 */
    double z1 = M_PI * 0.53 / 2, z3 = 3 * z1;
    double t1 = 2 * 0.3812241408 / z1, t3 = 2 * 0.4976948555 / z3;
    assert_near(h[1], -1.0 / 3.0 * t3 / t1, 2e-5);
}

/* Gray coarse code: every angle decodes to its own cell. */
static void test_coarse_gray(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    ess_sensor s;
    build(&c, &dev, &s);
    double psi[ESS_MAX_COARSE_ROWS];
    for (double a = -63.9; a < 64; a += 0.05) {
        for (int j = 0; j < s.n_coarse; j++)
            psi[j] = a * RAD_PER_DEG;
        double got = ess_coarse_read(&s, psi) * DEG_PER_RAD;
        assert_near(got, floor(a) + 0.5, 1e-9);
    }
}

/* ESS paper sec. 3.1 (2): with dH = 2 um the error reaches about 0.015 deg
 * for type A (we get 0.0139: the maximum of dH/(2H) rad at 45 deg) and
 * exceeds 0.008 deg for type B. */
static double max_error(const sunmc_config *c, const ess_deviations *dev, double beta)
{
    ess_sensor s;
    build(c, dev, &s);
    double m = 0;
    for (double a = -62; a <= 62; a += 0.25)
        m = fmax(m, fabs(output_deg(&s, a, beta) - a));
    return m;
}

static void test_paper_dH_dd_dphi_sizes(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    dev.dH_um = 2;
    double eA = max_error(&c, &dev, 0);
    assert_true(eA > 0.013 && eA < 0.016);
    ess_cfg(&c)->design.H_mm = 6.584;
    double eB = max_error(&c, &dev, 0);
    assert_true(eB > 0.008 && eB < eA);
    assert_near(eA / eB, 6.584 / 4.124, 0.02); /* smaller H, larger error */

    c = no_harmonics();
    memset(&dev, 0, sizeof dev);
    dev.dd_um = 1; /* sec. 3.2 (2): exceeds about 0.014 deg for type A */
    double eD = max_error(&c, &dev, 0);
    assert_true(eD > 0.0135 && eD < 0.0145);

    memset(&dev, 0, sizeof dev);
    dev.dphi_deg = 0.01; /* sec. 3.2 (3): less than 0.005 deg for type A */
    double eT = max_error(&c, &dev, 0);
    assert_true(eT > 1e-4 && eT < 0.005);
}

/* ESS paper Fig. 7: sampled at 0.5 deg, the tilt error varies with a period of
 * 1 deg: e(a) = e(a + 1) but e(a) != e(a + 0.5).  (Tilt shifts the four fine
 * rows by different amounts: per-row phase errors give a theta0/2 period.) */
static void test_tilt_period_1deg(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    dev.dphi_deg = 0.01;
    ess_sensor s;
    build(&c, &dev, &s);
    double d1 = 0, dh = 0;
    int n = 0;
    for (double a = -10; a <= 10; a += 0.5, n++) {
        double e0 = output_deg(&s, a, 0) - a;
        double e1 = output_deg(&s, a + 1, 0) - (a + 1);
        double eh = output_deg(&s, a + 0.5, 0) - (a + 0.5);
        d1 += fabs(e1 - e0);
        dh += fabs(eh - e0);
    }
    assert_true(dh / n > 1e-4);  /* a half-degree step changes the error */
    assert_true(d1 < 0.1 * dh);   /* a whole degree brings it back */
}

/* The dial tilted tau about the code-row axis (Y through x = 0), by an
 * independent ray trace: the dial is the plane z = -x tan(tau), the slit
 * the line (p + l cos dphi, dd + l sin dphi, Hr) (p the slit's pivot); the ray from the slit along
 * -s meets the plane at sensor x = x_r when p + l cos dphi - t s_x = x_r and
 * Hr - t s_z = -x_r tan(tau): a 2x2 linear system in (l, t), solved by
 * Cramer's rule; eta is minus the y of that point.  For pivots 0 and 1.5
 * (the slit's pivot moves the in-plane lever, not the dial's axis). */
static void test_dial_tilt_ray_trace(void **state)
{
    const double pivots[] = {0.0, 1.5};
    for (size_t k = 0; k < 2; k++) {
        sunmc_config c = no_harmonics();
        ess_config *ec = ess_cfg(&c);
        ec->design.tilt_pivot_mm = pivots[k];
        ess_deviations dev = {0};
        dev.dial_tilt_deg = 0.4;
        dev.dphi_deg = -0.3;
        dev.dH_um = 3;
        dev.dd_um = 2;
        ess_sensor s;
        build(&c, &dev, &s);
        double Hr = ec->design.H_mm + 3e-3, dd = 2e-3;
        double tt = tan(0.4 * RAD_PER_DEG), ph = -0.3 * RAD_PER_DEG;
        for (double xr = -4.2; xr <= 2.41; xr += 0.6)
            for (double a = -60; a <= 60; a += 12)
                for (double b = -30; b <= 30; b += 15) {
                    double ar = a * RAD_PER_DEG, br = b * RAD_PER_DEG;
                    double sv[3] = {sin(br), cos(br) * sin(ar), cos(br) * cos(ar)};
                    /* [cos ph, -s_x; 0, -s_z] (l, t) = (x_r - p, -x_r tt - Hr) */
                    double det = -cos(ph) * sv[2], r1 = xr - pivots[k], r2 = -xr * tt - Hr;
                    double l = (r1 * -sv[2] - -sv[0] * r2) / det;
                    double t = (cos(ph) * r2) / det;
                    double eta = -(dd + l * sin(ph) - t * sv[1]);
                    double got = ess_slit_eta_mm(&s, xr - pivots[k], sv[0] / sv[2], sv[1] / sv[2]);
                    assert_near(got, eta, 1e-12);
                }
    }
}

/* The dial tilt alone with the four fine rows at one x0: the rows sit at
 * H + x0 tan(tau), so the reading is dH's closed form with dH = x0
 * tan(tau), whatever beta; at x0 = 0 (on the axis) the tilt does nothing. */
static void test_dial_tilt_closed_form(void **state)
{
    const double xs[] = {1.8, -2.5, 0.0};
    for (size_t k = 0; k < 3; k++) {
        sunmc_config c = no_harmonics();
        ess_config *ec = ess_cfg(&c);
        for (int m = 0; m < 4; m++)
            ec->design.fine_rows_x_mm.v[m] = xs[k];
        ess_deviations dev = {0};
        dev.dial_tilt_deg = 0.3;
        ess_sensor s;
        build(&c, &dev, &s);
        double H = ec->design.H_mm, h = H + xs[k] * tan(0.3 * RAD_PER_DEG);
        for (double a = -62; a <= 62; a += 0.61)
            for (double b = -30; b <= 30; b += 30) {
                double expect = atan(h / H * tan(a * RAD_PER_DEG)) * DEG_PER_RAD;
                assert_near(output_deg(&s, a, b), expect, 1e-9);
            }
    }
}

/* ESS paper sec. 3.2 (1), (3), Figs. 6-7 with dphi read as the dial's
 * tilt about the row axis (type A, 0.01 deg, beta = 0, no harmonics), the
 * four statements the in-plane reading cannot make all at once:
 *  - the error stays below 0.005 deg (max over -62..62: 0.0022);
 *  - it grows with incidence: mean |error| 0.00016 at |alpha| < 5, 0.0016
 *    at 55..62 (the rows' mean height 1.5 tan(tau) is a dH of 0.26 um:
 *    (dH / 2H) sin 2 alpha, plus their alternation, tan(alpha) times the
 *    rows' height differences);
 *  - sampled every 0.5 deg it has a 1 deg period;
 *  - type B's error is less, by H_A / H_B. */
static void test_paper_dial_tilt_findings(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    dev.dial_tilt_deg = 0.01;
    ess_sensor s;
    build(&c, &dev, &s);
    double emax = 0, lo = 0, hi = 0;
    int nlo = 0, nhi = 0;
    for (double a = -62; a <= 62.001; a += 0.05) {
        double e = fabs(output_deg(&s, a, 0) - a);
        emax = fmax(emax, e);
        if (fabs(a) < 5)
            lo += e, nlo++;
        if (fabs(a) >= 55)
            hi += e, nhi++;
    }
    lo /= nlo;
    hi /= nhi;
    print_message("dial tilt 0.01 deg: max %.5f, mean |e| %.5f (|a| < 5), %.5f (55..62)\n", emax,
                  lo, hi);
    assert_true(emax > 0.0015 && emax < 0.005);
    assert_true(lo > 0.00005 && lo < 0.0003);
    assert_true(hi > 0.0012 && hi < 0.002);
    assert_true(hi > 5 * lo);
    /* Fig. 7: on a smooth trend (the mean height's dH), the error sampled
     * every 0.5 deg alternates: its second difference at 0.5 deg is large
     * and changes sign at every sample, at 1 deg (one period) it is the
     * trend's alone */
    double d1 = 0, dh = 0, prev = 0;
    int n = 0, flips = 0;
    for (double a = -40; a <= 40; a += 0.5, n++) {
        double e[5];
        for (int j = 0; j < 5; j++)
            e[j] = output_deg(&s, a + 0.5 * (j - 2), 0) - (a + 0.5 * (j - 2));
        double sh = e[1] - 2 * e[2] + e[3], s1 = e[0] - 2 * e[2] + e[4];
        dh += fabs(sh);
        d1 += fabs(s1);
        flips += n > 0 && sh * prev < 0;
        prev = sh;
    }
    print_message("0.5-deg samples: mean |2nd difference| %.6f at 0.5 deg, %.6f at 1 deg; sign "
                  "flips %d of %d\n", dh / n, d1 / n, flips, n - 1);
    assert_true(dh / n > 1e-4);
    assert_true(d1 < 0.05 * dh);
    assert_true(flips >= n - 1 - 6); /* all but the few samples around alpha = 0 */
    double eA = max_error(&c, &dev, 0);
    ess_cfg(&c)->design.H_mm = 6.584;
    double eB = max_error(&c, &dev, 0);
    print_message("max error: type A %.5f, type B %.5f\n", eA, eB);
    assert_true(eB < eA);
    assert_near(eA / eB, 6.584 / 4.124, 0.1);
}

/* Photocell non-uniformity: a common gain changes nothing; unequal gains give
 * an error of order gain/2 rad of fine phase. */
static void test_gain_errors(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    for (int m = 0; m < 4; m++)
        dev.gain_pct[m] = 1.0;
    assert_near(max_error(&c, &dev, 0), 0, 1e-9);
    dev.gain_pct[0] = -1;
    double e = max_error(&c, &dev, 0);
    double scale = ess_cfg(&c)->design.theta0_deg / (2 * M_PI);
    assert_true(e > 0.001 * scale && e < 0.03 * scale);
}

/* Unit construction: the same (seed, unit) gives the same deviations, and the
 * deviations respect their tolerances. */
static void test_deviation_sampling(void **state)
{
    sunmc_config c = base_config();
    ess_config *ec = ess_cfg(&c);
    ess_deviations a, b;
    for (long u = 0; u < 200; u++) {
        ess_deviations_sample(&c, 7, u, &a);
        ess_deviations_sample(&c, 7, u, &b);
        assert_memory_equal(&a, &b, sizeof a);
        assert_true(fabs(a.dH_um) <= ec->tol.dH_um.value);
        assert_true(fabs(a.dphi_deg) <= ec->tol.dphi_deg.value);
        for (int m = 0; m < 4; m++)
            assert_true(fabs(a.gain_pct[m]) <= ec->tol.gain_pct.value);
    }
    ess_deviations_sample(&c, 8, 0, &b);
    ess_deviations_sample(&c, 7, 0, &a);
    assert_true(a.dH_um != b.dH_um);
}

/* The true incidence seen on the turntable with no installation error is the
 * inner-frame angle, whatever beta. */
static void test_turntable_truth(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    ess_unit u;
    ess_unit_build(&c, &dev, &u);
    for (double a = -60; a <= 60; a += 7.5)
        for (double b = -30; b <= 30; b += 10) {
            double raw, truth;
            assert_int_equal(ess_unit_read(&u, a * RAD_PER_DEG, b * RAD_PER_DEG, NULL, &raw, &truth),
                             SUNMC_OK);
            assert_near(truth * DEG_PER_RAD, a, 1e-12);
            assert_near(raw * DEG_PER_RAD, a, 1e-9);
        }
    /* Sun behind the sensor: domain error, not a number. */
    double sv[3] = {0, 0, -1}, out;
    assert_int_equal(ess_sensor_output(&u.sensor, sv, NULL, &out), SUNMC_EDOM);
}

/* With the sun simulator tilted (toward X and Y) and the sensor mounted
 * rotated about all three axes, the truth of a reading is the incidence of
 * s = R_x(ix) R_y(iy) R_z(iz) R_x(alpha) R_y(beta) v_sun, computed here
 * from the elementary rotations; the campaign reading (its encoder
 * errors off) reads the same table position. */
static void test_turntable_truth_tilted(void **state)
{
    sunmc_config c = no_harmonics();
    ess_deviations dev = {0};
    dev.install_x_arcsec = 900;
    dev.install_y_arcsec = -1500;
    dev.install_z_arcsec = 2400;
    dev.sun_x_arcsec = 3000;
    dev.sun_y_arcsec = -2000;
    ess_unit u;
    ess_unit_build(&c, &dev, &u);
    mat3 rx, ry, rz, ta, tb, t1, t2, R;
    rot_x(900 * RAD_PER_ARCSEC, rx);
    rot_y(1500 * RAD_PER_ARCSEC, ry); /* install_y -1500, active */
    rot_z(2400 * RAD_PER_ARCSEC, rz);
    mat3_mul(rx, ry, t1);
    mat3_mul(t1, rz, R);
    double sx = 3000 * RAD_PER_ARCSEC, sy = -2000 * RAD_PER_ARCSEC;
    const double v[3] = {cos(sy) * sin(sx), sin(sy), cos(sy) * cos(sx)};
    c.encoder_arcsec = 0;
    for (double a = -50; a <= 50; a += 12.5)
        for (double b = -30; b <= 30; b += 15) {
            rot_x(a * RAD_PER_DEG, ta);
            rot_y(-b * RAD_PER_DEG, tb);
            mat3_mul(ta, tb, t1);
            mat3_mul(R, t1, t2);
            double s[3];
            mat3_vec(t2, v, s);
            double raw, truth;
            assert_int_equal(ess_unit_read(&u, a * RAD_PER_DEG, b * RAD_PER_DEG, NULL, &raw, &truth),
                             SUNMC_OK);
            assert_near(truth, atan2(s[1], s[2]), 1e-13);
            rng_stream r;
            rng_stream_init(&r, 1, 0, RNG_STREAM_CAL_NOISE);
            double ar = a * RAD_PER_DEG, br = b * RAD_PER_DEG;
            ess_campaign_point p;
            ess_campaign_batch(&c, &u, &r, 1, &ar, &br, &p);
            assert_near(p.a_true_rad, ar, 0);
            assert_near(p.b_true_rad, br, 0);
            assert_near(p.incidence_rad, atan2(s[1], s[2]), 1e-13);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dH_closed_form),       cmocka_unit_test(test_dd_closed_form),
        cmocka_unit_test(test_tilt_geometry),        cmocka_unit_test(test_third_harmonic_eq7),
        cmocka_unit_test(test_tilt_pivot_closed_form),
        cmocka_unit_test(test_derived_harmonics),    cmocka_unit_test(test_coarse_gray),
        cmocka_unit_test(test_paper_dH_dd_dphi_sizes), cmocka_unit_test(test_tilt_period_1deg),
        cmocka_unit_test(test_dial_tilt_ray_trace),  cmocka_unit_test(test_dial_tilt_closed_form),
        cmocka_unit_test(test_paper_dial_tilt_findings),
        cmocka_unit_test(test_gain_errors),          cmocka_unit_test(test_deviation_sampling),
        cmocka_unit_test(test_turntable_truth),      cmocka_unit_test(test_turntable_truth_tilted),
    };
    return cmocka_run_group_tests_name("ess_physics", tests, NULL, NULL);
}
