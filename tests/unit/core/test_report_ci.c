/* test_report_ci.c - the report's confidence intervals and the systematic
 * part of the after RMS: on hand-made unit results against values worked
 * out here (t table, Wilson's closed form, order-statistic ranks by hand),
 * the summary.tsv columns, Table 1's compact form; then end to end, the
 * coverage of the intervals over independent runs against a large run and
 * their 1/sqrt(N) shrink. */
#include "test_util.h"

#include "report.h"
#include "summary_print.h"
#include "status.h"

static const char *const fake_angles[] = {"alpha"};

static int fake_n_angles(const sunmc_config *c) { return 1; }

static void fake_label(const sunmc_config *c, char *buf, size_t len)
{
    snprintf(buf, len, "fake model");
}

static int fake_none(const sunmc_config *c, const char **names, int max) { return 0; }

static const sensor_family fake = {
    .name = "fake",
    .rms_unit = "deg",
    .arcsec_per_rms_unit = 3600.0,
    .model_label = fake_label,
    .n_angles = fake_n_angles,
    .angle_names = fake_angles,
    .dev_columns = fake_none,
    .par_columns = fake_none,
};

#define NU 9
#define SPEC_DEG (54.0 / 3600.0)
#define T975_DF5 2.570582 /* t table: 0.975 quantile, 5 degrees of freedom */
#define Z975 1.959963984540054

static void make_config(sunmc_config *c)
{
    memset(c, 0, sizeof *c);
    c->family = &fake;
    snprintf(c->product, sizeof c->product, "Test");
    c->spec_arcsec = 54.0;
    c->confidence = 0.95;
    c->bands_deg.n = 1;
    c->bands_deg.hi[0] = 60;
}

/* Units 0-8: unit 3's fit failed, unit 6 has no value, unit 8 no noise-free
 * value; 4 of the 9 meet the spec (0.010, 0.015, 0.005, 0.011). */
static const double bef[NU] = {0.20, 0.30, 0.25, 0.40, 0.10, 0.50, NAN, 0.22, 0.30};
static const double aft[NU] = {0.010, SPEC_DEG, 0.0151, NAN, 0.020, 0.005, NAN, 0.011, 0.016};
static const double sys[NU] = {0.008, 0.012, 0.011, NAN, 0.015, 0.004, NAN, 0.009, NAN};

static void make_results(unit_result *r)
{
    memset(r, 0, NU * sizeof *r);
    for (int u = 0; u < NU; u++) {
        r[u].unit = u;
        r[u].rms_before[0][0] = bef[u];
        r[u].rms_after[0][0] = aft[u];
        r[u].rms_after_sys[0][0] = sys[u];
    }
    r[3].fit_status = UNIT_FIT_FAILED;
    test_read_all(r, NU);
}

/* Header and data row `row` (1 = first) of the TSV in f into h[] and v[]
 * (pointing into hl and vl); returns the number of columns, -1 if short. */
static int read_row(FILE *f, int row, char *hl, char *vl, size_t len, char **h, char **v)
{
    if (!fgets(hl, (int)len, f))
        return -1;
    for (int i = 0; i < row; i++)
        if (!fgets(vl, (int)len, f))
            return -1;
    hl[strcspn(hl, "\n")] = vl[strcspn(vl, "\n")] = '\0';
    int nh = 0, nv = 0;
    char *save;
    for (char *t = strtok_r(hl, "\t", &save); t && nh < 64; t = strtok_r(NULL, "\t", &save))
        h[nh++] = t;
    for (char *t = strtok_r(vl, "\t", &save); t && nv < 64; t = strtok_r(NULL, "\t", &save))
        v[nv++] = t;
    return nh == nv ? nh : -1;
}

/* Mean and the t half-width of v[n] (two-pass, here). */
static void mean_half(const double *v, int n, double t, double *m, double *h)
{
    double s = 0, ss = 0;
    for (int i = 0; i < n; i++)
        s += v[i];
    *m = s / n;
    for (int i = 0; i < n; i++)
        ss += (v[i] - *m) * (v[i] - *m);
    *h = t * sqrt(ss / (n - 1)) / sqrt((double)n);
}

/* The hand-made run, summarized (group fixture). */
static sunmc_config c;
static unit_result res[NU];
static summary_row r;

static int summarize(void **state)
{
    make_config(&c);
    make_results(res);
    return report_summarize(&c, res, NU, &r) == SUNMC_OK ? 0 : -1;
}

