/* test_design_pareto.c - `design`'s Pareto front at equal yields (issue 29):
 * design.tsv's pareto column against the front recomputed from its hours
 * and yield columns (a candidate is off the front if another, not aliased,
 * costs no more and yields no less, one of them strictly, or is the same on
 * both and listed first), on spaces whose yields tie at 0, in between and
 * at 100 %. */
#include "test_tsv.h"

#define SPACE                                                                                     \
    "--set campaign.alpha_step_deg=0.2 --space steps_deg=0.5,0.3,0.2 --space max_lines=3 "       \
    "--space beta_step_deg=30 --space beta_max_deg=30 --space repeats=1 --space screen_units=12 " \
    "--space max_units=24 --space shortlist=3 --set run.block_units=12 "                         \
    "--set validation.alpha_step_deg=1.3 --set report.yield_target=0.5 --quiet"

/* Runs the design at spec (arcsec); the ties seen: equal-yield pairs, and
 * front members dearer than another front member. */
static void check_front(const char *spec, int *ties, int *dearer_on_front)
{
    char cmd[4096], out[16384], name[64];
    snprintf(name, sizeof name, "pareto_%s", spec);
    const char *d = test_tmp(name);
    snprintf(cmd, sizeof cmd, "%s design configs/ess_type_a.ini " SPACE
                              " --set report.spec_arcsec=%s --out %s",
             test_sunmc(), spec, d);
    /* exit 1 when no candidate passes; the table is written either way */
    int st = test_run(cmd, out, sizeof out);
    if (st != 0 && st != 1)
        fail_msg("%s: exit %d\n%s", cmd, st, out);
    snprintf(cmd, sizeof cmd, "%s/design.tsv", d);
    tsv *t = tsv_load(cmd);
    assert_true(t->nr >= 4);
    int on_front = 0;
    for (int i = 0; i < t->nr; i++) {
        int aliased_i = strcmp(tsv_str(t, i, "verdict"), "aliased") == 0;
        double hi = tsv_num(t, i, "hours"), yi = tsv_num(t, i, "yield");
        int want = !aliased_i && isfinite(yi);
        for (int j = 0; want && j < t->nr; j++) {
            double hj = tsv_num(t, j, "hours"), yj = tsv_num(t, j, "yield");
            if (j == i || strcmp(tsv_str(t, j, "verdict"), "aliased") == 0 || !isfinite(yj))
                continue;
            if (hj <= hi && yj >= yi && (hj < hi || yj > yi || j < i))
                want = 0;
        }
        for (int j = 0; j < i; j++)
            *ties += !aliased_i && strcmp(tsv_str(t, j, "verdict"), "aliased") != 0 &&
                     tsv_num(t, j, "yield") == yi;
        int got = (int)tsv_num(t, i, "pareto");
        if (got != want)
            fail_msg("spec %s: row %d (%s, %g h, yield %g) pareto %d, recomputed %d", spec, i + 1,
                     tsv_str(t, i, "candidate"), hi, yi, got, want);
        if (got) {
            *dearer_on_front += on_front > 0;
            on_front++;
        }
        /* listed by hours, then yield down */
        if (i > 0)
            assert_true(tsv_num(t, i - 1, "hours") <= hi);
    }
    assert_true(on_front >= 1);
    tsv_free(t);
}

static void front_at_equal_yields(void **state)
{
    int ties = 0, dearer = 0;
    /* every yield 0: the cheapest trusted candidate alone */
    check_front("20", &ties, &dearer);
    assert_int_equal(dearer, 0);
    /* ties in between and at 100 %, and dearer candidates that yield more */
    check_front("30", &ties, &dearer);
    check_front("35", &ties, &dearer);
    assert_true(ties >= 3);
    assert_true(dearer >= 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(front_at_equal_yields),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
