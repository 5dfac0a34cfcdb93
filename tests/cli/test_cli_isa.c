/* test_cli_isa.c - issue 22, rule 3: the build and the CPU path are part of a
 * result's identity.  manifest.ini records the kernel path chosen at run
 * time (kernel_isa) and the build; merge and --resume refuse a mix, naming
 * both; --isa baseline / SUNMC_ISA=baseline force the baseline (by running
 * sunmc-baseline, built beside sunmc) and both paths' results agree to
 * 1e-7 relative; a path the binary cannot run is refused. */
#include "test_util.h"

#include "unitfile.h"
#include "vmath.h"

#include <math.h>
#include <stdint.h>
#include <unistd.h>

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "isa");
}

#define E "configs/ess_type_a.ini"
#define TINY "--set campaign.alpha_step_deg=2 --set validation.alpha_step_deg=5 " \
             "--set campaign.beta_deg=-15,15 --quiet"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

/* Replace "key = old value" in a manifest by "key = value". */
static void set_manifest(const char *rel, const char *key, const char *value)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "sed -i 's|^%s = .*|%s = %s|' %s/%s", key, key, value, dir, rel);
    assert_int_equal(system(cmd), 0);
}

static void test_manifest_records_path_and_build(void **state)
{
    char out[16384], want[256];
    assert_int_equal(sunmc("run " E " --units 2 " TINY " --out $D/m", out, sizeof out), 0);
    snprintf(want, sizeof want, "kernel_isa = %s\n", vm_isa());
    assert_true(test_file_has(test_tmp("isa/m/manifest.ini"), want));
    snprintf(want, sizeof want, "build = %s\n", vm_build_id());
    assert_true(test_file_has(test_tmp("isa/m/manifest.ini"), want));
    assert_true(strcmp(vm_isa(), "avx2") == 0 || strcmp(vm_isa(), "baseline") == 0);
}

/* The reproducer: a shard from each CPU merged with exit 0 and a
 * --resume across them was accepted. */
static void test_mixed_paths_refused(void **state)
{
    char out[16384];
    const char *other = strcmp(vm_isa(), "avx2") == 0 ? "baseline" : "avx2";
    assert_int_equal(sunmc("run " E " --units 4 --shard 0/2 " TINY " --out $D/s0", out, sizeof out),
                     0);
    assert_int_equal(sunmc("run " E " --units 4 --shard 1/2 " TINY " --out $D/s1", out, sizeof out),
                     0);
    set_manifest("s1/manifest.ini", "kernel_isa", other);
    assert_int_equal(sunmc("merge $D/m $D/s0 $D/s1", out, sizeof out), 2);
    if (!strstr(out, "kernel_isa") || !strstr(out, vm_isa()) || !strstr(out, other) ||
        !strstr(out, "--isa baseline"))
        fail_msg("%s", out);
    set_manifest("s1/manifest.ini", "kernel_isa", vm_isa());
    set_manifest("s1/manifest.ini", "build", "cc 1.0, -O0");
    assert_int_equal(sunmc("merge $D/m $D/s0 $D/s1", out, sizeof out), 2);
    if (!strstr(out, "different builds") || !strstr(out, "cc 1.0, -O0"))
        fail_msg("%s", out);
    /* --resume of a checkpoint written on the other path */
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "mkdir -p %s/.r.resume && cp %s/s0/manifest.ini %s/.r.resume/ && "
             "printf 'units_done 0\\nblock_units 256\\n' > %s/.r.resume/progress && "
             "cp %s/s0/units.bin %s/.r.resume/units.bin",
             dir, dir, dir, dir, dir, dir);
    assert_int_equal(system(cmd), 0);
    set_manifest(".r.resume/manifest.ini", "kernel_isa", other);
    assert_int_equal(sunmc("run " E " --units 4 --shard 0/2 " TINY " --resume --out $D/r", out,
                           sizeof out),
                     2);
    if (!strstr(out, "kernel_isa") || !strstr(out, other))
        fail_msg("%s", out);
    /* a manifest of the older format (no kernel_isa) is refused, said so */
    set_manifest("s1/manifest.ini", "format", "1");
    assert_int_equal(sunmc("merge $D/m $D/s0 $D/s1", out, sizeof out), 2);
    if (!strstr(out, "manifest format 1"))
        fail_msg("%s", out);
}

