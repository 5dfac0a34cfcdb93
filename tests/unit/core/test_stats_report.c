/* test_stats_report.c - the report's statistics and writers on hand-made
 * unit results, against values worked out here: mean, max, min and the 95th
 * percentile of the RMS after (Hyndman-Fan type 7: linear interpolation
 * between order statistics at h = (k - 1) p, GSL's definition), the mean of
 * the per-unit improvement ratios before / after, the yield (units meeting
 * the spec, at or below it, over ALL units, failed fits included), failed
 * fits and NaN bands left out of the statistics, band edges, the spec
 * converted to the family's RMS unit; then every column of summary.tsv and
 * units.tsv (intervals included) and the printed Table 1. */
#include "test_util.h"

#include "report.h"
#include "summary_print.h"
#include "status.h"

#include <unistd.h>

/* ---- a family whose RMS unit is the degree (spec 54" = 0.015 deg) ---- */

static const char *const fake_angles[] = {"alpha", "beta"};
static const char *const fake_dev[] = {"d0_um", "d1_deg", "d2_px"};
static const char *const fake_par[] = {"p0", "p1"};

static int fake_n_angles(const sunmc_config *c) { return 2; }

static void fake_label(const sunmc_config *c, char *buf, size_t len)
{
    snprintf(buf, len, "fake model");
}

static int fake_dev_columns(const sunmc_config *c, const char **names, int max)
{
    for (int i = 0; i < 3 && i < max; i++)
        names[i] = fake_dev[i];
    return 3;
}

static int fake_par_columns(const sunmc_config *c, const char **names, int max)
{
    for (int i = 0; i < 2 && i < max; i++)
        names[i] = fake_par[i];
    return 2;
}

static const sensor_family fake = {
    .name = "fake",
    .alias_term = "the fake term",
    .rms_unit = "deg",
    .arcsec_per_rms_unit = 3600.0,
    .model_label = fake_label,
    .n_angles = fake_n_angles,
    .angle_names = fake_angles,
    .dev_columns = fake_dev_columns,
    .par_columns = fake_par_columns,
};

#define NB 3
#define NU 9
#define SPEC_DEG (54.0 / 3600.0)

static void make_config(sunmc_config *c)
{
    memset(c, 0, sizeof *c);
    c->family = &fake;
    snprintf(c->product, sizeof c->product, "Test product");
    c->seed = 11;
    c->spec_arcsec = 54.0;
    c->confidence = 0.95;
    c->bands_deg.n = NB;
    const double lo[NB] = {0, 30, 0}, hi[NB] = {30, 60, 60};
    for (int b = 0; b < NB; b++) {
        c->bands_deg.lo[b] = lo[b];
        c->bands_deg.hi[b] = hi[b];
    }
}

/* (before, after) of angle 0, band 0 per unit; NAN where the unit has no
 * value.  Unit 3's fit failed; unit 6 has no point in band 0; unit 8's
 * after is missing with its before present.  Unit 1 sits exactly at the
 * spec (passes), unit 2 just above it (fails). */
static const double bef0[NU] = {0.20, 0.30, 0.25, 0.40, 0.10, 0.50, NAN, 0.22, 0.30};
static const double aft0[NU] = {0.010, SPEC_DEG, 0.0151, NAN, 0.020, 0.005, NAN, 0.011, NAN};

