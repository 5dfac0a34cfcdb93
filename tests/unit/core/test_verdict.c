/* test_verdict.c - issue 37: one verdict, the spec as customers write it.
 * A unit with known errors at known points passes or fails each statistic
 * (rms, p99.7, max) and band rule as worked out by hand here; coverage loss
 * fails; the order statistic of a finite grid against its definition. */
#include "test_util.h"

#include "bands.h"
#include "report.h"
#include "verdict.h"

/* The DSS (three angles) with bands 0:20, 20:40, 0:60 and spec 10". */
static void build(config_state *st, const char *const *sets, int n)
{
    test_build(st, "configs/dss.ini", sets, n);
}

/* A unit whose every band read all of its 10 points with statistic stat
 * (arcsec) for every angle. */
static void unit_all(unit_result *r, double stat)
{
    memset(r, 0, sizeof *r);
    for (int b = 0; b < CONFIG_BANDS_MAX; b++) {
        r->points[b] = 10;
        for (int a = 0; a < UNIT_MAX_ANGLES; a++) {
            r->rms_after[a][b] = r->stat_after[a][b] = stat;
            r->read_after[a][b] = 10;
        }
    }
}

/* ---- the order statistic of a band's points ---- */

/* |errors| 1..n in a shuffled order; the nearest-rank p99.7 and the max. */
static double tail_of(long n, double level, int keep)
{
    band_tail t;
    band_tail_reset(&t, keep);
    for (long i = 0; i < n; i++) {
        double e = (double)((i * 7919) % n + 1); /* 7919 is prime: a permutation */
        band_tail_add_mask(&t, 2, 1u, e * e);
    }
    return band_tail_quantile(&t, 0, n, level);
}

static void test_order_statistic_by_hand(void **state)
{
    (void)state;
    /* max: the largest of any n */
    assert_near(tail_of(1, 1.0, 1), 1, 0);
    assert_near(tail_of(97, 1.0, 1), 97, 0);
    /* p99.7: the ceil(0.9973 n)-th smallest; the largest up to 370 points */
    assert_near(tail_of(10, VERDICT_P997_LEVEL, BAND_TAIL_MAX), 10, 0);
    assert_near(tail_of(370, VERDICT_P997_LEVEL, BAND_TAIL_MAX), 370, 0);  /* 369.001 -> 370 */
    assert_near(tail_of(371, VERDICT_P997_LEVEL, BAND_TAIL_MAX), 370, 0);  /* 369.998 -> 370 */
    assert_near(tail_of(1000, VERDICT_P997_LEVEL, BAND_TAIL_MAX), 998, 0); /* 997.3 -> 998 */
    /* 0.9973 x 10000 is 9973 whole: the 9973rd smallest */
    assert_near(tail_of(10000, VERDICT_P997_LEVEL, BAND_TAIL_MAX), 9973, 0);
    /* past what the tail keeps: NaN, never a smaller order statistic */
    assert_true(isnan(tail_of(30000, VERDICT_P997_LEVEL, BAND_TAIL_MAX)));
    assert_true(isnan(tail_of(5, 1.0, 0)));
    band_tail t;
    band_tail_reset(&t, 1);
    assert_true(isnan(band_tail_quantile(&t, 0, 0, 1.0)));
}

/* Bands of the mask only; NaN errors are skipped; equal errors kept. */
static void test_tail_masks(void **state)
{
    (void)state;
    band_tail t;
    band_tail_reset(&t, 3);
    const unsigned m[] = {1u, 2u, 3u, 0u, 1u};
    const double e2[] = {4, 9, 1, 100, NAN};
    band_tail_add_chunk(&t, 2, 5, m, e2);
    assert_near(band_tail_quantile(&t, 0, 2, 1.0), 2, 0); /* band 0: 4, 1 */
    assert_near(band_tail_quantile(&t, 1, 2, 1.0), 3, 0); /* band 1: 9, 1 */
    assert_near(band_tail_quantile(&t, 0, 2, 0.5), 1, 0); /* the smaller of the two */
    band_tail_reset(&t, 2);
    const unsigned m2[] = {1u, 1u, 1u};
    const double e22[] = {4, 4, 1};
    band_tail_add_chunk(&t, 1, 3, m2, e22);
    assert_near(band_tail_quantile(&t, 0, 3, 0.5), 2, 0); /* rank 2 of 1, 2, 2: 2 */
    long n[2] = {0, 0};
    band_count_chunk(n, 2, 5, m);
    assert_int_equal(n[0], 3);
    assert_int_equal(n[1], 2);
}

/* ---- the rule ---- */