/* sunmc-baseline beside the binary under test, or NULL (the ASan build
 * has none: only its refusal is tested there). */
static const char *baseline_binary(void)
{
    static char path[600];
    const char *self = test_sunmc(), *slash = strrchr(self, '/');
    snprintf(path, sizeof path, "%.*s/sunmc-baseline", slash ? (int)(slash - self) : 1,
             slash ? self : ".");
    return access(path, X_OK) == 0 ? path : NULL;
}

/* --isa / SUNMC_ISA force the path: baseline runs sunmc-baseline (the
 * kernels built for the baseline only) on any CPU, recorded in the
 * manifest; avx2 where the binary cannot run it is refused. */
static void test_isa_option(void **state)
{
    char out[16384], args[2048];
    snprintf(args, sizeof args, "run " E " --units 2 " TINY " --isa %s", vm_isa());
    assert_int_equal(sunmc(args, out, sizeof out), 0);
    assert_int_equal(sunmc("run " E " --units 2 --isa sse9", out, sizeof out), 2);
    assert_non_null(strstr(out, "one of baseline, avx2"));
    if (strcmp(vm_isa(), "avx2") != 0) {
        assert_int_equal(sunmc("run " E " --units 2 " TINY " --isa avx2", out, sizeof out), 2);
        if (!strstr(out, "runs the baseline"))
            fail_msg("%s", out);
    }
    /* a binary without sunmc-baseline beside it says so, exit 2 */
    snprintf(args, sizeof args, "mkdir -p %s/alone && cp %s %s/alone/sunmc && %s/alone/sunmc run "
             E " --units 2 " TINY " --isa baseline", dir, test_sunmc(), dir, dir);
    assert_int_equal(test_run(args, out, sizeof out), vm_forced_baseline() ? 0 : 2);
    if (!vm_forced_baseline() && !strstr(out, "alone/sunmc-baseline is missing"))
        fail_msg("%s", out);
    const char *base = baseline_binary();
    if (!base) {
        fprintf(stderr, "test_isa_option: no sunmc-baseline beside %s; forced runs skipped\n",
                test_sunmc());
        return;
    }
    const char *forms[] = {"--isa baseline", "--isa=baseline", "SUNMC_ISA"};
    for (int i = 0; i < 3; i++) {
        snprintf(args, sizeof args, "D=%s; %s %s run " E " --units 2 " TINY " %s --out $D/f%d",
                 dir, i == 2 ? "SUNMC_ISA=baseline" : "", test_sunmc(), i == 2 ? "" : forms[i],
                 i);
        assert_int_equal(test_run(args, out, sizeof out), 0);
        char rel[64];
        snprintf(rel, sizeof rel, "isa/f%d/manifest.ini", i);
        assert_true(test_file_has(test_tmp(rel), "kernel_isa = baseline\n"));
        assert_true(test_file_has(test_tmp(rel), " kernels baseline\n"));
    }
    /* sunmc-baseline itself cannot run the AVX2 clones */
    snprintf(args, sizeof args, "%s run " E " --units 2 " TINY " --isa avx2", base);
    assert_int_equal(test_run(args, out, sizeof out), 2);
    if (!strstr(out, "runs the baseline"))
        fail_msg("%s", out);
}

/* The largest relative difference of the doubles of two units.bin files of
 * one layout (*differ: how many differ at all). */
static double max_rel_bin(const char *a, const char *b, long *differ)
{
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    assert_non_null(fa);
    assert_non_null(fb);
    uint64_t ha[UNITFILE_HEADER_WORDS], hb[UNITFILE_HEADER_WORDS], wa, wb;
    assert_int_equal(fread(ha, sizeof ha, 1, fa), 1);
    assert_int_equal(fread(hb, sizeof hb, 1, fb), 1);
    assert_memory_equal(ha, hb, sizeof ha);
    double m = 0;
    *differ = 0;
    for (uint64_t k = 0; fread(&wa, 8, 1, fa) == 1; k++) {
        assert_int_equal(fread(&wb, 8, 1, fb), 1);
        if (k % ha[2] < UNITFILE_INT_WORDS) {
            assert_true(wa == wb); /* unit, fit status, counts: the same */
            continue;
        }
        double x, y;
        memcpy(&x, &wa, 8);
        memcpy(&y, &wb, 8);
        if (wa == wb)
            continue;
        (*differ)++;
        double r = fabs(x - y) / fmax(fabs(x), 1e-300);
        m = isnan(r) ? INFINITY : fmax(m, r);
    }
    fclose(fa);
    fclose(fb);
    return m;
}

