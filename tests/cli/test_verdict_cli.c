/* test_verdict_cli.c - issue 37 end to end: a unit blind over part of its
 * field fails, in every band that holds the blind part; the studies' yield
 * is run's under the same rule and never above run's worst band; inverse
 * limits end where the spot leaves the detector. */
#include "test_util.h"
#include "test_tsv.h"

static char dir[512];

#define OWN "docs/examples/dss_own.ini"
#define BLIND " --set tolerance.dx_px=690 --set tolerance.dx_px_dist=fixed"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "verdictcli");
}

static tsv *load(const char *name)
{
    char p[700];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return tsv_load(p);
}

static void ok(const char *args)
{
    char out[1 << 16];
    int rc = sunmc(args, out, sizeof out);
    if (rc != 0)
        fail_msg("%s: exit %d: %.3000s", args, rc, out);
}

/* dx_px 690 px (fixed): no unit reads a point below 25 deg.  Every unit
 * fails for coverage, also in a 0:50 band that averages the blind half
 * away and with the band's own RMS well inside the spec. */
static void test_blind_unit_fails(void **state)
{
    ok("run " OWN BLIND " --units 20 --quiet --set report.spec_arcsec=30 "
       "--set report.bands_deg=0:25,25:50,0:50 --out $D/blind");
    tsv *u = load("blind/units.tsv");
    assert_int_equal(u->nr, 20);
    for (int r = 0; r < u->nr; r++) {
        assert_string_equal(tsv_str(u, r, "pass"), "0");
        assert_string_equal(tsv_str(u, r, "verdict"), "coverage");
        assert_string_equal(tsv_str(u, r, "verdict_band"), "0:25");
        assert_near(tsv_num(u, r, "verdict_coverage"), 0, 0);
    }
    tsv_free(u);
    tsv *s = load("blind/summary.tsv");
    for (int r = 0; r < s->nr; r++) {
        assert_near(tsv_num(s, r, "spec_yield"), 0, 0);
        assert_near(tsv_num(s, r, "yield"), 0, 0); /* each band alone too */
    }
    tsv_free(s);
    /* judged on 0:50 alone: its points below 25 deg are not read */
    ok("run " OWN BLIND " --units 20 --quiet --set report.spec_arcsec=30 "
       "--set report.bands_deg=0:25,25:50,0:50 --set report.spec_bands=0:50 --out $D/blind50");
    s = load("blind50/summary.tsv");
    for (int r = 0; r < s->nr; r++)
        assert_near(tsv_num(s, r, "spec_yield"), 0, 0);
    tsv_free(s);
    /* with coverage waived, the same units pass on the points they see */
    ok("run " OWN BLIND " --units 20 --quiet --set report.spec_arcsec=30 "
       "--set report.bands_deg=0:25,25:50,0:50 --set report.spec_bands=0:50 "
       "--set report.min_coverage=0 --out $D/blind0");
    s = load("blind0/summary.tsv");
    assert_near(tsv_num(s, s->nr - 1, "spec_yield"), 1, 0);
    tsv_free(s);
}

/* The spec yield is at most every band's yield, and the budget's is run's. */
static void test_study_yield_is_runs(void **state)
{
    const char *sets = " --units 10 --seed 5 --quiet --set report.spec_arcsec=30";
    char args[1024];
    snprintf(args, sizeof args, "run " OWN "%s --out $D/r", sets);
    ok(args);
    snprintf(args, sizeof args,
             "budget " OWN "%s --set report.budget_units=10 --set report.budget_steps=1 "
             "--out $D/b",
             sets);
    ok(args);
    tsv *s = load("r/summary.tsv"), *b = load("b/budget.tsv");
    double spec = NAN, worst = 1;
    for (int r = 0; r < s->nr; r++)
        if (strcmp(tsv_str(s, r, "angle"), "total") == 0) {
            spec = tsv_num(s, r, "spec_yield");
            worst = fmin(worst, tsv_num(s, r, "yield"));
        }
    assert_true(spec <= worst);
    assert_true(spec > 0 && spec < 1); /* something to compare */
    assert_near(tsv_num(b, 0, "all_yield"), spec, 1e-6);
    tsv_free(s);
    tsv_free(b);
}

/* No inverse limit past the detector: a spot off the 1024 px detector is
 * not read, so dx_px and dy_px end at coverage below the half width. */
