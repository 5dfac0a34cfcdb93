/* test_tsvnum.c - the one writer of numbers into output files: NaN is "-",
 * a printed zero has no sign, everything else is printf's text. */
#include "test_util.h"

#include "tsvnum.h"

static void fmt_is(const char *fmt, double v, const char *want)
{
    char buf[64];
    int n = tsv_num_fmt(buf, sizeof buf, fmt, v);
    if (strcmp(buf, want) != 0)
        fail_msg("%s of %.17g: '%s', want '%s'", fmt, v, buf, want);
    assert_int_equal(n, (int)strlen(want));
}

static void numbers(void **state)
{
    (void)state;
    fmt_is("%.6g", NAN, "-");
    fmt_is("%.6g", -NAN, "-");
    fmt_is("%.6g", -0.0, "0");
    fmt_is("%.6g", -1e-200 * 1e-200, "0"); /* underflows to -0 */
    fmt_is("%.2f", -0.001, "0.00");
    fmt_is("%.0e", -0.0, "0e+00");
    fmt_is("%.6g", -1e-7, "-1e-07"); /* a small number keeps its sign */
    fmt_is("%.2f", -0.01, "-0.01");
    fmt_is("%.6g", -2.5, "-2.5");
    fmt_is("%.6g", 0.0, "0");
    fmt_is("%g", -INFINITY, "-inf");
    fmt_is("%.10g", 12345.678, "12345.678");
}

static void printf_fields(void **state)
{
    (void)state;
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    assert_non_null(f);
    tsv_printf(f, "%s\t%.6g\t%.6g\t%.2f\t%g\t%.6g\n", "a-0", NAN, -0.0, -0.004, -1.5, 2.0);
    tsv_printf(f, "%.6g", -0.0);
    tsv_printf(f, "\t%s\t%d\n", "nan-label", -0);
    fclose(f);
    assert_string_equal(text, "a-0\t-\t0\t0.00\t-1.5\t2\n0\tnan-label\t0\n");
    free(text);
    /* longer than the stack buffer */
    f = open_memstream(&text, &len);
    char big[6000];
    memset(big, 'x', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    tsv_printf(f, "%s\t%.6g\n", big, NAN);
    fclose(f);
    assert_int_equal(strlen(text), sizeof big - 1 + 3);
    assert_string_equal(text + sizeof big - 1, "\t-\n");
    free(text);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(numbers),
        cmocka_unit_test(printf_fields),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