static void make_results(unit_result *r)
{
    memset(r, 0, NU * sizeof *r);
    for (int u = 0; u < NU; u++) {
        r[u].unit = 100 + u;
        r[u].fit_status = UNIT_FIT_OK;
        r[u].fit_iterations = 3 + u;
        r[u].gross_cal = 10 * u;  /* campaign points dropped: not the report's gross count */
        r[u].gross_val = u % 3;   /* validation gross errors: 0+1+2+0+1+2+0+1+2 = 9 */
        r[u].fit_rms = 1e-4 * (u + 1);
        for (int i = 0; i < 3; i++)
            r[u].dev[i] = (u + 1) * 10.0 + i;
        for (int i = 0; i < 2; i++)
            r[u].par[i] = -(u + 1) - 0.25 * i;
        r[u].dev[3] = 999; /* beyond the family's columns */
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < NB; b++) {
                /* Band 2 is empty for every unit; band 1 and angle 1 get
                 * values of their own. */
                r[u].rms_before[a][b] = b == 2 ? NAN : 0.1 * (u + 1) + a + 10 * b;
                r[u].rms_after[a][b] = b == 2 ? NAN : 0.001 * (u + 1) * (1 + a + 2 * b);
            }
        r[u].rms_before[0][0] = bef0[u];
        r[u].rms_after[0][0] = aft0[u];
    }
    r[3].fit_status = UNIT_FIT_FAILED;
    r[3].rms_after[0][1] = r[3].rms_after[1][0] = r[3].rms_after[1][1] = NAN;
    r[5].alias_weak = 2; /* two weak directions: one unit */
    r[2].alias_weak = 1;
    test_read_all(r, NU);
}

/* The hand-made results and their summary, fresh for each test. */
static sunmc_config c;
static unit_result res[NU];
static summary_row rows[2 * NB];

static int summarize(void **state)
{
    (void)state;
    make_config(&c);
    make_results(res);
    return report_summarize(&c, res, NU, rows) == SUNMC_OK ? 0 : -1;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Type-7 quantile of v[n] (sorted here). */
static double quantile7(double *v, int n, double p)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    double h = (n - 1) * p;
    int lo = (int)floor(h);
    if (lo + 1 >= n)
        return v[n - 1];
    return v[lo] + (h - lo) * (v[lo + 1] - v[lo]);
}

/* The statistics of one angle and band, computed here. */
typedef struct {
    double bmean, amean, amax, amin, p95, imean, imax, imin, yield;
    long k;
} expect;

static expect expected(const unit_result *r, int n, int a, int b, double spec)
{
    expect e = {0};
    double after[NU];
    long pass = 0;
    e.amax = e.imax = -1e300;
    e.amin = e.imin = 1e300;
    for (int u = 0; u < n; u++) {
        double x = r[u].rms_before[a][b], y = r[u].rms_after[a][b];
        if (r[u].fit_status != UNIT_FIT_OK || isnan(x) || isnan(y))
            continue;
        e.bmean += x;
        e.amean += y;
        e.imean += x / y;
        e.amax = fmax(e.amax, y);
        e.amin = fmin(e.amin, y);
        e.imax = fmax(e.imax, x / y);
        e.imin = fmin(e.imin, x / y);
        after[e.k++] = y;
        pass += y <= spec;
    }
    e.bmean /= (double)e.k;
    e.amean /= (double)e.k;
    e.imean /= (double)e.k;
    e.p95 = quantile7(after, (int)e.k, 0.95);
    e.yield = (double)pass / n;
    return e;
}

static void hand_made_band(void **state)
{
    (void)state;
    assert_int_equal(report_n_rows(&c), 2 * NB);
    const summary_row *r = &rows[0];
    assert_int_equal(r->angle, 0);
    assert_int_equal(r->band, 0);
    /* Worked by hand: units 0, 1, 2, 4, 5, 7 count (3 failed, 6 and 8 have
     * no value in the band). */
    assert_near(r->rms_before_mean, (0.20 + 0.30 + 0.25 + 0.10 + 0.50 + 0.22) / 6, 1e-15);
    assert_near(r->rms_after_mean, (0.010 + SPEC_DEG + 0.0151 + 0.020 + 0.005 + 0.011) / 6, 1e-15);
    assert_near(r->rms_after_max, 0.020, 0);
    assert_near(r->rms_after_min, 0.005, 0);
    /* sorted 0.005 0.010 0.011 0.015 0.0151 0.020: h = 5 * 0.95 = 4.75 */
    assert_near(r->rms_after_p95, 0.0151 + 0.75 * (0.020 - 0.0151), 1e-15);
    double ratios = 0.20 / 0.010 + 0.30 / SPEC_DEG + 0.25 / 0.0151 + 0.10 / 0.020 + 0.50 / 0.005 +
                    0.22 / 0.011;
    assert_near(r->improvement_mean, ratios / 6, 1e-12);
    assert_near(r->improvement_max, 100.0, 1e-12);
    assert_near(r->improvement_min, 5.0, 1e-12);
    /* 0.010, 0.015 (at the spec), 0.005 and 0.011 meet 54" = 0.015 deg: 4 of 9 units */
    assert_near(r->yield, 4.0 / 9.0, 1e-15);
    assert_int_equal(r->units, NU);
    assert_int_equal(r->fit_failures, 1);
    assert_int_equal(r->gross_errors, 9);
    assert_int_equal(r->alias_units, 2);
}

