/* test_numtext.c - issue 36, rule 9: one reading of a typed number.
 * strtod took "0x10" as 16 and "inf" as a number, strtol took "+5" and
 * " 5": each input read numbers its own way.  num_parse_long and
 * num_parse_double take plain decimal text only, at both ends of the
 * types' ranges. */
#include "test_util.h"

#include "numtext.h"

#include <float.h>
#include <limits.h>

static void expect_long(const char *s, int rc, long want)
{
    long v = 12345;
    int got = num_parse_long(s, &v);
    if (got != rc)
        fail_msg("num_parse_long(\"%s\") = %d, expected %d", s, got, rc);
    if (rc == 0 && v != want)
        fail_msg("num_parse_long(\"%s\") read %ld, expected %ld", s, v, want);
    if (rc != 0 && v != 12345)
        fail_msg("num_parse_long(\"%s\") wrote %ld on a refusal", s, v);
}

static void expect_double(const char *s, int rc, double want)
{
    double v = 12345;
    int got = num_parse_double(s, &v);
    if (got != rc)
        fail_msg("num_parse_double(\"%s\") = %d, expected %d", s, got, rc);
    if (rc == 0 && v != want)
        fail_msg("num_parse_double(\"%s\") read %.17g, expected %.17g", s, v, want);
}

static void whole_numbers_decimal_only(void **state)
{
    expect_long("0", 0, 0);
    expect_long("7", 0, 7);
    expect_long("-3", 0, -3);
    expect_long("100000000", 0, 100000000);
    expect_long("0010", 0, 10); /* leading zeros are decimal, not octal */
    expect_long("0x5", -1, 0);
    expect_long("0X5", -1, 0);
    expect_long("+5", -1, 0);
    expect_long(" 5", -1, 0);
    expect_long("5 ", -1, 0);
    expect_long("1e3", -1, 0);
    expect_long("1.0", -1, 0);
    expect_long("", -1, 0);
    expect_long("-", -1, 0);
    expect_long("--5", -1, 0);
}

static void whole_numbers_at_the_ends_of_long(void **state)
{
    char s[64];
    snprintf(s, sizeof s, "%ld", LONG_MAX);
    expect_long(s, 0, LONG_MAX);
    snprintf(s, sizeof s, "%ld", LONG_MIN);
    expect_long(s, 0, LONG_MIN);
    expect_long("9223372036854775808", -2, 0);  /* LONG_MAX + 1 */
    expect_long("-9223372036854775809", -2, 0); /* LONG_MIN - 1 */
}

static void decimals_without_hex_inf_nan(void **state)
{
    expect_double("1.5", 0, 1.5);
    expect_double("-0.25", 0, -0.25);
    expect_double("+2", 0, 2);
    expect_double(".5", 0, 0.5);
    expect_double("1e3", 0, 1000);
    expect_double("2.5E-3", 0, 2.5e-3);
    expect_double("0x10", -1, 0);
    expect_double("0X1p4", -1, 0);
    expect_double("16 ", -1, 0);
    expect_double(" 16", -1, 0);
    expect_double("1,5", -1, 0);
    expect_double("", -1, 0);
    expect_double(".", -1, 0);
    expect_double("e3", -1, 0);
    expect_double("1e", -1, 0);
    expect_double("inf", -2, 0);
    expect_double("-Infinity", -2, 0);
    expect_double("NaN", -2, 0);
    expect_double("nan(1)", -2, 0);
}

static void decimals_at_the_ends_of_double(void **state)
{
    expect_double("1.7976931348623157e308", 0, DBL_MAX);
    expect_double("1.8e308", -2, 0);   /* overflows */
    expect_double("2.2250738585072014e-308", 0, DBL_MIN);
    expect_double("4.9406564584124654e-324", 0, 4.9406564584124654e-324); /* subnormal */
    expect_double("1e-400", -2, 0);    /* would read as 0 */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(whole_numbers_decimal_only),
        cmocka_unit_test(whole_numbers_at_the_ends_of_long),
        cmocka_unit_test(decimals_without_hex_inf_nan),
        cmocka_unit_test(decimals_at_the_ends_of_double),
    };
    return cmocka_run_group_tests_name("numtext", tests, NULL, NULL);
}
