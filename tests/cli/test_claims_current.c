/* test_claims_current.c - docs/claims.md cannot go stale (issue 40): the
 * table `make claims` writes from the code under test equals the committed
 * page byte for byte, so a change that moves any number of a row, or breaks
 * a row's reason (scripts/claims.sh then exits 1), fails here; and the
 * Table 1 script of the paper's protocol (scripts/paper-table1.sh) groups
 * its units by twenty and refuses fewer. */
#include "test_util.h"

/* Regenerated into a temporary folder, the table is the committed one. */
static void claims_table_is_current(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd, "SUNMC=%s CLAIMS_RUNS=%s bash scripts/claims.sh %s", test_sunmc(),
             test_tmp("runs"), test_tmp("claims.md"));
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s exited %d: %s", cmd, rc, out);
    snprintf(cmd, sizeof cmd, "diff docs/claims.md %s | head -20", test_tmp("claims.md"));
    test_run(cmd, out, sizeof out);
    if (out[0])
        fail_msg("docs/claims.md is stale (run `make claims`):\n%s", out);
    /* every row's command wrote its folder where CLAIMS_RUNS says, none in runs/ */
    snprintf(cmd, sizeof cmd, "test -s %s/a_run/units.tsv", test_tmp("runs"));
    assert_int_equal(system(cmd), 0);
}

/* 40 units are two groups of twenty: every cell has two groups; 19 units
 * are refused with exit 2 before anything runs. */
static void table1_groups_by_twenty(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd, "SUNMC=%s bash scripts/paper-table1.sh 40 %s", test_sunmc(),
             test_tmp("t1"));
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s exited %d: %s", cmd, rc, out);
    int rows = 0;
    for (char *line = strtok(out, "\n"); line; line = strtok(NULL, "\n")) {
        if (rows++ == 0) {
            assert_string_equal(line, "type\trange\tcell\tpaper\tmedian\tp5\tp95\tgroups\t"
                                      "fit_failures\tpaper_in_range");
            continue;
        }
        char ty[8], rg[8], cell[32], in[8];
        double paper, med, lo, hi;
        int groups, failures;
        assert_int_equal(sscanf(line, "%7s %7s %31s %lf %lf %lf %lf %d %d %7s", ty, rg, cell, &paper,
                                &med, &lo, &hi, &groups, &failures, in), 10);
        assert_int_equal(groups, 2);
        assert_true(lo <= med && med <= hi);
        assert_string_equal(in, (paper >= lo && paper <= hi) ? "yes" : "no");
    }
    assert_int_equal(rows, 1 + 2 * 3 * 5); /* two types, three ranges, five cells */
    snprintf(cmd, sizeof cmd, "SUNMC=%s bash scripts/paper-table1.sh 19 %s", test_sunmc(),
             test_tmp("t19"));
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    snprintf(cmd, sizeof cmd, "test -e %s", test_tmp("t19"));
    assert_int_not_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(claims_table_is_current),
        cmocka_unit_test(table1_groups_by_twenty),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
