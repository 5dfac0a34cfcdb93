/* test_cli_once.c - issue 36, rule 9: every argument is used once or
 * refused.  `--out o1 --out o2` wrote o2 only and `--units 3 --set
 * run.units=7` ran 7 (the last silently won); hex was a number in CSVs and
 * --until but not in --units; unit indices past the documented 1e8 were
 * accepted; `--units 0` was reported as --set run.units; `sunmc rnu` got
 * no suggestion; calibrate without --config never named it.  CLI tests of
 * build/sunmc (SUNMC). */
#include "test_util.h"

#include "suggest.h"

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "once");
}

#define P "configs/psd.ini"
#define Q "--quiet"

/* `sunmc ARGS` exits rc and its output holds every needle ("|" between). */
static void expect(const char *args, int rc, const char *needles)
{
    char cmd[4096], out[16384], want[1024];
    snprintf(cmd, sizeof cmd, "D=%s; timeout 60 %s %s", dir, test_sunmc(), args);
    int got = test_run(cmd, out, sizeof out);
    if (got != rc)
        fail_msg("sunmc %s: exit %d, expected %d: %s", args, got, rc, out);
    snprintf(want, sizeof want, "%s", needles);
    for (char *p = strtok(want, "|"); p; p = strtok(NULL, "|"))
        if (!strstr(out, p))
            fail_msg("sunmc %s: output lacks '%s': %s", args, p, out);
}

static int exists(const char *name)
{
    char path[1024];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &st) == 0;
}

/* The reproducers: the last of two values won without a word. */
static void repeated_option_refused(void **state)
{
    expect("run " P " --units 2 " Q " --out $D/o1 --out $D/o2", 2, "--out given twice");
    assert_false(exists("o1"));
    assert_false(exists("o2"));
    expect("run " P " --units 5 --units 6 " Q, 2, "--units N given twice");
    expect("run " P " --units 0:2 --units 1:3 " Q, 2, "--units FIRST:END given twice");
    /* N (run.units) and FIRST:END (the range of that run) are two values */
    expect("run " P " --units 50 --units 0:2 " Q, 0, "units 0:2 of the run of 50 units");
    expect("run " P " --units 2 --seed 1 --seed 2 " Q, 2, "--seed given twice");
    expect("run " P " --units 2 --threads 1 --threads=2 " Q, 2, "--threads given twice");
    expect("run " P " --units 2 " Q " --quiet", 2, "--quiet given twice");
    expect("run " P " --shard 0/2 --shard 1/2 " Q, 2, "--shard given twice");
    expect("curve " P " --unit 1 --unit 2 " Q, 2, "--unit given twice");
    expect("calibrate --config " P " --config " P " x.csv", 2, "--config given twice");
    expect("sensitivity " P " --until st:0.1 --until st:0.2 " Q, 2, "--until given twice");
}

/* Options documented as repeatable ([--set ...]..., --vary's two axes,
 * design's --space) still add up. */
static void repeatable_options_add_up(void **state)
{
    expect("config " P " --set run.seed=4 --set run.units=9", 0, "seed = 4|units = 9");
    expect("sweep " P " --units 2 " Q " --vary run.seed=1,2 --vary noise.adc_bits=12,14", 0,
           "adc_bits");
}

/* --units N with --set run.units (either order), --seed with --set run.seed. */
static void one_value_per_key(void **state)
{
    expect("run " P " --units 3 --set run.units=7 " Q, 2,
           "--units and --set run.units both give run.units");
    expect("run " P " --set 'run.units = 7' --units 3 " Q, 2, "--units and --set run.units");
    expect("run " P " --units 2 --seed 3 --set run.seed=4 " Q, 2,
           "--seed and --set run.seed both give run.seed");
    /* a range of a run of --set run.units units is one value each */
    expect("run " P " --units 0:2 --set run.units=7 " Q, 0, "units 0:2 of the run of 7 units");
}

/* Hex, '+', blanks and exponents are refused in every whole number, as
 * hex, inf and nan are in --until's half-width. */
