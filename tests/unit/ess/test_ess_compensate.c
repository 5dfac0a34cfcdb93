/* test_ess_compensate.c - the ESS compensation (the calibration model's
 * inverse) against an independent long-double inverse: Newton's method on
 * the fine-code equation in 64-bit precision from the double answer, then
 * eq. 13 by tanl and atanl.  Covers the shortcuts of issue 27 on both
 * sides of their limits: eq. 13's arctangent by series (|e| <= 1e-2,
 * |alpha_d| <= 1.4 rad; beyond, libm's), the later Halley turns by the
 * short series (|w dx| <= 0.1; beyond, libm's sine and cosine), the
 * noise-free pass from the noisy one's tangent, and the step test as one
 * comparison (Halley's error bound below 1e-15 rad). */
#include "test_util.h"

#include "ess_model.h"
#include "status.h"
#include "units.h"

#include <math.h>

#define THETA0_RAD (2.0 * RAD_PER_DEG)
#define N 997

/* The exact inverse of raw under m (paper's model), in long double:
 * alpha_d by bisection of the rising fine-code equation (its root lies
 * within 2 k of raw) to 1e-12 rad, then Newton's method; *ad gets it. */
static long double exact_alpha(const ess_model *m, double raw, long double *ad)
{
    long double w = m->omega, ks = m->p[ESS_P_KS], kc = m->p[ESS_P_KC];
    long double k = hypotl(ks, kc), lo = raw - 2 * k, hi = raw + 2 * k, x;
    for (int it = 0; it < 32; it++) {
        x = 0.5L * (lo + hi);
        long double g = x - ks * sinl(w * x) - kc * cosl(w * x) - (long double)raw;
        *(g < 0 ? &lo : &hi) = x;
    }
    x = 0.5L * (lo + hi);
    for (int it = 0; it < 3; it++) {
        long double g = x - ks * sinl(w * x) - kc * cosl(w * x) - (long double)raw;
        long double gp = 1.0L - w * (ks * cosl(w * x) - kc * sinl(w * x));
        x -= g / gp;
    }
    *ad = x;
    long double t = tanl(x);
    return atanl(((long double)m->p[ESS_P_B] - t) /
                 ((long double)m->p[ESS_P_C] * t - (long double)m->p[ESS_P_A]));
}

static void model(ess_model *m, double a, double b, double c, double k_rad)
{
    ess_model_init(m, THETA0_RAD, 0);
    m->p[ESS_P_A] = a;
    m->p[ESS_P_B] = b;
    m->p[ESS_P_C] = c;
    m->p[ESS_P_KS] = 0.8 * k_rad;
    m->p[ESS_P_KC] = -0.6 * k_rad;
    ess_model_prepare(m);
}

/* What a comparison saw: the largest error (rad), and how many lanes fell
 * on each side of eq. 13's series limits (|e| <= 1e-2, |alpha_d| <= 1.4). */
typedef struct {
    double worst;
    int e_in, e_out, ad_in, ad_out;
} seen;

/* Each of n compensated angles alpha[i] (of raw[i]) against the exact
 * inverse, to tol rad. */
static void check_exact(const ess_model *m, size_t n, const double *raw, const double *alpha,
                        const int *st, double tol, seen *s)
{
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(st[i], SUNMC_OK);
        long double ad, ref = exact_alpha(m, raw[i], &ad);
        double err = fabs((double)(alpha[i] - ref));
        double e = fabs((double)tanl(ref - ad));
        s->e_in += e <= 0.99e-2, s->e_out += e > 1.01e-2;
        s->ad_in += fabsl(ad) <= 1.39L, s->ad_out += fabsl(ad) > 1.41L;
        s->worst = fmax(s->worst, err);
        if (!(err <= tol))
            fail_msg("raw %.17g: %.17g, exact %.17Lg (error %.3g rad, tolerance %.3g)", raw[i],
                     alpha[i], ref, err, tol);
    }
}

/* raw0 over [lo, hi] deg, raw = raw0 plus noise of amplitude noise_rad;
 * both compensated alone and as a pair, all against the exact inverse. */
static void run_case(const ess_model *m, double lo_deg, double hi_deg, double noise_rad,
                     double tol, seen *s)
{
    static double raw[N], raw0[N], a[N], a0[N], b[N], b0[N];
    static int st[N], st0[N], sb[N], sb0[N];
    for (int i = 0; i < N; i++) {
        raw0[i] = (lo_deg + (hi_deg - lo_deg) * i / (N - 1)) * RAD_PER_DEG;
        raw[i] = raw0[i] + noise_rad * sin(7.3 * i);
    }
    assert_int_equal(ess_model_compensate_pair_batch(m, N, raw, raw0, a, a0, st, st0), SUNMC_OK);
    assert_int_equal(ess_model_compensate_batch(m, N, raw, b, sb), SUNMC_OK);
    assert_int_equal(ess_model_compensate_batch(m, N, raw0, b0, sb0), SUNMC_OK);
    /* the noisy pass of a pair is the batch's, bit for bit (a lane's bits
     * depend on its own values only) */
    assert_memory_equal(a, b, sizeof a);
    check_exact(m, N, raw, a, st, tol, s);
    check_exact(m, N, raw0, a0, st0, tol, s);
    check_exact(m, N, raw, b, sb, tol, s);
    check_exact(m, N, raw0, b0, sb0, tol, s);
}

