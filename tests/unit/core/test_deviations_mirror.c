/* test_deviations_mirror.c - the one deviation list drives the mirror unit of
 * `sunmc curve`: deviations_scale (core) negates every value of every entry
 * of each family's list, and each family's deviations struct holds nothing
 * but its list (and the derived fields named here), so a tolerance added by
 * its one line cannot be forgotten by the mirror. */
#include "test_util.h"

#include "deviation.h"
#include "dss_sensor.h"
#include "family.h"
#include "ess_sensor.h"

/* Sample unit 3 of family's default config, scale by s, and check every
 * listed value is s times what it was (and at least one is not zero, so the
 * check can fail). */
static void check_scaled(const char *family, void *dev, size_t dev_bytes, double s)
{
    sunmc_config c = test_family_config(family);
    const sensor_family *f = c.family;
    assert_non_null(f->deviations);
    memset(dev, 0, dev_bytes);
    deviations_sample(f->deviations, f->n_deviations, &c, 1, 3, dev);
    double before[256], after[256];
    int n = deviations_values(f->deviations, f->n_deviations, dev, before, 256);
    assert_true(n > 0 && n <= 256);
    deviations_scale(f->deviations, f->n_deviations, dev, s);
    assert_int_equal(deviations_values(f->deviations, f->n_deviations, dev, after, 256), n);
    int nonzero = 0;
    for (int k = 0; k < n; k++) {
        assert_true(after[k] == s * before[k]);
        nonzero += before[k] != 0;
    }
    assert_true(nonzero > n / 2);
}

static void ess_mirror_flips_every_deviation(void **state)
{
    ess_deviations d;
    check_scaled("ess", &d, sizeof d, -1);
    /* the struct is the list plus the derived roll measurement */
    assert_int_equal(sizeof d / sizeof(double), ESS_N_TOL_COLUMNS + 1);
}

static void dss_mirror_flips_every_deviation(void **state)
{
    dss_deviations d;
    check_scaled("dss", &d, sizeof d, -1);
    assert_int_equal(sizeof d / sizeof(double), DSS_N_DEV);
}

static void scale_by_two_doubles_each(void **state)
{
    ess_deviations d;
    check_scaled("ess", &d, sizeof d, 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ess_mirror_flips_every_deviation),
        cmocka_unit_test(dss_mirror_flips_every_deviation),
        cmocka_unit_test(scale_by_two_doubles_each),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
