/* test_ess_fit.c - the ESS compensation model, its Jacobian, its inverse,
 * the alias detector and the calibration fit (round trips). */
#include "test_ess_grid.h"
#include "test_util.h"

#include "ess_calib.h"
#include "ess_model.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

#include <stdlib.h>

#define THETA0_RAD (2.0 * RAD_PER_DEG)

static void truth_model(ess_model *m, double roll_arcsec)
{
    ess_model_init(m, THETA0_RAD, roll_arcsec * RAD_PER_ARCSEC);
    m->p[ESS_P_A] = 1.0004;
    m->p[ESS_P_B] = -2.0e-4;
    m->p[ESS_P_C] = 1.0e-4;
    m->p[ESS_P_KS] = 3.0e-4;
    m->p[ESS_P_KC] = -2.0e-4;
    m->p[ESS_P_INST_Y] = 100 * RAD_PER_ARCSEC;
    m->p[ESS_P_INST_Z] = -60 * RAD_PER_ARCSEC;
    m->p[ESS_P_SUN_Y] = 30 * RAD_PER_ARCSEC;
    ess_model_prepare(m);
}


static const double betas3[] = {-20, 0, 20};

/* Analytic gradient against central differences. */
static void test_jacobian(void **state)
{
    ess_model m;
    truth_model(&m, 15);
    double g[ESS_NP_MAX];
    const double h[ESS_NP] = {1e-6, 1e-7, 1e-7, 1e-7, 1e-7, 1e-6, 1e-6, 1e-6};
    for (double a = -60; a <= 60; a += 13.7)
        for (double b = -25; b <= 25; b += 12.5) {
            double ar = a * RAD_PER_DEG, br = b * RAD_PER_DEG;
            ess_model_predict(&m, ar, br, g);
            for (int j = 0; j < ESS_NP; j++) {
                ess_model mp = m, mm = m;
                mp.p[j] += h[j];
                mm.p[j] -= h[j];
                ess_model_prepare(&mp);
                ess_model_prepare(&mm);
                double fd = (ess_model_predict(&mp, ar, br, NULL) -
                             ess_model_predict(&mm, ar, br, NULL)) / (2 * h[j]);
                assert_near(g[j], fd, 1e-6 * fmax(1.0, fabs(fd)));
            }
        }
}

/* Compensation is the exact inverse of the forward model, to 1e-9 deg. */
static void test_compensate_inverts(void **state)
{
    ess_model m;
    truth_model(&m, 0);
    m.p[ESS_P_KS] = 0.035 * RAD_PER_DEG; /* the paper's k, largest case */
    m.p[ESS_P_KC] = -0.02 * RAD_PER_DEG;
    ess_model_prepare(&m);
    for (double a = -62; a <= 62; a += 0.0917) {
        double ar = a * RAD_PER_DEG, back;
        double raw = ess_model_structural(&m, tan(ar));
        assert_int_equal(ess_model_compensate(&m, raw, &back), SUNMC_OK);
        assert_near(back * DEG_PER_RAD, a, 1e-9);
    }
    /* A fine-code term too large to invert is refused, not iterated wildly. */
    m.p[ESS_P_KS] = 0.2 * RAD_PER_DEG;
    double out;
    assert_int_equal(ess_model_compensate(&m, 0.1, &out), SUNMC_EDOM);
}

/* The pair compensation (a noisy raw and the same reading without noise):
 * the noiseless one starts from the noisy one's solution, its sines,
 * cosines, tangent and arctangent turned from the noisy one's by series;
 * every alpha is the one ess_model_compensate_batch gives the raw alone,
 * to 1e-15 rad / (1 - w k) (a few ulp of alpha_d moved by g's rounding
 * over its slope, which is >= 1 - w k: the arithmetic's own limit), for
 * noise from 1e-7 rad to beyond the series' ranges
 * (0.3 rad: libm's calls, lane by lane) and for a fine-code term whose
 * first Halley step turns w x by more than a radian (w k = 0.9). */
