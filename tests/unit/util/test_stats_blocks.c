/* test_stats_blocks.c - a mean's and a ratio's interval from independent
 * blocks (stats_blocks.h), against hand computations. */
#include "test_util.h"

#include "stats_blocks.h"
#include "status.h"

#include <gsl/gsl_cdf.h>
#include <math.h>

/* x = 1, 2 | 3, 4 in two blocks: R = 2.5, block residual totals -2 and 2,
 * v = 2 / 1 * 8 / 4^2 = 1, half-width t_{0.975, 1} = 12.7062. */
static void two_blocks_by_hand(void **state)
{
    (void)state;
    const double x[] = {1, 2, 3, 4}, a[] = {1, 1, 1, 1};
    const long blk[] = {0, 0, 1, 1};
    double h = gsl_cdf_tdist_Pinv(0.975, 1), r;
    stats_interval ci;
    char err[SUNMC_ERRLEN];
    assert_int_equal(stats_blocks_ratio_t(x, a, blk, 4, 0.95, &r, &ci, err, sizeof err), SUNMC_OK);
    assert_float_equal(r, 2.5, 1e-15);
    assert_float_equal(ci.lo, 2.5 - h, 1e-12);
    assert_float_equal(ci.hi, 2.5 + h, 1e-12);
    stats_blocks b;
    stats_blocks_init(&b);
    for (int i = 0; i < 4; i++)
        stats_blocks_add(&b, blk[i], x[i]);
    long nb;
    assert_float_equal(stats_blocks_variance(&b, &nb), 1.0, 1e-15);
    assert_int_equal(nb, 2);
    assert_int_equal(stats_blocks_t(&b, 2.5, 0.95, &ci, err, sizeof err), SUNMC_OK);
    assert_float_equal(ci.hi, 2.5 + h, 1e-12);
    /* a share: 1, 1 | 0, 1 -> 0.75, block variance 2 * (0.5^2 + 0.5^2) / 16 */
    stats_blocks p;
    stats_blocks_init(&p);
    const double pass[] = {1, 1, 0, 1};
    for (int i = 0; i < 4; i++)
        stats_blocks_add(&p, blk[i], pass[i]);
    assert_float_equal(stats_blocks_deff(&p, 0.75, 4), (2 * 0.5 / 16) / (0.75 * 0.25 / 4), 1e-12);
}

/* Unequal blocks (a partial last one) and a shift: the ratio estimator's
 * variance is unchanged by adding a constant to every value. */
static void unequal_blocks_shift(void **state)
{
    (void)state;
    const double x[] = {2, 5, 1, 7, 3, 9}, a[] = {1, 1, 1, 1, 1, 1};
    const long blk[] = {0, 0, 0, 1, 1, 2};
    stats_blocks b, s;
    stats_blocks_init(&b);
    stats_blocks_init(&s);
    for (int i = 0; i < 6; i++) {
        stats_blocks_add(&b, blk[i], x[i]);
        stats_blocks_add(&s, blk[i], x[i] + 1000.0);
    }
    long n1, n2;
    double v = stats_blocks_variance(&b, &n1);
    /* by hand: R = 27 / 6 = 4.5; totals 8, 10, 9 against 13.5, 9, 4.5:
     * residuals -5.5, 1, 4.5; v = 3 / 2 * 51.5 / 36 */
    assert_float_equal(v, 1.5 * 51.5 / 36.0, 1e-12);
    assert_float_equal(stats_blocks_variance(&s, &n2), v, 1e-9);
    assert_int_equal(n1, 3);
    double r;
    stats_interval ci;
    char err[SUNMC_ERRLEN];
    stats_blocks_ratio_t(x, a, blk, 6, 0.9, &r, &ci, err, sizeof err);
    double h = gsl_cdf_tdist_Pinv(0.95, 2) * sqrt(v);
    assert_float_equal(ci.hi - r, h, 1e-12);
}

/* One block: no interval (NaN), never a made-up one; no blocks: the
 * independent units' ratio interval. */
static void one_block_none(void **state)
{
    (void)state;
    const double x[] = {1, 2, 3}, a[] = {1, 1, 1};
    const long blk[] = {4, 4, 4};
    double r, r2;
    stats_interval ci, ci2;
    char err[SUNMC_ERRLEN];
    stats_blocks_ratio_t(x, a, blk, 3, 0.95, &r, &ci, err, sizeof err);
    assert_true(isnan(ci.lo) && isnan(ci.hi));
    stats_blocks_ratio_t(x, a, NULL, 3, 0.95, &r, &ci, err, sizeof err);
    stats_ratio_t(x, a, 3, 0.95, &r2, &ci2, err, sizeof err);
    assert_memory_equal(&ci, &ci2, sizeof ci);
    stats_blocks b;
    stats_blocks_init(&b);
    stats_blocks_add(&b, 7, 1.0);
    assert_int_equal(stats_blocks_t(&b, 1.0, 0.95, &ci, err, sizeof err), SUNMC_OK);
    assert_true(isnan(ci.lo));
    assert_int_equal(stats_blocks_t(&b, 1.0, 1.0, &ci, err, sizeof err), SUNMC_EINPUT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(two_blocks_by_hand),
        cmocka_unit_test(unequal_blocks_shift),
        cmocka_unit_test(one_block_none),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
