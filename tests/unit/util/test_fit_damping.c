/* test_fit_damping.c - the engine's first damping (fit.h, mu0): GSL's 1e-3
 * of the largest scaled diagonal after fit_workspace_alloc; from a start
 * next to the solution, mu0 at the floor (1e-7) reaches the same solution
 * to the engine's tolerance in no more iterations, on y = x1 exp(x0 t) +
 * x2 (t + e sin 3t) with a small e (x1 and x2 nearly collinear).
 * test_psd_fit shows fewer iterations on the problem it was made for. */
#include "test_util.h"

#include "fit.h"
#include "status.h"

#define N 60

typedef struct {
    double t[N], y[N];
} exp_data;

static int exp_fdf(const double *x, void *params, double *f, double *J, size_t ld)
{
    const exp_data *d = params;
    for (size_t i = 0; i < N; i++) {
        double e = exp(x[0] * d->t[i]), w = d->t[i] + 1e-6 * sin(3.0 * d->t[i]);
        f[i] = e * x[1] + x[2] * w - d->y[i];
        J[i] = d->t[i] * e * x[1];
        J[ld + i] = e;
        J[2 * ld + i] = w;
    }
    return 0;
}

static void warm_start_same_answer(void **state)
{
    exp_data d;
    for (int i = 0; i < N; i++) {
        d.t[i] = 2.0 * i / (N - 1.0);
        d.y[i] = 1.3 * exp(-0.8 * d.t[i]) + 0.25 * d.t[i] + 0.01 * sin(5.1 * i);
    }
    fit_workspace *fw = fit_workspace_alloc(N, 3);
    assert_non_null(fw);
    assert_true(fw->mu0 == 1e-3);
    double cold[3] = {-0.8 * 1.01, 1.3 * 0.99, 0.2}, warm[3] = {cold[0], cold[1], cold[2]};
    fit_result rc, rw;
    assert_int_equal(fit_solve(fw, exp_fdf, &d, cold, 100, &rc), SUNMC_OK);
    fw->mu0 = 1e-7;
    assert_int_equal(fit_solve(fw, exp_fdf, &d, warm, 100, &rw), SUNMC_OK);
    assert_near(warm[0], cold[0], 1e-7);
    assert_near(warm[1], cold[1], 1e-7);
    assert_near(warm[2], cold[2], 1e-7);
    assert_true(rw.iterations <= rc.iterations);
    fit_workspace_free(fw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(warm_start_same_answer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