static void test_compensate_pair_matches_single(void **state)
{
    enum { N = 997 };
    static double raw[N], raw0[N], a[N], a0[N], s[N], s0[N];
    int st[N], st0[N], sts[N], sts0[N];
    const double noise[] = {1e-7, 1e-5, 1e-4, 1e-3, 3e-2, 0.3};
    const double k_rad[] = {3.6e-4, 0.9 / (2 * M_PI / (THETA0_RAD / 4))};
    double worst = 0;
    for (size_t q = 0; q < sizeof k_rad / sizeof *k_rad; q++)
        for (size_t j = 0; j < sizeof noise / sizeof *noise; j++) {
            ess_model m;
            truth_model(&m, 0);
            m.p[ESS_P_KS] = 0.8 * k_rad[q];
            m.p[ESS_P_KC] = -0.6 * k_rad[q];
            double tol = 1e-15 / (1.0 - m.omega * k_rad[q]);
            for (int i = 0; i < N; i++) {
                raw0[i] = (-61.9 + 123.8 * i / (N - 1)) * RAD_PER_DEG;
                raw[i] = raw0[i] + noise[j] * sin(7.3 * i); /* +- noise, any sign */
            }
            assert_int_equal(
                ess_model_compensate_pair_batch(&m, N, raw, raw0, a, a0, st, st0), SUNMC_OK);
            assert_int_equal(ess_model_compensate_batch(&m, N, raw, s, sts), SUNMC_OK);
            assert_int_equal(ess_model_compensate_batch(&m, N, raw0, s0, sts0), SUNMC_OK);
            for (int i = 0; i < N; i++) {
                assert_int_equal(st[i], SUNMC_OK);
                assert_int_equal(st0[i], SUNMC_OK);
                worst = fmax(worst, fmax(fabs(a[i] - s[i]), fabs(a0[i] - s0[i])));
                if (fabs(a[i] - s[i]) > tol || fabs(a0[i] - s0[i]) > tol)
                    fail_msg("k %g noise %g raw %d: pair %.17g %.17g, alone %.17g %.17g",
                             k_rad[q], noise[j], i, a[i], a0[i], s[i], s0[i]);
            }
        }
    print_message("pair against alone: largest difference %.3g rad\n", worst);
}

/* Eq. 12 with a = d, b = -c is tan(alpha + delta): check that identity, the
 * reason the roll must be fixed rather than fitted. */
static void test_rotation_degeneracy(void **state)
{
    ess_model m;
    ess_model_init(&m, THETA0_RAD, 0);
    double delta = 0.01;
    m.p[ESS_P_A] = 1;
    m.p[ESS_P_B] = tan(delta);
    m.p[ESS_P_C] = -tan(delta);
    for (double a = -1.0; a <= 1.0; a += 0.1)
        assert_near(ess_model_structural(&m, tan(a)), a + delta, 1e-12);
}

/* The alias detector fires for 1 deg (both directions) and 0.25 deg (one),
 * not for 0.2 or 0.3 deg. */
static void test_alias_detector(void **state)
{
    const double steps[] = {1.0, 0.25, 0.5, 0.2, 0.3};
    const int weak[] = {2, 1, 2, 0, 0};
    for (int s = 0; s < 5; s++) {
        ess_calib_workspace *cw = test_ess_grid(ESS_MODEL_PAPER, steps[s], betas3, 3);
        ess_alias al;
        ess_alias_check(cw->alpha_rad, cw->n, 2 * M_PI / (THETA0_RAD / 4), 0.2, &al);
        assert_int_equal(al.n_weak, weak[s]);
        /* Eigenvalues against a full spread's 1/2: at 0.25 deg the phases
         * are 0 and pi (sin = 0, cos = +-1: variances 0 and 1), at 0.2 deg
         * five phases 144 deg apart (1/2 each). */
        if (steps[s] == 0.25) {
            assert_near(al.eig_norm[0], 0, 1e-12);
            assert_near(al.eig_norm[1], 2, 1e-4);
            assert_near(fabs(al.evec[0][0]), 1, 1e-9); /* the sine direction */
        } else if (steps[s] == 0.2) {
            assert_near(al.eig_norm[0], 1, 0.02);
            assert_near(al.eig_norm[1], 1, 0.02);
        }
        ess_calib_free(cw);
    }
}

/* Noise-free data generated by the model are fitted back to 1e-6. */
static void test_fit_round_trip(void **state)
{
    ess_model truth, fit;
    truth_model(&truth, 20);
    ess_calib_workspace *cw = test_ess_grid(ESS_MODEL_PAPER, 0.2, betas3, 3);
    for (size_t i = 0; i < cw->n; i++)
        cw->raw_rad[i] = ess_model_predict(&truth, cw->alpha_rad[i], cw->beta_rad[i], NULL);
    fit_result fr;
    assert_int_equal(ess_calibrate(cw, THETA0_RAD, 20 * RAD_PER_ARCSEC, 0.2, 100, &fit, &fr),
                     SUNMC_OK);
    for (int j = 0; j < ESS_NP; j++)
        assert_near(fit.p[j], truth.p[j], 1e-6);
    assert_true(ess_calib_residual_rms(cw, &fit) < 1e-10);
    assert_int_equal(cw->alias.n_weak, 0);
    ess_calib_free(cw);
}

/* A 1-deg campaign cannot see the fine-code term: the fit keeps (ks, kc) at
 * 0 instead of trading them against b, and the rest still fits. */
static void test_fit_aliased_stays_sane(void **state)
{
    ess_model truth, fit;
    truth_model(&truth, 0);
    ess_calib_workspace *cw = test_ess_grid(ESS_MODEL_PAPER, 1.0, betas3, 3);
    for (size_t i = 0; i < cw->n; i++)
        cw->raw_rad[i] = ess_model_predict(&truth, cw->alpha_rad[i], cw->beta_rad[i], NULL);
    fit_result fr;
    assert_int_equal(ess_calibrate(cw, THETA0_RAD, 0, 0.2, 100, &fit, &fr), SUNMC_OK);
    assert_int_equal(cw->alias.n_weak, 2);
    assert_near(fit.p[ESS_P_KS], 0, 1e-7); /* truth: 3e-4 */
    assert_near(fit.p[ESS_P_KC], 0, 1e-7);
    /* The unresolved term leaks a little into the structure (its phase drifts
     * with the structural error), but the fit stays sane: a within 2e-4 (an
     * H error of 0.8 um), residual below the term's amplitude. */
    assert_near(fit.p[ESS_P_A], truth.p[ESS_P_A], 2e-4);
    assert_true(ess_calib_residual_rms(cw, &fit) <
                hypot(truth.p[ESS_P_KS], truth.p[ESS_P_KC]));
    ess_calib_free(cw);
}

