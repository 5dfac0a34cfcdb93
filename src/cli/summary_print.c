/* summary_print.c - Table 1 and the tables after it, for people
 * (summary_print.h), through the one table printer (table.h). */
#include "summary_print.h"
#include "campaign.h"
#include "sampling.h"
#include "table.h"
#include "thermal.h"
#include "verdict.h"
#include "status.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* Columns (in rows, at offsetof) holding an interval: decimals that show the
 * narrowest half-width (times scale) to two significant digits, from prec
 * to prec + 3. */
static int ci_decimals(const summary_row *rows, int n, size_t ci_offset, double scale, int prec)
{
    double h = INFINITY;
    for (int i = 0; i < n; i++) {
        const stats_interval *ci = (const stats_interval *)((const char *)&rows[i] + ci_offset);
        double half = 0.5 * (ci->hi - ci->lo) * scale;
        if (isfinite(half) && half > 0)
            h = fmin(h, half);
    }
    int d = isfinite(h) ? (int)ceil(-log10(h)) + 1 : prec;
    return d < prec ? prec : d > prec + 3 ? prec + 3 : d;
}

/* "v [lo, hi]" with d decimals (a bound that cannot be had is "-"), values
 * times scale, `unit` after the estimate; "- [-, -]" without an estimate. */
static void fmt_estimate(char *buf, size_t len, double v, stats_interval ci, int d, double scale,
                         const char *unit)
{
    char lo[32] = "-", hi[32] = "-";
    if (!isnan(ci.lo))
        snprintf(lo, sizeof lo, "%.*f", d, ci.lo * scale);
    if (!isnan(ci.hi))
        snprintf(hi, sizeof hi, "%.*f", d, ci.hi * scale);
    if (isfinite(v))
        snprintf(buf, len, "%.*f%s [%s, %s]", d, v * scale, unit, lo, hi);
    else
        snprintf(buf, len, "- [%s, %s]", lo, hi);
}

/* A table of ncols columns and n rows, NULL when out of memory. */
static table *table_of(int ncols, int n)
{
    table *t = table_new(ncols);
    for (int i = 0; t && i < n; i++)
        if (table_row(t) < 0) {
            table_free(t);
            return NULL;
        }
    return t;
}

/* Angle and band label columns at col0 and col0 + 1. */
static void label_columns(const sunmc_config *c, const sensor_family *fam,
                          const summary_row *rows, int n, table *t, int col0)
{
    char h[TABLE_CELL];
    report_band_head(fam, h, sizeof h);
    table_head(t, col0, "angle", "", TABLE_LEFT);
    table_head(t, col0 + 1, "band", h, TABLE_LEFT);
    for (int i = 0; i < n; i++) {
        table_set(t, i, col0, "%s", fam->angle_names[rows[i].angle]);
        report_band_label(c, rows[i].band, table_cell(t, i, col0 + 1), TABLE_CELL);
        if (rows[i].no_reading_units > 0)
            strcat(table_cell(t, i, col0 + 1), "*");
    }
}