static void non_decimal_numbers_refused(void **state)
{
    static const char *const bad[] = {"0x5", "0X5", "+5", "' 5'", "'5 '", "1e3", "5.0"};
    char args[256];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(args, sizeof args, "run " P " --units %s " Q, bad[i]);
        expect(args, 2, "--units needs a whole number");
        snprintf(args, sizeof args, "run " P " --units 2 --seed %s " Q, bad[i]);
        expect(args, 2, "--seed needs a whole number");
        snprintf(args, sizeof args, "run " P " --units 2 --threads %s " Q, bad[i]);
        expect(args, 2, "--threads needs a whole number");
        snprintf(args, sizeof args, "curve " P " --unit %s " Q, bad[i]);
        expect(args, 2, "--unit needs a unit index");
        snprintf(args, sizeof args, "run " P " --units 0:%s " Q, bad[i]);
        expect(args, 2, "FIRST:END needs whole numbers");
        snprintf(args, sizeof args, "run " P " --units 4 --shard %s/2 " Q, bad[i]);
        expect(args, 2, "--shard K/N");
    }
    expect("run " P " --units 16 --until yield:0x10 " Q, 2, "HALFWIDTH a decimal number > 0");
    expect("run " P " --units 16 --until yield:inf " Q, 2, "HALFWIDTH a decimal number > 0");
    expect("run " P " --units 16 --until yield:nan " Q, 2, "HALFWIDTH a decimal number > 0");
    expect("sensitivity " P " --until st:0X1 " Q, 2, "HALFWIDTH a decimal number > 0");
    /* the decimal forms are read */
    expect("run " P " --units 16 --until yield:1e0 " Q, 0, "--until yield:1e0: met after");
    expect("run " P " --units 0005 " Q, 0, "fit failures");
    /* a config value and a --vary value read hex no more */
    expect("run " P " --units 2 --set design.h_mm=0x4 " Q, 2, "design.h_mm = '0x4' is not a number");
    expect("run " P " --units 2 --set design.h_mm=0x4p0 " Q, 2, "is not a number");
    expect("run " P " --units 2 --set design.h_mm=4.0 " Q, 0, "fit failures");
    expect("sweep " P " --units 2 --vary design.h_mm=0x4,4.5 " Q, 2, "'0x4' is not a number");
}

/* --unit and --units FIRST:END against run.units' largest value (1e8):
 * the last index is taken, one past it refused. */
static void unit_index_limit_both_sides(void **state)
{
    expect("curve " P " --unit 99999999 " Q, 0, "");
    expect("curve " P " --unit 100000000 " Q, 2, "--unit needs a unit index from 0 to 99999999");
    expect("curve " P " --unit 99999999999 " Q, 2, "from 0 to 99999999");
    expect("simulate " P " --unit 99999999 --out $D/s_ok " Q, 0, "");
    assert_true(exists("s_ok"));
    expect("simulate " P " --unit 100000000 --out $D/s_bad " Q, 2, "from 0 to 99999999");
    assert_false(exists("s_bad"));
    expect("curve " P " --unit 0 " Q, 0, "");
    expect("curve " P " --unit -1 " Q, 2, "--unit needs a unit index");
    expect("run " P " --units 99999999:100000000 " Q, 0, "units 99999999:100000000");
    expect("run " P " --units 99999999:100000001 " Q, 2, "END <= 100000000");
}

/* --units N and --seed S: out of range is said as the option typed, at
 * both ends of run.units and run.seed. */
static void count_limits_name_the_option(void **state)
{
    expect("run " P " --units 0 " Q, 2, "--units needs a whole number from 1 to 100000000");
    expect("run " P " --units 1 " Q, 0, "fit failures");
    expect("run " P " --units 100000001 " Q, 2, "--units needs a whole number from 1 to");
    expect("run " P " --units 2 --seed -1 " Q, 2, "--seed needs a whole number from 0 to 2147483647");
    expect("run " P " --units 2 --seed 0 " Q, 0, "fit failures");
    expect("run " P " --units 2 --seed 2147483647 " Q, 0, "fit failures");
    expect("run " P " --units 2 --seed 2147483648 " Q, 2, "--seed needs a whole number from 0");
}

/* A swapped pair of letters is one edit: `sunmc rnu` -> run. */
static void mistyped_command_suggested(void **state)
{
    expect("rnu " P, 2, "unknown command 'rnu' (did you mean run?)");
    expect("smiulate " P, 2, "(did you mean simulate?)");
    expect("run " P " --treads 2", 2, "(did you mean --threads?)");
    assert_int_equal(suggest_distance("rnu", "run"), 1);
    assert_int_equal(suggest_distance("ab", "ba"), 1);
    assert_int_equal(suggest_distance("abc", "cab"), 2);
    const char *names[] = {"run", "curve"};
    assert_null(suggest_nearest("nur", names, 2)); /* two edits of three letters */
}

/* calibrate takes its config as --config CONFIG, and says so. */
static void calibrate_names_config(void **state)
{
    expect("calibrate " P " x.csv", 2,
           "needs --config CONFIG|was 'configs/psd.ini' meant as --config?");
    expect("calibrate x.csv", 2, "needs --config CONFIG");
    expect("run " P " " P, 2, "run takes one CONFIG and options");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(repeated_option_refused),
        cmocka_unit_test(repeatable_options_add_up),
        cmocka_unit_test(one_value_per_key),
        cmocka_unit_test(non_decimal_numbers_refused),
        cmocka_unit_test(unit_index_limit_both_sides),
        cmocka_unit_test(count_limits_name_the_option),
        cmocka_unit_test(mistyped_command_suggested),
        cmocka_unit_test(calibrate_names_config),
    };
    return cmocka_run_group_tests_name("cli_once", tests, setup, NULL);
}
