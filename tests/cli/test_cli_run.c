/* test_cli_run.c - `sunmc run` end to end: determinism across thread counts
 * and unit ranges, output files, and every command-line / config error
 * (exit status 2, FILE:LINE message, no output written). */
#include "test_util.h"

#include <sys/stat.h>
#include <unistd.h>

static char dir[128];

static int setup(void **state)
{
    snprintf(dir, sizeof dir, "/tmp/sunmc_test_cli_%ld", (long)getpid());
    char cmd[512];
    snprintf(cmd, sizeof cmd, "rm -rf %s && mkdir -p %s", dir, dir);
    return system(cmd) == 0 ? 0 : -1;
}

static int teardown(void **state)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static int run(const char *args, char *out, size_t len)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s %s", test_sunmc(), args);
    return test_run(cmd, out, len);
}

static int files_equal(const char *a, const char *b)
{
    char cmd[1024], out[256];
    snprintf(cmd, sizeof cmd, "cmp %s %s", a, b);
    return test_run(cmd, out, sizeof out) == 0;
}

/* summary.tsv and units.tsv of output directories d1 and d2 (under dir)
 * are the same bytes. */
static void assert_same_results(const char *d1, const char *d2, const char *what)
{
    const char *files[] = {"summary.tsv", "units.tsv"};
    char a[256], b[256];
    for (int i = 0; i < 2; i++) {
        snprintf(a, sizeof a, "%s/%s/%s", dir, d1, files[i]);
        snprintf(b, sizeof b, "%s/%s/%s", dir, d2, files[i]);
        if (!files_equal(a, b))
            fail_msg("%s differs between %s", files[i], what);
    }
}

#define SMALL "run configs/ess_type_a.ini --quiet --set campaign.alpha_step_deg=0.4 " \
              "--set validation.alpha_step_deg=0.7 --set campaign.beta_deg=-15,15"

