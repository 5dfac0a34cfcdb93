/* test_limits_edges.c - path rules and limits on both sides (issue 43):
 *  - an input in a sibling of --out that shares its prefix (runs/a2 for
 *    runs/a) is not inside --out; one inside is refused;
 *  - the output marker names files whole: a user's file named as a prefix
 *    of one sunmc wrote ("units" beside units.tsv) is not sunmc's, so the
 *    directory is not replaced;
 *  - a config name (key) of 63 characters is read, 64 refused; a text
 *    value of 63 bytes taken, 64 refused;
 *  - --units FIRST:END: FIRST == END refused, END = FIRST + 1 one unit,
 *    END at run.units' largest value taken, one past refused;
 *  - OMP_STACKSIZE without a suffix is KiB: exactly the 256K minimum runs,
 *    one KiB (or byte) below is refused. */
#include "test_util.h"

#define E "configs/ess_type_a.ini"
#define TINY "--set validation.alpha_step_deg=5 --set campaign.alpha_step_deg=2 --quiet"

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "lim");
}

static int run(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static void expect(const char *args, int want, const char *needle)
{
    char out[1 << 15];
    int rc = run(args, out, sizeof out);
    if (rc != want || (needle && !strstr(out, needle)))
        fail_msg("sunmc %s: expected exit %d%s%s, got %d:\n%s", args, want,
                 needle ? " and " : "", needle ? needle : "", rc, out);
}

static int exists(const char *rel)
{
    char p[1024];
    snprintf(p, sizeof p, "%s/%s", dir, rel);
    struct stat sb;
    return stat(p, &sb) == 0;
}

static void sibling_prefix_is_outside(void **state)
{
    expect("run " E " --units 2 " TINY " --out $D/a", 0, NULL);
    expect("run " E " --units 2 " TINY " --out $D/a2", 0, NULL);
    /* the input sits in $D/a2, whose name starts with $D/a */
    expect("run $D/a2/config.ini --units 2 " TINY " --out $D/a", 0, NULL);
    /* the input inside --out: refused, the directory kept */
    expect("run $D/a/config.ini --units 2 " TINY " --out $D/a", 2, "holds an input");
    assert_true(exists("a/config.ini"));
    /* --out given with a trailing slash: the same rules */
    expect("run $D/a2/config.ini --units 2 " TINY " --out $D/a/", 0, NULL);
    expect("run $D/a/config.ini --units 2 " TINY " --out $D/a/", 2, "holds an input");
}

static void marker_names_whole_files(void **state)
{
    char p[1024];
    expect("run " E " --units 2 " TINY " --out $D/m", 0, NULL);
    snprintf(p, sizeof p, "%s/m/units", dir);
    assert_int_equal(test_write_file(p, "mine\n"), 0);
    expect("run " E " --units 2 " TINY " --out $D/m", 2, "units");
    assert_true(exists("m/units"));
    assert_true(exists("m/units.tsv"));
    /* a file named as sunmc's with a suffix is not sunmc's either */
    assert_int_equal(remove(p), 0);
    snprintf(p, sizeof p, "%s/m/units.tsv.bak", dir);
    assert_int_equal(test_write_file(p, "mine\n"), 0);
    expect("run " E " --units 2 " TINY " --out $D/m", 2, "units.tsv.bak");
    assert_int_equal(remove(p), 0);
    /* only its own files: replaced */
    expect("run " E " --units 2 " TINY " --out $D/m", 0, NULL);
}

static void name_lengths(void **state)
{
    char ini[1024], p[1024], key63[64], key64[65], val63[64], val64[65];
    memset(key63, 'k', 63);
    key63[63] = '\0';
    memset(key64, 'k', 64);
    key64[64] = '\0';
    snprintf(p, sizeof p, "%s/k63.ini", dir);
    snprintf(ini, sizeof ini, "[sensor]\nfamily = ess\n[tolerance]\n%s = 1\n", key63);
    assert_int_equal(test_write_file(p, ini), 0);
    /* read as a name (then unknown), not refused for its length */
    expect("config $D/k63.ini", 2, "unknown key");
    char out[1 << 15];
    run("config $D/k63.ini", out, sizeof out);
    assert_null(strstr(out, "longer than"));
    snprintf(p, sizeof p, "%s/k64.ini", dir);
    snprintf(ini, sizeof ini, "[sensor]\nfamily = ess\n[tolerance]\n%s = 1\n", key64);
    assert_int_equal(test_write_file(p, ini), 0);
    expect("config $D/k64.ini", 2, "longer than 63 characters");
    /* a text value: sensor.product */
    memset(val63, 'v', 63);
    val63[63] = '\0';
    memset(val64, 'v', 64);
    val64[64] = '\0';
    char args[512];
    snprintf(args, sizeof args, "config " E " --set sensor.product=%s", val63);
    expect(args, 0, val63);
    snprintf(args, sizeof args, "config " E " --set sensor.product=%s", val64);
    expect(args, 2, "1 to 63 bytes");
    expect("config " E " --set sensor.product=v", 0, "product = v");
    expect("config " E " --set sensor.product=", 2, "1 to 63 bytes");
}

static void units_ranges(void **state)
{
    expect("run " E " --units 0:0 " TINY, 2, "0 <= FIRST < END");
    expect("run " E " --units 5:5 " TINY, 2, "0 <= FIRST < END");
    expect("run " E " --units 5:6 " TINY " --out $D/u1", 0, NULL);
    char p[1024];
    snprintf(p, sizeof p, "%s/u1/units.tsv", dir);
    FILE *f = fopen(p, "r");
    assert_non_null(f);
    char line[1 << 14];
    long rows = 0, first = -1;
    while (fgets(line, sizeof line, f))
        if (line[0] != '#' && rows++ == 1)
            first = atol(line);
    fclose(f);
    assert_int_equal(rows, 2); /* the header and unit 5 */
    assert_int_equal(first, 5);
    expect("run " E " --units 99999999:100000000 " TINY, 0, NULL);
    expect("run " E " --units 99999999:100000001 " TINY, 2, "END <= 100000000");
    expect("run " E " --units -1:3 " TINY, 2, NULL);
}

static void stack_size_suffixes(void **state)
{
    char out[1 << 15], cmd[1024];
    const struct {
        const char *env;
        int rc;
    } cases[] = {{"OMP_STACKSIZE=256", 0},      {"OMP_STACKSIZE=255", 2},
                 {"GOMP_STACKSIZE=256", 0},     {"GOMP_STACKSIZE=255", 2},
                 {"OMP_STACKSIZE=262144B", 0},  {"OMP_STACKSIZE=262143B", 2},
                 {"OMP_STACKSIZE=256K", 0},     {"OMP_STACKSIZE=255K", 2}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(cmd, sizeof cmd, "%s %s run " E " --units 2 " TINY, cases[i].env, test_sunmc());
        int rc = test_run(cmd, out, sizeof out);
        if (rc != cases[i].rc)
            fail_msg("%s: expected exit %d, got %d:\n%s", cases[i].env, cases[i].rc, rc, out);
        if (rc == 2)
            assert_non_null(strstr(out, "256K or more"));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sibling_prefix_is_outside),
        cmocka_unit_test(marker_names_whole_files),
        cmocka_unit_test(name_lengths),
        cmocka_unit_test(units_ranges),
        cmocka_unit_test(stack_size_suffixes),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