/* The paper's Table 1 (RMS after max/min, improvement mean/max/min) and p95. */
static void print_table1(FILE *f, const sunmc_config *c, const sensor_family *fam,
                         const summary_row *rows, int n, int prec)
{
    char h[TABLE_CELL], pct[24];
    table *t = table_of(8, n);
    if (!t)
        return;
    report_ci_label(c, pct, sizeof pct);
    label_columns(c, fam, rows, n, t, 0);
    snprintf(h, sizeof h, "max [%s]", fam->rms_unit);
    table_head(t, 2, "RMS after", h, TABLE_BAR);
    snprintf(h, sizeof h, "min [%s]", fam->rms_unit);
    table_head(t, 3, "RMS after", h, 0);
    snprintf(h, sizeof h, "mean %s", pct);
    table_head(t, 4, "times improvement", h, TABLE_BAR);
    table_head(t, 5, "improvement", "max", 0);
    table_head(t, 6, "improvement", "min", 0);
    snprintf(h, sizeof h, "[%s] %s", fam->rms_unit, pct);
    table_head(t, 7, "p95 of RMS after", h, TABLE_BAR);
    int di = ci_decimals(rows, n, offsetof(summary_row, improvement_mean_ci), 1.0, 2);
    int dp = ci_decimals(rows, n, offsetof(summary_row, rms_after_p95_ci), 1.0, prec);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        report_format_number(table_cell(t, i, 2), TABLE_CELL, r->rms_after_max, prec);
        report_format_number(table_cell(t, i, 3), TABLE_CELL, r->rms_after_min, prec);
        fmt_estimate(table_cell(t, i, 4), TABLE_CELL, r->improvement_mean, r->improvement_mean_ci, di,
                     1.0, "");
        report_format_number(table_cell(t, i, 5), TABLE_CELL, r->improvement_max, 2);
        report_format_number(table_cell(t, i, 6), TABLE_CELL, r->improvement_min, 2);
        fmt_estimate(table_cell(t, i, 7), TABLE_CELL, r->rms_after_p95, r->rms_after_p95_ci, dp, 1.0,
                     "");
    }
    table_print(f, t);
    table_free(t);
}

/* Mean RMS before, after and its systematic part, and the yield. */
static void print_means(FILE *f, const sunmc_config *c, const sensor_family *fam,
                        const summary_row *rows, int n, int prec)
{
    table *t = table_of(7, n);
    if (!t)
        return;
    static const char *const heads[3] = {"mean RMS before", "mean RMS after",
                                         "systematic part of after"};
    const size_t off[3] = {offsetof(summary_row, rms_before_mean_ci),
                           offsetof(summary_row, rms_after_mean_ci),
                           offsetof(summary_row, rms_after_sys_mean_ci)};
    char h[TABLE_CELL];
    char level[32];
    report_ci_label(c, level, sizeof level);
    snprintf(h, sizeof h, "[%s] %s", fam->rms_unit, level);
    label_columns(c, fam, rows, n, t, 0);
    for (int k = 0; k < 3; k++)
        table_head(t, 2 + k, heads[k], h, k == 0 ? TABLE_BAR : 0);
    report_ci_label(c, h, sizeof h);
    table_head(t, 5, "yield", h, TABLE_BAR);
    table_head(t, 6, "made worse", h, TABLE_BAR);
    int d[3];
    for (int k = 0; k < 3; k++)
        d[k] = ci_decimals(rows, n, off[k], 1.0, prec);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        const double v[3] = {r->rms_before_mean, r->rms_after_mean, r->rms_after_sys_mean};
        const stats_interval ci[3] = {r->rms_before_mean_ci, r->rms_after_mean_ci,
                                      r->rms_after_sys_mean_ci};
        for (int k = 0; k < 3; k++)
            fmt_estimate(table_cell(t, i, 2 + k), TABLE_CELL, v[k], ci[k], d[k], 1.0, "");
        fmt_estimate(table_cell(t, i, 5), TABLE_CELL, r->yield, r->yield_ci,
                     report_percent_decimals(r->yield, 1), 100.0, "%");
        fmt_estimate(table_cell(t, i, 6), TABLE_CELL, r->worse, r->worse_ci,
                     report_percent_decimals(r->worse, 1), 100.0, "%");
    }
    table_print(f, t);
    table_free(t);
}

#define PERCENT 100.0

/* The range of a count over rows[n] (the long at byte offset off of each
 * row) as text, "200" or "180-200", into buf; its largest value. */
static long count_range(const summary_row *rows, int n, size_t off, char *buf, size_t len)
{
    long lo = 0, hi = 0;
    for (int i = 0; i < n; i++) {
        long k = *(const long *)(const void *)((const char *)&rows[i] + off);
        lo = i == 0 || k < lo ? k : lo;
        hi = i == 0 || k > hi ? k : hi;
    }
    snprintf(buf, len, lo == hi ? "%ld" : "%ld-%ld", lo, hi);
    return hi;
}

