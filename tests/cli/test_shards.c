/* test_shards.c - shards of a run (`run --shard K/N`, `--units FIRST:END`)
 * merged by `sunmc merge` give the single run's files byte for byte; a
 * merge of parts that are not one run (gap, overlap, the same directory
 * twice, another seed, config or version, a damaged units.bin) is refused
 * with the units or the field named, and writes nothing.  units.bin round
 * trips every bit. */
#include "test_util.h"

#include "runner.h"
#include "unitfile.h"

#include <sys/stat.h>
#include <unistd.h>

static char dir[128];

#define SMALL_CONFIG "run configs/ess_type_a.ini --quiet --set campaign.alpha_step_deg=0.4 " \
                     "--set validation.alpha_step_deg=0.7 --set campaign.beta_deg=-15,15"
#define SMALL SMALL_CONFIG " --units 1000"

/* The test's private directory (test_tmp's, removed at exit). */
static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "shards");
}

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int same_file(const char *a, const char *b)
{
    char cmd[1024], out[256];
    snprintf(cmd, sizeof cmd, "cmp %s/%s %s/%s", dir, a, dir, b);
    return test_run(cmd, out, sizeof out) == 0;
}

static int exists(const char *name)
{
    char path[512];
    struct stat sb;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &sb) == 0;
}

static void run_ok(const char *fmt, const char *arg)
{
    char args[2048], out[8192];
    snprintf(args, sizeof args, fmt, arg);
    int st = sunmc(args, out, sizeof out);
    if (st != 0)
        fail_msg("sunmc %s: exit %d\n%s", args, st, out);
}

/* The whole run of 1000 units and its three shards, run once. */
static void make_runs(void)
{
    static int done;
    if (done++)
        return;
    run_ok(SMALL " --threads 2 --out $D/%s", "whole");
    run_ok(SMALL " --shard 0/3 --threads 1 --out $D/%s", "s0");
    run_ok(SMALL " --shard 1/3 --out $D/%s", "s1");
    run_ok(SMALL " --shard 2/3 --out $D/%s", "s2");
}

static void three_shards_merge_to_the_whole_run(void **state)
{
    make_runs();
    char out[16384];
    /* any order of the directories */
    assert_int_equal(sunmc("merge $D/merged $D/s2 $D/s0 $D/s1", out, sizeof out), 0);
    assert_non_null(strstr(out, "merged units 0:1000 from 3 shards"));
    assert_non_null(strstr(out, "times improvement")); /* Table 1 */
    const char *files[] = {"summary.tsv", "units.tsv", "config.ini", "manifest.ini", "units.bin"};
    char a[64], b[64];
    for (int i = 0; i < 5; i++) {
        snprintf(a, sizeof a, "whole/%s", files[i]);
        snprintf(b, sizeof b, "merged/%s", files[i]);
        if (!same_file(a, b))
            fail_msg("%s of the merge differs from the whole run's", files[i]);
    }
    /* --shard 1/3 of 1000 units is 333:666 */
    char path[512];
    snprintf(path, sizeof path, "%s/s1/manifest.ini", dir);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char text[1024];
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    assert_non_null(strstr(text, "first_unit = 333\nend_unit = 666\n"));
    assert_non_null(strstr(text, "seed = 1\n"));
}

/* With a list of operating temperatures (the per-temperature columns of
 * units.bin, units.tsv and summary.tsv): two shards of two threads and one
 * merge to the whole run, byte for byte; a merge with a run of other
 * temperatures is refused. */
#define THERMAL SMALL_CONFIG " --set environment.operating_temp_c=-30,0:60:30 --units 120"