/* Both paths agree to 1e-7 relative on every number of units.tsv (they
 * differ in the last bits only): the default path against --isa baseline.
 * Shards forced to the baseline merge into the forced whole run, byte for
 * byte; a forced shard and a default one (on an AVX2 CPU) are refused. */
static void test_paths_agree(void **state)
{
    if (!baseline_binary()) {
        fprintf(stderr, "test_paths_agree: no sunmc-baseline; skipped\n");
        skip();
    }
    char out[16384], cmd[4096];
    assert_int_equal(sunmc("run " E " --units 8 " TINY " --out $D/pa", out, sizeof out), 0);
    assert_int_equal(sunmc("run " E " --units 8 " TINY " --isa baseline --out $D/pb", out,
                           sizeof out), 0);
    snprintf(cmd, sizeof cmd,
             "paste %s/pa/units.tsv %s/pb/units.tsv | awk -F'\\t' 'NR > 1 { n = NF / 2; "
             "for (i = 1; i <= n; i++) { a = $i; b = $(i + n); if (a == b) continue; "
             "if (a + 0 != a || b + 0 != b) { print \"text differs: \" a \" \" b; exit 1 } "
             "d = a - b; if (d < 0) d = -d; s = (a < 0 ? -a : a) + 1e-300; "
             "if (d / s > m) m = d / s } } END { printf \"max rel %%.3g\\n\", m; "
             "exit m > 1e-7 }'",
             dir, dir);
    int rc = test_run(cmd, out, sizeof out);
    fprintf(stderr, "test_paths_agree: units.tsv %s", out);
    assert_int_equal(rc, 0);
    /* every double of units.bin within 1e-8 relative (measured: 1.1e-10
     * ESS, 6.1e-10 DSS over 40 units); on an AVX2 CPU some do differ, so
     * the path was switched indeed */
    long differ = 0;
    char pa[600], pb[600];
    snprintf(pa, sizeof pa, "%s/pa/units.bin", dir);
    snprintf(pb, sizeof pb, "%s/pb/units.bin", dir);
    double m = max_rel_bin(pa, pb, &differ);
    fprintf(stderr, "test_paths_agree: units.bin %ld doubles differ, max rel %.3g\n", differ, m);
    assert_true(m <= 1e-8);
    if (strcmp(vm_isa(), "avx2") == 0)
        assert_true(differ > 0);
    assert_int_equal(sunmc("run " E " --units 8 " TINY " --isa baseline --units 0:5 --out $D/q0",
                           out, sizeof out), 0);
    assert_int_equal(sunmc("run " E " --units 8 " TINY " --isa baseline --units 5:8 --out $D/q1",
                           out, sizeof out), 0);
    assert_int_equal(sunmc("merge $D/qm $D/q0 $D/q1", out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "cd %s && cmp pb/units.bin qm/units.bin && cmp pb/manifest.ini "
             "qm/manifest.ini && cmp pb/summary.tsv qm/summary.tsv", dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    if (strcmp(vm_isa(), "avx2") == 0) {
        assert_int_equal(sunmc("run " E " --units 8 " TINY " --units 5:8 --out $D/d1", out,
                               sizeof out), 0);
        assert_int_equal(sunmc("merge $D/qx $D/q0 $D/d1", out, sizeof out), 2);
        if (!strstr(out, "kernel_isa baseline against avx2"))
            fail_msg("%s", out);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_manifest_records_path_and_build),
        cmocka_unit_test(test_mixed_paths_refused),
        cmocka_unit_test(test_isa_option),
        cmocka_unit_test(test_paths_agree),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
