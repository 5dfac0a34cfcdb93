/* test_curve_cli.c - `sunmc curve` never writes a silent nan: every grid
 * point it sees gets an after-compensation error, or stderr says how many
 * did not (whatever --quiet says) and the table shows "-", not nan. */
#include "test_util.h"

#define B_UNIT "configs/ess_type_b.ini --unit 32 --set design.harmonics=given " \
               "--set validation.alpha_offset_deg=0 --set validation.beta_deg=-25,25 --quiet"

static int count_nan(const char *path)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[512];
    int n = 0;
    while (fgets(line, sizeof line, f))
        n += strstr(line, "nan") != NULL;
    fclose(f);
    return n;
}

/* a3/a1 = -0.25: the fitted fine-code term has w k = 0.995 and Halley's
 * iteration stalled on rounding at 64 of these points (nan, nothing said);
 * every point is now compensated and the unit improves as the paper's
 * Fig. 11 unit does (0.057 -> 0.017 deg). */
static void test_large_ripple_is_compensated(void **state)
{
    char out[16384], args[1024];
    const char *d = test_tmp("large_ripple");
    snprintf(args, sizeof args, "curve " B_UNIT " --set design.a3_ratio=-0.25 --out $D");
    assert_int_equal(test_sunmc_in(d, args, out, sizeof out), 0);
    assert_null(strstr(out, "WARNING"));
    assert_null(strstr(out, "nan"));
    char path[600];
    snprintf(path, sizeof path, "%s/curve.tsv", d);
    assert_int_equal(count_nan(path), 0);
}

/* a3/a1 = -0.3: the fitted term has no inverse (w k >= 1): every after
 * error is nan in the file, and stderr says so with the count. */
static void test_uninvertible_fit_is_flagged(void **state)
{
    char out[16384], args[1024];
    const char *d = test_tmp("uninvertible");
    snprintf(args, sizeof args,
             "curve " B_UNIT " --set design.a3_ratio=-0.3 --out $D");
    assert_int_equal(test_sunmc_in(d, args, out, sizeof out), 0);
    if (!strstr(out, "WARNING: 1908 of 1908 grid points seen could not be compensated"))
        fail_msg("no warning with the count: %s", out);
    char path[600];
    snprintf(path, sizeof path, "%s/curve.tsv", d);
    assert_int_equal(count_nan(path), 1908);
    /* the table: a dash where there is no after error */
    snprintf(args, sizeof args, "curve " B_UNIT " --set design.a3_ratio=-0.3");
    assert_int_equal(test_sunmc_in(d, args, out, sizeof out), 0);
    assert_null(strstr(out, "   nan"));
    assert_non_null(strstr(out, "        -"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_large_ripple_is_compensated),
        cmocka_unit_test(test_uninvertible_fit_is_flagged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
