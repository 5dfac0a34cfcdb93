/* test_output_columns.c - every column sunmc writes, recomputed from another file:
 *   summary.tsv from units.tsv (mean, max, min, p95 of type 7, mean of the
 *   per-unit improvement ratios, yield over all units, failures, gross
 *   errors, aliased units), and Table 1 on stdout against summary.tsv;
 *   units.tsv's RMS before from simulate's validation.csv (ESS: output -
 *   truth; DSS: the on-board formula of the DSS paper, eq. 9-10, evaluated
 *   here, bands by the field angle, the total as the angle between the two
 *   directions), and the DSS fitted parameters against the drawn deviations
 *   of a noise-free unit;
 *   budget.tsv's all columns, FLOOR and alone rows against runs of the same
 *   configs, in the budget's row (last angle, widest band);
 *   output errors: a write error at commit (a file-size limit) and an
 *   output path that is a file exit non-zero and leave nothing behind;
 *   out_commit on a stream whose writes fail (/dev/full), buffered and not. */
#include "test_util.h"
#include "test_tsv.h"

#include "csv.h"
#include "output.h"
#include "status.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[48];

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/sunmc_test_outputs_XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static void run_ok(const char *fmt, const char *a, const char *b)
{
    char cmd[2048], out[1 << 15];
    snprintf(cmd, sizeof cmd, fmt, test_sunmc(), a, b);
    int st = test_run(cmd, out, sizeof out);
    if (st != 0)
        fail_msg("%s: exit %d\n%s", cmd, st, out);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* ---- summary.tsv from units.tsv ---- */

static void summary_from_units(const char *run_dir, double arcsec_per_unit)
{
    char path[256];
    snprintf(path, sizeof path, "%s/summary.tsv", run_dir);
    tsv *s = tsv_load(path);
    snprintf(path, sizeof path, "%s/units.tsv", run_dir);
    tsv *u = tsv_load(path);
    assert_true(s->nr >= 3 && u->nr >= 8);
    long gross = 0, alias = 0, failed = 0;
    for (int i = 0; i < u->nr; i++) {
        gross += atol(tsv_str(u, i, "gross_val"));
        alias += atol(tsv_str(u, i, "alias_weak")) > 0;
        failed += strcmp(tsv_str(u, i, "fit_status"), "ok") != 0;
    }
    int yield_between = 0;
    for (int r = 0; r < s->nr; r++) {
        const char *unit = tsv_str(s, r, "rms_unit");
        char bcol[128], acol[128];
        snprintf(bcol, sizeof bcol, "rms_before_%s_%s_%s_%s", tsv_str(s, r, "angle"),
                 tsv_str(s, r, "band_lo_deg"), tsv_str(s, r, "band_hi_deg"), unit);
        snprintf(acol, sizeof acol, "rms_after_%s_%s_%s_%s", tsv_str(s, r, "angle"),
                 tsv_str(s, r, "band_lo_deg"), tsv_str(s, r, "band_hi_deg"), unit);
        char band[64];
        snprintf(band, sizeof band, "%s:%s", tsv_str(s, r, "band_lo_deg"),
                 tsv_str(s, r, "band_hi_deg"));
        assert_string_equal(tsv_str(s, r, "band"), band);
        double spec = tsv_num(s, r, "spec_arcsec") / arcsec_per_unit;
        double sb = 0, sa = 0, si = 0, amax = -INFINITY, amin = INFINITY, imax = -INFINITY,
               imin = INFINITY, after[TSV_MAX_ROWS];
        long k = 0, pass = 0;
        for (int i = 0; i < u->nr; i++) {
            double b = tsv_num(u, i, bcol), a = tsv_num(u, i, acol);
            if (strcmp(tsv_str(u, i, "fit_status"), "ok") != 0 || isnan(a) || isnan(b))
                continue;
            sb += b;
            sa += a;
            si += b / a;
            amax = fmax(amax, a);
            amin = fmin(amin, a);
            imax = fmax(imax, b / a);
            imin = fmin(imin, b / a);
            after[k++] = a;
            pass += a <= spec;
        }
        assert_true(k > 2);
        qsort(after, (size_t)k, sizeof after[0], cmp_double);
        double h = 0.95 * (double)(k - 1);
        int lo = (int)floor(h);
        double p95 = after[lo] + (h - lo) * (after[lo + 1 < k ? lo + 1 : lo] - after[lo]);
        expect_g6(tsv_num(s, r, "rms_before_mean"), sb / k, bcol);
        expect_g6(tsv_num(s, r, "rms_after_mean"), sa / k, acol);
        expect_g6(tsv_num(s, r, "rms_after_max"), amax, "rms_after_max");
        expect_g6(tsv_num(s, r, "rms_after_min"), amin, "rms_after_min");
        expect_g6(tsv_num(s, r, "rms_after_p95"), p95, "rms_after_p95");
        expect_g6(tsv_num(s, r, "improvement_mean"), si / k, "improvement_mean");
        expect_g6(tsv_num(s, r, "improvement_max"), imax, "improvement_max");
        expect_g6(tsv_num(s, r, "improvement_min"), imin, "improvement_min");
        expect_g6(tsv_num(s, r, "yield"), (double)pass / u->nr, "yield");
        yield_between += pass > 0 && pass < u->nr;
        assert_int_equal(atol(tsv_str(s, r, "units")), u->nr);
        assert_int_equal(atol(tsv_str(s, r, "fit_failures")), failed);
        assert_int_equal(atol(tsv_str(s, r, "gross_errors")), gross);
        assert_int_equal(atol(tsv_str(s, r, "alias_units")), alias);
    }
    assert_true(yield_between > 0); /* the spec splits the units somewhere */
    tsv_free(s);
    tsv_free(u);
}

/* A printed interval bound: a number, or "-" when there is none. */
static double shown_bound(const char *text)
{
    return strcmp(text, "-") == 0 ? NAN : strtod(text, NULL);
}

/* printed value v[k] against summary.tsv row r, column col[k] (times scale
 * k), within tol[k]; NaN must be printed as nan or "-". */
static void expect_shown(tsv *s, int r, int n, const double *v, const char *const *col,
                         const double *scale, const double *tol)
{
    for (int k = 0; k < n; k++) {
        double want = tsv_num(s, r, col[k]) * scale[k];
        if (isnan(want) ? !isnan(v[k]) : !(fabs(v[k] - want) <= tol[k]))
            fail_msg("Table 1 row %d %s: printed %g, summary.tsv %g", r, col[k], v[k], want);
    }
}

/* Table 1 as printed (stdout of run, in file `table`) against summary.tsv:
 * the first block (RMS after max, min | improvement mean [lo, hi], max, min
 * | p95 [lo, hi]) and the second (mean before, after, systematic part, each
 * [lo, hi] | yield [lo, hi]). */
static void table_matches_summary(const char *table, const char *run_dir, double tol)
{
    char path[256], line[1024];
    snprintf(path, sizeof path, "%s/summary.tsv", run_dir);
    tsv *s = tsv_load(path);
    FILE *f = fopen(table, "r");
    assert_non_null(f);
    int r1 = 0, r2 = 0;
    while (fgets(line, sizeof line, f)) {
        char angle[16], band[16], b[8][16];
        double x[8];
        if (sscanf(line, "%15s %15s | %lf %lf | %lf [%15[^,], %15[^]]] %lf %lf | %lf [%15[^,], %15[^]]]",
                   angle, band, &x[0], &x[1], &x[2], b[0], b[1], &x[3], &x[4], &x[5], b[2],
                   b[3]) == 12) {
            assert_true(r1 < s->nr);
            assert_string_equal(angle, tsv_str(s, r1, "angle"));
            assert_string_equal(band, tsv_str(s, r1, "band"));
            const char *col[10] = {"rms_after_max",          "rms_after_min",
                                   "improvement_mean",       "improvement_mean_ci_lo",
                                   "improvement_mean_ci_hi", "improvement_max",
                                   "improvement_min",        "rms_after_p95",
                                   "rms_after_p95_ci_lo",    "rms_after_p95_ci_hi"};
            const double v[10] = {x[0], x[1], x[2], shown_bound(b[0]), shown_bound(b[1]),
                                  x[3], x[4], x[5], shown_bound(b[2]), shown_bound(b[3])};
            const double one[10] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
            const double t[10] = {tol, tol, 0.005, 0.005, 0.005, 0.005, 0.005, tol, tol, tol};
            expect_shown(s, r1++, 10, v, col, one, t);
        } else if (sscanf(line,
                          "%15s %15s | %lf [%15[^,], %15[^]]] %lf [%15[^,], %15[^]]] %lf [%15[^,], "
                          "%15[^]]] | %lf%% [%15[^,], %15[^]]]",
                          angle, band, &x[0], b[0], b[1], &x[1], b[2], b[3], &x[2], b[4], b[5],
                          &x[3], b[6], b[7]) == 14) {
            assert_true(r2 < s->nr);
            assert_string_equal(angle, tsv_str(s, r2, "angle"));
            const char *col[12] = {"rms_before_mean",       "rms_before_mean_ci_lo",
                                   "rms_before_mean_ci_hi", "rms_after_mean",
                                   "rms_after_mean_ci_lo",  "rms_after_mean_ci_hi",
                                   "rms_after_sys_mean",    "rms_after_sys_mean_ci_lo",
                                   "rms_after_sys_mean_ci_hi", "yield",
                                   "yield_ci_lo",           "yield_ci_hi"};
            double v[12];
            for (int k = 0; k < 4; k++) {
                v[3 * k] = x[k];
                v[3 * k + 1] = shown_bound(b[2 * k]);
                v[3 * k + 2] = shown_bound(b[2 * k + 1]);
            }
            const double sc[12] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 100, 100, 100};
            const double t[12] = {tol, tol, tol, tol, tol, tol, tol, tol, tol, 0.05, 0.05, 0.05};
            expect_shown(s, r2++, 12, v, col, sc, t);
        }
    }
    fclose(f);
    assert_int_equal(r1, s->nr);
    assert_int_equal(r2, s->nr);
    tsv_free(s);
}