/* What calibration leaves (modelform.h): the model-form part and the after
 * mean square split into the reading's noise, the calibration's
 * estimation error and model form, on the units with the model-form pass. */
static void print_floor(FILE *f, const sunmc_config *c, const sensor_family *fam,
                        const summary_row *rows, int n, int prec)
{
    char h[TABLE_CELL], pct[24], nk[64];
    if (count_range(rows, n, offsetof(summary_row, mf_units), nk, sizeof nk) == 0)
        return;
    table *t = table_of(6, n);
    if (!t)
        return;
    report_ci_label(c, pct, sizeof pct);
    snprintf(h, sizeof h, "[%s] %s", fam->rms_unit, pct);
    label_columns(c, fam, rows, n, t, 0);
    table_head(t, 2, "model-form part", h, TABLE_BAR);
    static const char *const heads[3] = {"noise of reading", "estimation", "model form"};
    for (int k = 0; k < 3; k++)
        table_head(t, 3 + k, heads[k], pct, k == 0 ? TABLE_BAR : 0);
    int d = ci_decimals(rows, n, offsetof(summary_row, rms_after_mf_mean_ci), 1.0, prec);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        fmt_estimate(table_cell(t, i, 2), TABLE_CELL, r->rms_after_mf_mean, r->rms_after_mf_mean_ci,
                     d, 1.0, "");
        const double v[3] = {r->share_noise, r->share_estimation, r->share_model_form};
        const stats_interval ci[3] = {r->share_noise_ci, r->share_estimation_ci,
                                      r->share_model_form_ci};
        for (int k = 0; k < 3; k++)
            fmt_estimate(table_cell(t, i, 3 + k), TABLE_CELL, v[k], ci[k], 1, PERCENT, "%");
    }
    fprintf(f, "\nwhat calibration leaves: the mean square after calibration in three parts, "
               "on the %s units\nwith the model-form pass (one in %ld: "
               "report.model_form_every):\n",
            nk, c->model_form_every);
    table_print(f, t);
    table_free(t);
    fprintf(f, "Model-form part: after-RMS of the unit calibrated on its campaign without noise "
               "and read\nwithout noise: what the calibration model cannot represent.  Noise "
               "of reading: after^2 - systematic^2;\nestimation (the campaign's noise through "
               "the fit): systematic^2 - model form^2; model form^2.\nShares of the mean "
               "square, ratio of means with delta-method intervals (docs/statistics.md).\n");
}

/* A row's temperature as the tables show it: "20 (lab)", "-30", "worst". */
static void temp_label(const summary_row *r, char *buf, size_t len)
{
    if (r->condition == REPORT_WORST)
        snprintf(buf, len, "worst");
    else
        snprintf(buf, len, "%g%s", r->temp_c, r->condition == REPORT_LAB ? " (lab)" : "");
}

/* The range of the operating temperatures, "-30..60 C". */
static void range_label(const sunmc_config *c, char *buf, size_t len)
{
    int nt = thermal_n_temps(c);
    double lo = INFINITY, hi = -INFINITY;
    for (int t = 0; t < nt; t++) {
        lo = fmin(lo, thermal_temp_c(c, t));
        hi = fmax(hi, thermal_temp_c(c, t));
    }
    if (lo == hi)
        snprintf(buf, len, "%g C", lo);
    else
        snprintf(buf, len, "%g..%g C", lo, hi);
}

/* Validation at the operating temperatures: every set of rows (lab, each
 * temperature, worst over them) with mean RMS before/after, p95, max and
 * yield; then the yield over the range beside the lab's. */