static void hand_made_intervals(void **state)
{
    /* Units 0, 1, 2, 4, 5, 7, 8 count (3 failed, 6 has no value): k = 7,
     * 6 degrees of freedom. */
    assert_int_equal(r.stat_units, 7);
    assert_near(r.confidence, 0.95, 0);
    const double a7[7] = {0.010, SPEC_DEG, 0.0151, 0.020, 0.005, 0.011, 0.016};
    double m, h;
    mean_half(a7, 7, 2.446912 /* t 0.975, 6 df */, &m, &h);
    assert_near(r.rms_after_mean, m, 1e-15);
    assert_near(r.rms_after_mean_ci.lo, m - h, 1e-6 * h); /* table t to 7 digits */
    assert_near(r.rms_after_mean_ci.hi, m + h, 1e-6 * h);
    const double b7[7] = {0.20, 0.30, 0.25, 0.10, 0.50, 0.22, 0.30};
    mean_half(b7, 7, 2.446912, &m, &h);
    assert_near(r.rms_before_mean_ci.lo, m - h, 1e-6 * h);
    double ratio[7];
    for (int i = 0; i < 7; i++)
        ratio[i] = b7[i] / a7[i];
    mean_half(ratio, 7, 2.446912, &m, &h);
    assert_near(r.improvement_mean, m, 1e-12);
    assert_near(r.improvement_mean_ci.hi, m + h, 1e-6 * h);
    /* Systematic part: units 0, 1, 2, 4, 5, 7 (8 has none): 6 values. */
    const double s6[6] = {0.008, 0.012, 0.011, 0.015, 0.004, 0.009};
    mean_half(s6, 6, T975_DF5, &m, &h);
    assert_near(r.rms_after_sys_mean, m, 1e-15);
    assert_near(r.rms_after_sys_mean_ci.lo, m - h, 1e-6 * h);
    assert_near(r.rms_after_sys_mean_ci.hi, m + h, 1e-6 * h);
    /* Yield 4 of 9 (failures count as failing), Wilson's closed form. */
    double p = 4.0 / 9, z2n = Z975 * Z975 / 9;
    double centre = (p + z2n / 2) / (1 + z2n);
    double half = Z975 / (1 + z2n) * sqrt(p * (1 - p) / 9 + z2n / 36);
    assert_near(r.yield, p, 1e-15);
    assert_near(r.yield_ci.lo, centre - half, 1e-12);
    assert_near(r.yield_ci.hi, centre + half, 1e-12);
    /* p95 of 7 sorted values 0.005 0.010 0.011 0.015 0.0151 0.016 0.020;
     * K ~ Bin(7, 0.95): P(K <= 5) = 0.0444 > 0.025 >= P(K <= 4) = 0.0038,
     * so the lower rank is 5 (0.0151); P(K <= 6) = 0.302 < 0.975: no upper
     * bound.  The estimate: h = 6 * 0.95 = 5.7, 0.016 + 0.7 * 0.004. */
    assert_near(r.rms_after_p95, 0.016 + 0.7 * 0.004, 1e-15);
    assert_near(r.rms_after_p95_ci.lo, 0.0151, 0);
    assert_true(isnan(r.rms_after_p95_ci.hi));
    assert_true(r.rms_after_p95_ci.lo <= r.rms_after_p95);
}

/* A larger sample: the p95 interval's ranks worked out here (n = 100:
 * ranks 90 and 100); a constant sample's t interval has zero width. */
static void p95_ranks_at_100(void **state)
{
    static unit_result big[100];
    memset(big, 0, sizeof big);
    for (int u = 0; u < 100; u++) {
        big[u].rms_before[0][0] = 1.0;
        big[u].rms_after[0][0] = 0.001 * ((u * 37) % 100 + 1); /* a permutation of 1..100 */
        big[u].rms_after_sys[0][0] = 0.0005;
    }
    test_read_all(big, 100);
    summary_row rb;
    assert_int_equal(report_summarize(&c, big, 100, &rb), SUNMC_OK);
    /* Bin(100, 0.95): P(K <= 90) = 0.0282 > 0.025 >= P(K <= 89) = 0.0115
     * -> l = 90; P(K <= 98) = 0.9629 < 0.975 <= P(K <= 99) = 0.9941 -> u = 100.
     * (Checked against the brute-force sum in test_stats_ci.) */
    assert_near(rb.rms_after_p95_ci.lo, 0.090, 1e-15);
    assert_near(rb.rms_after_p95_ci.hi, 0.100, 1e-15);
    assert_near(rb.rms_after_p95, 0.001 * (95 + 0.05), 1e-15); /* h = 99 * 0.95 = 94.05 */
    /* A constant sample: zero-width interval. */
    assert_near(rb.rms_after_sys_mean_ci.lo, 0.0005, 1e-18);
    assert_near(rb.rms_after_sys_mean_ci.hi, 0.0005, 1e-18);
}

/* No level in (0, 1) (a config not built from the key table): estimates
 * stay, intervals are NaN; no units: NaN everywhere. */