static void shards_with_temperatures_merge_to_the_whole_run(void **state)
{
    char out[65536];
    run_ok(THERMAL " --threads 1 --out $D/%s", "tw");
    run_ok(THERMAL " --shard 0/2 --threads 2 --out $D/%s", "t0");
    run_ok(THERMAL " --shard 1/2 --threads 2 --out $D/%s", "t1");
    assert_int_equal(sunmc("merge $D/tm $D/t1 $D/t0", out, sizeof out), 0);
    assert_non_null(strstr(out, "yield over -30..60 C (at every temperature)"));
    const char *files[] = {"summary.tsv", "units.tsv", "units.bin"};
    char a[64], b[64];
    for (int i = 0; i < 3; i++) {
        snprintf(a, sizeof a, "tw/%s", files[i]);
        snprintf(b, sizeof b, "tm/%s", files[i]);
        if (!same_file(a, b))
            fail_msg("%s of the merge with temperatures differs from the whole run's", files[i]);
    }
    assert_int_equal(sunmc("run configs/ess_type_a.ini --quiet --set campaign.alpha_step_deg=0.4 "
                           "--set validation.alpha_step_deg=0.7 --set campaign.beta_deg=-15,15 "
                           "--units 120 --shard 1/2 --out $D/t1lab",
                           out, sizeof out),
                     0);
    assert_int_not_equal(sunmc("merge $D/tx $D/t0 $D/t1lab", out, sizeof out), 0);
    assert_false(exists("tx"));
    char cmd[512];
    snprintf(cmd, sizeof cmd, "head -1 %s/tw/units.tsv | tr '\\t' '\\n' | grep -c '_at_-30C$'", dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_int_equal(atoi(out), 6); /* before and after, 3 bands */
    (void)state;
}

/* A refused merge: exit 2, the message holds needle, OUT not written. */
static void refused(const char *shards, const char *needle)
{
    char args[1024], out[8192], with_d[512] = "";
    for (const char *p = shards; *p;) {
        size_t k = strcspn(p, " ");
        size_t used = strlen(with_d);
        snprintf(with_d + used, sizeof with_d - used, "$D/%.*s ", (int)k, p);
        p += k + (p[k] == ' ');
    }
    snprintf(args, sizeof args, "merge $D/refused %s", with_d);
    int st = sunmc(args, out, sizeof out);
    if (st != 2)
        fail_msg("merge %s: exit %d, expected 2\n%s", shards, st, out);
    if (!strstr(out, needle))
        fail_msg("merge %s: message '%s' lacks '%s'", shards, out, needle);
    assert_false(exists("refused"));
}

static void merges_that_are_not_one_run_are_refused(void **state)
{
    make_runs();
    refused("s0 s2", "units 333:666 are missing: ");
    refused("s2 s0", "s0 ends at 333, ");
    run_ok(SMALL " --units 300:700 --out $D/%s", "mid");
    refused("s0 mid s2", "units 300:333 are in both ");
    refused("s0 s1 s1/ s2", "are the same directory (units 333:666 twice)");
    run_ok(SMALL " --shard 1/3 --seed 2 --out $D/%s", "seed2");
    refused("s0 seed2 s2", "seed2 are of different runs: seed 1 against 2");
    run_ok(SMALL " --shard 1/3 --set noise.row_current_pct=0.5 --out $D/%s", "cfg2");
    refused("s0 cfg2 s2", "cfg2 are of different runs: config");
    refused("s0 cfg2 s2", "(first difference: [noise] row_current_pct = ");
    /* threads and block size are not part of a run's identity */
    run_ok(SMALL " --shard 1/3 --threads 1 --set run.block_units=7 --out $D/%s", "blk7");
    char out[16384];
    assert_int_equal(sunmc("merge $D/blk $D/s0 $D/blk7 $D/s2", out, sizeof out), 0);
    assert_true(same_file("whole/summary.tsv", "blk/summary.tsv"));
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "cd %s && cp -r s1 ver && sed -i 's/^sunmc_version = .*/sunmc_version = 0.0.1/' "
             "ver/manifest.ini && cp -r s1 cut && truncate -s -100 cut/units.bin && "
             "cp -r s0 cfged && sed -i 's/^seed = 1/seed = 3/' cfged/config.ini",
             dir);
    assert_int_equal(system(cmd), 0);
    refused("s0 ver s2", "sunmc version 0.1.0 against 0.0.1");
    refused("s0 cut s2", "cut/units.bin: truncated record");
    refused("cfged s1 s2", "config.ini does not match its manifest");
    refused("s0 nowhere s2", "nowhere/manifest.ini");
    assert_int_equal(sunmc("merge $D/refused", out, sizeof out), 2);
    assert_non_null(strstr(out, "needs OUT and at least one SHARD_DIR"));
}

