/* test_cli_logs.c - issue 22, rules 8 and 9: limits are checked, never
 * overflowed (thread stacks, unit ranges); progress goes to logs too;
 * budget warns about shares outside 0..100 % and marks significance as the
 * printed interval shows it. */
#include "test_util.h"

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "logs");
}

#define D "configs/dss.ini"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static void must_have(const char *out, const char *needle)
{
    if (!strstr(out, needle))
        fail_msg("output lacks '%s': %s", needle, out);
}

static int count(const char *out, const char *needle)
{
    int n = 0;
    for (const char *p = out; (p = strstr(p, needle)) != NULL; p++)
        n++;
    return n;
}

/* The reproducer: OMP_STACKSIZE=16K segfaulted with no message. */
static void test_thread_stack_checked(void **state)
{
    char out[16384], cmd[1024];
    const char *small[] = {"OMP_STACKSIZE=16K", "OMP_STACKSIZE=255k", "GOMP_STACKSIZE=100",
                           "OMP_STACKSIZE=65536B"};
    for (int i = 0; i < 4; i++) {
        snprintf(cmd, sizeof cmd, "%s %s run " D " --units 4 --threads 2 --quiet", small[i],
                 test_sunmc());
        int rc = test_run(cmd, out, sizeof out);
        if (rc != 2 || !strstr(out, "256K or more"))
            fail_msg("%s: exit %d: %s", small[i], rc, out);
    }
    const char *fine[] = {"OMP_STACKSIZE=256K", "OMP_STACKSIZE=4M", "OMP_STACKSIZE=1G"};
    for (int i = 0; i < 3; i++) {
        snprintf(cmd, sizeof cmd, "%s %s run " D " --units 4 --threads 2 --quiet", fine[i],
                 test_sunmc());
        if (test_run(cmd, out, sizeof out) != 0)
            fail_msg("%s: %s", fine[i], out);
    }
}

/* The reproducer: `run` printed no progress when stderr was a file
 * or a pipe (batch logs).  Now a line per 10 % (or 30 s), never a line per
 * refresh. */
static void test_progress_in_logs(void **state)
{
    char out[65536];
    assert_int_equal(sunmc("run " D " --units 300 --set run.block_units=8 --threads 1 2>&1 "
                           ">/dev/null | cat",
                           out, sizeof out),
                     0);
    int n = count(out, "sunmc run: ");
    if (n < 1 || n > 11)
        fail_msg("%d progress lines: %s", n, out);
    must_have(out, "/300 units (");
    assert_null(strchr(out, '\r'));
    /* --quiet: none */
    assert_int_equal(sunmc("run " D " --units 30 --quiet 2>&1 >/dev/null | cat", out, sizeof out),
                     0);
    assert_int_equal(count(out, "sunmc run: "), 0);
}

/* The reproducer: `budget` shares of 103.7 % and -17.8 % printed
 * without a warning; "-0.00% [-0.00, -0.00]" was marked significant. */
static void test_budget_outside_warned(void **state)
{
    char out[65536];
    assert_int_equal(sunmc("budget " D " --units 20 --set report.budget_units=20 "
                           "--set report.budget_steps=2 --quiet",
                           out, sizeof out),
                     0);
    must_have(out, "WARNING: ");
    must_have(out, "outside 0..100 %");
    must_have(out, "glass_thickness_um before 103.44%");
    /* every printed interval that shows 0.00 at an end carries the ~ mark */
    for (const char *p = out; (p = strstr(p, "-0.00]")) != NULL; p++)
        if (p[6] != '~')
            fail_msg("'%.40s' marked significant", p - 20);
    for (const char *p = out; (p = strstr(p, "[ -0.00,")) != NULL; p++) {
        const char *close = strchr(p, ']');
        if (close && close[1] != '~' && strstr(p, "-0.00]") == close - 5)
            fail_msg("'%.40s' marked significant", p);
    }
}

/* `run --units 250:260` did not print the range. */
static void test_range_printed(void **state)
{
    char out[65536];
    assert_int_equal(sunmc("run " D " --units 250:260 --quiet", out, sizeof out), 0);
    must_have(out, "units 250:260 of the run of 1000 units");
    assert_int_equal(sunmc("run " D " --units 10 --quiet", out, sizeof out), 0);
    assert_null(strstr(out, "of the run of"));
}

/* sweep's header said "10 units each" / "seed 1" while run.units or
 * run.seed was an axis. */
static void test_sweep_header_axes(void **state)
{
    char out[65536];
    assert_int_equal(sunmc("sweep " D " --units 2 --vary run.seed=1,2 --quiet", out, sizeof out),
                     0);
    must_have(out, "2 units each, run.seed per point");
    assert_int_equal(sunmc("sweep " D " --vary run.units=2,3 --quiet", out, sizeof out), 0);
    must_have(out, "run.units per point, seed 1");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_thread_stack_checked),
        cmocka_unit_test(test_progress_in_logs),
        cmocka_unit_test(test_budget_outside_warned),
        cmocka_unit_test(test_range_printed),
        cmocka_unit_test(test_sweep_header_axes),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