/* A point of weight 0 (a gross error) does not pull the fit. */
static void test_fit_ignores_dropped_points(void **state)
{
    ess_model truth, fit;
    truth_model(&truth, 0);
    ess_calib_workspace *cw = test_ess_grid(ESS_MODEL_PAPER, 0.2, betas3, 3);
    for (size_t i = 0; i < cw->n; i++)
        cw->raw_rad[i] = ess_model_predict(&truth, cw->alpha_rad[i], cw->beta_rad[i], NULL);
    cw->raw_rad[100] += 2 * RAD_PER_DEG;
    cw->weight[100] = 0;
    fit_result fr;
    assert_int_equal(ess_calibrate(cw, THETA0_RAD, 0, 0.2, 100, &fit, &fr), SUNMC_OK);
    assert_near(fit.p[ESS_P_B], truth.p[ESS_P_B], 1e-8);
    ess_calib_free(cw);
}

/* The vectorised batch (the fit's residuals and Jacobian) agrees with the
 * scalar model point by point, a dropped point gives zeros even where the
 * model is not finite, and a point's value does not depend on its place in
 * the array (the pads and vector lanes are the same code for all). */
static void test_batch_matches_scalar(void **state)
{
    ess_model m;
    truth_model(&m, 15);
    ess_calib_workspace *cw = test_ess_grid(ESS_MODEL_PAPER, 0.7, betas3, 3);
    size_t n = cw->n, ld = vm_pad(n + 3);
    cw->table.n = n;
    ess_table_fill(&cw->table, cw->alpha_rad, cw->beta_rad);
    double *sw = vm_alloc(n), *raw = vm_alloc(n), *f = vm_alloc(ld), *J = vm_alloc(ld * ESS_NP);
    for (size_t i = 0; i < n; i++) {
        sw[i] = i % 7 == 3 ? 0.0 : 1.0 + 0.1 * (double)(i % 3);
        raw[i] = i % 7 == 3 ? NAN : 0.01 * (double)i;
    }
    ess_model_batch(&m, &cw->table, raw, sw, f, J, ld);
    for (size_t i = 0; i < n; i++) {
        double g[ESS_NP_MAX];
        double p = ess_model_predict(&m, cw->alpha_rad[i], cw->beta_rad[i], g);
        if (sw[i] == 0.0) {
            assert_true(f[i] == 0.0);
            for (int j = 0; j < ESS_NP; j++)
                assert_true(J[(size_t)j * ld + i] == 0.0);
            continue;
        }
        assert_near(f[i], sw[i] * (p - raw[i]), 1e-14);
        for (int j = 0; j < ESS_NP; j++)
            assert_near(J[(size_t)j * ld + i], sw[i] * g[j], 1e-12 * (1 + fabs(g[j])));
    }
    /* the same points shifted by one place give the same bits */
    ess_table t2 = cw->table;
    double *a2 = vm_alloc(n + 1), *b2 = vm_alloc(n + 1), *p1 = vm_alloc(n), *p2 = vm_alloc(n + 1);
    for (size_t i = 0; i < n; i++) {
        a2[i + 1] = cw->alpha_rad[i];
        b2[i + 1] = cw->beta_rad[i];
    }
    double *m2[9];
    for (int k = 0; k < 9; k++)
        t2.m[k] = m2[k] = vm_alloc(n + 1);
    t2.n = n + 1;
    ess_table_fill(&t2, a2, b2);
    ess_model_predict_batch(&m, &cw->table, p1);
    ess_model_predict_batch(&m, &t2, p2);
    assert_memory_equal(p1, p2 + 1, n * sizeof *p1);
    for (int k = 0; k < 9; k++)
        free(m2[k]);
    free(a2), free(b2), free(p1), free(p2), free(sw), free(raw), free(f), free(J);
    ess_calib_free(cw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jacobian),           cmocka_unit_test(test_compensate_inverts),
        cmocka_unit_test(test_compensate_pair_matches_single),
        cmocka_unit_test(test_rotation_degeneracy), cmocka_unit_test(test_alias_detector),
        cmocka_unit_test(test_fit_round_trip),     cmocka_unit_test(test_fit_aliased_stays_sane),
        cmocka_unit_test(test_fit_ignores_dropped_points),
        cmocka_unit_test(test_batch_matches_scalar),
    };
    return cmocka_run_group_tests_name("ess_fit", tests, NULL, NULL);
}