static void test_threads_byte_identical(void **state)
{
    char out[8192], args[1024], a[256], b[256];
    snprintf(args, sizeof args, SMALL " --units 40 --threads 1 --out %s/t1", dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    snprintf(args, sizeof args, SMALL " --units 40 --threads 2 --out %s/t2", dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    const char *files[] = {"summary.tsv", "units.tsv", "config.ini"};
    for (int i = 0; i < 3; i++) {
        snprintf(a, sizeof a, "%s/t1/%s", dir, files[i]);
        snprintf(b, sizeof b, "%s/t2/%s", dir, files[i]);
        if (!files_equal(a, b))
            fail_msg("%s differs between --threads 1 and 2", files[i]);
    }
    /* Table 1 is printed */
    assert_non_null(strstr(out, "times improvement"));
    /* --profile prints the split and leaves every output file as it was */
    snprintf(args, sizeof args, SMALL " --units 40 --threads 2 --profile --out %s/tp", dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    assert_non_null(strstr(out, "profile: campaign"));
    assert_non_null(strstr(out, "ms per unit per thread"));
    for (int i = 0; i < 3; i++) {
        snprintf(a, sizeof a, "%s/t1/%s", dir, files[i]);
        snprintf(b, sizeof b, "%s/tp/%s", dir, files[i]);
        if (!files_equal(a, b))
            fail_msg("%s differs with --profile", files[i]);
    }
}

/* The files of a run of 40 units streamed in blocks of 7 (the last block
 * short) are those of one block of 256. */
static void test_block_size_byte_identical(void **state)
{
    char out[8192], args[1024];
    snprintf(args, sizeof args, SMALL " --units 40 --threads 2 --out %s/b256", dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    snprintf(args, sizeof args, SMALL " --units 40 --threads 2 --set run.block_units=7 --out %s/b7",
             dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    assert_same_results("b256", "b7", "blocks of 256 and of 7");
}

/* run --until stops at a block end once the half-width is met, says after
 * how many units, and writes the files of a fixed run of that many; a
 * target not met by --units N says so and ends at N. */
static void test_until_equals_fixed_run(void **state)
{
    char out[8192], args[1024];
    snprintf(args, sizeof args,
             SMALL " --units 400 --set run.block_units=16 --until yield:0.02 --out %s/until", dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    const char *line = strstr(out, "--until yield:0.02: met after ");
    assert_non_null(line);
    long n = atol(line + strlen("--until yield:0.02: met after "));
    /* Wilson's interval at 100 % yield, [n/(n+z^2), 1], has half-width
     * z^2 / (2 (n + z^2)) <= 0.02 first at n = 93: the block end is 96. */
    assert_int_equal(n, 96);
    snprintf(args, sizeof args, SMALL " --units %ld --out %s/fixed", n, dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    assert_same_results("until", "fixed", "--until and the fixed run");
    snprintf(args, sizeof args, SMALL " --units 20 --set run.block_units=16 --until "
             "rms_after_mean:1e-9");
    assert_int_equal(run(args, out, sizeof out), 0);
    assert_non_null(strstr(out, "NOT met"));
    assert_non_null(strstr(out, "after all 20 units"));
    assert_int_equal(run(SMALL " --until yield", out, sizeof out), 2);
    assert_int_equal(run(SMALL " --until yield:0", out, sizeof out), 2);
    assert_int_equal(run(SMALL " --until max:1", out, sizeof out), 2);
    assert_non_null(strstr(out, "unknown statistic 'max'"));
    assert_int_equal(run(SMALL " --units 5:9 --until yield:0.1", out, sizeof out), 2);
}

/* Units 0..39 and the halves 0:17, 17:40 give the same unit rows. */
static void test_unit_ranges_compose(void **state)
{
    char out[8192], args[1024], cmd[1024];
    snprintf(args, sizeof args, SMALL " --units 40 --out %s/all", dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    snprintf(args, sizeof args, SMALL " --units 0:17 --out %s/h1", dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    snprintf(args, sizeof args, SMALL " --units 17:40 --out %s/h2", dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd,
             "(cat %s/h1/units.tsv; tail -n +2 %s/h2/units.tsv) > %s/joined.tsv", dir, dir, dir);
    assert_int_equal(system(cmd), 0);
    char a[256], b[256];
    snprintf(a, sizeof a, "%s/all/units.tsv", dir);
    snprintf(b, sizeof b, "%s/joined.tsv", dir);
    assert_true(files_equal(a, b));
}

/* summary.tsv has its header columns and one row per band. */
static void test_summary_columns(void **state)
{
    char out[8192], args[1024], path[256];
    snprintf(args, sizeof args, SMALL " --units 10 --out %s/cols", dir);
    assert_int_equal(run(args, out, sizeof out), 0);
    snprintf(path, sizeof path, "%s/cols/summary.tsv", dir);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[4096];
    assert_non_null(fgets(line, sizeof line, f));
    const char *cols[] = {"product", "band", "units", "rms_before_mean", "rms_after_mean",
                          "rms_after_max", "rms_after_min", "improvement_mean",
                          "improvement_max", "improvement_min", "yield", "fit_failures"};
    for (int i = 0; i < 12; i++)
        if (!strstr(line, cols[i]))
            fail_msg("summary.tsv header lacks %s", cols[i]);
    int rows = 0;
    while (fgets(line, sizeof line, f))
        rows++;
    fclose(f);
    assert_int_equal(rows, 3);
}

/* A bad config: exit 2, FILE:LINE message, and nothing written. */
static void expect_bad(const char *ini, const char *extra, const char *needle)
{
    char path[256], args[1024], out[4096], outdir[256];
    snprintf(path, sizeof path, "%s/bad.ini", dir);
    snprintf(outdir, sizeof outdir, "%s/should_not_exist", dir);
    assert_int_equal(test_write_file(path, ini), 0);
    snprintf(args, sizeof args, "run %s --units 5 --quiet --out %s %s", path, outdir, extra);
    int st = run(args, out, sizeof out);
    if (st != 2)
        fail_msg("exit status %d, expected 2; output: %s", st, out);
    if (!strstr(out, needle))
        fail_msg("message '%s' lacks '%s'", out, needle);
    struct stat sb;
    assert_int_not_equal(stat(outdir, &sb), 0);
}

static void test_bad_configs_exit_2(void **state)
{
    char where[300];
    snprintf(where, sizeof where, "%s/bad.ini:3:", dir);
    expect_bad("[design]\nH_mm = 4\n[bogus]\n", "", where);
    expect_bad("[design]\nH_mm = 4\nzz = 1\n", "", "zz");
    expect_bad("[design]\nH_mm = 4\nH_mm = 4.1\n", "", "duplicate");
    expect_bad("[design]\nH_mm = 4\ntheta0_deg = two\n", "", "theta0_deg");
    expect_bad("[design]\nH_mm = 4\nfov_deg = 85\n", "", "fov_deg");
    expect_bad("[design]\nH_mm = 4\n", "--set tolerance.dH_um=-1", "tolerance.dH_um");
}

static void test_bad_command_lines(void **state)
{
    char out[4096];
    assert_int_equal(run("run configs/ess_type_a.ini --bogus", out, sizeof out), 2);
    assert_int_equal(run("run configs/ess_type_a.ini --units 5:3", out, sizeof out), 2);
    assert_int_equal(run("run configs/ess_type_a.ini --threads 0", out, sizeof out), 2);
    assert_int_equal(run("run", out, sizeof out), 2);
    assert_int_equal(run("frobnicate", out, sizeof out), 2);
    assert_int_equal(run("run /nonexistent.ini", out, sizeof out), 2);
    assert_non_null(strstr(out, "/nonexistent.ini"));
    assert_int_equal(run("--version", out, sizeof out), 0);
    assert_non_null(strstr(out, "sunmc "));
    assert_int_equal(run("--help", out, sizeof out), 0);
    assert_non_null(strstr(out, "tolerance.dH_um"));
    assert_int_equal(run("run --help", out, sizeof out), 0);
}

/* `sunmc config` prints every key with its origin; the dump is a valid config. */
static void test_config_command(void **state)
{
    static char out[65536];
    char args[512], path[256];
    assert_int_equal(run("config configs/ess_type_a.ini --set design.H_mm=5", out, sizeof out), 0);
    assert_non_null(strstr(out, "H_mm = 5  # --set design.H_mm"));
    assert_non_null(strstr(out, "configs/ess_type_a.ini:"));
    assert_non_null(strstr(out, "# default"));
    snprintf(path, sizeof path, "%s/dump.ini", dir);
    assert_int_equal(test_write_file(path, out), 0);
    snprintf(args, sizeof args, "config %s", path);
    assert_int_equal(run(args, out, sizeof out), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_threads_byte_identical), cmocka_unit_test(test_unit_ranges_compose),
        cmocka_unit_test(test_block_size_byte_identical),
        cmocka_unit_test(test_until_equals_fixed_run),
        cmocka_unit_test(test_summary_columns),        cmocka_unit_test(test_bad_configs_exit_2),
        cmocka_unit_test(test_bad_command_lines),      cmocka_unit_test(test_config_command),
    };
    return cmocka_run_group_tests_name("cli_run", tests, setup, teardown);
}
