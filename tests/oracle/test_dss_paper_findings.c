/* test_dss_paper_findings.c - single error sources of the physical DSS against
 * closed forms and the DSS paper's findings (sec. 3, Figs. 2-5).
 *
 * Errors are the on-board angles (eq. 9-10) minus the table's truth (eq.
 * 3-4), with the table set to reach truth (alpha, beta): b2 = -alpha,
 * b1 = atan(tan beta cos b2).  Except in the refraction test the cover glass
 * is removed (thickness 0), so each source acts alone. */
#include "test_util.h"

#include "config.h"
#include "rotation.h"
#include "dss_sensor.h"
#include "status.h"
#include "units.h"

static sunmc_config dss_test_config(void) { return test_family_config("dss"); }

/* Errors (arcsec) of a sensor with deviations dev at truth (a, b) deg. */
static void errors(const sunmc_config *c, const dss_deviations *dev, double a_deg, double b_deg,
                   double *ea, double *eb)
{
    dss_sensor s;
    dss_sensor_init(&s, &dss_cfg(c)->design, dev, 0);
    double b2 = -a_deg * RAD_PER_DEG, b1 = atan(tan(b_deg * RAD_PER_DEG) * cos(b2));
    double x, y, am, bm, a0, b0;
    assert_int_equal(dss_sensor_read(&s, b1, b2, NULL, &x, &y), SUNMC_OK);
    dss_sensor_angles(&s, x, y, &am, &bm);
    table_truth(b1, b2, &a0, &b0);
    assert_near(a0, a_deg * RAD_PER_DEG, 1e-14);
    assert_near(b0, b_deg * RAD_PER_DEG, 1e-14);
    *ea = (am - a0) * ARCSEC_PER_RAD;
    *eb = (bm - b0) * ARCSEC_PER_RAD;
}

static sunmc_config no_glass(void)
{
    sunmc_config c = dss_test_config();
    dss_cfg(&c)->design.glass_thickness_mm = 0;
    dss_cfg(&c)->design.mount = DSS_MOUNT_ALIGNED; /* the paper's eq. 6 */
    return c;
}

/* Fig. 2, dh = 0.2 px: the alpha error depends on alpha only, equals
 * atan((h + dh)/h tan alpha) - alpha, and rises then falls with |alpha|
 * (peak where tan^2 alpha = h / (h + dh), near 45 deg, inside the field);
 * beta behaves the same in beta. */
static void test_dh_alone(void **state)
{
    sunmc_config c = no_glass();
    dss_config *dc = dss_cfg(&c);
    dss_deviations dev = {0};
    dev.dh_px = 0.2;
    double h = dc->design.h_mm, dh = dev.dh_px * dc->design.pixel_um * MM_PER_UM;
    double peak_a = 0, peak_at = 0;
    for (double a = -60; a <= 60; a += 2.5) {
        double ea0, eb0;
        errors(&c, &dev, a, 0, &ea0, &eb0);
        double expect = (atan((h + dh) / h * tan(a * RAD_PER_DEG)) - a * RAD_PER_DEG) *
                        ARCSEC_PER_RAD;
        assert_near(ea0, expect, 1e-7);
        for (double b = -60; b <= 60; b += 10) {
            double ea, eb;
            errors(&c, &dev, a, b, &ea, &eb);
            assert_near(ea, ea0, 1e-7); /* alpha's error does not depend on beta */
            double ea_t, eb_t;
            errors(&c, &dev, b, a, &ea_t, &eb_t);
            assert_near(eb_t, ea0, 1e-7); /* beta: the same tendency */
        }
        if (fabs(ea0) > peak_a) {
            peak_a = fabs(ea0);
            peak_at = fabs(a);
        }
    }
    double a_star = atan(sqrt(h / (h + dh))) * DEG_PER_RAD;
    assert_near(peak_at, a_star, 2.5);
    double e10, e60, e_star, unused;
    errors(&c, &dev, 10, 0, &e10, &unused);
    errors(&c, &dev, 60, 0, &e60, &unused);
    errors(&c, &dev, a_star, 0, &e_star, &unused);
    assert_true(fabs(e10) < fabs(e_star));
    assert_true(fabs(e60) < 0.9 * fabs(e_star)); /* falls again before the edge */
    assert_true(fabs(e60) > fabs(e10));
}