#define ESS_SMALL                                                                                 \
    "--set campaign.alpha_step_deg=0.4 --set validation.alpha_step_deg=0.7 "                      \
    "--set report.spec_arcsec=30"
#define DSS_SMALL                                                                                 \
    "--set campaign.b_step_deg=10 --set validation.b_step_deg=10 --set report.spec_arcsec=4"

static void ess_summary_and_table(void **state)
{
    (void)state;
    char out[256], table[256];
    snprintf(out, sizeof out, "%s/ess", dir);
    snprintf(table, sizeof table, "%s/ess_table.txt", dir);
    run_ok("%s run configs/ess_type_a.ini --units 20 --seed 5 --quiet " ESS_SMALL
           " --out %s > %s",
           out, table);
    summary_from_units(out, 3600.0);
    table_matches_summary(table, out, 0.5e-4);
}

static void dss_summary_and_table(void **state)
{
    (void)state;
    char out[256], table[256];
    snprintf(out, sizeof out, "%s/dss", dir);
    snprintf(table, sizeof table, "%s/dss_table.txt", dir);
    run_ok("%s run configs/dss.ini --units 12 --seed 5 --quiet " DSS_SMALL " --out %s > %s", out,
           table);
    summary_from_units(out, 1.0);
    table_matches_summary(table, out, 0.005);
}

