/* test_unitsum_checksum.c - issue 22, rule 7: checkpoint records and units.bin
 * carry checksums (unitsum.h).  A flipped bit in a committed checkpoint
 * block or in a shard's units.bin is refused on --resume and on merge (exit
 * 2, naming the file and the units); an edited checksum list is refused
 * with FILE:LINE; untouched runs resume and merge to the whole run's files
 * byte for byte (test_resume, test_shards, test_golden hold the rest).
 * A merged config.ini of part of a run states the merged units, and
 * running it reproduces the merge. */
#include "test_util.h"

#include "params_io.h"
#include "unitsum.h"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[128];

#define RUN "run configs/ess_type_a.ini --quiet --set campaign.alpha_step_deg=0.4 " \
            "--set validation.alpha_step_deg=0.7 --set campaign.beta_deg=-15,15 "    \
            "--units 600 --set run.block_units=32"

static int setup(void **state)
{
    (void)state;
    return test_private_dir(dir, sizeof dir, "checksum");
}

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static void sh(const char *fmt, const char *arg)
{
    char cmd[2048], full[2300], out[4096];
    snprintf(cmd, sizeof cmd, fmt, arg);
    snprintf(full, sizeof full, "cd %s && %s", dir, cmd);
    if (test_run(full, out, sizeof out) != 0)
        fail_msg("%s: %s", full, out);
}

/* Flip bit 2 of byte `at` of file rel (under dir). */
static void flip(const char *rel, long at)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, rel);
    FILE *f = fopen(path, "r+b");
    assert_non_null(f);
    assert_int_equal(fseek(f, at, SEEK_SET), 0);
    int c = fgetc(f);
    assert_int_not_equal(c, EOF);
    assert_int_equal(fseek(f, at, SEEK_SET), 0);
    fputc(c ^ 4, f);
    assert_int_equal(fclose(f), 0);
}

static long file_size(const char *rel)
{
    char path[512];
    struct stat sb;
    snprintf(path, sizeof path, "%s/%s", dir, rel);
    return stat(path, &sb) == 0 ? (long)sb.st_size : -1;
}

static void expect(int status, const char *out, const char *needle)
{
    assert_int_equal(status, 2);
    if (!strstr(out, needle))
        fail_msg("'%s' lacks '%s'", out, needle);
}

/* ---- the checksum tree ---- */

static void node_is_hash_of_its_two_children(void **state)
{
    (void)state;
    unitsum_acc a;
    unitsum_init(&a, 1);
    unsigned long long rec[70];
    for (int i = 0; i < 70; i++) {
        rec[i] = 1000u + (unsigned)i;
        assert_int_equal(unitsum_add(&a, &rec[i], sizeof rec[i]), SUNMC_OK);
    }
    long n;
    const unsigned long long *leaf = unitsum_leaves(&a, &n);
    assert_int_equal(n, 70);
    assert_true(leaf[3] == params_fnv1a64(PARAMS_FNV1A64_INIT, &rec[3], 8));
    unsigned long long l[70];
    memcpy(l, leaf, sizeof l);
    unsigned long long out[UNITSUM_MAX];
    int nout;
    long node_units;
    unitsum_finish(&a, out, &nout, &node_units);
    /* 70 leaves > 32: 35 nodes of 2 > 32: 18 nodes of 4, the last of 2 units */
    assert_int_equal(nout, 18);
    assert_int_equal(node_units, 4);
    unsigned long long p01[2] = {l[0], l[1]}, p23[2] = {l[2], l[3]}, p6869[2] = {l[68], l[69]};
    unsigned long long q[2] = {params_fnv1a64(PARAMS_FNV1A64_INIT, p01, 16),
                               params_fnv1a64(PARAMS_FNV1A64_INIT, p23, 16)};
    assert_true(out[0] == params_fnv1a64(PARAMS_FNV1A64_INIT, q, 16));
    /* the last node has no right child: its left child's hash carries up */
    assert_true(out[17] == params_fnv1a64(PARAMS_FNV1A64_INIT, p6869, 16));
    unitsum_free(&a);
}

static void thirty_two_leaves_stay_leaves(void **state)
{
    (void)state;
    unitsum_acc a;
    unitsum_init(&a, 8);
    unsigned long long r = 7;
    for (int i = 0; i < 32 * 8; i++)
        unitsum_add(&a, &r, sizeof r);
    unsigned long long out[UNITSUM_MAX];
    int nout;
    long node_units;
    unitsum_finish(&a, out, &nout, &node_units);
    assert_int_equal(nout, 32);
    assert_int_equal(node_units, 8);
    unitsum_free(&a);
    unitsum_init(&a, 8);
    for (int i = 0; i < 32 * 8 + 1; i++)
        unitsum_add(&a, &r, sizeof r);
    unitsum_finish(&a, out, &nout, &node_units);
    assert_int_equal(nout, 17); /* 33 leaves: one level up */
    assert_int_equal(node_units, 16);
    unitsum_free(&a);
}