static void every_row_against_recomputation(void **state)
{
    (void)state;
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < NB; b++) {
            const summary_row *r = &rows[a * NB + b];
            assert_int_equal(r->angle, a);
            assert_int_equal(r->band, b);
            assert_int_equal(r->fit_failures, 1);
            if (b == 2) { /* no unit has a value: NaN statistics, nobody passes */
                assert_true(isnan(r->rms_before_mean) && isnan(r->rms_after_mean));
                assert_true(isnan(r->rms_after_max) && isnan(r->rms_after_min));
                assert_true(isnan(r->rms_after_p95) && isnan(r->improvement_mean));
                assert_true(isnan(r->improvement_max) && isnan(r->improvement_min));
                assert_near(r->yield, 0.0, 0);
                continue;
            }
            expect e = expected(res, NU, a, b, SPEC_DEG);
            assert_true(e.k >= 5);
            assert_near(r->rms_before_mean, e.bmean, 1e-14);
            assert_near(r->rms_after_mean, e.amean, 1e-14);
            assert_near(r->rms_after_max, e.amax, 0);
            assert_near(r->rms_after_min, e.amin, 0);
            assert_near(r->rms_after_p95, e.p95, 1e-15);
            assert_near(r->improvement_mean, e.imean, 1e-12 * e.imean);
            assert_near(r->improvement_max, e.imax, 1e-12 * e.imax);
            assert_near(r->improvement_min, e.imin, 1e-12 * e.imin);
            assert_near(r->yield, e.yield, 1e-15);
        }
    /* The ratio of the means is not the mean of the ratios. */
    assert_true(fabs(rows[0].improvement_mean - rows[0].rms_before_mean / rows[0].rms_after_mean) >
                1.0);
}

/* No unit at all, and every unit failed. */
static void empty_and_all_failed(void **state)
{
    (void)state;
    for (int u = 0; u < NU; u++)
        res[u].fit_status = UNIT_FIT_FAILED;
    assert_int_equal(report_summarize(&c, res, NU, rows), SUNMC_OK);
    assert_int_equal(rows[0].fit_failures, NU);
    assert_true(isnan(rows[0].rms_after_mean) && isnan(rows[0].rms_after_max));
    assert_true(isnan(rows[0].rms_after_p95) && isnan(rows[0].improvement_min));
    assert_near(rows[0].yield, 0.0, 0);
    assert_int_equal(report_summarize(&c, res, 0, rows), SUNMC_OK);
    assert_int_equal(rows[0].units, 0);
    assert_true(isnan(rows[0].yield) && isnan(rows[0].rms_before_mean));
}