static void no_level_and_no_units(void **state)
{
    sunmc_config c0 = c;
    c0.confidence = 0;
    summary_row r0;
    assert_int_equal(report_summarize(&c0, res, NU, &r0), SUNMC_OK);
    assert_true(r0.rms_after_mean > 0 && r0.yield > 0);
    assert_true(isnan(r0.rms_after_mean_ci.lo) && isnan(r0.yield_ci.hi));
    assert_true(isnan(r0.rms_after_p95_ci.lo) && isnan(r0.improvement_mean_ci.lo));
    assert_int_equal(report_summarize(&c, res, 0, &r0), SUNMC_OK);
    assert_true(isnan(r0.rms_after_mean) && isnan(r0.rms_after_mean_ci.lo));
    assert_true(isnan(r0.yield) && isnan(r0.yield_ci.lo) && isnan(r0.rms_after_sys_mean));
    /* One unit: a mean, no interval. */
    assert_int_equal(report_summarize(&c, res, 1, &r0), SUNMC_OK);
    assert_near(r0.rms_after_mean, 0.010, 0);
    assert_true(isnan(r0.rms_after_mean_ci.lo));
    /* A higher level widens the interval. */
    summary_row r99;
    c0.confidence = 0.99;
    assert_int_equal(report_summarize(&c0, res, NU, &r99), SUNMC_OK);
    assert_true(r99.rms_after_mean_ci.hi - r99.rms_after_mean_ci.lo >
                r.rms_after_mean_ci.hi - r.rms_after_mean_ci.lo);
    assert_true(r99.yield_ci.lo < r.yield_ci.lo);
}

/* Every S with an interval is followed by S_ci_lo and S_ci_hi holding the
 * row's bounds; confidence and stat_units are written. */
static void summary_columns(void **state)
{
    FILE *f = tmpfile();
    assert_non_null(f);
    report_write_summary_header(f, 0, NULL);
    report_write_summary_rows(f, &c, &r, 0, NULL);
    rewind(f);
    char hl[4096], vl[4096], *h[64], *v[64];
    int nh = read_row(f, 1, hl, vl, sizeof hl, h, v);
    fclose(f);
    assert_true(nh > 0);
    const char *stat[] = {"rms_before_mean", "rms_after_mean", "rms_after_sys_mean",
                          "rms_after_p95", "improvement_mean", "yield"};
    const stats_interval ci[] = {r.rms_before_mean_ci,  r.rms_after_mean_ci,
                                 r.rms_after_sys_mean_ci, r.rms_after_p95_ci,
                                 r.improvement_mean_ci, r.yield_ci};
    int found = 0;
    for (int i = 0; i + 2 < nh; i++)
        for (int k = 0; k < 6; k++) {
            if (strcmp(h[i], stat[k]) != 0)
                continue;
            char lo[64], hi[64];
            snprintf(lo, sizeof lo, "%s_ci_lo", stat[k]);
            snprintf(hi, sizeof hi, "%s_ci_hi", stat[k]);
            assert_string_equal(h[i + 1], lo);
            assert_string_equal(h[i + 2], hi);
            /* "-": a bound that could not be formed */
            double wl = strcmp(v[i + 1], "-") == 0 ? NAN : strtod(v[i + 1], NULL);
            double wh = strcmp(v[i + 2], "-") == 0 ? NAN : strtod(v[i + 2], NULL);
            if (isnan(ci[k].hi))
                assert_true(isnan(wh));
            else
                assert_near(wh, ci[k].hi, 1e-5 * fabs(ci[k].hi));
            assert_near(wl, ci[k].lo, 1e-5 * fabs(ci[k].lo));
            found++;
        }
    assert_int_equal(found, 6);
    for (int i = 0; i < nh; i++) {
        if (strcmp(h[i], "confidence") == 0)
            assert_string_equal(v[i], "0.95");
        if (strcmp(h[i], "stat_units") == 0)
            assert_string_equal(v[i], "7");
    }
}

/* Table 1: yield and the means in the compact "v [lo, hi]" form, the
 * footnote naming the methods and n. */
static void printed_compact(void **state)
{
    FILE *f = tmpfile();
    assert_non_null(f);
    summary_print(f, &c, &r);
    rewind(f);
    char text[8192];
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    char want[128];
    snprintf(want, sizeof want, "%.1f%% [%.1f, %.1f]", 100 * r.yield, 100 * r.yield_ci.lo,
             100 * r.yield_ci.hi);
    if (!strstr(text, want))
        fail_msg("table lacks '%s':\n%s", want, text);
    const char *needles[] = {"Student t", "order statistic", "Wilson", "n = 7", "95% CI",
                             "Systematic part", "0.0188 [0.0151, -]"};
    for (size_t i = 0; i < sizeof needles / sizeof needles[0]; i++)
        if (!strstr(text, needles[i]))
            fail_msg("table lacks '%s':\n%s", needles[i], text);
}

