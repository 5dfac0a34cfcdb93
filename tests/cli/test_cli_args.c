/* test_cli_args.c - issue 22, rule 4: every argument is consumed or refused.
 * `--` ends the options (it hung every command), `--name=value` is
 * `--name value`, single-dash options, extra positionals and malformed
 * numbers exit 2 with the fix, and every name the user types gets a
 * did-you-mean.  CLI tests of build/sunmc (SUNMC). */
#include "test_util.h"

#include "suggest.h"

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "args");
}

#define E "configs/ess_type_a.ini"
#define D "configs/dss.ini"
#define TINY "--set campaign.alpha_step_deg=2 --set validation.alpha_step_deg=5 " \
             "--set campaign.beta_deg=-15,15 --quiet"

/* `sunmc ARGS` (with timeout: a hang fails) exits rc (any when < 0) and its output holds
 * every needle ("|" between). */
static void expect(const char *args, int rc, const char *needles)
{
    char cmd[4096], out[16384], want[1024];
    snprintf(cmd, sizeof cmd, "D=%s; timeout 60 %s %s", dir, test_sunmc(), args);
    int got = test_run(cmd, out, sizeof out);
    if (rc >= 0 && got != rc)
        fail_msg("sunmc %s: exit %d, expected %d: %s", args, got, rc, out);
    snprintf(want, sizeof want, "%s", needles);
    for (char *p = strtok(want, "|"); p; p = strtok(NULL, "|"))
        if (!strstr(out, p))
            fail_msg("sunmc %s: output lacks '%s': %s", args, p, out);
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* The issue's reproducer: a bare `--` hung every command at 100 % CPU. */
static void test_double_dash_ends_options(void **state)
{
    expect("run " E " --units 3 " TINY " --", 0, "fit failures");
    expect("config -- " D, 0, "family = dss");
    expect("budget -- " D " " D, 2, "unexpected argument");
    expect("curve " D " --unit 1 --quiet -- --out", 2, "unexpected argument '--out'");
    expect("merge --", 2, "needs OUT");
    expect("compensate --", 2, "");
}

/* getopt_long's --name=value form is the same as --name value. */
static void test_equals_form(void **state)
{
    expect("run " E " --units=3 " TINY, 0, "fit failures");
    expect("run " E " --units=3 --threads=1 --set=campaign.alpha_step_deg=2 "
           "--set validation.alpha_step_deg=5 --set campaign.beta_deg=-15,15 --quiet",
           0, "fit failures");
    expect("run " E " --quiet=yes", 2, "takes no value");
    expect("run " E " --units=", 2, "--units needs a whole number");
}

/* `run $E -o runs/x` ran 1000 units and wrote nothing; `run A.ini B.ini`
 * ran A only. */
static void test_stray_arguments_refused(void **state)
{
    expect("run " E " -o $D/x", 2, "unknown option -o|did you mean --out?|options start with --");
    assert_false(exists(test_tmp("args/x")));
    expect("run " E " " D, 2, "unexpected argument 'configs/dss.ini'|run takes one CONFIG");
    expect("run " E " -q", 2, "did you mean --quiet?");
    expect("sweep " D " -v x=1", 2, "did you mean --vary?");
    expect("run " E " -units 3", 2, "did you mean --units?");
    expect("calibrate --config " D " a.csv b.csv", 2, "unexpected argument 'b.csv'");
    expect("compensate a b c", 2, "unexpected argument 'c'");
    expect("simulate " D " --unit 1 --out $D/s extra", 2, "unexpected argument 'extra'");
    expect("run " E " --out --quiet", 2, "--out needs a value before the next option");
    expect("run " E " --outt $D/o", 2, "unknown option --outt (did you mean --out?)");
    expect("merge $D/m -x", 2, "unknown option -x");
}

/* Malformed numbers say what is wanted (not a --set run.units message). */
static void test_malformed_numbers(void **state)
{
    expect("run " E " --units 1e3", 2, "--units needs a whole number (e.g. 1000, not 1e3)");
    expect("run " E " --seed 1.5", 2, "--seed needs a whole number");
    /* rule 8: a range beyond run.units' largest value overflowed (segfault) */
    expect("run " D " --units 9223372036854775806:9223372036854775807", 2,
           "END <= 100000000");
    expect("run " D " --units 99999999:100000001", 2, "END <= 100000000");
    expect("run " D " --units 5:3", 2, "0 <= FIRST < END");
}

/* did-you-mean for every name: keys of --set/--vary/--only, sections,
 * commands; `--set "a = 3"` is trimmed like a config line. */
static void test_did_you_mean(void **state)
{
    expect("run " D " --set toleranc.dh_px=1", 2, "unknown section [toleranc] (did you mean [tolerance]?)");
    expect("run " D " --set tolerance.dh_pxx=1", 2, "did you mean tolerance.dh_px?");
    expect("sweep " D " --vary tolerance.dh_pxx=1,2", 2, "did you mean tolerance.dh_px?");
    expect("sweep " D " --vary tolerence.dh_px=1,2", 2, "tolerence.dh_px");
    expect("curve " D " --only dh_pxx=1", 2, "did you mean tolerance.dh_px?");
    expect("runn " D, 2, "unknown command 'runn' (did you mean run?)");
    expect("budgte " D, 2, "(did you mean budget?)");
    expect("config " D " --set \"tolerance.dh_px = 0.3\"", 0, "dh_px = 0.3");
    expect("config " D " --set \" tolerance . dh_px=0.3 \"", 0, "dh_px = 0.3");
    char p[600];
    snprintf(p, sizeof p, "%s/bad.ini", dir);
    assert_int_equal(test_write_file(p, "[sensr]\nfamily = dss\n"), 0);
    expect("config $D/bad.ini", 2, "bad.ini:1: unknown section [sensr] (did you mean [sensor]?)");
    /* every other name typed: short commands, options, values of choice keys */
    expect("rn " D, 2, "unknown command 'rn' (did you mean run?)");
    expect("x " D, 2, "unknown command 'x' (see sunmc --help)");
    expect("run " D " --unit 3", 2, "unknown option --unit (did you mean --units?)");
    expect("curve " D " --unitt 3", 2, "unknown option --unitt (did you mean --unit?)");
    expect("curve " D " --onli dh_px=1", 2, "(did you mean --only?)");
    expect("curve " E " --only tolerance.dh_um=2", 2, "did you mean tolerance.dH_um?");
    expect("sweep " D " --vary tolerance.dh_px=1,2 --vary tolerance.dh_pxx=1,2", 2,
           "did you mean tolerance.dh_px?");
    expect("run " D " --set report.yield_interval=wilsn", 2,
           "one of wilson|clopper_pearson|clopper_pearson_lower (did you mean wilson?)");
    expect("config " D " --set sensor.family=dsss", 2, "one of ess|dss|psd (did you mean dss?)");
    expect("run " D " --until rms_after_meen:0.1", 2,
           "unknown statistic 'rms_after_meen' (did you mean rms_after_mean?)");
    expect("run " D " --isa avx", 2, "--isa avx: one of baseline, avx2 (did you mean avx2?)");
    expect("calibrate --sensor dsss --config " D " x.csv", 2,
           "not 'dsss' (did you mean dss?)");
    /* --duplicates is checked before the data file is read */
    expect("calibrate --duplicates averge --config " D " /nonexistent.csv", 2,
           "--duplicates averge: one of average, refuse, keep (did you mean average?)");
}

/* `sunmc --family dss --help` said "unknown command". */
static void test_family_help(void **state)
{
    expect("--family dss --help", 0, "usage: sunmc COMMAND|config keys of the dss family");
    expect("--family nosuch --help", 2, "--family takes one of");
}

/* design --space was cut at 127 characters: a long list loses its last
 * values (or 0.25 becomes 0.2); now it is whole or refused. */
static void test_space_never_cut(void **state)
{
    char args[2048], list[600] = "steps_deg=";
    for (int i = 0; i < 30; i++) /* 194 characters, 31 values ending in 0.25 */
        snprintf(list + strlen(list), sizeof list - strlen(list), "0.%03d,", 100 + i);
    strcat(list, "0.25");
    assert_true(strlen(list) > 127);
    snprintf(args, sizeof args,
             "design " E " --space '%s' --space repeats=1 --space max_lines=1 "
             "--space beta_max_deg=0 --set campaign.search_screen_units=10 --units 2 --out $D/sp",
             list);
    expect(args, -1, "no candidate met the target"); /* exit 1, files written */
    assert_true(test_file_has(test_tmp("args/sp/config.ini"), "0.128, 0.129, 0.25  #"));
    /* a value that cannot be held whole is refused, never cut */
    char huge[1200] = "steps_deg=0.1";
    while (strlen(huge) < 1100)
        strcat(huge, ",0.1");
    snprintf(args, sizeof args, "design " E " --space %s --out $D/sp2", huge);
    expect(args, 2, "--space value too long");
}

/* suggest_nearest: at most two edits, fewer than half the word. */
static void test_suggest_limits(void **state)
{
    const char *names[] = {"run", "budget", "sweep"};
    assert_string_equal(suggest_nearest("runn", names, 3), "run");
    assert_string_equal(suggest_nearest("BUDGET", names, 3), "budget");
    assert_string_equal(suggest_nearest("swep", names, 3), "sweep");
    assert_null(suggest_nearest("xyz", names, 3));
    assert_null(suggest_nearest("bud", names, 3)); /* 3 edits */
    assert_string_equal(suggest_nearest("rn", names, 3), "run"); /* 1 of the longer's 3 */
    assert_null(suggest_nearest("r", names, 3));                 /* 2 of 3: too far */
    char hint[96];
    suggest_hint("keeep", "average|refuse|keep", hint, sizeof hint);
    assert_string_equal(hint, " (did you mean keep?)");
    suggest_hint("psd", "ess, dss or psd", hint, sizeof hint);
    assert_string_equal(hint, " (did you mean psd?)");
    suggest_hint("zzzz", "ess, dss or psd", hint, sizeof hint);
    assert_string_equal(hint, "");
    assert_int_equal(suggest_distance("abc", "abd"), 1);
    assert_int_equal(suggest_distance("", "abc"), 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_double_dash_ends_options),
        cmocka_unit_test(test_equals_form),
        cmocka_unit_test(test_stray_arguments_refused),
        cmocka_unit_test(test_malformed_numbers),
        cmocka_unit_test(test_did_you_mean),
        cmocka_unit_test(test_family_help),
        cmocka_unit_test(test_space_never_cut),
        cmocka_unit_test(test_suggest_limits),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
