/* test_shards_bounds.c - `run --shard K/N` and `merge` at their edges
 * (issue 29): the N parts tile the units for every N <= 16 over unit counts
 * N does not divide, each unit in the shard an independent per-unit formula
 * gives; N = units accepted, N = units + 1 refused; merge refuses a gap or an
 * overlap of exactly one unit, naming those units, and merges the adjacent
 * parts; 10 units in 4 shards merge to the whole run. */
#include "test_util.h"

#include "cli.h"

#include <sys/stat.h>

static char dir[128];

#define TINY "run configs/ess_type_a.ini --quiet --set campaign.alpha_step_deg=1.1 " \
             "--set validation.alpha_step_deg=2.3 --set campaign.beta_deg=0"

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "shards_bounds");
}

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static void run_ok(const char *args)
{
    char out[8192];
    int st = sunmc(args, out, sizeof out);
    if (st != 0)
        fail_msg("sunmc %s: exit %d\n%s", args, st, out);
}

/* The shard of unit u when N shards split U units with the start of shard
 * k at floor(k U / N): u is in shard k iff k U < (u + 1) N <= (k + 1) U, so
 * k = ceil((u + 1) N / U) - 1, worked out unit by unit. */
static long shard_of_unit(long u, long n, long units)
{
    return ((u + 1) * n + units - 1) / units - 1;
}

static void shards_tile_every_split(void **state)
{
    static const long counts[] = {1,  2,  3,  5,  7,   10,   11,   13,   16,     17,     31,
                                  33, 97, 100, 101, 1000, 1001, 4097, 65537, 1000003};
    for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
        long units = counts[c];
        for (long n = 1; n <= 16 && n <= units; n++) {
            long prev_end = 0, min_size = units, max_size = 0;
            for (long k = 0; k < n; k++) {
                long first = -1, end = -1;
                cli_shard_units(k, n, units, &first, &end);
                if (first != prev_end)
                    fail_msg("%ld units, shard %ld/%ld starts at %ld, the one before ends at %ld",
                             units, k, n, first, prev_end);
                long size = end - first;
                min_size = size < min_size ? size : min_size;
                max_size = size > max_size ? size : max_size;
                /* each unit of the shard, and the units just outside it */
                for (long u = first; u < end; u++)
                    if (shard_of_unit(u, n, units) != k)
                        fail_msg("%ld units in %ld shards: unit %ld in shard %ld, not %ld", units,
                                 n, u, k, shard_of_unit(u, n, units));
                prev_end = end;
            }
            if (prev_end != units)
                fail_msg("%ld units in %ld shards end at %ld", units, n, prev_end);
            /* near-equal: sizes units/N or units/N + 1, none empty */
            assert_true(min_size >= 1);
            assert_true(max_size - min_size <= 1);
            assert_int_equal(min_size, units / n);
        }
    }
    /* The example: 10 units in 4 shards are 0:2 2:5 5:7 7:10. */
    const long want[5] = {0, 2, 5, 7, 10};
    for (long k = 0; k < 4; k++) {
        long first, end;
        cli_shard_units(k, 4, 10, &first, &end);
        assert_int_equal(first, want[k]);
        assert_int_equal(end, want[k + 1]);
    }
}

/* N = units: one unit each, accepted; N = units + 1 refused. */
static void shard_count_at_the_unit_count(void **state)
{
    char out[8192];
    run_ok(TINY " --units 10 --shard 9/10 --out $D/last");
    char path[512];
    snprintf(path, sizeof path, "%s/last/manifest.ini", dir);
    assert_true(test_file_has(path, "first_unit = 9\nend_unit = 10\n"));
    assert_int_equal(sunmc(TINY " --units 10 --shard 0/11 --out $D/no", out, sizeof out), 2);
    assert_non_null(strstr(out, "--shard 0/11: more shards than the 10 units"));
}

static int exists(const char *name)
{
    char path[512];
    struct stat sb;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &sb) == 0;
}

static void refused(const char *args, const char *needle)
{
    char out[8192];
    int st = sunmc(args, out, sizeof out);
    if (st != 2 || !strstr(out, needle))
        fail_msg("%s: exit %d (want 2), message lacks '%s':\n%s", args, st, needle, out);
    assert_false(exists("refused"));
}

/* Parts one unit apart, one unit over, exactly adjacent, one inside another. */
static void merge_one_unit_gap_and_overlap(void **state)
{
    run_ok(TINY " --units 0:3 --out $D/a");
    run_ok(TINY " --units 4:6 --out $D/gap");
    run_ok(TINY " --units 2:6 --out $D/over");
    run_ok(TINY " --units 3:6 --out $D/next");
    run_ok(TINY " --units 1:2 --out $D/inside");
    refused("merge $D/refused $D/a $D/gap", "units 3:4 are missing: ");
    refused("merge $D/refused $D/gap $D/a", "ends at 3, ");
    refused("merge $D/refused $D/a $D/over", "units 2:3 are in both ");
    refused("merge $D/refused $D/a $D/inside", "units 1:2 are in both ");
    char out[8192];
    assert_int_equal(sunmc("merge $D/m $D/next $D/a", out, sizeof out), 0);
    assert_non_null(strstr(out, "merged units 0:6 from 2 shards"));
}

static int same_file(const char *a, const char *b)
{
    char cmd[1024], out[256];
    snprintf(cmd, sizeof cmd, "cmp %s/%s %s/%s", dir, a, dir, b);
    return test_run(cmd, out, sizeof out) == 0;
}

/* 10 units in 4 shards (sizes 2 3 2 3) merge to the whole run. */
static void uneven_shards_merge_to_the_whole_run(void **state)
{
    char args[1024], out[8192];
    run_ok(TINY " --units 10 --out $D/whole10");
    for (int k = 0; k < 4; k++) {
        snprintf(args, sizeof args, TINY " --units 10 --shard %d/4 --out $D/q%d", k, k);
        run_ok(args);
    }
    char path[512];
    snprintf(path, sizeof path, "%s/q1/manifest.ini", dir);
    assert_true(test_file_has(path, "first_unit = 2\nend_unit = 5\n"));
    assert_int_equal(sunmc("merge $D/m10 $D/q3 $D/q1 $D/q0 $D/q2", out, sizeof out), 0);
    assert_non_null(strstr(out, "merged units 0:10 from 4 shards"));
    assert_true(same_file("whole10/summary.tsv", "m10/summary.tsv"));
    assert_true(same_file("whole10/units.tsv", "m10/units.tsv"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(shards_tile_every_split),
        cmocka_unit_test(shard_count_at_the_unit_count),
        cmocka_unit_test(merge_one_unit_gap_and_overlap),
        cmocka_unit_test(uneven_shards_merge_to_the_whole_run),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