/* The spec in the family's unit: one unit a hair on each side of 54". */
static void spec_in_family_unit(void **state)
{
    (void)state;
    memset(res, 0, sizeof res);
    for (int u = 0; u < 2; u++)
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < NB; b++) {
                res[u].rms_before[a][b] = 1.0;
                res[u].rms_after[a][b] = (u == 0 ? 53.99 : 54.01) / 3600.0;
            }
    test_read_all(res, 2);
    assert_int_equal(report_summarize(&c, res, 2, rows), SUNMC_OK);
    for (int i = 0; i < 2 * NB; i++)
        assert_near(rows[i].yield, 0.5, 0);
    /* The 95th percentile of two values: 0.95 of the way from the first. */
    assert_near(rows[0].rms_after_p95, (53.99 + 0.95 * 0.02) / 3600.0, 1e-15);
}

/* ---- writers: read back what they wrote ---- */

/* Split a line into its tab-separated fields. */
static int split_tsv(char *line, char **f, int max)
{
    int n = 0;
    char *save = NULL;
    line[strcspn(line, "\n")] = '\0';
    for (char *t = strtok_r(line, "\t", &save); t && n < max; t = strtok_r(NULL, "\t", &save))
        f[n++] = t;
    return n;
}

static int col_of(char **names, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], name) == 0)
            return i;
    fail_msg("no column %s", name);
    return -1;
}

/* Value written with %.6g (or %.10g) equals v to its printed digits. */
static void assert_printed(const char *text, double v, const char *what)
{
    double got = strcmp(text, "-") == 0 ? NAN : strtod(text, NULL); /* "-": not formed */
    if (isnan(v)) {
        if (!isnan(got))
            fail_msg("%s: wrote %s, expected nan", what, text);
        return;
    }
    if (!(fabs(got - v) <= 6e-6 * fabs(v)))
        fail_msg("%s: wrote %s, expected %.10g", what, text, v);
}