static void print_thermal(FILE *f, const sunmc_config *c, const sensor_family *fam,
                          const summary_row *rows, int prec)
{
    int n = report_n_rows(c);
    table *t = table_of(8, n);
    if (!t)
        return;
    char h[TABLE_CELL], pct[24], range[64];
    range_label(c, range, sizeof range);
    report_ci_label(c, pct, sizeof pct);
    fprintf(f, "\nvalidation at the operating temperatures (environment.operating_temp_c), "
               "calibrated at %g C;\nworst = each unit's worst RMS over %s, passing only where "
               "it passes at every temperature:\n",
            c->cal_temp_c, range);
    table_head(t, 0, "temp", "C", TABLE_LEFT);
    for (int i = 0; i < n; i++)
        temp_label(&rows[i], table_cell(t, i, 0), TABLE_CELL);
    label_columns(c, fam, rows, n, t, 1);
    snprintf(h, sizeof h, "[%s] %s", fam->rms_unit, pct);
    table_head(t, 3, "mean RMS before", h, TABLE_BAR);
    table_head(t, 4, "mean RMS after", h, TABLE_BAR);
    table_head(t, 5, "p95 of RMS after", h, 0);
    snprintf(h, sizeof h, "[%s]", fam->rms_unit);
    table_head(t, 6, "max RMS after", h, 0);
    table_head(t, 7, "yield", pct, TABLE_BAR);
    int db = ci_decimals(rows, n, offsetof(summary_row, rms_before_mean_ci), 1.0, prec);
    int da = ci_decimals(rows, n, offsetof(summary_row, rms_after_mean_ci), 1.0, prec);
    int dp = ci_decimals(rows, n, offsetof(summary_row, rms_after_p95_ci), 1.0, prec);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        fmt_estimate(table_cell(t, i, 3), TABLE_CELL, r->rms_before_mean, r->rms_before_mean_ci, db,
                     1.0, "");
        fmt_estimate(table_cell(t, i, 4), TABLE_CELL, r->rms_after_mean, r->rms_after_mean_ci, da,
                     1.0, "");
        fmt_estimate(table_cell(t, i, 5), TABLE_CELL, r->rms_after_p95, r->rms_after_p95_ci, dp, 1.0,
                     "");
        report_format_number(table_cell(t, i, 6), TABLE_CELL, r->rms_after_max, prec);
        fmt_estimate(table_cell(t, i, 7), TABLE_CELL, r->yield, r->yield_ci,
                     report_percent_decimals(r->yield, 1), PERCENT, "%");
    }
    table_print(f, t);
    table_free(t);
    int wb = report_widest_band(c);
    for (int a = 0; a < fam->n_angles(c); a++) {
        const summary_row *w = &rows[report_primary_row(c, a, wb)];
        const summary_row *l = &rows[a * c->bands_deg.n + wb];
        char band[32], yw[96], yl[96];
        report_band_label(c, wb, band, sizeof band);
        fmt_estimate(yw, sizeof yw, w->yield, w->yield_ci, report_percent_decimals(w->yield, 1),
                     PERCENT, "%");
        fmt_estimate(yl, sizeof yl, l->yield, l->yield_ci, report_percent_decimals(l->yield, 1),
                     PERCENT, "%");
        fprintf(f, "yield over %s (at every temperature), %s %s: %s   at the lab's %g C: %s\n",
                range, fam->angle_names[a], band, yw, c->cal_temp_c, yl);
    }
}

void summary_print_campaign(FILE *f, const sunmc_config *c)
{
    campaign_info ci;
    char err[SUNMC_ERRLEN], text[2 * SUNMC_ERRLEN];
    if (campaign_describe(c, &ci, err, sizeof err) != SUNMC_OK || !ci.known)
        return;
    fprintf(f,
            "campaign: %ld points on %ld lines, %d reading%s each: %.2f turntable hours "
            "(campaign.dwell_s, point_settle_s, line_settle_s, slew_deg_per_s)\n",
            ci.points, ci.lines, c->cal_repeats, c->cal_repeats == 1 ? "" : "s", ci.hours);
    campaign_extrapolation_text(&ci, c->family->grid->axis_names, text, sizeof text);
    if (text[0])
        fprintf(f, "WARNING: %s: the calibration is extrapolated there; let the campaign "
                   "cover the validation angles\n",
                text);
}

