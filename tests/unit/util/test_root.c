/* test_root.c - root_bisect_increasing against closed-form roots: to
 * adjacent doubles, for a steep and for a nearly flat function. */
#include "test_util.h"
#include "root.h"

#include <float.h>

static double cube_minus_two(double x, const void *ctx)
{
    (void)ctx;
    return x * x * x - 2.0;
}

/* x - k sin x - c with k near 1: slope 1 - k cos x, about 1e-6 at 0. */
static double flat(double x, const void *ctx)
{
    const double *k = ctx;
    return x - k[0] * sin(x) - k[1];
}

static void test_closed_forms(void **state)
{
    double r = root_bisect_increasing(cube_minus_two, NULL, 0.0, 2.0);
    assert_true(fabs(r - cbrt(2.0)) <= 2 * DBL_EPSILON * cbrt(2.0));
    /* the root of x - k sin x = c for c = x0 - k sin x0 is x0 */
    const double x0 = 1e-2, k[2] = {1.0 - 1e-6, x0 - (1.0 - 1e-6) * sin(x0)};
    r = root_bisect_increasing(flat, k, -1.0, 1.0);
    assert_true(fabs(r - x0) < 1e-9); /* the flat slope amplifies rounding: still near x0 */
    assert_true(fabs(flat(r, k)) <= fabs(flat(nextafter(r, 2.0), k)));
    assert_true(fabs(flat(r, k)) <= fabs(flat(nextafter(r, -2.0), k)));
    /* an exact zero at a midpoint is returned as it is: x^3 - 2 has none
     * in doubles, x - 0 sin x - 0.5 on [0, 1] has it at the first */
    const double half[2] = {0.0, 0.5};
    assert_true(root_bisect_increasing(flat, half, 0.0, 1.0) == 0.5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_closed_forms)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