static void summary_tsv_columns(void **state)
{
    (void)state;
    FILE *f = tmpfile();
    assert_non_null(f);
    const char *lead[1] = {"campaign.alpha_step_deg"};
    const char *const lead_v[1] = {"0.2525"};
    report_write_summary_header(f, 1, lead);
    report_write_summary_rows(f, &c, rows, 1, lead_v);
    rewind(f);
    char hline[4096], line[4096];
    char *h[96], *v[96];
    assert_non_null(fgets(hline, sizeof hline, f));
    int nh = split_tsv(hline, h, 96);
    const char *want[] = {"campaign.alpha_step_deg",
                          "product",
                          "family",
                          "angle",
                          "band",
                          "band_lo_deg",
                          "band_hi_deg",
                          "units",
                          "rms_unit",
                          "rms_before_mean",
                          "rms_before_mean_ci_lo",
                          "rms_before_mean_ci_hi",
                          "rms_after_mean",
                          "rms_after_mean_ci_lo",
                          "rms_after_mean_ci_hi",
                          "rms_after_sys_mean",
                          "rms_after_sys_mean_ci_lo",
                          "rms_after_sys_mean_ci_hi",
                          "rms_after_max",
                          "rms_after_min",
                          "rms_after_p95",
                          "rms_after_p95_ci_lo",
                          "rms_after_p95_ci_hi",
                          "improvement_mean",
                          "improvement_mean_ci_lo",
                          "improvement_mean_ci_hi",
                          "improvement_max",
                          "improvement_min",
                          "yield",
                          "yield_ci_lo",
                          "yield_ci_hi",
                          "spec_arcsec",
                          "confidence",
                          "stat_units",
                          "fit_failures",
                          "gross_errors",
                          "alias_units",
                          "model",
                          "campaign_points",
                          "campaign_hours",
                          "extrapolation_deg",
                          "no_reading_units",
                          "worse",
                          "worse_ci_lo",
                          "worse_ci_hi",
                          "yield_interval",
                          "spec_yield",
                          "spec_yield_ci_lo",
                          "spec_yield_ci_hi",
                          "spec_statistic",
                          "spec_bands",
                          "min_coverage",
                          "band_points",
                          "rms_after_mf_mean",
                          "rms_after_mf_mean_ci_lo",
                          "rms_after_mf_mean_ci_hi",
                          "mf_units",
                          "share_noise",
                          "share_noise_ci_lo",
                          "share_noise_ci_hi",
                          "share_estimation",
                          "share_estimation_ci_lo",
                          "share_estimation_ci_hi",
                          "share_model_form",
                          "share_model_form_ci_lo",
                          "share_model_form_ci_hi"};
    assert_int_equal(nh, (int)(sizeof want / sizeof want[0]));
    for (int i = 0; i < nh; i++)
        assert_string_equal(h[i], want[i]);
    for (int i = 0; i < 2 * NB; i++) {
        const summary_row *r = &rows[i];
        assert_non_null(fgets(line, sizeof line, f));
        assert_int_equal(split_tsv(line, v, 96), nh);
        assert_printed(v[col_of(h, nh, "campaign.alpha_step_deg")], 0.2525, "lead");
        assert_string_equal(v[col_of(h, nh, "product")], "Test product");
        assert_string_equal(v[col_of(h, nh, "family")], "fake");
        assert_string_equal(v[col_of(h, nh, "angle")], fake_angles[r->angle]);
        char band[32];
        snprintf(band, sizeof band, "%g:%g", c.bands_deg.lo[r->band], c.bands_deg.hi[r->band]);
        assert_string_equal(v[col_of(h, nh, "band")], band);
        assert_printed(v[col_of(h, nh, "band_lo_deg")], c.bands_deg.lo[r->band], "band_lo_deg");
        assert_printed(v[col_of(h, nh, "band_hi_deg")], c.bands_deg.hi[r->band], "band_hi_deg");
        assert_int_equal(atol(v[col_of(h, nh, "units")]), NU);
        assert_string_equal(v[col_of(h, nh, "rms_unit")], "deg");
        assert_printed(v[col_of(h, nh, "rms_before_mean")], r->rms_before_mean, "before mean");
        assert_printed(v[col_of(h, nh, "rms_after_mean")], r->rms_after_mean, "after mean");
        assert_printed(v[col_of(h, nh, "rms_after_max")], r->rms_after_max, "after max");
        assert_printed(v[col_of(h, nh, "rms_after_min")], r->rms_after_min, "after min");
        assert_printed(v[col_of(h, nh, "rms_after_p95")], r->rms_after_p95, "p95");
        assert_printed(v[col_of(h, nh, "improvement_mean")], r->improvement_mean, "imp mean");
        assert_printed(v[col_of(h, nh, "improvement_max")], r->improvement_max, "imp max");
        assert_printed(v[col_of(h, nh, "improvement_min")], r->improvement_min, "imp min");
        assert_printed(v[col_of(h, nh, "yield")], r->yield, "yield");
        assert_printed(v[col_of(h, nh, "rms_after_sys_mean")], r->rms_after_sys_mean, "sys mean");
        assert_int_equal(atol(v[col_of(h, nh, "campaign_points")]), r->campaign_points);
        assert_printed(v[col_of(h, nh, "campaign_hours")], r->campaign_hours, "hours");
        assert_printed(v[col_of(h, nh, "extrapolation_deg")], r->extrapolation_deg, "extrap");
        const char *est[6] = {"rms_before_mean", "rms_after_mean", "rms_after_sys_mean",
                              "rms_after_p95",   "improvement_mean", "yield"};
        const stats_interval ci[6] = {r->rms_before_mean_ci,  r->rms_after_mean_ci,
                                      r->rms_after_sys_mean_ci, r->rms_after_p95_ci,
                                      r->improvement_mean_ci, r->yield_ci};
        for (int k = 0; k < 6; k++) {
            char name[64];
            snprintf(name, sizeof name, "%s_ci_lo", est[k]);
            assert_printed(v[col_of(h, nh, name)], ci[k].lo, name);
            snprintf(name, sizeof name, "%s_ci_hi", est[k]);
            assert_printed(v[col_of(h, nh, name)], ci[k].hi, name);
        }
        assert_printed(v[col_of(h, nh, "confidence")], 0.95, "confidence");
        assert_int_equal(atol(v[col_of(h, nh, "stat_units")]), r->stat_units);
        assert_printed(v[col_of(h, nh, "spec_arcsec")], 54.0, "spec");
        assert_int_equal(atol(v[col_of(h, nh, "fit_failures")]), 1);
        assert_int_equal(atol(v[col_of(h, nh, "gross_errors")]), 9);
        assert_int_equal(atol(v[col_of(h, nh, "alias_units")]), 2);
        assert_string_equal(v[col_of(h, nh, "model")], "fake model");
        if (r->band != 2)
            assert_true(r->rms_after_max > r->rms_after_min);
    }
    assert_null(fgets(line, sizeof line, f));
    fclose(f);
}