/* Rows whose statistics leave out units that have a fit (marked "*"). */
static void warn_no_reading(FILE *f, const sunmc_config *c, const sensor_family *fam,
                            const summary_row *rows, int n)
{
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        if (r->no_reading_units == 0)
            continue;
        char band[32];
        report_band_label(c, r->band, band, sizeof band);
        fprintf(f,
                "* %s %s: statistics over %ld of %ld units: %ld units with a fit have no usable "
                "reading in this band (every reading a gross error, or the sun not seen there)"
                " and count as failing in its yield\n",
                fam->angle_names[r->angle], band, r->stat_units, r->units, r->no_reading_units);
    }
}

/* Loud warnings about a result that is doubtful as a whole: calibration
 * that makes units worse, a campaign most units cannot resolve. */
/* Under a sampling design: how the intervals come about, and a warning
 * when too few blocks leave the means without one. */
static void print_design(FILE *f, const sunmc_config *c, long units)
{
    static const char *const names[] = {"random", "Latin hypercube", "Sobol' (digitally shifted)"};
    if (c->sampling == CONFIG_SAMPLING_RANDOM)
        return;
    fprintf(f,
            "Tolerance draws: %s design in blocks of %ld units (run.sampling); the means'\n"
            "intervals are Student t over the block totals, the yield's and p95's never "
            "narrower than for independent units (docs/statistics.md).\n",
            names[c->sampling], c->sampling_block);
    if (units <= c->sampling_block)
        fprintf(f, "WARNING: %ld units in design blocks of %ld: with one block the means have\n"
                   "no interval ('-'); run at least %ld units, or lower run.sampling_block.\n",
                units, c->sampling_block, 2 * c->sampling_block);
}

static void print_warnings(FILE *f, const sunmc_config *c, const sensor_family *fam,
                           const summary_row *rows, int n)
{
    print_design(f, c, rows[0].units);
    warn_no_reading(f, c, fam, rows, n);
    for (int i = 0; i < n; i++)
        if (rows[i].stat_units == 0) {
            fprintf(f,
                    "WARNING: no statistic ('-') where no unit has a fit and a reading: %ld of "
                    "%ld units' fits failed; the yield counts them as failing.  Look at the "
                    "fit status in units.tsv, or calibrate one unit with `simulate` and "
                    "`calibrate` to see why.\n",
                    rows[0].fit_failures, rows[0].units);
            break;
        }
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        if (!(r->rms_after_mean > r->rms_before_mean))
            continue;
        char band[32];
        report_band_label(c, r->band, band, sizeof band);
        fprintf(f,
                "WARNING: calibration makes the units worse: in %s %s the mean RMS after "
                "(%.4g %s) exceeds the mean RMS before (%.4g %s), mean improvement %.2fx.  The "
                "campaign does not determine the model where the units are validated: make the "
                "campaign cover the validation range and the field of view, with a step that "
                "resolves every term of the model.\n",
                fam->angle_names[r->angle], band, r->rms_after_mean, fam->rms_unit,
                r->rms_before_mean, fam->rms_unit, r->improvement_mean);
        break;
    }
    if (fam->alias_term && rows[0].units > 0 && 2 * rows[0].alias_units > rows[0].units)
        fprintf(f,
                "WARNING: %ld of %ld units (%.0f%%) could not resolve %s from their campaign: "
                "it is held at 0 (calibration.alias_threshold) and its error stays in the RMS "
                "after.  Change the campaign step so that it samples the term at more phases.\n",
                rows[0].alias_units, rows[0].units,
                100.0 * (double)rows[0].alias_units / (double)rows[0].units, fam->alias_term);
}