/* ---- merge: a flipped bit in a shard's units.bin ---- */

static void make_shards(void)
{
    static int done;
    if (done++)
        return;
    char out[8192];
    assert_int_equal(sunmc(RUN " --out $D/whole", out, sizeof out), 0);
    assert_int_equal(sunmc(RUN " --units 0:300 --out $D/s0", out, sizeof out), 0);
    assert_int_equal(sunmc(RUN " --units 300:600 --out $D/s1", out, sizeof out), 0);
}

static void flipped_bit_in_a_shard_is_refused_on_merge(void **state)
{
    (void)state;
    make_shards();
    char out[8192];
    long rec = (file_size("s1/units.bin") - 64) / 300;
    sh("cp -r s1 f1", "");
    /* unit 300 + 100 = 400: in the node 364:428 (nodes of 64 from 300) */
    flip("f1/units.bin", 64 + 100 * rec + 8 * 9);
    expect(sunmc("merge $D/m $D/s0 $D/f1", out, sizeof out), out,
           "f1/units.bin: the records of units 364:428 do not match their checksum in ");
    assert_non_null(strstr(out, "f1/manifest.ini"));
    assert_int_equal(file_size("m"), -1); /* nothing written */
    /* the last unit's last byte */
    sh("rm -rf f1 && cp -r s1 f1", "");
    flip("f1/units.bin", file_size("f1/units.bin") - 1);
    expect(sunmc("merge $D/m $D/s0 $D/f1", out, sizeof out), out, "units 556:600 do not match");
    /* the header's spare word */
    sh("rm -rf f1 && cp -r s1 f1", "");
    flip("f1/units.bin", 7 * 8);
    expect(sunmc("merge $D/m $D/s0 $D/f1", out, sizeof out), out, "header word 8 is not zero");
    /* an edited checksum, a malformed list, a list of another split */
    sh("rm -rf f1 && cp -r s1 f1 && sed -i 's/^units_fnv1a64 = ./units_fnv1a64 = f/;"
       "s/^units_fnv1a64 = ff/units_fnv1a64 = 0f/' f1/manifest.ini", "");
    expect(sunmc("merge $D/m $D/s0 $D/f1", out, sizeof out), out, "units 300:364 do not match");
    sh("rm -rf f1 && cp -r s1 f1 && sed -i 's/^units_fnv1a64 = .*/units_fnv1a64 = 12 zz/' "
       "f1/manifest.ini", "");
    expect(sunmc("merge $D/m $D/s0 $D/f1", out, sizeof out), out,
           "f1/manifest.ini:14: units_fnv1a64 = 12 zz: not a list of at most 32 hashes");
    sh("rm -rf f1 && cp -r s1 f1 && sed -i 's/^units_sum_units = 64/units_sum_units = 128/' "
       "f1/manifest.ini", "");
    expect(sunmc("merge $D/m $D/s0 $D/f1", out, sizeof out), out, "do not fit the 5 of 128 units");
    sh("rm -rf f1 && cp -r s1 f1 && sed -i 's/^units_sum_units = 64/units_sum_units = 0/' "
       "f1/manifest.ini", "");
    expect(sunmc("merge $D/m $D/s0 $D/f1", out, sizeof out), out,
           "units_sum_units = 0: must be at least 1");
    /* untouched: the whole run's files, manifest and checksums included */
    assert_int_equal(sunmc("merge $D/m $D/s0 $D/s1", out, sizeof out), 0);
    sh("cmp whole/manifest.ini m/manifest.ini && cmp whole/units.bin m/units.bin", "");
    sh("grep -q '^units_sum_units = 64$' m/manifest.ini", "");
}

/* ---- issue 22: a merged config.ini states the merged units ---- */

