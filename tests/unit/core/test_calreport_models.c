/* test_calreport_models.c - the recommendation of a model comparison
 * (calreport_models_recommend), with a 5 % gain:
 *  - a complex model 3 % better for a single reading and 11 % for the
 *    mean of ten (aeroztark split B's hybrid against its physics):
 *    recommended;
 *  - the same without means: the simpler one;
 *  - better for means but worse for a single reading: the simpler one;
 *  - a simpler model within 5 % of a complex one on both: the simpler;
 *    one 6 % worse for means: the complex one stays. */
#include "test_util.h"

#include "calreport.h"

static calreport_models two(double s0, double m0, double s1, double m1, double per_point)
{
    calreport_models cm;
    memset(&cm, 0, sizeof cm);
    cm.n = 2;
    const char *names[2] = {"physical", "hybrid"};
    const double single[2] = {s0, s1}, mean[2] = {m0, m1};
    for (int k = 0; k < 2; k++) {
        snprintf(cm.m[k].name, sizeof cm.m[k].name, "%s", names[k]);
        cm.m[k].np = k ? 80 : 10;
        cm.m[k].ok = 1;
        cm.m[k].rms_out_arcsec = single[k];
        cm.m[k].per_point = per_point;
        cm.m[k].rms_out_mean_arcsec = mean[k];
    }
    return cm;
}

static void test_complex_better_for_means(void **state)
{
    calreport_models cm = two(1077.75, 482.59, 1042.00, 430.85, 10);
    calreport_models_recommend(&cm, 0.05, 1.5);
    assert_int_equal(cm.best, 1);
    assert_non_null(strstr(cm.note, "recommended hybrid: held out 1042 arcsec for a single "
                                    "reading, 431 for the mean of 10"));
    cm = two(1077.75, 482.59, 1042.00, 430.85, 1);
    calreport_models_recommend(&cm, 0.05, 1.5);
    assert_int_equal(cm.best, 0);
}

static void test_worse_single_keeps_simpler(void **state)
{
    calreport_models cm = two(1000, 500, 1001, 400, 10);
    calreport_models_recommend(&cm, 0.05, 1.5);
    assert_int_equal(cm.best, 0);
    cm = two(1000, 500, 1000, 400, 10); /* equal single: the means decide */
    calreport_models_recommend(&cm, 0.05, 1.5);
    assert_int_equal(cm.best, 1);
}

static void test_simpler_within_gain(void **state)
{
    /* the simpler model listed second */
    calreport_models cm = two(1000, 400, 1040, 418, 10);
    cm.m[0].np = 80;
    cm.m[1].np = 10;
    calreport_models_recommend(&cm, 0.05, 1.5);
    assert_int_equal(cm.best, 1);
    cm = two(1000, 400, 1040, 424, 10); /* 6 % worse for means */
    cm.m[0].np = 80;
    cm.m[1].np = 10;
    calreport_models_recommend(&cm, 0.05, 1.5);
    assert_int_equal(cm.best, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_complex_better_for_means),
        cmocka_unit_test(test_worse_single_keeps_simpler),
        cmocka_unit_test(test_simpler_within_gain),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
