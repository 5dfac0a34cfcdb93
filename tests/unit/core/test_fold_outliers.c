/* test_fold_outliers.c - issue 39: a cross-validation part unlike the
 * others (fold_outliers.h).  The rule's limits both sides: the ratio to the
 * median (2 is not above 2), the fewest parts judged (5, not 4), the most
 * marked (a quarter, not one more); parts not scored never judged; the
 * pooled RMS with and without the marked parts in closed form. */
#include "test_util.h"

#include "fold_outliers.h"

static int mark(const double *rms, int n, unsigned char *out, double *median)
{
    return fold_outliers_mark(rms, n, out, median);
}

static void test_ratio_both_sides(void **state)
{
    unsigned char out[8];
    double median;
    const double above[] = {1, 1, 1, 1, 2.0001};
    assert_int_equal(mark(above, 5, out, &median), 1);
    assert_true(median == 1.0);
    assert_int_equal(out[4], 1);
    assert_int_equal(out[0] + out[1] + out[2] + out[3], 0);
    const double at[] = {1, 1, 1, 1, 2.0};
    assert_int_equal(mark(at, 5, out, &median), 0);
    assert_int_equal(out[4], 0);
    /* the median of an even count: the mean of the middle two (3 and 4) */
    const double even[] = {3, 1, 4, 10, 2, 7.0, 5, 6};
    assert_int_equal(mark(even, 8, out, &median), 1);
    assert_true(median == 4.5);
    assert_int_equal(out[3], 1); /* 10 > 9 */
    assert_int_equal(out[5], 0); /* 7 < 9 */
}

static void test_fewest_and_most(void **state)
{
    unsigned char out[8];
    double median;
    const double four[] = {1, 1, 1, 5};
    assert_int_equal(mark(four, 4, out, &median), 0);
    assert_true(isnan(median));
    assert_int_equal(out[3], 0);
    /* five scored of six: judged, the unscored part never marked */
    const double gap[] = {1, 1, NAN, 1, 1, 5};
    assert_int_equal(mark(gap, 6, out, &median), 1);
    assert_int_equal(out[2], 0);
    assert_int_equal(out[5], 1);
    /* a quarter marked: 2 of 8 */
    const double quarter[] = {1, 1, 1, 1, 1, 1, 3, 3};
    assert_int_equal(mark(quarter, 8, out, &median), 2);
    assert_int_equal(out[6] + out[7], 2);
    /* more than a quarter: 2 of 7, the spread is the sensor's */
    assert_int_equal(mark(quarter + 1, 7, out, &median), 0);
    for (int f = 0; f < 7; f++)
        assert_int_equal(out[f], 0);
    /* more parts than it judges */
    static double many[FOLD_OUTLIER_MAX_FOLDS + 1];
    static unsigned char o[FOLD_OUTLIER_MAX_FOLDS + 1];
    for (int f = 0; f <= FOLD_OUTLIER_MAX_FOLDS; f++)
        many[f] = f == 0 ? 9 : 1;
    assert_int_equal(fold_outliers_mark(many, FOLD_OUTLIER_MAX_FOLDS, o, &median), 1);
    assert_int_equal(fold_outliers_mark(many, FOLD_OUTLIER_MAX_FOLDS + 1, o, &median), 0);
    assert_int_equal(o[0], 0);
}

static void test_pool_closed_form(void **state)
{
    /* three parts: 2 values of 1, 2 of 4, 1 of 25 (sums 2, 32, 25) */
    const double sum2[] = {2, 32, 25};
    const long cnt[] = {2, 2, 1};
    const unsigned char none[] = {0, 0, 0}, last[] = {0, 0, 1}, all[] = {1, 1, 1};
    double rms_all;
    double r = fold_outliers_pool(sum2, cnt, 3, none, 10.0, &rms_all);
    assert_true(fabs(r - 10.0 * sqrt(59.0 / 5.0)) < 1e-12);
    assert_true(rms_all == r);
    r = fold_outliers_pool(sum2, cnt, 3, last, 10.0, &rms_all);
    assert_true(fabs(r - 10.0 * sqrt(34.0 / 4.0)) < 1e-12);
    assert_true(fabs(rms_all - 10.0 * sqrt(59.0 / 5.0)) < 1e-12);
    assert_true(isnan(fold_outliers_pool(sum2, cnt, 3, all, 1.0, &rms_all)));
    assert_true(isnan(fold_outliers_pool(sum2, cnt, 0, none, 1.0, &rms_all)) && isnan(rms_all));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ratio_both_sides),
        cmocka_unit_test(test_fewest_and_most),
        cmocka_unit_test(test_pool_closed_form),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