static void test_limits_end_at_the_field(void **state)
{
    ok("budget " OWN " --units 10 --quiet --set report.budget_units=20 --set report.budget_steps=3 "
       "--set report.spec_arcsec=60 --set report.yield_target=0.9 --out $D/lim");
    tsv *b = load("lim/budget.tsv");
    int seen = 0;
    for (int r = 1; r < b->nr - 1; r++) {
        const char *src = tsv_str(b, r, "source");
        if (strcmp(src, "dx_px") != 0 && strcmp(src, "dy_px") != 0)
            continue;
        seen++;
        double lim = tsv_num(b, r, "limit");
        if (!(lim < 512))
            fail_msg("%s limit %g px: past the 512 px half detector", src, lim);
        assert_string_equal(tsv_str(b, r, "limit_end"), "coverage");
    }
    assert_int_equal(seen, 2);
    tsv_free(b);
}

/* design's yields are the verdict's: the input campaign's candidate has
 * run's spec yield (the same units), far below the 25:50 band's yield
 * alone that the widest band would have given. */
static void test_design_judges_the_spec(void **state)
{
    const char *sets = " --units 20 --quiet --set report.spec_arcsec=25";
    char args[512];
    snprintf(args, sizeof args, "run " OWN "%s --out $D/dr", sets);
    ok(args);
    snprintf(args, sizeof args,
             "design " OWN "%s --set campaign.search_steps_deg=5,10 --out $D/dd > /dev/null; "
             "test $? -le 1",
             sets);
    ok(args);
    tsv *s = load("dr/summary.tsv"), *d = load("dd/design.tsv");
    double spec = NAN, band = NAN;
    for (int r = 0; r < s->nr; r++)
        if (strcmp(tsv_str(s, r, "angle"), "total") == 0) {
            spec = tsv_num(s, r, "spec_yield");
            if (strcmp(tsv_str(s, r, "band"), "25:50") == 0)
                band = tsv_num(s, r, "yield");
        }
    assert_true(band >= spec + 0.3); /* the two rules differ here */
    int found = 0;
    for (int r = 0; r < d->nr; r++)
        if (strcmp(tsv_str(d, r, "input"), "1") == 0) {
            assert_near(tsv_num(d, r, "yield"), spec, 1e-6);
            found = 1;
        }
    assert_true(found);
    tsv_free(s);
    tsv_free(d);
}

/* The order statistics of a real run, against what they must be: over a
 * band of n points the max lies between the RMS and sqrt(n) times it, and
 * p99.7 on fewer than 371 points is the max. */
static void test_max_and_p997_of_a_run(void **state)
{
    const char *base = "run configs/dss.ini --units 6 --quiet --set report.spec_bands=0:20 "
                       "--set report.spec_arcsec=3600";
    char args[512];
    snprintf(args, sizeof args, "%s --set report.spec_statistic=max --out $D/mx", base);
    ok(args);
    snprintf(args, sizeof args, "%s --set report.spec_statistic=p99.7 --out $D/pq", base);
    ok(args);
    tsv *m = load("mx/units.tsv"), *q = load("pq/units.tsv"), *s = load("mx/summary.tsv");
    double n = tsv_num(s, 0, "band_points");
    assert_true(n > 10 && n < 371);
    for (int r = 0; r < m->nr; r++) {
        assert_string_equal(tsv_str(m, r, "verdict_band"), "0:20");
        double mx = tsv_num(m, r, "verdict_stat_arcsec");
        double rms = tsv_num(m, r, "rms_after_total_0_20_arcsec");
        if (!(rms <= mx * (1 + 1e-5) && mx <= sqrt(n) * rms * (1 + 1e-5)))
            fail_msg("unit %d: max %g, rms %g over %g points", r, mx, rms, n);
        assert_near(tsv_num(q, r, "verdict_stat_arcsec"), mx, 1e-6 * mx);
    }
    tsv_free(m);
    tsv_free(q);
    tsv_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blind_unit_fails),
        cmocka_unit_test(test_study_yield_is_runs),
        cmocka_unit_test(test_limits_end_at_the_field),
        cmocka_unit_test(test_max_and_p997_of_a_run),
        cmocka_unit_test(test_design_judges_the_spec),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