/* The arithmetic's own limit: a few ulp of alpha_d moved by g's rounding
 * over its slope (>= 1 - w k), plus eq. 13's last bit. */
static double comp_tolerance(const ess_model *m, double k_rad)
{
    return 2.5e-16 + 4.5e-16 / (1.0 - m->omega * k_rad);
}

/* The shipped tolerances' structural terms and the paper's k (0.035 deg),
 * noise from 1e-7 rad to beyond the noise-free pass's series (0.03 rad):
 * every angle within 7e-16 rad (4e-14 deg) of the exact inverse. */
static void test_compensate_exact_paper_k(void **state)
{
    const double noise[] = {1e-7, 5e-5, 3e-4, 3e-2};
    const double abc[][3] = {{1.0004, -2e-4, 1e-4}, {0.9995, 3e-4, -2.5e-4}, {1, 0, 0}};
    seen s = {0};
    for (size_t j = 0; j < sizeof abc / sizeof *abc; j++)
        for (size_t q = 0; q < sizeof noise / sizeof *noise; q++) {
            ess_model m;
            model(&m, abc[j][0], abc[j][1], abc[j][2], 0.035 * RAD_PER_DEG);
            run_case(&m, -62, 62, noise[q], 7e-16, &s);
        }
    print_message("paper k: largest error %.3g rad\n", s.worst);
}

/* w k = 0.9: Halley's later steps turn w x by more than the short series'
 * 0.1 (and the first by more than a radian), lane by lane to libm. */
static void test_compensate_exact_large_k(void **state)
{
    ess_model m;
    double k_rad = 0.9 / (2 * M_PI / (THETA0_RAD / 4));
    model(&m, 1.0004, -2e-4, 1e-4, k_rad);
    seen s = {0};
    const double noise[] = {1e-5, 3e-3, 0.3};
    for (size_t q = 0; q < sizeof noise / sizeof *noise; q++)
        run_case(&m, -62, 62, noise[q], comp_tolerance(&m, k_rad), &s);
    print_message("w k = 0.9: largest error %.3g rad (tolerance %.3g)\n", s.worst,
                  comp_tolerance(&m, k_rad));
}

/* Eq. 13's structural correction e = tan(alpha - alpha_d) = -b / (1 +
 * td^2 - b td) here (a = 1, c = 0): with b = 0.015 it is above the
 * series' 1e-2 within about 35 deg and below it beyond, so lanes on both
 * sides of the limit (and of the noise-free pass's) meet in one chunk;
 * with b = 0.2 every lane is far beyond it (where the series would be
 * wrong by up to 2e-9 rad). */
static void test_eq13_series_limit(void **state)
{
    ess_model m;
    model(&m, 1.0, 0.015, 0.0, 0.035 * RAD_PER_DEG);
    seen s = {0};
    run_case(&m, -62, 62, 5e-5, 7e-16, &s);
    assert_true(s.e_in > 500);
    assert_true(s.e_out > 500);
    model(&m, 1.0, 0.2, 0.0, 0.035 * RAD_PER_DEG);
    seen far = {0};
    run_case(&m, -62, 62, 5e-5, 7e-16, &far);
    assert_int_equal(far.e_in, 0);
}

/* Beyond |alpha_d| = 1.4 rad (80.2 deg) eq. 13 is libm's arctangent:
 * either side agrees with the exact inverse.  With c = 0.005 the tangent
 * of alpha passes through infinity at tan alpha_d = a / c (89.71 deg),
 * where eq. 13's principal value jumps from +90 to -90 deg while alpha_d
 * + atan(e) would go on past 90 (e small again): the series must not be
 * taken there. */
static void test_eq13_angle_limit(void **state)
{
    ess_model m;
    model(&m, 1.0004, -2e-4, 1e-4, 0.035 * RAD_PER_DEG);
    seen s = {0};
    run_case(&m, 78, 84, 5e-5, 1e-15, &s);
    run_case(&m, -84, -78, 5e-5, 1e-15, &s);
    assert_true(s.ad_in > 500);
    assert_true(s.ad_out > 500);
    model(&m, 1.0, 0.0, 0.005, 0.035 * RAD_PER_DEG);
    seen wrap = {0};
    run_case(&m, 89.76, 89.95, 1e-6, 1e-14, &wrap);
    assert_true(wrap.e_in > 500);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compensate_exact_paper_k),
        cmocka_unit_test(test_compensate_exact_large_k),
        cmocka_unit_test(test_eq13_series_limit),
        cmocka_unit_test(test_eq13_angle_limit),
    };
    return cmocka_run_group_tests_name("ess_compensate", tests, NULL, NULL);
}