/* Fig. 3, dx = dy = 0.1 px.  In this model the principal-point error is a
 * shift of the pinhole over the detector: the spot moves by dx along X for
 * every sun direction, so alpha' = atan(tan alpha - dx/h) and beta is not
 * touched at all (and dy moves only beta).  The alpha error is largest at
 * the centre (~ dx/h cos^2 alpha).  The DSS paper reports that dx also
 * moves beta and that the error is smaller at the centre: it models the
 * principal point as a tilt of the initial sun vector (dx, dy, -h) that the
 * table then rotates (eq. 6) and subtracts (dx, dy) afterwards (eq. 9-10);
 * a tilt rotated by b1 about X and then b2 about Y leaks into both angles
 * asymmetrically.  In a pinhole sensor the offset is a translation, and a
 * translation cannot move the spot across X. */
static void test_principal_point(void **state)
{
    sunmc_config c = no_glass();
    dss_config *dc = dss_cfg(&c);
    double h = dc->design.h_mm, pix = dc->design.pixel_um * MM_PER_UM;
    dss_deviations dx = {0}, dy = {0};
    dx.dx_px = 0.1;
    dy.dy_px = 0.1;
    double centre = 0, edge = 0;
    for (double a = -60; a <= 60; a += 5)
        for (double b = -60; b <= 60; b += 5) {
            double ea, eb;
            errors(&c, &dx, a, b, &ea, &eb);
            assert_near(eb, 0.0, 1e-7);
            double expect = (atan(tan(a * RAD_PER_DEG) - dx.dx_px * pix / h) - a * RAD_PER_DEG) *
                            ARCSEC_PER_RAD;
            assert_near(ea, expect, 1e-7);
            if (a == 0)
                centre = fabs(ea);
            if (fabs(a) == 60)
                edge = fabs(ea);
            errors(&c, &dy, a, b, &ea, &eb);
            assert_near(ea, 0.0, 1e-7);
            expect = (atan(tan(b * RAD_PER_DEG) - dy.dy_px * pix / h) - b * RAD_PER_DEG) *
                     ARCSEC_PER_RAD;
            assert_near(eb, expect, 1e-7);
        }
    assert_near(centre, dx.dx_px * pix / h * ARCSEC_PER_RAD, 1e-6);
    assert_true(edge < 0.3 * centre);
}

/* Max |error| (arcsec) of alpha (which = 0) or beta over truth angles
 * with both |alpha|, |beta| <= lim deg. */
static double max_err(const sunmc_config *c, const dss_deviations *dev, int which, double lim)
{
    double m = 0, step = lim / 10;
    for (double a = -lim; a <= lim + 1e-9; a += step)
        for (double b = -lim; b <= lim + 1e-9; b += step) {
            double ea, eb;
            errors(c, dev, a, b, &ea, &eb);
            m = fmax(m, fabs(which == 0 ? ea : eb));
        }
    return m;
}

/* Fig. 4, c1, c2, c3 = 10": negligible in the centre, growing to the edge,
 * with the paper's symmetries:
 *   alpha(c1) ~ beta(c2): both vanish on the axes and are odd in alpha and
 *     in beta, with the same sign in each quadrant (a saddle);
 *   alpha(c2) ~ beta(c1): even, growing along the other axis, and on the
 *     axes alpha(c2)(0, x) = -beta(c1)(x, 0);
 *   alpha(c3) ~ beta(c3): alpha(c3)(a, b) = -beta(c3)(b, a) to first order. */
static void test_installation(void **state)
{
    sunmc_config c = no_glass();
    dss_deviations d1 = {0}, d2 = {0}, d3 = {0};
    d1.c1_arcsec = d2.c2_arcsec = d3.c3_arcsec = 10;
    const dss_deviations *all[3] = {&d1, &d2, &d3};
    for (int k = 0; k < 3; k++)
        for (int w = 0; w < 2; w++) {
            double centre = max_err(&c, all[k], w, 1.0), edge = max_err(&c, all[k], w, 60.0);
            assert_true(edge > 1.0);
            assert_true(centre < 0.02 * edge);
            assert_true(centre < 0.2);
        }
    for (double a = -60; a <= 60; a += 10)
        for (double b = -60; b <= 60; b += 10) {
            double a1, b1, a2, b2, a3, b3, a3t, b3t, ma, mb, na, nb;
            errors(&c, &d1, a, b, &a1, &b1);
            errors(&c, &d2, a, b, &a2, &b2);
            errors(&c, &d3, a, b, &a3, &b3);
            errors(&c, &d3, b, a, &a3t, &b3t);
            /* c3: alpha pattern is beta's, transposed and negated */
            assert_near(a3, -b3t, 0.01 * 14);
            /* c1 alpha and c2 beta: saddles of the same sign, zero on the axes */
            if (a == 0 || b == 0) {
                assert_near(a1, 0, 2e-3);
                assert_near(b2, 0, 2e-3);
            } else {
                assert_true(a1 * b2 > 0);
                assert_true(a1 * (a * b) > 0);
            }
            errors(&c, &d1, -a, b, &ma, &mb);
            errors(&c, &d2, a, -b, &na, &nb);
            assert_near(ma, -a1, 2e-3);  /* odd in alpha */
            assert_near(nb, -b2, 2e-3);  /* odd in beta */
        }
    for (double x = -60; x <= 60; x += 10) {
        double a2, b2, a1, b1;
        errors(&c, &d2, 0, x, &a2, &b2);
        errors(&c, &d1, x, 0, &a1, &b1);
        assert_near(a2, -b1, 1e-6);
        if (fabs(x) >= 30)
            assert_true(fabs(a2) > 1.0);
    }
}

