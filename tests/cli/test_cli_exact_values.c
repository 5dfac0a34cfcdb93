/* test_cli_exact_values.c - issue 22, rule 2: exact values wherever a value is
 * recorded or compared.  Config echoes and the config hash held values cut
 * to 10 digits (%.10g): shards of two campaigns merged, --resume mixed
 * them, and a run's own config.ini did not reproduce it. */
#include "test_util.h"

#include "shortest.h"

#include <float.h>

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "exact");
}

#define E "configs/ess_type_a.ini"
#define D "configs/dss.ini"
#define TINY "--set campaign.alpha_step_deg=2 --set validation.alpha_step_deg=5 " \
             "--set campaign.beta_deg=-15,15 --quiet"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int same_file(const char *a, const char *b)
{
    char cmd[2048], out[256];
    snprintf(cmd, sizeof cmd, "cmp %s/%s %s/%s", dir, a, dir, b);
    return test_run(cmd, out, sizeof out) == 0;
}

/* shortest_double reads back exactly, in as few digits as it can. */
static void test_shortest_round_trip(void **state)
{
    const double v[] = {0.7, 0.70000000004, 0.2000000000123, 0.1 + 0.2, 1.0 / 3, DBL_MIN,
                        DBL_MAX, -0.0, 5e-324, 123456789012345678.0, 1e21, 0.25};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        char buf[SHORTEST_TEXT_MAX];
        shortest_double(v[i], buf, sizeof buf);
        if (strtod(buf, NULL) != v[i])
            fail_msg("%s does not read back as %.17g", buf, v[i]);
    }
    char buf[SHORTEST_TEXT_MAX];
    shortest_double(0.7, buf, sizeof buf);
    assert_string_equal(buf, "0.7");
    shortest_double(0.1 + 0.2, buf, sizeof buf);
    assert_string_equal(buf, "0.30000000000000004");
    shortest_double(0.70000000004, buf, sizeof buf);
    assert_string_equal(buf, "0.70000000004");
}

/* The issue's reproducer: re-running a run's own config.ini reproduces its
 * units.bin bit for bit (a value past 10 digits was cut). */
static void test_config_ini_reproduces_run(void **state)
{
    char out[16384];
    assert_int_equal(sunmc("run " D " --units 3 --set tolerance.dh_px=0.2000000000123 "
                           "--set tolerance.dx_px=0.30000000000000004 --quiet --out $D/a",
                           out, sizeof out), 0);
    assert_true(test_file_has(test_tmp("exact/a/config.ini"), "dh_px = 0.2000000000123"));
    assert_int_equal(sunmc("run $D/a/config.ini --units 3 --quiet --out $D/b", out, sizeof out), 0);
    assert_true(same_file("a/units.bin", "b/units.bin"));
    assert_true(same_file("a/units.tsv", "b/units.tsv"));
    /* and the value is not the rounded one: that run differs */
    assert_int_equal(sunmc("run " D " --units 3 --set tolerance.dh_px=0.2 "
                           "--set tolerance.dx_px=0.3 --quiet --out $D/c",
                           out, sizeof out), 0);
    assert_false(same_file("a/units.bin", "c/units.bin"));
}

/* The issue's reproducer: shards of alpha_step 0.7 and 0.70000000004
 * (531 vs 534 points) merged with exit 0; --resume with the changed value
 * was accepted. */
static void test_near_values_never_mix(void **state)
{
    char out[16384];
    assert_int_equal(sunmc("run " E " --units 4 --shard 0/2 " TINY
                           " --set campaign.alpha_step_deg=0.7 --out $D/s0", out, sizeof out), 0);
    assert_int_equal(sunmc("run " E " --units 4 --shard 1/2 " TINY
                           " --set campaign.alpha_step_deg=0.70000000004 --out $D/s1",
                           out, sizeof out), 0);
    assert_int_equal(sunmc("merge $D/m $D/s0 $D/s1", out, sizeof out), 2);
    if (!strstr(out, "config"))
        fail_msg("merge message does not name the config: %s", out);
    /* --resume of a finished directory with the other value: refused */
    int rc = sunmc("run " E " --units 4 --shard 0/2 " TINY
                   " --set campaign.alpha_step_deg=0.70000000004 --resume --out $D/s0", out,
                   sizeof out);
    assert_int_equal(rc, 2);
    if (!strstr(out, "holds a finished run, not this one") || !strstr(out, "config"))
        fail_msg("%s", out);
    assert_true(test_file_has(test_tmp("exact/s0/config.ini"), "alpha_step_deg = 0.7  #"));
    /* issue 22's smaller item: --resume with another seed reran everything */
    rc = sunmc("run " E " --units 4 --shard 0/2 " TINY
               " --set campaign.alpha_step_deg=0.7 --seed 2 --resume --out $D/s0", out,
               sizeof out);
    assert_int_equal(rc, 2);
    if (!strstr(out, "seed 1 against 2"))
        fail_msg("%s", out);
}

/* The issue's reproducer: a product label with " #" was written unescaped
 * into config.ini, which then read back cut (shards unmergeable).  Refused
 * at input; a '#' without a blank before it round-trips. */
static void test_label_round_trips(void **state)
{
    char out[16384];
    assert_int_equal(sunmc("config " E " --set 'sensor.product=Typ A #2'", out, sizeof out), 2);
    if (!strstr(out, "starts a comment"))
        fail_msg("%s", out);
    assert_int_equal(sunmc("config " E " --set 'sensor.product=#2'", out, sizeof out), 2);
    assert_int_equal(sunmc("run " E " --units 2 " TINY " --set 'sensor.product=Typ A#2; x=1' "
                           "--out $D/l", out, sizeof out), 0);
    assert_int_equal(sunmc("run $D/l/config.ini --units 2 --quiet --out $D/l2", out, sizeof out),
                     0);
    assert_true(same_file("l/units.bin", "l2/units.bin"));
    assert_true(test_file_has(test_tmp("exact/l2/config.ini"), "product = Typ A#2; x=1  #"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shortest_round_trip),
        cmocka_unit_test(test_config_ini_reproduces_run),
        cmocka_unit_test(test_near_values_never_mix),
        cmocka_unit_test(test_label_round_trips),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