static void test_rms_every_band(void **state)
{
    (void)state;
    config_state st;
    build(&st, NULL, 0);
    const sunmc_config *c = &st.cfg;
    unit_result r;
    verdict v;
    unit_all(&r, 9.99);
    verdict_unit(c, &r, 2, VERDICT_LAB, &v);
    assert_true(v.pass);
    assert_int_equal(v.why, VERDICT_PASS);
    assert_near(v.coverage, 1.0, 0);
    unit_all(&r, 10.0); /* at the spec: meets it */
    verdict_unit(c, &r, 2, VERDICT_LAB, &v);
    assert_true(v.pass);
    /* one band over: fails there, whatever the others */
    r.stat_after[2][1] = 10.01;
    verdict_unit(c, &r, 2, VERDICT_LAB, &v);
    assert_false(v.pass);
    assert_int_equal(v.why, VERDICT_OVER_SPEC);
    assert_int_equal(v.band, 1);
    assert_near(v.stat, 10.01, 0);
    /* the other angles are their own */
    verdict_unit(c, &r, 0, VERDICT_LAB, &v);
    assert_true(v.pass);
    /* passing: the band closest to the spec decides */
    unit_all(&r, 5);
    r.stat_after[2][2] = 7;
    verdict_unit(c, &r, 2, VERDICT_LAB, &v);
    assert_true(v.pass);
    assert_int_equal(v.band, 2);
    assert_near(v.stat, 7, 0);
    /* a band alone */
    r.stat_after[2][0] = 11;
    verdict_band(c, &r, 2, 1, VERDICT_LAB, &v);
    assert_true(v.pass);
    verdict_band(c, &r, 2, 0, VERDICT_LAB, &v);
    assert_false(v.pass);
    config_state_free(&st);
}

/* Coverage: every point by default; report.min_coverage on both sides. */
static void test_coverage(void **state)
{
    (void)state;
    config_state st;
    build(&st, NULL, 0);
    unit_result r;
    verdict v;
    unit_all(&r, 1);
    r.read_after[2][1] = 9; /* one of 10 points of 20:40 unread */
    verdict_unit(&st.cfg, &r, 2, VERDICT_LAB, &v);
    assert_false(v.pass);
    assert_int_equal(v.why, VERDICT_COVERAGE);
    assert_int_equal(v.band, 1);
    assert_near(v.coverage, 0.9, 1e-15);
    config_state_free(&st);
    const char *at[] = {"report.min_coverage=0.9"};
    build(&st, at, 1);
    verdict_unit(&st.cfg, &r, 2, VERDICT_LAB, &v);
    assert_true(v.pass);
    config_state_free(&st);
    const char *past[] = {"report.min_coverage=0.9001"};
    build(&st, past, 1);
    verdict_unit(&st.cfg, &r, 2, VERDICT_LAB, &v);
    assert_false(v.pass);
    config_state_free(&st);
    /* nothing read fails even at min_coverage 0 */
    const char *none[] = {"report.min_coverage=0"};
    build(&st, none, 1);
    r.read_after[2][1] = 0;
    r.stat_after[2][1] = NAN;
    verdict_unit(&st.cfg, &r, 2, VERDICT_LAB, &v);
    assert_false(v.pass);
    assert_int_equal(v.why, VERDICT_COVERAGE);
    config_state_free(&st);
}

/* report.spec_bands: only the named bands; a band not in the list refused. */
static void test_named_bands(void **state)
{
    (void)state;
    config_state st;
    const char *one[] = {"report.spec_bands=0:20,  0:60"};
    build(&st, one, 1);
    assert_int_equal(verdict_band_mask(&st.cfg), 5u);
    unit_result r;
    verdict v;
    unit_all(&r, 1);
    r.stat_after[2][1] = 99;  /* 20:40 is not the spec's */
    r.read_after[2][1] = 0;
    verdict_unit(&st.cfg, &r, 2, VERDICT_LAB, &v);
    assert_true(v.pass);
    r.stat_after[2][2] = 10.5;
    verdict_unit(&st.cfg, &r, 2, VERDICT_LAB, &v);
    assert_false(v.pass);
    assert_int_equal(v.band, 2);
    config_state_free(&st);
    build(&st, NULL, 0);
    assert_int_equal(verdict_band_mask(&st.cfg), 7u); /* all */
    config_state_free(&st);
    const char *bad[] = {"report.spec_bands=0:21", "report.spec_bands=0:20,", "report.spec_bands=20",
                         "report.spec_bands=0:20:40", "report.spec_bands=al"};
    for (int i = 0; i < 5; i++) {
        char err[SUNMC_ERRLEN];
        assert_int_equal(config_build(&st, "configs/dss.ini", &bad[i], 1, err, sizeof err),
                         SUNMC_EINPUT);
        assert_non_null(strstr(err, "report.spec_bands"));
    }
    /* the longest value: 63 characters of a valid list */
    char set[128], list[64];
    snprintf(list, sizeof list, "0:20,%*s0:60", 63 - 9, "");
    assert_int_equal(strlen(list), 63);
    snprintf(set, sizeof set, "report.spec_bands=%s", list);
    const char *longest[] = {set};
    build(&st, longest, 1);
    assert_int_equal(verdict_band_mask(&st.cfg), 5u);
    config_state_free(&st);
}

