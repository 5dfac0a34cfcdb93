/* test_study_minimum.c - issue 36, rule 5: studies refuse what they cannot
 * estimate.  budget of a config whose units cannot be fitted printed nan
 * rows and "0 with a fit in every run" with exit 0; budget --units 1 marked
 * [nan, nan] intervals "~"; sensitivity --units 2 printed ST = 2.449
 * [2.449, 127.683].  Now each needs STUDY_MIN_UNITS units (with a fit in
 * every run), refuses below with the count, and flags indices outside
 * 0..1. */
#include "test_util.h"

#include "report.h"

static char dir[512];

/* A fast ESS: one beta line, a coarse validation grid. */
#define E "configs/ess_type_a.ini --set validation.alpha_step_deg=2.3 --set campaign.beta_deg=0"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "studymin");
}

static void expect(const char *args, int rc_want, const char *text)
{
    char out[1 << 16];
    int rc = sunmc(args, out, sizeof out);
    if (rc != rc_want || (text && !strstr(out, text)))
        fail_msg("%s: exit %d (expected %d with '%s'): %.3000s", args, rc, rc_want,
                 text ? text : "", out);
}

static int exists(const char *name)
{
    char p[700];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    struct stat sb;
    return stat(p, &sb) == 0;
}

/* The limit on both sides, for every study that takes --units. */
static void test_units_limit(void **state)
{
    assert_int_equal(STUDY_MIN_UNITS, 10);
    expect("budget " E " --units 9 --quiet --out $D/b9", 2, "budget needs at least 10 units, not 9");
    expect("budget " E " --units 1 --quiet --out $D/b1", 2, "needs at least 10 units, not 1");
    expect("sensitivity " E " --units 9 --quiet --out $D/s9", 2,
           "sensitivity needs at least 10 units, not 9");
    expect("sensitivity " E " --units 2 --quiet --out $D/s2", 2, "at least 10 units, not 2");
    expect("allocate " E " --units 9 --quiet --out $D/a9", 2, "allocate needs at least 10 units");
    assert_false(exists("b9") || exists("b1") || exists("s9") || exists("s2") || exists("a9"));
    expect("budget " E " --units 10 --quiet --set report.budget_units=10 "
           "--set report.budget_steps=1 --out $D/b10",
           0, "10 units per run (10 with a fit in every run)");
    expect("sensitivity " E " --units 10 --quiet --out $D/s10", 0,
           "N = 10 units (10 with a fit in every run)");
    assert_true(exists("b10/budget.tsv") && exists("s10/sensitivity.tsv"));
}

/* Units that cannot be fitted: "not enough units", not a table of nan. */
static void test_unfitted_units_refused(void **state)
{
    expect("budget configs/psd_kenscl.ini --units 20 --quiet --out $D/ken", 1,
           "only 0 of 20 units have a fit in every run");
    expect("budget configs/psd_kenscl.ini --units 20 --quiet --out $D/ken", 1, "not enough units");
    assert_false(exists("ken"));
}

/* An index outside 0..1 is marked ! and named in a warning; none is
 * marked when every index lies inside. */
static void test_index_outside_flagged(void **state)
{
    char out[1 << 16];
    assert_int_equal(sunmc("sensitivity configs/psd.ini --units 10 --quiet", out, sizeof out), 0);
    const char *w = strstr(out, "WARNING: ");
    assert_non_null(w);
    int n = atoi(w + strlen("WARNING: "));
    int marks = 0;
    for (const char *p = out; (p = strchr(p, '!')) != NULL && p < w; p++)
        marks++;
    assert_true(n >= 1);
    assert_int_equal(marks, n);
    assert_non_null(strstr(out, "outside 0..1 (marked !)"));
    /* every index printed outside 0..1 carries !, and none inside does:
     * each "V [LO, HI]" of the table, V before the bracket */
    int outside = 0;
    for (const char *p = strstr(out, "| "); p && p < w; p = strchr(p + 1, '[')) {
        const char *close = strchr(p, ']');
        if (*p != '[' || !close || close > w)
            continue;
        const char *b = p;
        while (b > out && b[-1] == ' ')
            b--;
        while (b > out && b[-1] != ' ')
            b--;
        double v = atof(b);
        int out_of_range = v < -5e-4 || v > 1 + 5e-4;
        outside += out_of_range;
        if (out_of_range != (close[1] == '!'))
            fail_msg("%.40s: outside 0..1 = %d, marked = %d", b, out_of_range, close[1] == '!');
    }
    assert_int_equal(outside, n);
    /* every index that carries ! prints outside 0..1 */
    for (const char *p = out; (p = strchr(p, '!')) != NULL && p < w; p++) {
        const char *b = p;
        while (b > out && *b != '[')
            b--;
        while (b > out && b[-1] == ' ')
            b--;
        while (b > out && b[-1] != ' ')
            b--;
        double v = atof(b);
        if (!(v < -5e-4 || v > 1 + 5e-4))
            fail_msg("%.30s marked but inside 0..1", b);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_units_limit),
        cmocka_unit_test(test_unfitted_units_refused),
        cmocka_unit_test(test_index_outside_flagged),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