static void units_tsv_columns(void **state)
{
    (void)state;
    FILE *f = tmpfile();
    assert_non_null(f);
    report_write_units(f, &c, res, NU);
    rewind(f);
    char hline[8192], line[8192];
    char *h[128], *v[128];
    assert_non_null(fgets(hline, sizeof hline, f));
    int nh = split_tsv(hline, h, 128);
    /* before, after, after_sys, after_mf; the verdict's five */
    assert_int_equal(nh, 7 + 3 + 2 + 1 + 4 * 2 * NB + 5);
    for (int u = 0; u < NU; u++) {
        const unit_result *r = &res[u];
        assert_non_null(fgets(line, sizeof line, f));
        assert_int_equal(split_tsv(line, v, 128), nh);
        assert_int_equal(atol(v[col_of(h, nh, "unit")]), r->unit);
        assert_string_equal(v[col_of(h, nh, "fit_status")], u == 3 ? "failed" : "ok");
        assert_int_equal(atoi(v[col_of(h, nh, "fit_iterations")]), r->fit_iterations);
        assert_int_equal(atoi(v[col_of(h, nh, "alias_weak")]), r->alias_weak);
        assert_int_equal(atoi(v[col_of(h, nh, "gross_cal")]), r->gross_cal);
        assert_int_equal(atoi(v[col_of(h, nh, "gross_val")]), r->gross_val);
        for (int i = 0; i < 3; i++)
            assert_printed(v[col_of(h, nh, fake_dev[i])], r->dev[i], fake_dev[i]);
        for (int i = 0; i < 2; i++)
            assert_printed(v[col_of(h, nh, fake_par[i])], r->par[i], fake_par[i]);
        assert_printed(v[col_of(h, nh, "fit_rms_deg")], r->fit_rms, "fit_rms");
        const double lo[NB] = {0, 30, 0}, hi[NB] = {30, 60, 60};
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < NB; b++) {
                char name[96];
                snprintf(name, sizeof name, "rms_before_%s_%g_%g_deg", fake_angles[a], lo[b], hi[b]);
                assert_printed(v[col_of(h, nh, name)], r->rms_before[a][b], name);
                snprintf(name, sizeof name, "rms_after_%s_%g_%g_deg", fake_angles[a], lo[b], hi[b]);
                assert_printed(v[col_of(h, nh, name)], r->rms_after[a][b], name);
                snprintf(name, sizeof name, "rms_after_sys_%s_%g_%g_deg", fake_angles[a], lo[b],
                         hi[b]);
                assert_printed(v[col_of(h, nh, name)], r->rms_after_sys[a][b], name);
            }
    }
    assert_null(fgets(line, sizeof line, f));
    fclose(f);
}

/* A printed interval bound: a number, or "-" when there is none. */
static double bound(const char *text)
{
    return strcmp(text, "-") == 0 ? NAN : strtod(text, NULL);
}

static void assert_shown(double got, double want, double tol)
{
    if (isnan(want))
        assert_true(isnan(got));
    else
        assert_near(got, want, tol);
}

/* Table 1 on stdout: each printed number is the row's, in the right column:
 * first block max, min | improvement mean [lo, hi] max min | p95 [lo, hi];
 * second block before, after, systematic part [lo, hi] each | yield [lo, hi]. */