/* ---- end to end ---- */

#define SMALL                                                                                \
    "--set validation.alpha_step_deg=2.3 --set campaign.beta_deg=0 --quiet "                  \
    "--set calibration.priors=off"
#define SEEDS 20
#define SUB_UNITS 50
#define REF_UNITS 1000

/* Column `name` of data row `row` (1 = first) of the TSV at path. */
static double summary_value(const char *path, int row, const char *name)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char hl[4096], vl[4096], *h[64], *v[64];
    int n = read_row(f, row, hl, vl, sizeof hl, h, v);
    fclose(f);
    for (int i = 0; i < n; i++)
        if (strcmp(h[i], name) == 0)
            return strtod(v[i], NULL);
    fail_msg("%s has no column %s in row %d", path, name, row);
    return NAN;
}

static void run_sunmc(const char *args)
{
    char cmd[2048], out[16384];
    snprintf(cmd, sizeof cmd, "%s run configs/ess_type_a.ini %s " SMALL, test_sunmc(), args);
    if (test_run(cmd, out, sizeof out) != 0)
        fail_msg("%s failed:\n%s", cmd, out);
}

/* The check at a suite-sized scale (`make coverage` runs it at
 * 20 x 200 against 4000 units): over 20 independent seeds of 50 units, the
 * 95 % interval of rms_after_mean and of improvement_mean covers the mean
 * of a 1000-unit run in at least 16 of 20 (widest band). */
static void coverage_against_large_run(void **state)
{
    char args[512], path[512];
    snprintf(args, sizeof args, "--units %d --seed 1000 --out %s", REF_UNITS, test_tmp("ref"));
    run_sunmc(args);
    snprintf(path, sizeof path, "%s", test_tmp("ref/summary.tsv"));
    double ref_after = summary_value(path, 3, "rms_after_mean");
    double ref_imp = summary_value(path, 3, "improvement_mean");
    int cover_after = 0, cover_imp = 0;
    for (int s = 1; s <= SEEDS; s++) {
        char name[32];
        snprintf(name, sizeof name, "s%d", s);
        snprintf(args, sizeof args, "--units %d --seed %d --out %s", SUB_UNITS, s, test_tmp(name));
        run_sunmc(args);
        snprintf(name, sizeof name, "s%d/summary.tsv", s);
        snprintf(path, sizeof path, "%s", test_tmp(name));
        cover_after += summary_value(path, 3, "rms_after_mean_ci_lo") <= ref_after &&
                       ref_after <= summary_value(path, 3, "rms_after_mean_ci_hi");
        cover_imp += summary_value(path, 3, "improvement_mean_ci_lo") <= ref_imp &&
                     ref_imp <= summary_value(path, 3, "improvement_mean_ci_hi");
    }
    print_message("covered: rms_after_mean %d/%d, improvement_mean %d/%d\n", cover_after, SEEDS,
                  cover_imp, SEEDS);
    assert_true(cover_after >= 16);
    assert_true(cover_imp >= 16);
}

/* Widths from 250 to 1000 units (units 0-249 are the first quarter of the
 * 1000-unit run above, seed 1000): about half, as 1/sqrt(N). */
static void widths_shrink(void **state)
{
    char args[512], p250[512], p1000[512];
    snprintf(args, sizeof args, "--units 250 --seed 1000 --out %s", test_tmp("n250"));
    run_sunmc(args);
    snprintf(p250, sizeof p250, "%s", test_tmp("n250/summary.tsv"));
    snprintf(p1000, sizeof p1000, "%s", test_tmp("ref/summary.tsv"));
    const char *stat[] = {"rms_before_mean", "rms_after_mean", "rms_after_sys_mean",
                          "improvement_mean"};
    for (int k = 0; k < 4; k++)
        for (int row = 1; row <= 3; row++) {
            char lo[64], hi[64];
            snprintf(lo, sizeof lo, "%s_ci_lo", stat[k]);
            snprintf(hi, sizeof hi, "%s_ci_hi", stat[k]);
            double w250 = summary_value(p250, row, hi) - summary_value(p250, row, lo);
            double w1000 = summary_value(p1000, row, hi) - summary_value(p1000, row, lo);
            print_message("%s row %d: width ratio 250/1000 = %.3f\n", stat[k], row, w250 / w1000);
            assert_near(w250 / w1000, 2.0, 0.4);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(hand_made_intervals, summarize),
        cmocka_unit_test_setup(p95_ranks_at_100, summarize),
        cmocka_unit_test_setup(no_level_and_no_units, summarize),
        cmocka_unit_test_setup(summary_columns, summarize),
        cmocka_unit_test_setup(printed_compact, summarize),
        cmocka_unit_test(coverage_against_large_run),
        cmocka_unit_test(widths_shrink),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