/* No fit: fails, no band; at temperatures the worst decides. */
static void test_fit_and_temperatures(void **state)
{
    (void)state;
    config_state st;
    build(&st, NULL, 0);
    unit_result r;
    verdict v;
    unit_all(&r, 1);
    r.fit_status = UNIT_FIT_FAILED;
    verdict_unit(&st.cfg, &r, 2, VERDICT_LAB, &v);
    assert_false(v.pass);
    assert_int_equal(v.why, VERDICT_NO_FIT);
    assert_int_equal(v.band, -1);
    config_state_free(&st);
    const char *temps[] = {"environment.operating_temp_c=-30,60"};
    build(&st, temps, 1);
    unit_all(&r, 1);
    for (int t = 0; t < 2; t++)
        for (int b = 0; b < 3; b++) {
            r.stat_after_t[t][2][b] = t == 1 && b == 2 ? 12 : 3;
            r.read_after_t[t][2][b] = 10;
        }
    verdict_unit(&st.cfg, &r, 2, VERDICT_LAB, &v);
    assert_true(v.pass);
    verdict_unit(&st.cfg, &r, 2, 0, &v);
    assert_true(v.pass);
    verdict_unit(&st.cfg, &r, 2, 1, &v);
    assert_false(v.pass);
    verdict_unit(&st.cfg, &r, 2, VERDICT_WORST, &v);
    assert_false(v.pass);
    assert_int_equal(v.band, 2);
    assert_near(v.stat, 12, 0);
    assert_false(verdict_pass(&st.cfg, &r));
    r.stat_after_t[1][2][2] = 4;
    verdict_unit(&st.cfg, &r, 2, VERDICT_WORST, &v);
    assert_true(v.pass);
    assert_near(v.stat, 4, 0); /* the temperature closest to the spec */
    r.read_after_t[0][2][0] = 5;
    verdict_band(&st.cfg, &r, 2, 0, VERDICT_WORST, &v);
    assert_false(v.pass);
    assert_int_equal(v.why, VERDICT_COVERAGE);
    config_state_free(&st);
}

/* The rule as every table states it; the names. */
static void test_rule_text(void **state)
{
    (void)state;
    config_state st;
    const char *sets[] = {"report.spec_statistic=p99.7", "report.spec_bands=0:20, 20:40",
                          "report.min_coverage=0.95", "report.spec_arcsec=20"};
    build(&st, sets, 4);
    char t[256];
    verdict_rule_text(&st.cfg, t, sizeof t);
    assert_string_equal(t, "p99.7 of |total| <= 20\" in each named band (0:20, 20:40), at least "
                           "95 % of the points read");
    config_state_free(&st);
    build(&st, NULL, 0);
    verdict_rule_text(&st.cfg, t, sizeof t);
    assert_string_equal(t, "rms of |total| <= 10\" in every band (0:20, 20:40, 0:60), every "
                           "point read");
    assert_int_equal(verdict_angle(&st.cfg), 2);
    assert_int_equal(verdict_tail_keep(&st.cfg), 0);
    config_state_free(&st);
    const char *mx[] = {"report.spec_statistic=max"};
    build(&st, mx, 1);
    assert_int_equal(verdict_tail_keep(&st.cfg), 1);
    assert_near(verdict_level(&st.cfg), 1.0, 0);
    config_state_free(&st);
    assert_string_equal(verdict_why_name(VERDICT_COVERAGE), "coverage");
    assert_string_equal(verdict_why_name(VERDICT_OVER_SPEC), "over_spec");
    assert_string_equal(verdict_why_name(VERDICT_NO_FIT), "no_fit");
    assert_string_equal(verdict_why_name(VERDICT_PASS), "pass");
}

/* The report's spec yield counts the verdict; a band row's yield the band
 * alone (hand-made units). */
static void test_report_counts_the_verdict(void **state)
{
    (void)state;
    config_state st;
    build(&st, NULL, 0);
    enum { N = 4 };
    unit_result r[N];
    for (int u = 0; u < N; u++) {
        unit_all(&r[u], 1);
        r[u].unit = u;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                r[u].rms_before[a][b] = 50;
    }
    r[1].stat_after[2][0] = 20;  /* over in 0:20 */
    r[2].read_after[2][1] = 8;   /* blind in part of 20:40 */
    summary_row rows[3 * 3];
    assert_int_equal(report_summarize(&st.cfg, r, N, rows), SUNMC_OK);
    const summary_row *t0 = &rows[2 * 3 + 0], *t1 = &rows[2 * 3 + 1], *t2 = &rows[2 * 3 + 2];
    assert_near(t0->spec_yield, 0.5, 0);
    assert_near(t1->spec_yield, 0.5, 0);
    assert_near(t0->yield, 0.75, 0);
    assert_near(t1->yield, 0.75, 0);
    assert_near(t2->yield, 1.0, 0);
    assert_near(rows[0].spec_yield, 1.0, 0); /* alpha: every unit meets it */
    assert_true(t0->spec_yield_ci.lo < 0.5 && t0->spec_yield_ci.hi > 0.5);
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_order_statistic_by_hand),
        cmocka_unit_test(test_tail_masks),
        cmocka_unit_test(test_rms_every_band),
        cmocka_unit_test(test_coverage),
        cmocka_unit_test(test_named_bands),
        cmocka_unit_test(test_fit_and_temperatures),
        cmocka_unit_test(test_rule_text),
        cmocka_unit_test(test_report_counts_the_verdict),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
