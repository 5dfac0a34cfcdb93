/* test_calibrate_trust.c - issue 22, rules 5 and 6: lab data the fit cannot
 * stand behind is refused or flagged, and compensate never turns a reading
 * the sensor cannot produce into a plausible angle. */
#include "test_util.h"

static char dir[512];

#define E "configs/ess_type_a.ini"
#define D "configs/dss.ini"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

/* One simulated and calibrated unit of each family, shared by the tests. */
static int setup(void **state)
{
    if (test_private_dir(dir, sizeof dir, "labtrust") != 0)
        return -1;
    const char *steps[] = {
        "simulate " E " --unit 3 --quiet --out $D/le", "simulate " D " --unit 3 --quiet --out $D/ld",
        "calibrate --config " E " $D/le/campaign.csv --quiet --out $D/ce",
        "calibrate --config " D " $D/ld/campaign.csv --quiet --out $D/cd"};
    return test_sunmc_steps(dir, steps, (int)(4));
}

static char *slurp(const char *args)
{
    static char out[65536];
    int rc = sunmc(args, out, sizeof out);
    if (rc != 0)
        fail_msg("%s: exit %d: %s", args, rc, out);
    return out;
}

/* The reproducer: ESS output_deg 95 -> -85.04 deg, 180 -> -0.037
 * deg; DSS x_px 5000 on a +-1023.5 px detector -> -84.5 deg.  Now nan with
 * a count on stderr; readings inside the range are unchanged. */
static void test_compensate_marks_impossible(void **state)
{
    char p[700];
    snprintf(p, sizeof p, "%s/re.csv", dir);
    assert_int_equal(test_write_file(p, "output_deg\n10\n95\n180\n-95\n89.99\n-60\n"), 0);
    char *out = slurp("compensate $D/ce/params.ini $D/re.csv");
    const char *bad[] = {"\n95,-\n", "\n180,-\n", "\n-95,-\n"};
    for (int i = 0; i < 3; i++)
        if (!strstr(out, bad[i]))
            fail_msg("'%s' not marked: %s", bad[i] + 1, out);
    if (!strstr(out, "\n10,9.9") || !strstr(out, "\n-60,-60.0"))
        fail_msg("readings in range changed: %s", out);
    if (!strstr(out, "3 rows not compensated: 3 outside the output's range") ||
        !strstr(out, "readings the calibrated sensor cannot produce"))
        fail_msg("%s", out);
    snprintf(p, sizeof p, "%s/rd.csv", dir);
    assert_int_equal(test_write_file(p, "x_px,y_px\n10,10\n5000,0\n0,-5000\n1023.9,0\n1024.1,0\n"
                                        "-1000,0\n"),
                     0);
    out = slurp("compensate $D/cd/params.ini $D/rd.csv");
    const char *dbad[] = {"\n5000,0,-,-\n", "\n0,-5000,-,-\n", "\n1024.1,0,-,-\n"};
    for (int i = 0; i < 3; i++)
        if (!strstr(out, dbad[i]))
            fail_msg("'%s' not marked: %s", dbad[i] + 1, out);
    assert_null(strstr(out, "\n1023.9,0,-,"));
    assert_null(strstr(out, "\n-1000,0,-,"));
    assert_non_null(strstr(out, "3 rows not compensated: 3 outside the detector"));
    assert_true(test_file_has(test_tmp("labtrust/cd/params.ini"), "detector_px              = 2048"));
}

/* Write campaign.csv of the ESS unit with its outputs shifted by up to
 * +-0.2 deg (a campaign the model cannot describe), the first row's weight
 * w (1: unweighted). */
static void garbage_campaign(const char *name, const char *w)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "grep -v '^#' %s/le/campaign.csv | awk -F, 'BEGIN { srand(7); OFS = \",\" } "
             "NR == 1 { print; next } { $3 = $3 + (rand() - 0.5) * 0.4; if (NR == 2) $4 = %s; "
             "print }' > %s/%s",
             dir, w, dir, name);
    assert_int_equal(system(cmd), 0);
}

/* The reproducer: one row of weight 10 (or 1e6) took a garbage
 * campaign past the "model does not describe these data" refusal (the
 * residual shrank by sqrt(max weight): 0.344" for a 357" misfit). */
static void test_weights_do_not_pass_garbage(void **state)
{
    const char *w[] = {"1", "10", "1e6"};
    for (int i = 0; i < 3; i++) {
        char name[32], args[256], out[65536];
        snprintf(name, sizeof name, "garbage%d.csv", i);
        garbage_campaign(name, w[i]);
        snprintf(args, sizeof args, "calibrate --config " E " $D/%s --out $D/g%d", name, i);
        int rc = sunmc(args, out, sizeof out);
        if (rc == 0 || !strstr(out, "the model does not describe these data"))
            fail_msg("weight %s: exit %d: %s", w[i], rc, out);
        if (!strstr(out, "of a row of the median weight"))
            fail_msg("weight %s: the message does not say whose residual: %s", w[i], out);
    }
}

/* The reproducer: exactly duplicated rows counted as independent
 * readings (every standard error shrank by sqrt 2, the model advice
 * flipped).  Default: counted once, with a warning naming the lines; the
 * result equals that of the file without them. */
static void test_duplicates(void **state)
{
    char cmd[4096], out[65536];
    snprintf(cmd, sizeof cmd,
             "grep -v '^#' %s/le/campaign.csv > %s/once.csv && cp %s/once.csv %s/twice.csv && "
             "tail -n +2 %s/once.csv >> %s/twice.csv",
             dir, dir, dir, dir, dir, dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(sunmc("calibrate --config " E " $D/once.csv --out $D/c1", out, sizeof out),
                     0);
    assert_int_equal(sunmc("calibrate --config " E " $D/twice.csv --out $D/c2", out, sizeof out),
                     0);
    if (!strstr(out, "534 rows repeat an earlier row exactly") || !strstr(out, "536 = 2") ||
        !strstr(out, "--duplicates=average"))
        fail_msg("%s", out);
    /* the same parameters (to 9 digits: rows of weight 0 still move the
     * sums' last bits) and the same standard errors */
    snprintf(cmd, sizeof cmd,
             "for k in 1 2; do sed -n '/^\\[parameters\\]/,/^\\[/p' %s/c$k/params.ini | "
             "awk '/=/ { printf \"%%s %%.9g %%s\\n\", $1, $3, $NF }' > %s/p$k; done; "
             "test -s %s/p1 && cmp %s/p1 %s/p2",
             dir, dir, dir, dir, dir);
    if (test_run(cmd, out, sizeof out) != 0)
        fail_msg("params.ini of the doubled file differs from the single one: %s", out);
    assert_int_equal(sunmc("calibrate --config " E " $D/twice.csv --duplicates=refuse --out $D/c3",
                           out, sizeof out),
                     2);
    if (!strstr(out, "twice.csv:536: repeats line 2 exactly"))
        fail_msg("%s", out);
    assert_int_equal(sunmc("calibrate --config " E " $D/twice.csv --duplicates keep --quiet",
                           out, sizeof out),
                     0);
    assert_non_null(strstr(out, "counted as independent readings (--duplicates=keep)"));
    assert_int_equal(sunmc("calibrate --config " E " $D/once.csv --duplicates=sometimes", out,
                           sizeof out),
                     2);
    assert_non_null(strstr(out, "one of average, refuse, keep"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compensate_marks_impossible),
        cmocka_unit_test(test_weights_do_not_pass_garbage),
        cmocka_unit_test(test_duplicates),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