/* The yield under the spec (verdict.h), the rule it judged by, per
 * measured angle; the studies' angle first named. */
static void print_spec(FILE *f, const sunmc_config *c, const sensor_family *fam,
                       const summary_row *rows)
{
    char rule[256];
    verdict_rule_text(c, rule, sizeof rule);
    fprintf(f, "YIELD under the spec: %s; the band rows above judge each band alone\n", rule);
    for (int a = 0; a < fam->n_angles(c); a++) {
        const summary_row *r = &rows[report_primary_row(c, a, 0)];
        char y[96];
        fmt_estimate(y, sizeof y, r->spec_yield, r->spec_yield_ci,
                     report_percent_decimals(r->spec_yield, 1), PERCENT, "%");
        fprintf(f, "  %-6s %s%s\n", fam->angle_names[a], y,
                a == verdict_angle(c) ? "   (the yield budget, design and allocate use)" : "");
    }
    if (c->spec_statistic == VERDICT_RMS)
        return;
    fprintf(f, "  validation points per band:");
    for (int b = 0; b < c->bands_deg.n; b++) {
        char band[32];
        report_band_label(c, b, band, sizeof band);
        fprintf(f, " %s %ld%s", band, rows[b].band_points, b + 1 < c->bands_deg.n ? "," : "");
    }
    fprintf(f, "; %s over n points is the %s\n", verdict_statistic_name(c),
            c->spec_statistic == VERDICT_MAX
                ? "largest |error|"
                : "ceil(0.9973 n)-th smallest |error| (the largest up to 370 points, the "
                  "second largest up to 740)");
}

void summary_print(FILE *f, const sunmc_config *c, const summary_row *rows)
{
    const sensor_family *fam = c->family;
    int n = report_n_lab_rows(c);
    const char *u = fam->rms_unit;
    const int prec = report_decimals(fam);
    char model[256];
    fam->model_label(c, model, sizeof model);
    char spec[64] = "";
    if (strcmp(u, "arcsec") != 0) /* the spec in the table's unit too */
        snprintf(spec, sizeof spec, " = %.*f %s", prec + 1,
                 c->spec_arcsec / fam->arcsec_per_rms_unit, u);
    fprintf(f, "\n%s (%s): %ld units, seed %ld, spec %g arcsec%s\ncalibration model: %s\n",
            c->product, fam->name, rows[0].units, c->seed, c->spec_arcsec, spec, model);
    summary_print_campaign(f, c);
    print_table1(f, c, fam, rows, n, prec);
    fputc('\n', f);
    print_means(f, c, fam, rows, n, prec);
    char nk[64];
    count_range(rows, n, offsetof(summary_row, stat_units), nk, sizeof nk);
    fprintf(f,
            "%g%% intervals: means and improvement Student t over the n = %s units with a fit,\n"
            "p95 distribution-free order statistics (estimate: Hyndman-Fan type 7), yield %s\n"
            "(report.yield_interval) over all %ld units (a failed fit fails); max/min over the\n"
            "same n, no interval.\n"
            "Systematic part: after-RMS of the same validation points read without noise.\n"
            "Made worse: share of those units whose RMS after exceeds their RMS before "
            "(Wilson).\n",
            100.0 * c->confidence, nk, report_yield_interval_name(c), rows[0].units);
    fprintf(f, "RMS in %s.  fit failures: %ld   gross errors (validation readings): %ld", u,
            rows[0].fit_failures, rows[0].gross_errors);
    if (fam->alias_term)
        fprintf(f, "   units whose campaign aliases %s: %ld", fam->alias_term, rows[0].alias_units);
    fputc('\n', f);
    print_floor(f, c, fam, rows, n, prec);
    print_warnings(f, c, fam, rows, n);
    if (thermal_n_temps(c) > 0)
        print_thermal(f, c, fam, rows, prec);
    print_spec(f, c, fam, rows);
}