static void printed_table(void **state)
{
    (void)state;
    FILE *f = tmpfile();
    assert_non_null(f);
    summary_print(f, &c, rows);
    rewind(f);
    char line[1024];
    int seen1 = 0, seen2 = 0;
    while (fgets(line, sizeof line, f)) {
        char angle[16], band[16], b[8][16], t[8][16];
        double x[8];
        if (sscanf(line, "%15s %15s | %15s %15s | %15s [%15[^,], %15[^]]] %15s %15s | %15s [%15[^,], %15[^]]]",
                   angle, band, t[0], t[1], t[2], b[0], b[1], t[3], t[4], t[5], b[2],
                   b[3]) == 12 && strcmp(t[0], "|") != 0) {
            for (int k = 0; k < 6; k++) /* a number, or "-" where there is none: never nan */
                x[k] = bound(t[k]);
            const summary_row *r = &rows[seen1++];
            assert_string_equal(angle, fake_angles[r->angle]);
            const double got[9] = {x[0], x[1], x[2], bound(b[0]), bound(b[1]),
                                   x[3], x[4], x[5], bound(b[2])};
            const double want[9] = {r->rms_after_max,        r->rms_after_min,
                                    r->improvement_mean,     r->improvement_mean_ci.lo,
                                    r->improvement_mean_ci.hi, r->improvement_max,
                                    r->improvement_min,      r->rms_after_p95,
                                    r->rms_after_p95_ci.lo};
            const double tol[9] = {0.5e-4, 0.5e-4, 0.005, 0.005, 0.005, 0.005, 0.005, 0.5e-4, 0.5e-4};
            for (int k = 0; k < 9; k++)
                assert_shown(got[k], want[k], tol[k]);
            assert_shown(bound(b[3]), r->rms_after_p95_ci.hi, 0.5e-4);
        } else if (sscanf(line,
                          "%15s %15s | %15s [%15[^,], %15[^]]] %15s [%15[^,], %15[^]]] %15s [%15[^,], "
                          "%15[^]]] | %lf%% [%15[^,], %15[^]]]",
                          angle, band, t[0], b[0], b[1], t[1], b[2], b[3], t[2], b[4], b[5],
                          &x[3], b[6], b[7]) == 14) {
            for (int k = 0; k < 3; k++)
                x[k] = bound(t[k]);
            const summary_row *r = &rows[seen2++];
            assert_string_equal(angle, fake_angles[r->angle]);
            const double v[4] = {r->rms_before_mean, r->rms_after_mean, r->rms_after_sys_mean,
                                 100 * r->yield};
            const stats_interval ci[4] = {r->rms_before_mean_ci, r->rms_after_mean_ci,
                                          r->rms_after_sys_mean_ci, r->yield_ci};
            const double scale[4] = {1, 1, 1, 100}, tol[4] = {0.5e-4, 0.5e-4, 0.5e-4, 0.05};
            for (int k = 0; k < 4; k++) {
                assert_shown(x[k], v[k], tol[k]);
                assert_shown(bound(b[2 * k]), scale[k] * ci[k].lo, tol[k]);
                assert_shown(bound(b[2 * k + 1]), scale[k] * ci[k].hi, tol[k]);
            }
        }
    }
    assert_int_equal(seen1, 2 * NB);
    assert_int_equal(seen2, 2 * NB);
    fclose(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(hand_made_band, summarize),
        cmocka_unit_test_setup(every_row_against_recomputation, summarize),
        cmocka_unit_test_setup(empty_and_all_failed, summarize),
        cmocka_unit_test_setup(spec_in_family_unit, summarize),
        cmocka_unit_test_setup(summary_tsv_columns, summarize),
        cmocka_unit_test_setup(units_tsv_columns, summarize),
        cmocka_unit_test_setup(printed_table, summarize),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