/* ---- units.tsv from simulate's validation readings ---- */

static double column_value(const csv_table *t, size_t r, const char *name)
{
    int c;
    char err[SUNMC_ERRLEN];
    if (csv_column(t, name, 1, &c, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    return strtod(t->field[r * (size_t)t->n_cols + (size_t)c], NULL);
}

static csv_table *read_csv(const char *path)
{
    csv_table *t;
    char err[SUNMC_ERRLEN];
    if (csv_read(path, &t, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    return t;
}

static int in_band(double x, double lo, double hi)
{
    return lo == 0 ? x <= hi + 1e-9 : x > lo + 1e-9 && x <= hi + 1e-9;
}

/* Unit `unit` of cfg (with sets) run alone and simulated: its units.tsv
 * row and simulate's validation.csv. */
static void run_and_simulate(const char *cfg, const char *sets, long unit, const char *name,
                             tsv **u, csv_table **v)
{
    char cmd[2048], out[1 << 14], path[256];
    snprintf(cmd, sizeof cmd,
             "%s run %s --units %ld:%ld --quiet %s --out %s/%s_run && "
             "%s simulate %s --unit %ld %s --out %s/%s_sim > /dev/null",
             test_sunmc(), cfg, unit, unit + 1, sets, dir, name, test_sunmc(), cfg, unit, sets,
             dir, name);
    int st = test_run(cmd, out, sizeof out);
    if (st != 0)
        fail_msg("%s: exit %d\n%s", cmd, st, out);
    snprintf(path, sizeof path, "%s/%s_sim/validation.csv", dir, name);
    *v = read_csv(path);
    snprintf(path, sizeof path, "%s/%s_run/units.tsv", dir, name);
    *u = tsv_load(path);
    assert_int_equal((*u)->nr, 1);
    assert_int_equal(atol(tsv_str(*u, 0, "unit")), unit);
}

static void ess_before_from_validation(void **state)
{
    (void)state;
    tsv *u;
    csv_table *v;
    run_and_simulate("configs/ess_type_a.ini", ESS_SMALL, 3, "ess3", &u, &v);
    const double lo[3] = {0, 30, 0}, hi[3] = {30, 60, 62};
    for (int b = 0; b < 3; b++) {
        double sum = 0;
        long n = 0;
        for (size_t i = 0; i < v->n_rows; i++) {
            double truth = column_value(v, i, "truth_deg"), raw = column_value(v, i, "output_deg");
            if (in_band(fabs(truth), lo[b], hi[b])) {
                sum += (raw - truth) * (raw - truth);
                n++;
            }
        }
        assert_true(n > 20);
        char col[64];
        snprintf(col, sizeof col, "rms_before_alpha_%g_%g_deg", lo[b], hi[b]);
        expect_g6(tsv_num(u, 0, col), sqrt(sum / n), col);
        snprintf(col, sizeof col, "rms_after_alpha_%g_%g_deg", lo[b], hi[b]);
        assert_true(tsv_num(u, 0, col) < 0.5 * sqrt(sum / n)); /* calibration helped */
    }
    tsv_free(u);
    csv_free(v);
}

/* The default on-board formula, written here: the field angle th whose
 * spot through the nominal glass lies r from the centre, by bisection on
 * r(th) = (h - t) tan th + t tan(asin(sin th / n)), then the direction. */
static void dss_onboard(double x_px, double y_px, double *a, double *b)
{
    const double pixel_mm = 5.5e-3, h_mm = 3.0, t_mm = 0.4, n = 1.52; /* configs/dss.ini */
    double x = x_px * pixel_mm, y = y_px * pixel_mm, r = hypot(x, y), lo = 0, hi = 1.5;
    for (int it = 0; it < 200; it++) {
        double th = 0.5 * (lo + hi);
        double rt = (h_mm - t_mm) * tan(th) + t_mm * tan(asin(sin(th) / n));
        *(rt < r ? &lo : &hi) = th;
    }
    double k = r > 0 ? tan(0.5 * (lo + hi)) / r : 1 / h_mm;
    *a = atan(-x * k);
    *b = atan(-y * k);
}

static void direction(double a, double b, double v[3])
{
    double n = sqrt(1 + tan(a) * tan(a) + tan(b) * tan(b));
    v[0] = tan(a) / n;
    v[1] = tan(b) / n;
    v[2] = 1 / n;
}

static void dss_before_from_validation(void **state)
{
    (void)state;
    tsv *u;
    csv_table *v;
    run_and_simulate("configs/dss.ini", DSS_SMALL, 2, "dss2", &u, &v);
    const double lo[3] = {0, 20, 0}, hi[3] = {20, 40, 60};
    const char *angle[3] = {"alpha", "beta", "total"};
    const double d2r = M_PI / 180, r2s = 180 * 3600 / M_PI;
    for (int b = 0; b < 3; b++) {
        double sum[3] = {0, 0, 0};
        long n = 0;
        for (size_t i = 0; i < v->n_rows; i++) {
            double a0 = column_value(v, i, "truth_alpha_deg") * d2r;
            double b0 = column_value(v, i, "truth_beta_deg") * d2r, a, bb;
            dss_onboard(column_value(v, i, "x_px"), column_value(v, i, "y_px"), &a, &bb);
            double field = atan(hypot(tan(a0), tan(b0))) / d2r;
            if (!in_band(field, lo[b], hi[b]))
                continue;
            double p[3], q[3];
            direction(a, bb, p);
            direction(a0, b0, q);
            double cx = p[1] * q[2] - p[2] * q[1], cy = p[2] * q[0] - p[0] * q[2],
                   cz = p[0] * q[1] - p[1] * q[0];
            double tot = atan2(sqrt(cx * cx + cy * cy + cz * cz),
                               p[0] * q[0] + p[1] * q[1] + p[2] * q[2]);
            sum[0] += (a - a0) * (a - a0);
            sum[1] += (bb - b0) * (bb - b0);
            sum[2] += tot * tot;
            n++;
        }
        assert_true(n > 4);
        for (int k = 0; k < 3; k++) {
            char col[64];
            snprintf(col, sizeof col, "rms_before_%s_%g_%g_arcsec", angle[k], lo[b], hi[b]);
            expect_g6(tsv_num(u, 0, col), sqrt(sum[k] / n) * r2s, col);
        }
    }
    tsv_free(u);
    csv_free(v);
}

/* A noise-free DSS unit's fit recovers its drawn deviations: units.tsv's
 * fit_* columns against its deviation columns. */
static void dss_fit_columns_are_deviations(void **state)
{
    (void)state;
    char path[256];
    run_ok("%s run configs/dss.ini --units 4 --quiet " DSS_SMALL
           " --set noise.centroid_px=0 --set noise.encoder_arcsec=0 --set noise.s_curve=off"
           " --set tolerance.glass_index=0 --set calibration.fit_glass_index=off"
           " --set tolerance.dh_px=3 --set tolerance.dx_px=2 --set tolerance.dy_px=2"
           " --set tolerance.c1_arcsec=200 --set tolerance.c2_arcsec=200"
           " --set tolerance.c3_arcsec=200 --set tolerance.glass_thickness_um=20"
           " --set tolerance.prnu_pct=0 --set tolerance.dsnu_pct=0 --set tolerance.glass_ghost=0"
           " --out %s/dss_fit%s",
           dir, "");
    snprintf(path, sizeof path, "%s/dss_fit/units.tsv", dir);
    tsv *u = tsv_load(path);
    const char *pairs[7][2] = {{"fit_dx_px", "dx_px"},       {"fit_dy_px", "dy_px"},
                               {"fit_dh_px", "dh_px"},       {"fit_c1_arcsec", "c1_arcsec"},
                               {"fit_c2_arcsec", "c2_arcsec"}, {"fit_c3_arcsec", "c3_arcsec"},
                               {"fit_glass_thickness_um", "glass_thickness_um"}};
    const double tol[7] = {1e-4, 1e-4, 1e-3, 0.05, 0.05, 0.05, 0.05};
    for (int r = 0; r < u->nr; r++) {
        assert_string_equal(tsv_str(u, r, "fit_status"), "ok");
        for (int k = 0; k < 7; k++) {
            double fit = tsv_num(u, r, pairs[k][0]), dev = tsv_num(u, r, pairs[k][1]);
            if (!(fabs(fit - dev) <= tol[k]))
                fail_msg("unit %d: %s = %g, drawn %s = %g", r, pairs[k][0], fit, pairs[k][1], dev);
        }
        assert_near(tsv_num(u, r, "fit_glass_index"), 0.0, 0);
    }
    tsv_free(u);
}

/* ---- budget.tsv against runs of the same configs ---- */

static void summary_row_of(const char *run_dir, const char *angle, const char *band,
                           double *before, double *after, double *yield)
{
    char path[256];
    snprintf(path, sizeof path, "%s/summary.tsv", run_dir);
    tsv *s = tsv_load(path);
    for (int r = 0; r < s->nr; r++)
        if (strcmp(tsv_str(s, r, "angle"), angle) == 0 && strcmp(tsv_str(s, r, "band"), band) == 0) {
            *before = tsv_num(s, r, "rms_before_mean");
            *after = tsv_num(s, r, "rms_after_mean");
            *yield = tsv_num(s, r, "spec_yield"); /* the studies judge by the spec */
            tsv_free(s);
            return;
        }
    fail_msg("%s: no row %s %s", path, angle, band);
}

static void budget_rows_are_runs(const char *cfg, const char *sets, const char *angle,
                                 const char *band, const char *name)
{
    char path[256], sub[128], args[1024];
    snprintf(sub, sizeof sub, "%s/budget_%s", dir, name);
    snprintf(args, sizeof args, "%s --units 10 --seed 3 --quiet %s", cfg, sets);
    char cmd[4000], out[1 << 15];
    snprintf(cmd, sizeof cmd, "%s budget %s --set report.budget_units=10 --set report.budget_steps=1 "
                              "--out %s",
             test_sunmc(), args, sub);
    int st = test_run(cmd, out, sizeof out);
    if (st != 0)
        fail_msg("%s: exit %d\n%s", cmd, st, out);
    snprintf(path, sizeof path, "%s/budget.tsv", sub);
    tsv *b = tsv_load(path);
    assert_true(b->nr >= 4);
    for (int r = 0; r < b->nr; r++) {
        assert_string_equal(tsv_str(b, r, "angle"), angle);
        assert_string_equal(tsv_str(b, r, "band"), band);
    }
    /* FLOOR first, INTERACTION after the sources, then the three parts of
     * the mean square after calibration (shares summing to 1); ranks 1..n
     * between: sources with a share outside the noise first, by the share
     * after calibration, then before, each counted only outside the noise
     * (worked out here) */
    assert_string_equal(tsv_str(b, 0, "source"), "FLOOR");
    assert_string_equal(tsv_str(b, b->nr - 4, "source"), "INTERACTION");
    const char *parts[3] = {"NOISE_OF_READING", "ESTIMATION", "MODEL_FORM"};
    double psum = 0;
    for (int k = 0; k < 3; k++) {
        assert_string_equal(tsv_str(b, b->nr - 3 + k, "kind"), "after_part");
        assert_string_equal(tsv_str(b, b->nr - 3 + k, "source"), parts[k]);
        assert_string_equal(tsv_str(b, b->nr - 3 + k, "share_before"), "-");
        psum += tsv_num(b, b->nr - 3 + k, "share_after");
    }
    assert_true(fabs(psum - 1.0) < 1e-5);
    double prev[3] = {0};
    for (int r = 1; r < b->nr - 4; r++) {
        assert_int_equal(atoi(tsv_str(b, r, "rank")), r);
        double key[3];
        const char *sig[2] = {"significant_after", "significant_before"};
        const char *sh[2] = {"share_after", "share_before"};
        for (int w = 0; w < 2; w++) {
            double v = tsv_num(b, r, sh[w]);
            key[1 + w] = strcmp(tsv_str(b, r, sig[w]), "yes") == 0 && fabs(v) >= 5e-5 ? v : 0;
        }
        key[0] = key[1] == 0 && key[2] == 0; /* in the noise: last */
        assert_string_equal(tsv_str(b, r, "in_noise"), key[0] ? "yes" : "no");
        if (r > 1) {
            int later = key[0] > prev[0] ||
                        (key[0] == prev[0] && (key[1] < prev[1] ||
                                               (key[1] == prev[1] && key[2] <= prev[2])));
            if (!later)
                fail_msg("%s ranked %d out of order", tsv_str(b, r, "source"), r);
        }
        memcpy(prev, key, sizeof prev);
    }
    /* all: the run itself; FLOOR: every source at 0; a source alone */
    char run[256], sets2[1024];
    double rb, ra, ry;
    snprintf(run, sizeof run, "%s/all", sub);
    snprintf(cmd, sizeof cmd, "%s run %s --out %s", test_sunmc(), args, run);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    summary_row_of(run, angle, band, &rb, &ra, &ry);
    expect_g6(tsv_num(b, 0, "all_before"), rb, "all before");
    expect_g6(tsv_num(b, 0, "all_after"), ra, "all after");
    expect_g6(tsv_num(b, 0, "all_yield"), ry, "all yield");
    char zero_all[1024] = "", one[160], key[4][96];
    for (int r = 1; r < b->nr - 4; r++) {
        const char *src = tsv_str(b, r, "source");
        int tol = strcmp(tsv_str(b, r, "kind"), "tolerance") == 0;
        snprintf(one, sizeof one, " --set %s%s=0", tol ? "tolerance." : "", src);
        strcat(zero_all, one);
        if (r < 4)
            snprintf(key[r], sizeof key[r], "%s%s", tol ? "tolerance." : "", src);
    }
    snprintf(run, sizeof run, "%s/floor", sub);
    snprintf(cmd, sizeof cmd, "%s run %s %s --out %s", test_sunmc(), args, zero_all, run);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    summary_row_of(run, angle, band, &rb, &ra, &ry);
    expect_g6(tsv_num(b, 0, "before_alone"), rb, "FLOOR before");
    expect_g6(tsv_num(b, 0, "after_alone"), ra, "FLOOR after");
    for (int r = 1; r < b->nr - 4 && r < 4; r++) {
        /* alone: every source at 0 but this one at its value */
        snprintf(sets2, sizeof sets2, "%s --set %s=%s", zero_all, key[r],
                 tsv_str(b, r, "tolerance"));
        snprintf(run, sizeof run, "%s/alone_%d", sub, r);
        snprintf(cmd, sizeof cmd, "%s run %s %s --out %s", test_sunmc(), args, sets2, run);
        assert_int_equal(test_run(cmd, out, sizeof out), 0);
        summary_row_of(run, angle, band, &rb, &ra, &ry);
        expect_g6(tsv_num(b, r, "before_alone"), rb, "before alone");
        expect_g6(tsv_num(b, r, "after_alone"), ra, "after alone");
    }
    tsv_free(b);
}

static void ess_budget_rows(void **state)
{
    (void)state;
    budget_rows_are_runs("configs/ess_type_a.ini",
                         ESS_SMALL " --set tolerance.dphi_deg=0 --set tolerance.slit_width_um=0"
                                   " --set tolerance.harmonic_phase_deg=0 --set tolerance.etch_um=0"
                                   " --set tolerance.sun_x_arcsec=0 --set tolerance.sun_y_arcsec=0"
                                   " --set tolerance.install_z_arcsec=0",
                         "alpha", "0:62", "ess");
}

static void dss_budget_rows(void **state)
{
    (void)state;
    budget_rows_are_runs("configs/dss.ini",
                         DSS_SMALL " --set tolerance.c1_arcsec=0 --set tolerance.c2_arcsec=0"
                                   " --set tolerance.glass_index=0",
                         "total", "0:60", "dss");
}

/* ---- output errors ---- */

static int dir_entries(const char *path)
{
    DIR *d = opendir(path);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

static int entries_starting(const char *path, const char *prefix);

/* A write error at commit (here: the file-size limit) fails the command
 * and leaves no file, not even a temporary (a checkpoint .full.resume is
 * kept when it holds units, on purpose: --resume writes them once there
 * is room; test_cli_lock checks both cases). */
static void run_write_error(void **state)
{
    (void)state;
    char cmd[1024], out[8192], sub[128];
    snprintf(sub, sizeof sub, "%s/full", dir);
    assert_int_equal(mkdir(sub, 0777), 0);
    snprintf(cmd, sizeof cmd,
             "trap '' XFSZ; ulimit -f 4; %s run configs/ess_type_a.ini --units 200 --quiet " ESS_SMALL
             " --set validation.alpha_step_deg=5 --set campaign.alpha_step_deg=2 --out %s",
             test_sunmc(), sub);
    int st = test_run(cmd, out, sizeof out);
    assert_int_not_equal(st, 0);
    assert_non_null(strstr(out, "write error"));
    assert_int_equal(dir_entries(sub), 0);
    assert_int_equal(entries_starting(dir, ".full.tmp"), 0);
}

/* An output path that is a regular file: refused, the file untouched. */
static void out_is_a_file(void **state)
{
    (void)state;
    char cmd[1024], out[8192], path[128];
    snprintf(path, sizeof path, "%s/plain", dir);
    assert_int_equal(test_write_file(path, "keep\n"), 0);
    snprintf(cmd, sizeof cmd, "%s run configs/ess_type_a.ini --units 2 --quiet " ESS_SMALL " --out %s",
             test_sunmc(), path);
    assert_int_not_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "not a directory"));
    FILE *f = fopen(path, "r");
    char text[16] = "";
    assert_non_null(fgets(text, sizeof text, f));
    fclose(f);
    assert_string_equal(text, "keep\n");
}

/* Entries of dir whose names start with prefix. */
static int entries_starting(const char *path, const char *prefix)
{
    DIR *d = opendir(path);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
    closedir(d);
    return n;
}

/* out_commit on streams whose writes fail: the error is reported, nothing
 * is moved into place and the temporary directory is gone. */
static void commit_detects_write_errors(void **state)
{
    (void)state;
    for (int unbuffered = 0; unbuffered < 2; unbuffered++) {
        char sub[128], name[32], err[SUNMC_ERRLEN] = "";
        snprintf(name, sizeof name, "commit%d", unbuffered);
        snprintf(sub, sizeof sub, "%s/%s", dir, name);
        out_set os;
        FILE *good, *bad;
        assert_int_equal(out_begin(&os, sub, err, sizeof err), SUNMC_OK);
        assert_int_equal(out_open(&os, "good.tsv", &good, err, sizeof err), SUNMC_OK);
        assert_int_equal(out_open(&os, "bad.tsv", &bad, err, sizeof err), SUNMC_OK);
        int full = open("/dev/full", O_WRONLY);
        assert_true(full >= 0);
        assert_true(dup2(full, fileno(bad)) >= 0);
        close(full);
        if (unbuffered)
            setvbuf(bad, NULL, _IONBF, 0); /* the error shows on the stream at once */
        fprintf(good, "a\tb\n1\t2\n");
        fprintf(bad, "a\tb\n1\t2\n"); /* buffered: the error shows when flushed */
        assert_int_equal(out_commit(&os, err, sizeof err), SUNMC_EIO);
        assert_non_null(strstr(err, "bad.tsv: write error"));
        assert_int_equal(dir_entries(sub), -1); /* not created */
        char tmp[40];
        snprintf(tmp, sizeof tmp, ".%s.", name);
        assert_int_equal(entries_starting(dir, tmp), 0);
    }
    /* a set that writes fine is moved into place, with its marker */
    char sub[128], err[SUNMC_ERRLEN];
    snprintf(sub, sizeof sub, "%s/commit_ok", dir);
    out_set os;
    FILE *f;
    assert_int_equal(out_begin(&os, sub, err, sizeof err), SUNMC_OK);
    assert_int_equal(out_open(&os, "x.tsv", &f, err, sizeof err), SUNMC_OK);
    fprintf(f, "x\n1\n");
    assert_int_equal(out_commit(&os, err, sizeof err), SUNMC_OK);
    assert_int_equal(dir_entries(sub), 2);
    /* out_abort leaves the directory as it was and removes the temporary */
    assert_int_equal(out_begin(&os, sub, err, sizeof err), SUNMC_OK);
    assert_int_equal(out_open(&os, "y.tsv", &f, err, sizeof err), SUNMC_OK);
    fprintf(f, "y\n");
    out_abort(&os);
    assert_int_equal(dir_entries(sub), 2);
    assert_int_equal(entries_starting(dir, ".commit_ok."), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ess_summary_and_table),
        cmocka_unit_test(dss_summary_and_table),
        cmocka_unit_test(ess_before_from_validation),
        cmocka_unit_test(dss_before_from_validation),
        cmocka_unit_test(dss_fit_columns_are_deviations),
        cmocka_unit_test(ess_budget_rows),
        cmocka_unit_test(dss_budget_rows),
        cmocka_unit_test(run_write_error),
        cmocka_unit_test(out_is_a_file),
        cmocka_unit_test(commit_detects_write_errors),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