/* --shard and its errors */
static void shard_option_errors(void **state)
{
    char out[4096];
    assert_int_equal(sunmc(SMALL " --shard 3/3", out, sizeof out), 2);
    assert_non_null(strstr(out, "--shard K/N needs 0 <= K < N"));
    assert_int_equal(sunmc(SMALL " --shard 1", out, sizeof out), 2);
    assert_int_equal(sunmc(SMALL " --shard -1/3", out, sizeof out), 2);
    assert_int_equal(sunmc(SMALL " --shard 0/3 --units 0:10", out, sizeof out), 2);
    assert_int_equal(sunmc(SMALL " --shard 0/3 --until yield:0.1", out, sizeof out), 2);
    assert_int_equal(sunmc(SMALL " --shard 0/1001", out, sizeof out), 2);
    assert_non_null(strstr(out, "more shards than the 1000 units"));
}

/* Records written and read back are the same bits (NaN, -0, subnormals,
 * a full-precision value units.tsv would round). */
static void units_file_round_trip(void **state)
{
    sunmc_config c = test_family_config("dss");
    unitfile_layout l;
    unitfile_layout_of(&c, &l);
    unit_result in[3], back[3];
    memset(in, 0, sizeof in);
    for (int u = 0; u < 3; u++) {
        in[u].unit = 40 + u;
        in[u].fit_status = u == 1;
        in[u].fit_iterations = 7 * u;
        in[u].gross_val = u;
        for (int i = 0; i < l.nd; i++)
            in[u].dev[i] = 0.1 * (i + 1) / 3.0 + u;
        for (int i = 0; i < l.np; i++)
            in[u].par[i] = -(double)i / 7.0;
        in[u].fit_rms = 4.9406564584124654e-324;
        for (int a = 0; a < l.na; a++)
            for (int b = 0; b < l.nb; b++) {
                in[u].rms_before[a][b] = 1.0 / 3.0 + a + b;
                in[u].rms_after[a][b] = u == 1 ? NAN : -0.0;
                in[u].rms_after_sys[a][b] = 1e300 * (a + 1);
            }
    }
    char path[512], err[SUNMC_ERRLEN];
    snprintf(path, sizeof path, "%s/rt.bin", dir);
    FILE *f = fopen(path, "wb");
    assert_int_equal(unitfile_write_header(f, &l, err, sizeof err), SUNMC_OK);
    assert_int_equal(unitfile_write(f, &l, in, 3, err, sizeof err), SUNMC_OK);
    fclose(f);
    f = fopen(path, "rb");
    long got = 0;
    assert_int_equal(unitfile_read_header(f, path, &l, err, sizeof err), SUNMC_OK);
    assert_int_equal(unitfile_read(f, path, &l, back, 3, &got, err, sizeof err), SUNMC_OK);
    assert_int_equal(got, 3);
    assert_memory_equal(in, back, sizeof in);
    fclose(f);
    /* another layout (the ESS's) is refused with both named */
    sunmc_config e = test_family_config("ess");
    unitfile_layout le;
    unitfile_layout_of(&e, &le);
    f = fopen(path, "rb");
    assert_int_equal(unitfile_read_header(f, path, &le, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "this config's have"));
    fclose(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(three_shards_merge_to_the_whole_run),
        cmocka_unit_test(merges_that_are_not_one_run_are_refused),
        cmocka_unit_test(shard_option_errors),
        cmocka_unit_test(units_file_round_trip),
        cmocka_unit_test(shards_with_temperatures_merge_to_the_whole_run),
    };
    return cmocka_run_group_tests_name("shards", tests, setup, NULL);
}