static void merged_config_states_its_units_and_reproduces(void **state)
{
    (void)state;
    make_shards();
    char out[16384];
    assert_int_equal(sunmc("merge $D/m0 $D/s0", out, sizeof out), 0);
    assert_true(test_file_has(test_tmp("checksum/m0/config.ini"),
                              "\nunits = 300  # sunmc merge of units 0:300 (the shards' "
                              "run.units: 600)\n"));
    assert_int_equal(sunmc("run $D/m0/config.ini --quiet --out $D/r0", out, sizeof out), 0);
    sh("cmp m0/units.bin r0/units.bin && cmp m0/summary.tsv r0/summary.tsv && "
       "cmp m0/manifest.ini r0/manifest.ini", "");
    assert_int_equal(sunmc("merge $D/m1 $D/s1", out, sizeof out), 0);
    assert_true(test_file_has(test_tmp("checksum/m1/config.ini"),
                              "\nunits = 600  # sunmc merge of units 300:600: run it with "
                              "--units 300:600\n"));
    assert_int_equal(sunmc("run $D/m1/config.ini --units 300:600 --quiet --out $D/r1", out,
                           sizeof out), 0);
    sh("cmp m1/units.bin r1/units.bin && cmp m1/summary.tsv r1/summary.tsv", "");
    /* the shards of the whole run keep its units line; a merge of merges says 0:600 */
    sh("cmp whole/config.ini m/config.ini || (diff whole/config.ini m/config.ini; false)", "");
    assert_int_equal(sunmc("merge $D/mm $D/m0 $D/s1", out, sizeof out), 0);
    assert_true(test_file_has(test_tmp("checksum/mm/config.ini"),
                              "\nunits = 600  # sunmc merge of units 0:600"));
    sh("cmp whole/summary.tsv mm/summary.tsv && cmp whole/units.bin mm/units.bin", "");
}

/* ---- resume: a flipped bit in a committed checkpoint block ---- */

static long committed(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/.%s.resume/progress", dir, name);
    FILE *f = fopen(path, "r");
    long k = -1;
    if (f) {
        if (fscanf(f, "units_done %ld", &k) != 1)
            k = -1;
        fclose(f);
    }
    return k;
}

static long killed_at(const char *name, long units)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "exec %s " RUN " --threads 1 --out %s/%s", test_sunmc(), dir, name);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    long k = -1;
    for (int i = 0; i < 20000 && (k = committed(name)) < units; i++)
        usleep(2000);
    kill(pid, SIGKILL);
    int st;
    waitpid(pid, &st, 0);
    if (k < units || k >= 600)
        fail_msg("the run was not caught part-way (%ld units committed)", k);
    return k;
}

static void flipped_bit_in_a_checkpoint_is_refused_on_resume(void **state)
{
    (void)state;
    make_shards();
    char out[16384];
    long k = killed_at("ck", 96);
    long rec = (file_size("whole/units.bin") - 64) / 600;
    sh("cp -r .ck.resume keep", "");
    flip(".ck.resume/units.bin", 64 + 40 * rec + 8 * 8); /* unit 40: block 32:64 */
    expect(sunmc(RUN " --out $D/ck --resume", out, sizeof out), out,
           ".ck.resume/units.bin: the records of units 32:64 do not match their checksum in ");
    assert_non_null(strstr(out, ".ck.resume/units.sum"));
    assert_non_null(strstr(out, "to start over"));
    assert_int_equal(committed("ck"), k); /* kept as it was */
    /* a flipped checksum, and a units.sum short of a line */
    sh("rm -rf .ck.resume && cp -r keep .ck.resume", "");
    flip(".ck.resume/units.sum", 17 * 2 + 3);
    expect(sunmc(RUN " --out $D/ck --resume", out, sizeof out), out, "units 64:96 do not match");
    sh("rm -rf .ck.resume && cp -r keep .ck.resume && sed -i '$d' .ck.resume/units.sum", "");
    expect(sunmc(RUN " --out $D/ck --resume", out, sizeof out), out, "block checksums its progress");
    sh("rm .ck.resume/units.sum", "");
    expect(sunmc(RUN " --out $D/ck --resume", out, sizeof out), out, "block checksums its progress");
    /* untouched: resumes to the whole run, byte for byte */
    sh("rm -rf .ck.resume && cp -r keep .ck.resume", "");
    assert_int_equal(sunmc(RUN " --out $D/ck --resume", out, sizeof out), 0);
    for (int i = 0; i < 4; i++) {
        static const char *const f[] = {"units.bin", "manifest.ini", "units.tsv", "summary.tsv"};
        char c[256];
        snprintf(c, sizeof c, "cmp whole/%s ck/%s", f[i], f[i]);
        sh("%s", c);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(node_is_hash_of_its_two_children),
        cmocka_unit_test(thirty_two_leaves_stay_leaves),
        cmocka_unit_test(flipped_bit_in_a_shard_is_refused_on_merge),
        cmocka_unit_test(merged_config_states_its_units_and_reproduces),
        cmocka_unit_test(flipped_bit_in_a_checkpoint_is_refused_on_resume),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
