/* test_fit_prior.c - Gaussian priors as extra residual rows of the
 * Levenberg-Marquardt engine (fit_prior_set, issue 25): on a linear model
 * y = A x the fit with priors equals the closed-form posterior mean
 * (A^T A + W^2)^-1 (A^T y + W^2 mu), solved here by Cramer's rule, its
 * covariance (A^T A + W^2)^-1; weight 0 or a vanishing weight (sigma ->
 * infinity) reproduces the plain fit; a nonlinear model's fit with a huge
 * weight sits at the prior's mean; bad weights are refused. */
#include "test_util.h"

#include "fit.h"
#include "status.h"
#include "vmath.h"

#define N 40

typedef struct {
    double t[N], y[N];
} line_data;

/* f_i = x0 + x1 t_i - y_i */
static int line_fdf(const double *x, void *params, double *f, double *J, size_t ld)
{
    const line_data *d = params;
    for (size_t i = 0; i < N; i++) {
        f[i] = x[0] + x[1] * d->t[i] - d->y[i];
        J[i] = 1.0;
        J[ld + i] = d->t[i];
    }
    return 0;
}

/* f_i = exp(x0 t_i) x1 - y_i: nonlinear in x0 */
static int exp_fdf(const double *x, void *params, double *f, double *J, size_t ld)
{
    const line_data *d = params;
    for (size_t i = 0; i < N; i++) {
        double e = exp(x[0] * d->t[i]);
        f[i] = e * x[1] - d->y[i];
        J[i] = d->t[i] * e * x[1];
        J[ld + i] = e;
    }
    return 0;
}

static void make_data(line_data *d)
{
    for (int i = 0; i < N; i++) {
        d->t[i] = -1.0 + 2.0 * i / (N - 1.0);
        /* a line plus a deterministic wiggle standing for noise */
        d->y[i] = 0.3 + 1.7 * d->t[i] + 0.05 * sin(7.3 * i);
    }
}

static void posterior_equals_closed_form(void **state)
{
    line_data d;
    make_data(&d);
    fit_workspace *fw = fit_workspace_alloc(N, 2);
    assert_non_null(fw);
    const double mu[2] = {1.0, -2.0}, w[2] = {3.0, 0.5};
    assert_int_equal(fit_prior_set(fw, mu, w), SUNMC_OK);
    double x[2] = {0, 0};
    fit_result res;
    assert_int_equal(fit_solve(fw, line_fdf, &d, x, 100, &res), SUNMC_OK);
    /* closed form: M = A^T A + W^2, r = A^T y + W^2 mu */
    double s1 = 0, st = 0, stt = 0, sy = 0, sty = 0;
    for (int i = 0; i < N; i++) {
        s1 += 1;
        st += d.t[i];
        stt += d.t[i] * d.t[i];
        sy += d.y[i];
        sty += d.t[i] * d.y[i];
    }
    double m00 = s1 + w[0] * w[0], m01 = st, m11 = stt + w[1] * w[1];
    double r0 = sy + w[0] * w[0] * mu[0], r1 = sty + w[1] * w[1] * mu[1];
    double det = m00 * m11 - m01 * m01;
    /* to the engine's convergence (a further step would lower the cost by
     * < 1e-12 of it: x within ~1e-7 here); the prior moves x by ~0.1 */
    assert_near(x[0], (r0 * m11 - m01 * r1) / det, 1e-6);
    assert_near(x[1], (m00 * r1 - m01 * r0) / det, 1e-6);
    /* the data rows' chisq, and the prior's share separately */
    double chisq = 0;
    for (int i = 0; i < N; i++) {
        double f = x[0] + x[1] * d.t[i] - d.y[i];
        chisq += f * f;
    }
    assert_near(res.chisq, chisq, 1e-12);
    double pc = pow(w[0] * (x[0] - mu[0]), 2) + pow(w[1] * (x[1] - mu[1]), 2);
    assert_near(res.chisq_prior, pc, 1e-12 + 1e-9 * pc);
    assert_true(res.chisq_prior > 1e-3); /* the prior pulled */
    /* covariance: M^-1 */
    assert_int_equal(fit_covariance(fw), SUNMC_OK);
    assert_near(gsl_matrix_get(fw->covar, 0, 0), m11 / det, 1e-12 * m11 / det + 1e-15);
    assert_near(gsl_matrix_get(fw->covar, 0, 1), -m01 / det, 1e-12);
    assert_near(gsl_matrix_get(fw->covar, 1, 1), m00 / det, 1e-12 * m00 / det + 1e-15);
    fit_workspace_free(fw);
}

/* sigma -> infinity (weight 1e-12) and weight 0 both give the plain fit. */
static void vanishing_prior_is_plain_fit(void **state)
{
    line_data d;
    make_data(&d);
    fit_workspace *fw = fit_workspace_alloc(N, 2);
    double plain[2] = {0, 0}, x0w[2] = {0, 0}, tiny[2] = {0, 0};
    fit_result res;
    assert_int_equal(fit_solve(fw, exp_fdf, &d, plain, 100, &res), SUNMC_OK);
    const double mu[2] = {5.0, -5.0}, zero[2] = {0, 0}, eps[2] = {1e-12, 1e-12};
    assert_int_equal(fit_prior_set(fw, mu, zero), SUNMC_OK);
    assert_int_equal(fit_solve(fw, exp_fdf, &d, x0w, 100, &res), SUNMC_OK);
    assert_true(x0w[0] == plain[0] && x0w[1] == plain[1]);
    assert_int_equal(fit_prior_set(fw, mu, eps), SUNMC_OK);
    assert_int_equal(fit_solve(fw, exp_fdf, &d, tiny, 100, &res), SUNMC_OK);
    assert_near(tiny[0], plain[0], 1e-9);
    assert_near(tiny[1], plain[1], 1e-9);
    fit_prior_clear(fw);
    assert_int_equal(fw->prior_on, 0);
    fit_workspace_free(fw);
}

/* A weight far above the data's pins a nonlinear fit at the prior. */
static void strong_prior_pins(void **state)
{
    line_data d;
    make_data(&d);
    fit_workspace *fw = fit_workspace_alloc(N, 2);
    const double mu[2] = {0.2, 0.9}, w[2] = {1e6, 1e6};
    assert_int_equal(fit_prior_set(fw, mu, w), SUNMC_OK);
    double x[2] = {0, 1};
    fit_result res;
    assert_int_equal(fit_solve(fw, exp_fdf, &d, x, 200, &res), SUNMC_OK);
    assert_near(x[0], mu[0], 1e-6);
    assert_near(x[1], mu[1], 1e-6);
    fit_workspace_free(fw);
}

static void bad_weights_refused(void **state)
{
    fit_workspace *fw = fit_workspace_alloc(N, 2);
    const double mu[2] = {0, 0}, neg[2] = {1, -1}, inf[2] = {INFINITY, 1}, nan_mu[2] = {NAN, 0};
    const double ok[2] = {1, 1};
    assert_int_equal(fit_prior_set(fw, mu, neg), SUNMC_EINPUT);
    assert_int_equal(fit_prior_set(fw, mu, inf), SUNMC_EINPUT);
    assert_int_equal(fit_prior_set(fw, nan_mu, ok), SUNMC_EINPUT);
    assert_int_equal(fw->prior_on, 0);
    fit_workspace_free(fw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(posterior_equals_closed_form),
        cmocka_unit_test(vanishing_prior_is_plain_fit),
        cmocka_unit_test(strong_prior_pins),
        cmocka_unit_test(bad_weights_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