/* Fig. 5, refraction of the nominal cover glass read with the paper's
 * eq. 9-10 (design.onboard_refraction = ignored): the alpha error grows with
 * |alpha| at fixed beta, and beta's with |beta| at fixed alpha, over the
 * field up to 50 deg per axis (and 60 deg on the axes).  In the corners
 * beyond (field angle > 65 deg) it levels off and turns down, like the dh
 * curve, because the on-board atan(r/h) saturates. */
static void test_refraction(void **state)
{
    sunmc_config c = dss_test_config();
    assert_true(dss_cfg(&c)->design.glass_thickness_mm > 0);
    dss_cfg(&c)->design.onboard_refraction = DSS_ONBOARD_IGNORED; /* the paper's eq. 9-10 */
    dss_cfg(&c)->design.mount = DSS_MOUNT_ALIGNED;
    dss_deviations dev = {0};
    for (double fixed = -50; fixed <= 50; fixed += 25) {
        double prev_a = -1, prev_b = -1;
        for (double x = 0; x <= (fixed == 0 ? 60 : 50); x += 5) {
            double ea, eb, ea2, eb2;
            errors(&c, &dev, x, fixed, &ea, &eb);
            errors(&c, &dev, fixed, x, &ea2, &eb2);
            assert_true(fabs(ea) > prev_a);
            assert_true(fabs(eb2) > prev_b);
            prev_a = fabs(ea) + (x == 0 ? 1e-9 : 0);
            prev_b = fabs(eb2) + (x == 0 ? 1e-9 : 0);
        }
        assert_true(prev_a > 3600); /* degrees, not arcseconds: 0.4 mm of glass at 60 deg */
    }
}

/* Deviations are drawn per (seed, unit, deviation) and within their ranges. */
static void test_deviation_sampling(void **state)
{
    sunmc_config c = dss_test_config();
    dss_deviations a, b, other;
    dss_deviations_sample(&c, 7, 3, &a);
    dss_deviations_sample(&c, 7, 3, &b);
    dss_deviations_sample(&c, 7, 4, &other);
    assert_memory_equal(&a, &b, sizeof a);
    assert_true(a.dh_px != other.dh_px);
    double v[DSS_N_DEV];
    dss_deviations_values(&a, v);
    /* the thermal tolerances and the detector's tilt are 0 by default; the
     * fixed pattern's amplitudes uniform below PRNU 1 %, DSNU 0.1 %; the
     * ghost fixed at 1 */
    const double lim[DSS_N_DEV] = {0.2, 0.1, 0.1, 10, 10, 10, 10, 0.005, 10, 10,
                                   0,   0,   0,   0,  0,  0,  1,  0.1,   1};
    for (int i = 0; i < DSS_N_DEV; i++)
        assert_true(fabs(v[i]) <= lim[i] && (v[i] != 0.0) == (lim[i] > 0));
    assert_true(v[DSS_N_DEV - 1] == lim[DSS_N_DEV - 1]);
    dss_cfg(&c)->tol.dx_px.value = 0.5; /* another tolerance does not reshuffle dh */
    dss_deviations_sample(&c, 7, 3, &b);
    assert_true(a.dh_px == b.dh_px && a.dx_px != b.dx_px);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dh_alone),    cmocka_unit_test(test_principal_point),
        cmocka_unit_test(test_installation), cmocka_unit_test(test_refraction),
        cmocka_unit_test(test_deviation_sampling),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
