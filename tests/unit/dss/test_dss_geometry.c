/* test_dss_geometry.c - the DSS rotations, rotary table, cover-glass optics
 * and S-curve centroid against independent derivations. */
#include "test_util.h"

#include "dss_centroid.h"
#include "optics.h"
#include "rotation.h"
#include "status.h"
#include "units.h"

static void assert_mat_near(const mat3 a, const mat3 b, double tol)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            assert_near(a[i][j], b[i][j], tol);
}

static const double angle_sets[][3] = {
    {0.3, -0.7, 1.1}, {-1.2, 0.4, -0.25}, {2.0, 1.5, -2.8}, {1e-4, -5e-5, 3e-5}, {0, 0.9, 0}};
#define N_SETS (sizeof angle_sets / sizeof angle_sets[0])

/* Closed form = Ry(ty) Rx(tx) Rz(tz), the product of elementary rotations. */
static void test_zxy_is_product(void **state)
{
    for (size_t k = 0; k < N_SETS; k++) {
        double tx = angle_sets[k][0], ty = angle_sets[k][1], tz = angle_sets[k][2];
        mat3 c, rx, ry, rz, t, p;
        rot_zxy(tx, ty, tz, c);
        rot_x(tx, rx);
        rot_y(ty, ry);
        rot_z(tz, rz);
        mat3_mul(rx, rz, t);
        mat3_mul(ry, t, p);
        assert_mat_near(c, p, 1e-15);
    }
}

/* Orthonormal with determinant +1. */
static void test_zxy_orthonormal(void **state)
{
    for (size_t k = 0; k < N_SETS; k++) {
        mat3 c, ct, p;
        rot_zxy(angle_sets[k][0], angle_sets[k][1], angle_sets[k][2], c);
        mat3_transpose(c, ct);
        mat3_mul(c, ct, p);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                assert_near(p[i][j], i == j ? 1.0 : 0.0, 1e-15);
        double det = c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1]) -
                     c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0]) +
                     c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
        assert_near(det, 1.0, 1e-14);
    }
}

/* Composition order: z first, then x, then y.  The new Y axis is the last
 * rotation's axis, so it is the old axis Rz^T Rx^T e_y; the order matters
 * (zxy differs from yxz for finite angles); and single-axis cases reduce to
 * the elementary matrix; a passive x rotation by +a tilts e_z toward +y. */
static void test_zxy_order(void **state)
{
    double tx = 0.4, ty = -0.3, tz = 0.7;
    mat3 c, rx, ry, rz, t, other;
    rot_zxy(tx, ty, tz, c);
    rot_x(tx, rx);
    rot_y(ty, ry);
    rot_z(tz, rz);
    /* The final frame's Y axis, expressed in the old frame, is row 2 of C
     * and does not depend on ty. */
    mat3 c0;
    rot_zxy(tx, 0.0, tz, c0);
    for (int j = 0; j < 3; j++)
        assert_near(c[1][j], c0[1][j], 1e-15);
    /* yxz order differs. */
    mat3_mul(rx, ry, t);
    mat3_mul(rz, t, other);
    double diff = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            diff = fmax(diff, fabs(other[i][j] - c[i][j]));
    assert_true(diff > 0.05);
    mat3 e;
    rot_zxy(tx, 0, 0, e);
    assert_mat_near(e, rx, 0);
    rot_zxy(0, ty, 0, e);
    assert_mat_near(e, ry, 0);
    rot_zxy(0, 0, tz, e);
    assert_mat_near(e, rz, 0);
    double z[3] = {0, 0, 1}, v[3];
    mat3_vec(rx, z, v);
    assert_near(v[1], sin(tx), 1e-15);
    assert_near(v[2], cos(tx), 1e-15);
}

/* Derivatives against central differences. */
static void test_zxy_derivatives(void **state)
{
    const double h = 1e-6;
    for (size_t k = 0; k < N_SETS; k++) {
        double a[3] = {angle_sets[k][0], angle_sets[k][1], angle_sets[k][2]};
        mat3 d[3];
        rot_zxy_deriv(a[0], a[1], a[2], d[0], d[1], d[2]);
        for (int w = 0; w < 3; w++) {
            double ap[3] = {a[0], a[1], a[2]}, am[3] = {a[0], a[1], a[2]};
            ap[w] += h;
            am[w] -= h;
            mat3 cp, cm, num;
            rot_zxy(ap[0], ap[1], ap[2], cp);
            rot_zxy(am[0], am[1], am[2], cm);
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    num[i][j] = (cp[i][j] - cm[i][j]) / (2 * h);
            assert_mat_near(d[w], num, 1e-9);
        }
    }
}

/* The table's sun vector R(b) e_z = (-sin b2 cos b1, sin b1, cos b1 cos b2)
 * and its angles are the DSS paper's eq. 3-4. */
