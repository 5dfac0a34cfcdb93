/* test_isa.c - issue 22, rule 3: the build and the CPU path are part of a
 * result's identity.  manifest.ini records the kernel path chosen at run
 * time (kernel_isa) and the build; merge and --resume refuse a mix, naming
 * both; --isa / SUNMC_ISA refuse a path this binary does not take.  When a
 * baseline build is at hand (SUNMC_BASELINE, from `make BUILD=build/base
 * KERNEL_ISA=baseline`), both paths' results agree to 1e-7 relative. */
#include "test_util.h"

#include "unitfile.h"
#include "vmath.h"

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
        !strstr(out, "KERNEL_ISA=baseline"))
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

static void test_isa_option(void **state)
{
    char out[16384], args[512];
    const char *other = strcmp(vm_isa(), "avx2") == 0 ? "baseline" : "avx2";
    snprintf(args, sizeof args, "run " E " --units 2 " TINY " --isa %s", vm_isa());
    assert_int_equal(sunmc(args, out, sizeof out), 0);
    snprintf(args, sizeof args, "run " E " --units 2 " TINY " --isa %s", other);
    assert_int_equal(sunmc(args, out, sizeof out), 2);
    if (!strstr(out, "runs the") || !strstr(out, vm_isa()))
        fail_msg("%s", out);
    snprintf(args, sizeof args, "SUNMC_ISA=%s %s run " E " --units 2 " TINY, other, test_sunmc());
    assert_int_equal(test_run(args, out, sizeof out), 2);
    assert_int_equal(sunmc("run " E " --units 2 --isa sse9", out, sizeof out), 2);
    assert_non_null(strstr(out, "one of baseline, avx2"));
}

/* Both paths agree to 1e-7 relative on every number of units.tsv (they
 * differ in the last bits only); needs a baseline build (SUNMC_BASELINE). */
static void test_paths_agree(void **state)
{
    const char *base = getenv("SUNMC_BASELINE");
    if (!base || access(base, X_OK) != 0) {
        fprintf(stderr, "test_paths_agree: SUNMC_BASELINE not set; skipped\n");
        skip();
    }
    char out[16384], cmd[4096];
    assert_int_equal(sunmc("run " E " --units 8 " TINY " --out $D/pa", out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "D=%s; %s run " E " --units 8 " TINY " --out $D/pb", dir, base);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd,
             "paste %s/pa/units.tsv %s/pb/units.tsv | awk -F'\\t' 'NR > 1 { n = NF / 2; "
             "for (i = 1; i <= n; i++) { a = $i; b = $(i + n); if (a == b) continue; "
             "if (a + 0 != a || b + 0 != b) { print \"text differs: \" a \" \" b; exit 1 } "
             "d = a - b; if (d < 0) d = -d; s = (a < 0 ? -a : a) + 1e-300; "
             "if (d / s > m) m = d / s } } END { printf \"max rel %%.3g\\n\", m; "
             "exit m > 1e-7 }'",
             dir, dir);
    int rc = test_run(cmd, out, sizeof out);
    fprintf(stderr, "test_paths_agree: %s", out);
    assert_int_equal(rc, 0);
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
