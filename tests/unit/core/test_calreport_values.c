/* test_calreport_values.c - an empirical model's figures as the report's
 * parameter rows (calreport_set_values, what the spline and table models
 * of every family report instead of fitted parameters):
 *  - each name and value in order, with no standard error (NaN), the
 *    count set;
 *  - rows replace a longer earlier set: the count shrinks, nothing of the
 *    earlier set is counted;
 *  - the limits: no rows (count 0), CALREPORT_MAX_PAR rows (the last one
 *    set), a name one byte too long for a row cut to fit;
 *  - the printed report shows each row's name and value. */
#include "test_util.h"

#include "calreport.h"

static void test_rows_in_order(void **state)
{
    (void)state;
    calreport *r = calloc(1, sizeof *r);
    assert_non_null(r);
    calreport_init(r, "dss", "spline");
    static const char *const names[] = {"smoothing", "edf_alpha", "edf_beta"};
    const double v[] = {0.25, 11.5, 12.75};
    calreport_set_values(r, names, v, 3);
    assert_int_equal(r->np, 3);
    for (int i = 0; i < 3; i++) {
        assert_string_equal(r->name[i], names[i]);
        assert_true(r->value[i] == v[i]);
        assert_true(isnan(r->se[i]));
    }
    /* a shorter set replaces it */
    static const char *const one[] = {"nodes"};
    const double n1[] = {4096};
    calreport_set_values(r, one, n1, 1);
    assert_int_equal(r->np, 1);
    assert_string_equal(r->name[0], "nodes");
    assert_true(r->value[0] == 4096);
    free(r);
}

static void test_limits(void **state)
{
    (void)state;
    calreport *r = calloc(1, sizeof *r);
    assert_non_null(r);
    calreport_init(r, "psd", "table");
    calreport_set_values(r, NULL, NULL, 0);
    assert_int_equal(r->np, 0);
    const char *names[CALREPORT_MAX_PAR];
    double v[CALREPORT_MAX_PAR];
    char buf[CALREPORT_MAX_PAR][16];
    for (int i = 0; i < CALREPORT_MAX_PAR; i++) {
        snprintf(buf[i], sizeof buf[i], "p%d", i);
        names[i] = buf[i];
        v[i] = i + 0.5;
    }
    char longname[CALREPORT_NAME_MAX + 1];
    memset(longname, 'x', CALREPORT_NAME_MAX);
    longname[CALREPORT_NAME_MAX] = '\0';
    names[0] = longname;
    calreport_set_values(r, names, v, CALREPORT_MAX_PAR);
    assert_int_equal(r->np, CALREPORT_MAX_PAR);
    assert_string_equal(r->name[CALREPORT_MAX_PAR - 1], buf[CALREPORT_MAX_PAR - 1]);
    assert_true(r->value[CALREPORT_MAX_PAR - 1] == CALREPORT_MAX_PAR - 0.5);
    assert_true(isnan(r->se[CALREPORT_MAX_PAR - 1]));
    assert_int_equal(strlen(r->name[0]), CALREPORT_NAME_MAX - 1);
    free(r);
}

/* The printed report lists each row's name and value. */
static void test_printed(void **state)
{
    (void)state;
    calreport *r = calloc(1, sizeof *r);
    assert_non_null(r);
    calreport_init(r, "ess", "spline");
    r->fit_ok = 1;
    static const char *const names[] = {"smoothing", "edf"};
    const double v[] = {0.125, 9.5};
    calreport_set_values(r, names, v, 2);
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    assert_non_null(f);
    calreport_print(f, r);
    fclose(f);
    assert_non_null(strstr(text, "  smoothing                +1.250000000e-01  +- nan\n"));
    assert_non_null(strstr(text, "  edf                      +9.500000000e+00  +- nan\n"));
    free(text);
    free(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_in_order),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_printed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