static void test_table_truth(void **state)
{
    for (double b1 = -60; b1 <= 60; b1 += 7.5)
        for (double b2 = -60; b2 <= 60; b2 += 7.5) {
            double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG;
            mat3 R;
            table_rotation(r1, r2, R);
            double z[3] = {0, 0, 1}, u[3];
            mat3_vec(R, z, u);
            assert_near(u[0], -sin(r2) * cos(r1), 1e-15);
            assert_near(u[1], sin(r1), 1e-15);
            assert_near(u[2], cos(r1) * cos(r2), 1e-15);
            double a, b, a0, b0;
            sun_angles_of(u, &a, &b);
            table_truth(r1, r2, &a0, &b0);
            assert_near(a0, -r2, 0);
            assert_near(a, a0, 1e-14);
            assert_near(b, b0, 1e-14);
        }
}

/* table_solve inverts R(b) v = w; and fails for an unreachable w. */
static void test_table_solve(void **state)
{
    mat3 M;
    rot_zxy(3e-4, -2e-4, 5e-4, M);
    double v[3] = {M[2][0], M[2][1], M[2][2]};
    for (double b1 = -55; b1 <= 55; b1 += 11)
        for (double b2 = -55; b2 <= 55; b2 += 11) {
            mat3 R;
            double w[3], s1, s2;
            table_rotation(b1 * RAD_PER_DEG, b2 * RAD_PER_DEG, R);
            mat3_vec(R, v, w);
            assert_int_equal(table_solve(v, w, &s1, &s2), SUNMC_OK);
            assert_near(s1, b1 * RAD_PER_DEG, 1e-12);
            assert_near(s2, b2 * RAD_PER_DEG, 1e-12);
        }
    double vx[3] = {0.8, 0, 0.6}, wy[3] = {0, 1, 0}, s1, s2;
    assert_int_equal(table_solve(vx, wy, &s1, &s2), SUNMC_EDOM);
}

/* Angle between vectors: small angles to full precision. */
static void test_angle_between(void **state)
{
    double u[3], v[3];
    sun_vector_of(0.3, -0.2, u);
    sun_vector_of(0.3 + 1e-9, -0.2, v);
    double e = angle_between(u, v);
    /* d(direction)/d(alpha) at (alpha, beta): |d u / d alpha| */
    double h = 1e-6, up[3];
    sun_vector_of(0.3 + h, -0.2, up);
    double rate = angle_between(u, up) / h;
    assert_near(e, 1e-9 * rate, 1e-15); /* acos of the dot product would be off by ~1e-8 */
    double a, b;
    sun_angles_of(u, &a, &b);
    assert_near(a, 0.3, 1e-15);
    assert_near(b, -0.2, 1e-15);
}

/* Scalar Snell's law, written independently of the vector trace. */
static double radial_mm(double theta, double H, double t, double n)
{
    double tg = asin(sin(theta) / n);
    return (H - t) * tan(theta) + t * tan(tg);
}

/* The vector ray trace agrees with scalar Snell and with the closed form;
 * the spot does not depend on where the glass sits; no glass or n = 1 gives
 * the pinhole formula. */
static void test_optics_trace(void **state)
{
    const double P[3] = {0.0011, -0.0007, 3.0011};
    const double t = 0.4, n = 1.52;
    for (double th = 0; th <= 70; th += 5)
        for (double phi = 0; phi < 360; phi += 45) {
            double T = th * RAD_PER_DEG, F = phi * RAD_PER_DEG;
            double u[3] = {sin(T) * cos(F), sin(T) * sin(F), cos(T)};
            double s0[2], s1[2], s2[2], s3[2];
            assert_int_equal(optics_trace(u, P, 0.0, t, n, s0), SUNMC_OK);
            assert_int_equal(optics_trace(u, P, 1.7, t, n, s1), SUNMC_OK);
            double r = radial_mm(T, P[2], t, n);
            assert_near(s0[0], P[0] - r * cos(F), 1e-12);
            assert_near(s0[1], P[1] - r * sin(F), 1e-12);
            assert_near(s1[0], s0[0], 1e-12);
            assert_near(s1[1], s0[1], 1e-12);
            double q = optics_q(u, P[2], t, n, NULL);
            assert_near(s0[0], P[0] - u[0] * q, 1e-12);
            assert_near(s0[1], P[1] - u[1] * q, 1e-12);
            assert_int_equal(optics_trace(u, P, 0.0, 0.0, n, s2), SUNMC_OK);
            assert_int_equal(optics_trace(u, P, 0.5, t, 1.0, s3), SUNMC_OK);
            assert_near(s2[0], P[0] - P[2] * tan(T) * cos(F), 1e-12);
            assert_near(s3[0], s2[0], 1e-12);
            assert_near(s3[1], s2[1], 1e-12);
        }
    /* The glass pulls the spot in: at 60 deg, by t (tan 60 - tan asin(sin 60 / n)). */
    double u60[3] = {sin(M_PI / 3), 0, cos(M_PI / 3)}, sg[2], sn[2];
    optics_trace(u60, P, 0, t, n, sg);
    optics_trace(u60, P, 0, 0, n, sn);
    assert_near(sg[0] - sn[0], t * (tan(M_PI / 3) - tan(asin(sin(M_PI / 3) / n))), 1e-12);
}

/* Error paths of the optics. */
static void test_optics_errors(void **state)
{
    const double P[3] = {0, 0, 3};
    double s[2], th;
    double below[3] = {0.6, 0, -0.8}, grazing[3] = {1, 0, 0}, up[3] = {0, 0, 1};
    assert_int_equal(optics_trace(below, P, 0, 0.4, 1.5, s), SUNMC_EDOM);
    assert_int_equal(optics_trace(grazing, P, 0, 0.4, 1.5, s), SUNMC_EDOM);
    assert_int_equal(optics_trace(up, P, 2.9, 0.4, 1.5, s), SUNMC_EDOM);
    assert_int_equal(optics_trace(up, P, -0.1, 0.4, 1.5, s), SUNMC_EDOM);
    assert_int_equal(optics_field_angle(1e6, 3, 0.4, 1.5, &th), SUNMC_EDOM);
}

/* The closed form's gradient against central differences. */
static void test_optics_gradient(void **state)
{
    double u[3] = {0.5, -0.3, 0}, g[OPTICS_NGRAD];
    u[2] = sqrt(1 - u[0] * u[0] - u[1] * u[1]);
    double x[OPTICS_NGRAD] = {u[0], u[1], u[2], 3.0, 0.4, 1.52};
    optics_q(u, 3.0, 0.4, 1.52, g);
    const double h = 1e-6;
    for (int k = 0; k < OPTICS_NGRAD; k++) {
        double xp[OPTICS_NGRAD], xm[OPTICS_NGRAD];
        memcpy(xp, x, sizeof x);
        memcpy(xm, x, sizeof x);
        xp[k] += h;
        xm[k] -= h;
        double qp = optics_q(xp, xp[3], xp[4], xp[5], NULL);
        double qm = optics_q(xm, xm[3], xm[4], xm[5], NULL);
        assert_near(g[k], (qp - qm) / (2 * h), 1e-7);
    }
}

/* Field angle inverts the radial distance. */
static void test_field_angle_inverse(void **state)
{
    for (double th = 0; th <= 75; th += 2.5) {
        double T = th * RAD_PER_DEG, got;
        assert_int_equal(optics_field_angle(radial_mm(T, 3.0, 0.4, 1.52), 3.0, 0.4, 1.52, &got),
                         SUNMC_OK);
        assert_near(got, T, 1e-12);
    }
}

/* The Bessel series equals the brute-force centroid; the bias is odd and
 * vanishes at pixel centres and edges; a larger spot has a smaller S-curve. */
static void test_scurve(void **state)
{
    const double sizes[] = {2.5, 4.0, 60.0 / 5.5};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        double amp[DSS_SCURVE_HARMONICS];
        dss_scurve_amplitudes(sizes[k], amp);
        double peak = 0;
        for (double x = -0.5; x <= 0.5; x += 0.01) {
            double b = dss_scurve_bias(amp, x);
            peak = fmax(peak, fabs(test_disc_centroid(sizes[k], x) - x));
            assert_near(b, test_disc_centroid(sizes[k], x) - x, sizes[k] < 5 ? 2e-5 : 2e-6);
            assert_near(dss_scurve_bias(amp, -x), -b, 1e-15);
        }
        assert_true(peak > 1e-3); /* the comparison above is not trivial */
        assert_near(dss_scurve_bias(amp, 0.0), 0.0, 1e-15);
        assert_near(dss_scurve_bias(amp, 0.5), 0.0, 1e-12);
    }
    double a_small[DSS_SCURVE_HARMONICS], a_big[DSS_SCURVE_HARMONICS];
    dss_scurve_amplitudes(2.5, a_small);
    dss_scurve_amplitudes(10.9, a_big);
    assert_true(fabs(a_big[0]) < fabs(a_small[0]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zxy_is_product),     cmocka_unit_test(test_zxy_orthonormal),
        cmocka_unit_test(test_zxy_order),          cmocka_unit_test(test_zxy_derivatives),
        cmocka_unit_test(test_table_truth),        cmocka_unit_test(test_table_solve),
        cmocka_unit_test(test_angle_between),      cmocka_unit_test(test_optics_trace),
        cmocka_unit_test(test_optics_errors),      cmocka_unit_test(test_optics_gradient),
        cmocka_unit_test(test_field_angle_inverse), cmocka_unit_test(test_scurve),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
