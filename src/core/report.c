/* report.c - statistics over units and the TSV / table writers. */
#include "report.h"
#include "campaign.h"
#include "sampling.h"
#include "stats_blocks.h"
#include "thermal.h"
#include "status.h"

#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#define REPORT_PERCENTILE 0.95

int report_decimals(const sensor_family *fam)
{
    if (fam->rms_decimals > 0)
        return fam->rms_decimals;
    return strcmp(fam->rms_unit, "deg") == 0 ? 4 : 2;
}

void report_ci_label(const sunmc_config *c, char *buf, size_t len)
{
    snprintf(buf, len, "[%g%% CI]", 100.0 * c->confidence);
}

int report_percent_decimals(double frac, int min_decimals)
{
    int d = min_decimals;
    for (; d < 6; d++) {
        char t[32];
        snprintf(t, sizeof t, "%.*f", d, 100.0 * frac);
        double shown = strtod(t, NULL);
        if (!((frac < 1 && shown >= 100) || (frac > 0 && shown <= 0)))
            break;
    }
    return d;
}

/* Sets of rows: the lab's; with operating temperatures, one per
 * temperature and the worst over them. */
static int n_sets(const sunmc_config *c)
{
    int nt = thermal_n_temps(c);
    return nt > 0 ? nt + 2 : 1;
}

int report_n_rows(const sunmc_config *c, const sensor_family *fam)
{
    return fam->n_angles(c) * c->bands_deg.n * n_sets(c);
}

int report_n_lab_rows(const sunmc_config *c, const sensor_family *fam)
{
    return fam->n_angles(c) * c->bands_deg.n;
}

int report_primary_row(const sunmc_config *c, const sensor_family *fam, int angle, int band)
{
    int nt = thermal_n_temps(c);
    int set = nt > 0 ? nt + 1 : 0;
    return (set * fam->n_angles(c) + angle) * c->bands_deg.n + band;
}

void report_band_label(const sunmc_config *c, int i, char *buf, size_t len)
{
    snprintf(buf, len, "%g:%g", c->bands_deg.lo[i], c->bands_deg.hi[i]);
}

/* What the statistics of one angle and band keep while units stream by:
 * running moments for the means, max/min of the improvement, the pass count,
 * and the RMS after of every unit with a value (the p95 needs them all). */
typedef struct {
    stats_moments before, after, sys, ratio;
    long pass;           /* units meeting the spec */
    long no_reading;     /* units with a fit but no usable reading in the band */
    long worse;          /* units whose RMS after exceeds their RMS before */
    double imp_max, imp_min;
    double *after_v;     /* after values, arrival order until sorted */
    double *block_v;     /* their sampling blocks (a design only, sampling.h) */
    size_t cap;
    /* a sampling design's block totals (sampling.h): the means' and the
     * yield's intervals come from them (stats_blocks.h) */
    stats_blocks b_before, b_after, b_sys, b_ratio, b_pass;
} band_cell;

struct report_acc {
    const sunmc_config *c;
    const sensor_family *fam;
    int na, nb, nt;      /* angles, bands, operating temperatures (thermal.h) */
    double spec;         /* report.spec_arcsec in the rms unit */
    long n, gross, alias, failed;
    campaign_info campaign;
    /* set-major: the lab's, each operating temperature, the worst over them */
    band_cell cell[(UNIT_MAX_TEMPS + 2) * UNIT_MAX_ANGLES * CONFIG_BANDS_MAX];
};

report_acc *report_acc_new(const sunmc_config *c, const sensor_family *fam)
{
    report_acc *a = calloc(1, sizeof *a);
    if (!a)
        return NULL;
    a->c = c;
    a->fam = fam;
    a->na = fam->n_angles(c);
    a->nb = c->bands_deg.n;
    a->nt = thermal_n_temps(c);
    a->spec = c->spec_arcsec / fam->arcsec_per_rms_unit;
    char err[SUNMC_ERRLEN];
    if (campaign_describe(c, &a->campaign, err, sizeof err) != SUNMC_OK) {
        free(a);
        return NULL;
    }
    for (int i = 0; i < a->na * a->nb * n_sets(c); i++) {
        band_cell *s = &a->cell[i];
        s->imp_max = -INFINITY;
        s->imp_min = INFINITY;
        stats_blocks_init(&s->b_before);
        stats_blocks_init(&s->b_after);
        stats_blocks_init(&s->b_sys);
        stats_blocks_init(&s->b_ratio);
        stats_blocks_init(&s->b_pass);
    }
    return a;
}

void report_acc_free(report_acc *a)
{
    if (!a)
        return;
    for (int i = 0; i < a->na * a->nb * n_sets(a->c); i++) {
        free(a->cell[i].after_v);
        free(a->cell[i].block_v);
    }
    free(a);
}

long report_acc_units(const report_acc *a)
{
    return a->n;
}

/* Room for one more after value (and its block under a design). */
static int cell_grow(band_cell *s, long block)
{
    if ((size_t)s->after.n < s->cap)
        return SUNMC_OK;
    size_t cap = s->cap ? s->cap + s->cap / 2 : 256;
    double *v = realloc(s->after_v, cap * sizeof *v);
    if (!v)
        return SUNMC_ENOMEM;
    s->after_v = v;
    if (block >= 0) {
        double *b = realloc(s->block_v, cap * sizeof *b);
        if (!b)
            return SUNMC_ENOMEM;
        s->block_v = b;
    }
    s->cap = cap;
    return SUNMC_OK;
}

/* A design's block totals of one unit (block >= 0; sampling.h). */
static void cell_add_blocks(band_cell *s, long block, double bef, double aft, double sys)
{
    stats_blocks_add(&s->b_before, block, bef);
    stats_blocks_add(&s->b_after, block, aft);
    stats_blocks_add(&s->b_ratio, block, bef / aft);
    if (isfinite(sys))
        stats_blocks_add(&s->b_sys, block, sys);
    s->block_v[s->after.n] = (double)block;
}

/* One unit's RMS before, after and its systematic part (NaN: none) in a
 * cell, the unit in sampling block `block` (-1: independent units); a unit
 * without a fit only counts in the yield's denominator (a fail). */
static int cell_add(band_cell *s, long block, int fit_ok, double bef, double aft, double sys,
                    double spec)
{
    int usable = fit_ok && isfinite(bef) && isfinite(aft);
    if (block >= 0)
        stats_blocks_add(&s->b_pass, block, usable && aft <= spec ? 1.0 : 0.0);
    if (!fit_ok)
        return SUNMC_OK;
    if (!usable) {
        s->no_reading++;
        return SUNMC_OK;
    }
    if (cell_grow(s, block) != SUNMC_OK)
        return SUNMC_ENOMEM;
    if (block >= 0)
        cell_add_blocks(s, block, bef, aft, sys);
    s->after_v[s->after.n] = aft;
    stats_moments_add(&s->before, bef);
    stats_moments_add(&s->after, aft);
    stats_moments_add(&s->ratio, bef / aft);
    s->imp_max = fmax(s->imp_max, bef / aft);
    s->imp_min = fmin(s->imp_min, bef / aft);
    s->pass += aft <= spec;
    s->worse += aft > bef;
    if (isfinite(sys))
        stats_moments_add(&s->sys, sys);
    return SUNMC_OK;
}

/* A unit's cells at the operating temperatures and the worst over them. */
static int thermal_add(report_acc *acc, const unit_result *ur, int a, int b)
{
    int ok = ur->fit_status == UNIT_FIT_OK, nab = acc->na * acc->nb, i = a * acc->nb + b;
    long blk = sampling_block_of(acc->c, ur->unit);
    for (int t = 0; t < acc->nt; t++)
        if (cell_add(&acc->cell[(1 + t) * nab + i], blk, ok, ur->rms_before_t[t][a][b],
                     ur->rms_after_t[t][a][b], NAN, acc->spec) != SUNMC_OK)
            return SUNMC_ENOMEM;
    return cell_add(&acc->cell[(1 + acc->nt) * nab + i], blk, ok,
                    thermal_worst(ur->rms_before_t, acc->nt, a, b),
                    thermal_worst(ur->rms_after_t, acc->nt, a, b), NAN, acc->spec);
}

int report_acc_add(report_acc *acc, const unit_result *results, long n)
{
    for (long u = 0; u < n; u++) {
        const unit_result *ur = &results[u];
        acc->n++;
        acc->gross += ur->gross_val;
        acc->alias += ur->alias_weak > 0;
        acc->failed += ur->fit_status != UNIT_FIT_OK;
        for (int a = 0; a < acc->na; a++)
            for (int b = 0; b < acc->nb; b++)
                if (cell_add(&acc->cell[a * acc->nb + b], sampling_block_of(acc->c, ur->unit),
                             ur->fit_status == UNIT_FIT_OK,
                             ur->rms_before[a][b], ur->rms_after[a][b], ur->rms_after_sys[a][b],
                             acc->spec) != SUNMC_OK ||
                    (acc->nt > 0 && thermal_add(acc, ur, a, b) != SUNMC_OK))
                    return SUNMC_ENOMEM;
    }
    return SUNMC_OK;
}

/* Means with Student-t intervals, max/min, p95 with its order-statistic
 * interval, yield with Wilson's; conf outside (0, 1) leaves the intervals
 * NaN (a config not built from the key table).  Sorts s's after values
 * unless !quantiles (then max, min and p95 are left NaN). */
/* The yield's interval by report.yield_interval: Wilson's score interval,
 * Clopper-Pearson's, or its one-sided lower bound at level conf (the
 * two-sided interval at 2 conf - 1 gives the lower bound; upper bound 1). */
static void yield_interval(int method, long pass, long n, double conf, stats_interval *ci)
{
    char err[SUNMC_ERRLEN];
    if (method == CONFIG_YIELD_WILSON) {
        stats_wilson(pass, n, conf, ci, err, sizeof err);
    } else if (method == CONFIG_YIELD_CLOPPER_PEARSON) {
        stats_clopper_pearson(pass, n, conf, ci, err, sizeof err);
    } else {
        stats_clopper_pearson(pass, n, 2.0 * conf - 1.0, ci, err, sizeof err);
        if (n > 0)
            ci->hi = 1.0;
    }
}

void report_yield_ci(const sunmc_config *c, long pass, long n, stats_interval *ci)
{
    yield_interval(c->yield_interval, pass, n, c->confidence, ci);
}

/* report.yield_interval's values, for summary.tsv. */
static const char *const yield_interval_key[] = {"wilson", "clopper_pearson",
                                                 "clopper_pearson_lower"};

const char *report_yield_interval_name(const sunmc_config *c)
{
    static const char *const names[] = {"Wilson score", "Clopper-Pearson",
                                        "one-sided Clopper-Pearson lower bound"};
    return names[c->yield_interval >= 0 && c->yield_interval < 3 ? c->yield_interval : 0];
}

/* Under a sampling design (sampling.h) the intervals from the block
 * totals (stats_blocks.h): the means' Student t over the blocks; the
 * yield's by its method at the effective count n / deff when the blocks
 * vary more than independent units would (deff > 1; never narrower than
 * independent units); p95's by Woodruff's method. */
static void cell_design_intervals(band_cell *s, long n, double level, int method, int quantiles,
                                  summary_row *r)
{
    char err[SUNMC_ERRLEN];
    stats_blocks_t(&s->b_before, r->rms_before_mean, level, &r->rms_before_mean_ci, err, sizeof err);
    stats_blocks_t(&s->b_after, r->rms_after_mean, level, &r->rms_after_mean_ci, err, sizeof err);
    stats_blocks_t(&s->b_sys, r->rms_after_sys_mean, level, &r->rms_after_sys_mean_ci, err,
                   sizeof err);
    stats_blocks_t(&s->b_ratio, r->improvement_mean, level, &r->improvement_mean_ci, err,
                   sizeof err);
    double deff = n > 0 ? stats_blocks_deff(&s->b_pass, r->yield, n) : 1.0;
    if (deff > 1.0) {
        long n_eff = (long)floor((double)n / deff);
        n_eff = n_eff < 1 ? 1 : n_eff;
        yield_interval(method, lround(r->yield * (double)n_eff), n_eff, level, &r->yield_ci);
    }
    size_t k = (size_t)s->after.n;
    if (k > 0 && quantiles)
        stats_blocks_quantile_ci(s->after_v, s->block_v, k, REPORT_PERCENTILE, level,
                                 &r->rms_after_p95_ci, err, sizeof err);
}

static void cell_statistics(band_cell *s, long n, double conf, int method, int design,
                            int quantiles, summary_row *r)
{
    char err[SUNMC_ERRLEN];
    int has_level = conf > 0.0 && conf < 1.0;
    double level = has_level ? conf : 0.5; /* any valid level; replaced by NaN below */
    size_t k = (size_t)s->after.n;
    stats_moments_t(&s->before, level, &r->rms_before_mean, &r->rms_before_mean_ci, err, sizeof err);
    stats_moments_t(&s->after, level, &r->rms_after_mean, &r->rms_after_mean_ci, err, sizeof err);
    stats_moments_t(&s->sys, level, &r->rms_after_sys_mean, &r->rms_after_sys_mean_ci, err,
                    sizeof err);
    stats_moments_t(&s->ratio, level, &r->improvement_mean, &r->improvement_mean_ci, err,
                    sizeof err);
    yield_interval(method, s->pass, n, level, &r->yield_ci);
    stats_wilson(s->worse, (long)k, level, &r->worse_ci, err, sizeof err);
    r->worse = k > 0 ? (double)s->worse / (double)k : NAN;
    r->rms_after_p95_ci = (stats_interval){NAN, NAN};
    r->yield = n > 0 ? (double)s->pass / (double)n : NAN;
    r->rms_after_max = r->rms_after_min = r->rms_after_p95 = NAN;
    r->improvement_max = r->improvement_min = NAN;
    if (k > 0 && quantiles) {
        if (design)
            gsl_sort2(s->after_v, 1, s->block_v, 1, k);
        else
            gsl_sort(s->after_v, 1, k);
        r->rms_after_min = s->after_v[0];
        r->rms_after_max = s->after_v[k - 1];
        r->rms_after_p95 = stats_quantile_sorted(s->after_v, k, REPORT_PERCENTILE);
        stats_quantile_ci(s->after_v, k, REPORT_PERCENTILE, level, &r->rms_after_p95_ci, NULL,
                          NULL, err, sizeof err);
        r->improvement_max = s->imp_max;
        r->improvement_min = s->imp_min;
    }
    if (design)
        cell_design_intervals(s, n, level, method, quantiles, r);
    if (!has_level) {
        stats_interval none = {NAN, NAN};
        r->rms_before_mean_ci = r->rms_after_mean_ci = r->rms_after_sys_mean_ci = none;
        r->improvement_mean_ci = r->yield_ci = r->rms_after_p95_ci = r->worse_ci = none;
    }
}

void report_acc_rows(report_acc *acc, summary_row *rows)
{
    int nab = acc->na * acc->nb;
    for (int i = 0; i < nab * n_sets(acc->c); i++) {
        int set = i / nab, a = i % nab / acc->nb, b = i % acc->nb;
        summary_row *r = &rows[i];
        band_cell *s = &acc->cell[i];
        memset(r, 0, sizeof *r);
        r->angle = a;
        r->band = b;
        r->condition = set == 0 ? REPORT_LAB
                     : set <= acc->nt ? REPORT_OPERATING : REPORT_WORST;
        r->temp_c = set == 0 ? acc->c->cal_temp_c
                  : set <= acc->nt ? thermal_temp_c(acc->c, set - 1) : NAN;
        r->units = acc->n;
        r->fit_failures = acc->failed;
        r->gross_errors = acc->gross;
        r->alias_units = acc->alias;
        r->confidence = acc->c->confidence;
        r->campaign_points = acc->campaign.points;
        r->campaign_hours = acc->campaign.known ? acc->campaign.hours : NAN;
        r->extrapolation_deg = acc->campaign.known ? acc->campaign.extrapolation_deg : NAN;
        r->stat_units = s->after.n;
        r->no_reading_units = s->no_reading;
        cell_statistics(s, acc->n, acc->c->confidence, acc->c->yield_interval,
                        acc->c->sampling != CONFIG_SAMPLING_RANDOM, 1, r);
    }
}

/* The estimates with an interval, by name, and where their interval is. */
static const struct {
    const char *name;
    size_t ci;
} report_stats[] = {
    {"yield", offsetof(summary_row, yield_ci)},
    {"rms_after_mean", offsetof(summary_row, rms_after_mean_ci)},
    {"rms_before_mean", offsetof(summary_row, rms_before_mean_ci)},
    {"rms_after_sys_mean", offsetof(summary_row, rms_after_sys_mean_ci)},
    {"rms_after_p95", offsetof(summary_row, rms_after_p95_ci)},
    {"improvement_mean", offsetof(summary_row, improvement_mean_ci)},
};
#define REPORT_N_STATS ((int)(sizeof report_stats / sizeof report_stats[0]))

int report_stat_find(const char *name)
{
    for (int i = 0; i < REPORT_N_STATS; i++)
        if (strcmp(report_stats[i].name, name) == 0)
            return i;
    return -1;
}

void report_stat_list(char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < REPORT_N_STATS && used < len; i++)
        used += (size_t)snprintf(buf + used, len - used, "%s%s", i ? ", " : "",
                                 report_stats[i].name);
}

int report_widest_band(const sunmc_config *c)
{
    int w = 0;
    for (int i = 1; i < c->bands_deg.n; i++)
        if (c->bands_deg.hi[i] - c->bands_deg.lo[i] >= c->bands_deg.hi[w] - c->bands_deg.lo[w])
            w = i;
    return w;
}

double report_acc_halfwidth(report_acc *acc, int stat, int band)
{
    double h = 0;
    int quantiles = strcmp(report_stats[stat].name, "rms_after_p95") == 0;
    for (int a = 0; a < acc->na; a++) {
        summary_row r;
        cell_statistics(&acc->cell[a * acc->nb + band], acc->n, acc->c->confidence,
                        acc->c->yield_interval, acc->c->sampling != CONFIG_SAMPLING_RANDOM,
                        quantiles, &r);
        const stats_interval *ci = (const stats_interval *)((const char *)&r + report_stats[stat].ci);
        double half = 0.5 * (ci->hi - ci->lo);
        if (!(half >= 0))
            return NAN;
        h = fmax(h, half);
    }
    return h;
}

int report_summarize(const sunmc_config *c, const sensor_family *fam, const unit_result *results,
                     long n, summary_row *rows)
{
    report_acc *acc = report_acc_new(c, fam);
    int st = acc ? report_acc_add(acc, results, n) : SUNMC_ENOMEM;
    if (st == SUNMC_OK)
        report_acc_rows(acc, rows);
    report_acc_free(acc);
    return st;
}

/* ---- Table 1 for people ---- */

#define TABLE_ROWS ((UNIT_MAX_TEMPS + 2) * UNIT_MAX_ANGLES * CONFIG_BANDS_MAX)
#define TABLE_CELL 64
#define TABLE_COLS 8

/* A column of the printed table: two header lines and one cell per row;
 * `bar` puts a " | " before it. */
typedef struct {
    char head[2][TABLE_CELL];
    char cell[TABLE_ROWS][TABLE_CELL];
    int bar;
    int left; /* left-aligned (labels) */
} table_col;

static void table_print(FILE *f, const table_col *cols, int ncols, int nrows)
{
    int w[TABLE_COLS];
    for (int j = 0; j < ncols; j++) {
        w[j] = (int)strlen(cols[j].head[0]);
        w[j] = w[j] > (int)strlen(cols[j].head[1]) ? w[j] : (int)strlen(cols[j].head[1]);
        for (int i = 0; i < nrows; i++)
            w[j] = w[j] > (int)strlen(cols[j].cell[i]) ? w[j] : (int)strlen(cols[j].cell[i]);
    }
    for (int line = -2; line < nrows; line++) {
        for (int j = 0; j < ncols; j++) {
            const char *t = line < 0 ? cols[j].head[line + 2] : cols[j].cell[line];
            fprintf(f, "%s%*s", j == 0 ? "" : cols[j].bar ? " | " : "  ",
                    cols[j].left ? -w[j] : w[j], t);
        }
        fputc('\n', f);
    }
}

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

int report_format_number(char *buf, size_t len, double v, int d)
{
    return isfinite(v) ? snprintf(buf, len, "%.*f", d, v) : snprintf(buf, len, "-");
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

static void set_head(table_col *col, const char *h0, const char *h1, int bar)
{
    snprintf(col->head[0], TABLE_CELL, "%s", h0);
    snprintf(col->head[1], TABLE_CELL, "%s", h1);
    col->bar = bar;
    col->left = 0;
}

void report_band_head(const sensor_family *fam, char *buf, size_t len)
{
    snprintf(buf, len, "%s deg", fam && fam->band_name ? fam->band_name : "|angle|");
}

/* Angle and band label columns. */
static void label_columns(const sunmc_config *c, const sensor_family *fam,
                          const summary_row *rows, int n, table_col *cols)
{
    char h[TABLE_CELL];
    report_band_head(fam, h, sizeof h);
    set_head(&cols[0], "angle", "", 0);
    set_head(&cols[1], "band", h, 0);
    cols[0].left = cols[1].left = 1;
    for (int i = 0; i < n; i++) {
        snprintf(cols[0].cell[i], TABLE_CELL, "%s", fam->angle_names[rows[i].angle]);
        report_band_label(c, rows[i].band, cols[1].cell[i], TABLE_CELL);
        if (rows[i].no_reading_units > 0)
            strcat(cols[1].cell[i], "*");
    }
}

/* The paper's Table 1 (RMS after max/min, improvement mean/max/min) and p95. */
static void print_table1(FILE *f, const sunmc_config *c, const sensor_family *fam,
                         const summary_row *rows, int n, int prec, table_col *cols)
{
    char h[TABLE_CELL], pct[24];
    report_ci_label(c, pct, sizeof pct);
    label_columns(c, fam, rows, n, cols);
    snprintf(h, sizeof h, "max [%s]", fam->rms_unit);
    set_head(&cols[2], "RMS after", h, 1);
    snprintf(h, sizeof h, "min [%s]", fam->rms_unit);
    set_head(&cols[3], "RMS after", h, 0);
    snprintf(h, sizeof h, "mean %s", pct);
    set_head(&cols[4], "times improvement", h, 1);
    set_head(&cols[5], "improvement", "max", 0);
    set_head(&cols[6], "improvement", "min", 0);
    snprintf(h, sizeof h, "[%s] %s", fam->rms_unit, pct);
    set_head(&cols[7], "p95 of RMS after", h, 1);
    int di = ci_decimals(rows, n, offsetof(summary_row, improvement_mean_ci), 1.0, 2);
    int dp = ci_decimals(rows, n, offsetof(summary_row, rms_after_p95_ci), 1.0, prec);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        report_format_number(cols[2].cell[i], TABLE_CELL, r->rms_after_max, prec);
        report_format_number(cols[3].cell[i], TABLE_CELL, r->rms_after_min, prec);
        fmt_estimate(cols[4].cell[i], TABLE_CELL, r->improvement_mean, r->improvement_mean_ci, di,
                     1.0, "");
        report_format_number(cols[5].cell[i], TABLE_CELL, r->improvement_max, 2);
        report_format_number(cols[6].cell[i], TABLE_CELL, r->improvement_min, 2);
        fmt_estimate(cols[7].cell[i], TABLE_CELL, r->rms_after_p95, r->rms_after_p95_ci, dp, 1.0,
                     "");
    }
    table_print(f, cols, 8, n);
}

/* Mean RMS before, after and its systematic part, and the yield. */
static void print_means(FILE *f, const sunmc_config *c, const sensor_family *fam,
                        const summary_row *rows, int n, int prec, table_col *cols)
{
    static const char *const heads[3] = {"mean RMS before", "mean RMS after",
                                         "systematic part of after"};
    const size_t off[3] = {offsetof(summary_row, rms_before_mean_ci),
                           offsetof(summary_row, rms_after_mean_ci),
                           offsetof(summary_row, rms_after_sys_mean_ci)};
    char h[TABLE_CELL];
    char level[32];
    report_ci_label(c, level, sizeof level);
    snprintf(h, sizeof h, "[%s] %s", fam->rms_unit, level);
    label_columns(c, fam, rows, n, cols);
    for (int k = 0; k < 3; k++)
        set_head(&cols[2 + k], heads[k], h, k == 0);
    report_ci_label(c, h, sizeof h);
    set_head(&cols[5], "yield", h, 1);
    set_head(&cols[6], "made worse", h, 1);
    int d[3];
    for (int k = 0; k < 3; k++)
        d[k] = ci_decimals(rows, n, off[k], 1.0, prec);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        const double v[3] = {r->rms_before_mean, r->rms_after_mean, r->rms_after_sys_mean};
        const stats_interval ci[3] = {r->rms_before_mean_ci, r->rms_after_mean_ci,
                                      r->rms_after_sys_mean_ci};
        for (int k = 0; k < 3; k++)
            fmt_estimate(cols[2 + k].cell[i], TABLE_CELL, v[k], ci[k], d[k], 1.0, "");
        fmt_estimate(cols[5].cell[i], TABLE_CELL, r->yield, r->yield_ci,
                     report_percent_decimals(r->yield, 1), 100.0, "%");
        fmt_estimate(cols[6].cell[i], TABLE_CELL, r->worse, r->worse_ci,
                     report_percent_decimals(r->worse, 1), 100.0, "%");
    }
    table_print(f, cols, 7, n);
}

#define PERCENT 100.0

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
                          const summary_row *rows, int prec, table_col *cols)
{
    int n = report_n_rows(c, fam);
    char h[TABLE_CELL], pct[24], range[64];
    range_label(c, range, sizeof range);
    report_ci_label(c, pct, sizeof pct);
    fprintf(f, "\nvalidation at the operating temperatures (environment.operating_temp_c), "
               "calibrated at %g C;\nworst = each unit's worst RMS over %s, passing only where "
               "it passes at every temperature:\n",
            c->cal_temp_c, range);
    set_head(&cols[0], "temp", "C", 0);
    cols[0].left = 1;
    for (int i = 0; i < n; i++)
        temp_label(&rows[i], cols[0].cell[i], TABLE_CELL);
    table_col *lab = cols + 1;
    label_columns(c, fam, rows, n, lab);
    lab[0].bar = 0;
    snprintf(h, sizeof h, "[%s] %s", fam->rms_unit, pct);
    set_head(&cols[3], "mean RMS before", h, 1);
    set_head(&cols[4], "mean RMS after", h, 1);
    set_head(&cols[5], "p95 of RMS after", h, 0);
    snprintf(h, sizeof h, "[%s]", fam->rms_unit);
    set_head(&cols[6], "max RMS after", h, 0);
    set_head(&cols[7], "yield", pct, 1);
    int db = ci_decimals(rows, n, offsetof(summary_row, rms_before_mean_ci), 1.0, prec);
    int da = ci_decimals(rows, n, offsetof(summary_row, rms_after_mean_ci), 1.0, prec);
    int dp = ci_decimals(rows, n, offsetof(summary_row, rms_after_p95_ci), 1.0, prec);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        fmt_estimate(cols[3].cell[i], TABLE_CELL, r->rms_before_mean, r->rms_before_mean_ci, db,
                     1.0, "");
        fmt_estimate(cols[4].cell[i], TABLE_CELL, r->rms_after_mean, r->rms_after_mean_ci, da,
                     1.0, "");
        fmt_estimate(cols[5].cell[i], TABLE_CELL, r->rms_after_p95, r->rms_after_p95_ci, dp, 1.0,
                     "");
        report_format_number(cols[6].cell[i], TABLE_CELL, r->rms_after_max, prec);
        fmt_estimate(cols[7].cell[i], TABLE_CELL, r->yield, r->yield_ci,
                     report_percent_decimals(r->yield, 1), PERCENT, "%");
    }
    table_print(f, cols, 8, n);
    int wb = report_widest_band(c);
    for (int a = 0; a < fam->n_angles(c); a++) {
        const summary_row *w = &rows[report_primary_row(c, fam, a, wb)];
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

void report_print_campaign(FILE *f, const sunmc_config *c)
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

void report_print_table(FILE *f, const sunmc_config *c, const sensor_family *fam,
                        const summary_row *rows)
{
    int n = report_n_lab_rows(c, fam);
    const char *u = fam->rms_unit;
    const int prec = report_decimals(fam);
    static table_col cols[TABLE_COLS]; /* large; the report prints from one thread */
    char model[256];
    fam->model_label(c, model, sizeof model);
    char spec[64] = "";
    if (strcmp(u, "arcsec") != 0) /* the spec in the table's unit too */
        snprintf(spec, sizeof spec, " = %.*f %s", prec + 1,
                 c->spec_arcsec / fam->arcsec_per_rms_unit, u);
    fprintf(f, "\n%s (%s): %ld units, seed %ld, spec %g arcsec%s\ncalibration model: %s\n",
            c->product, fam->name, rows[0].units, c->seed, c->spec_arcsec, spec, model);
    report_print_campaign(f, c);
    print_table1(f, c, fam, rows, n, prec, cols);
    fputc('\n', f);
    print_means(f, c, fam, rows, n, prec, cols);
    long kmin = rows[0].stat_units, kmax = rows[0].stat_units;
    for (int i = 1; i < n; i++) {
        kmin = rows[i].stat_units < kmin ? rows[i].stat_units : kmin;
        kmax = rows[i].stat_units > kmax ? rows[i].stat_units : kmax;
    }
    char nk[64];
    snprintf(nk, sizeof nk, kmin == kmax ? "%ld" : "%ld-%ld", kmin, kmax);
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
    print_warnings(f, c, fam, rows, n);
    if (thermal_n_temps(c) > 0)
        print_thermal(f, c, fam, rows, prec, cols);
}

/* ---- summary.tsv and units.tsv ---- */

static void summary_header(FILE *f, int n_lead, const char *const *lead_names, int thermal)
{
    for (int i = 0; i < n_lead; i++)
        fprintf(f, "%s\t", lead_names[i]);
    fprintf(f, "product\tfamily\tangle\tband\tband_lo_deg\tband_hi_deg\tunits\trms_unit\t"
               "rms_before_mean\trms_before_mean_ci_lo\trms_before_mean_ci_hi\t"
               "rms_after_mean\trms_after_mean_ci_lo\trms_after_mean_ci_hi\t"
               "rms_after_sys_mean\trms_after_sys_mean_ci_lo\trms_after_sys_mean_ci_hi\t"
               "rms_after_max\trms_after_min\t"
               "rms_after_p95\trms_after_p95_ci_lo\trms_after_p95_ci_hi\t"
               "improvement_mean\timprovement_mean_ci_lo\timprovement_mean_ci_hi\t"
               "improvement_max\timprovement_min\tyield\tyield_ci_lo\tyield_ci_hi\tspec_arcsec\t"
               "confidence\tstat_units\tfit_failures\tgross_errors\talias_units\tmodel\t"
               "campaign_points\tcampaign_hours\textrapolation_deg\tno_reading_units\t"
               "worse\tworse_ci_lo\tworse_ci_hi\tyield_interval");
    fprintf(f, "%s\n", thermal ? "\tcondition\ttemp_c" : "");
}

void report_write_summary_header(FILE *f, int n_lead, const char *const *lead_names)
{
    summary_header(f, n_lead, lead_names, 0);
}

void report_write_summary_header_of(FILE *f, const sunmc_config *c, int n_lead,
                                    const char *const *lead_names)
{
    summary_header(f, n_lead, lead_names, thermal_n_temps(c) > 0);
}

/* summary.tsv's condition column. */
static const char *const condition_key[] = {"lab", "operating", "worst"};

/* "S\tS_ci_lo\tS_ci_hi\t" */
static void write_estimate(FILE *f, double v, stats_interval ci)
{
    fprintf(f, "%.6g\t%.6g\t%.6g\t", v, ci.lo, ci.hi);
}

void report_write_summary_rows(FILE *f, const sunmc_config *c, const sensor_family *fam,
                               const summary_row *rows, int n_lead, const char *const *lead_values)
{
    int n = report_n_rows(c, fam);
    char model[256];
    fam->model_label(c, model, sizeof model);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        char band[32];
        report_band_label(c, r->band, band, sizeof band);
        for (int j = 0; j < n_lead; j++)
            fprintf(f, "%s\t", lead_values[j]);
        fprintf(f, "%s\t%s\t%s\t%s\t%g\t%g\t%ld\t%s\t", c->product, fam->name,
                fam->angle_names[r->angle], band, c->bands_deg.lo[r->band],
                c->bands_deg.hi[r->band], r->units, fam->rms_unit);
        write_estimate(f, r->rms_before_mean, r->rms_before_mean_ci);
        write_estimate(f, r->rms_after_mean, r->rms_after_mean_ci);
        write_estimate(f, r->rms_after_sys_mean, r->rms_after_sys_mean_ci);
        fprintf(f, "%.6g\t%.6g\t", r->rms_after_max, r->rms_after_min);
        write_estimate(f, r->rms_after_p95, r->rms_after_p95_ci);
        write_estimate(f, r->improvement_mean, r->improvement_mean_ci);
        fprintf(f, "%.6g\t%.6g\t", r->improvement_max, r->improvement_min);
        write_estimate(f, r->yield, r->yield_ci);
        fprintf(f, "%g\t%g\t%ld\t%ld\t%ld\t%ld\t%s\t%ld\t%.6g\t%.6g\t%ld\t", c->spec_arcsec,
                r->confidence, r->stat_units, r->fit_failures, r->gross_errors, r->alias_units,
                model, r->campaign_points, r->campaign_hours, r->extrapolation_deg,
                r->no_reading_units);
        fprintf(f, "%.6g\t%.6g\t%.6g\t%s", r->worse, r->worse_ci.lo, r->worse_ci.hi,
                yield_interval_key[c->yield_interval]);
        if (thermal_n_temps(c) > 0)
            fprintf(f, "\t%s\t%g", condition_key[r->condition], r->temp_c);
        fputc('\n', f);
    }
}

void report_write_units_header(FILE *f, const sunmc_config *c, const sensor_family *fam)
{
    const char *dev[UNIT_MAX_DEV], *par[UNIT_MAX_PAR];
    int nd = fam->dev_columns(c, dev, UNIT_MAX_DEV);
    int np = fam->par_columns(c, par, UNIT_MAX_PAR);
    int na = fam->n_angles(c), nb = c->bands_deg.n;
    fprintf(f, "unit\tfit_status\tfit_gsl_status\tfit_iterations\talias_weak\tgross_cal\tgross_val");
    for (int i = 0; i < nd; i++)
        fprintf(f, "\t%s", dev[i]);
    for (int i = 0; i < np; i++)
        fprintf(f, "\t%s", par[i]);
    fprintf(f, "\tfit_rms_%s", fam->rms_unit);
    const char *which[3] = {"before", "after", "after_sys"};
    for (int w = 0; w < 3; w++)
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                fprintf(f, "\trms_%s_%s_%g_%g_%s", which[w], fam->angle_names[a],
                        c->bands_deg.lo[b], c->bands_deg.hi[b], fam->rms_unit);
    /* at each operating temperature, then the worst over them (thermal.h) */
    int nt = thermal_n_temps(c);
    for (int t = 0; t <= nt && nt > 0; t++)
        for (int w = 0; w < 2; w++)
            for (int a = 0; a < na; a++)
                for (int b = 0; b < nb; b++) {
                    double lo = c->bands_deg.lo[b], hi = c->bands_deg.hi[b];
                    fprintf(f, "\trms_%s_%s_%g_%g_%s", which[w], fam->angle_names[a], lo, hi,
                            fam->rms_unit);
                    if (t < nt)
                        fprintf(f, "_at_%gC", thermal_temp_c(c, t));
                    else
                        fprintf(f, "_worst");
                }
    fputc('\n', f);
}

void report_write_unit_rows(FILE *f, const sunmc_config *c, const sensor_family *fam,
                            const unit_result *results, long n)
{
    const char *names[UNIT_MAX_PAR];
    int nd = fam->dev_columns(c, names, UNIT_MAX_DEV);
    int np = fam->par_columns(c, names, UNIT_MAX_PAR);
    int na = fam->n_angles(c), nb = c->bands_deg.n;
    for (long u = 0; u < n; u++) {
        const unit_result *r = &results[u];
        fprintf(f, "%ld\t%s\t%d\t%d\t%d\t%d\t%d", r->unit,
                r->fit_status == UNIT_FIT_OK ? "ok" : "failed", r->fit_gsl_status,
                r->fit_iterations, r->alias_weak, r->gross_cal, r->gross_val);
        for (int i = 0; i < nd; i++)
            fprintf(f, "\t%.10g", r->dev[i]);
        for (int i = 0; i < np; i++)
            fprintf(f, "\t%.10g", r->par[i]);
        fprintf(f, "\t%.6g", r->fit_rms);
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                fprintf(f, "\t%.6g", r->rms_before[a][b]);
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                fprintf(f, "\t%.6g", r->rms_after[a][b]);
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                fprintf(f, "\t%.6g", r->rms_after_sys[a][b]);
        int nt = thermal_n_temps(c);
        for (int t = 0; t <= nt && nt > 0; t++)
            for (int w = 0; w < 2; w++) {
                const double(*v)[UNIT_MAX_ANGLES][CONFIG_BANDS_MAX] =
                    w == 0 ? r->rms_before_t : r->rms_after_t;
                for (int a = 0; a < na; a++)
                    for (int b = 0; b < nb; b++)
                        fprintf(f, "\t%.6g", t < nt ? v[t][a][b] : thermal_worst(v, nt, a, b));
            }
        fputc('\n', f);
    }
}

void report_write_units(FILE *f, const sunmc_config *c, const sensor_family *fam,
                        const unit_result *results, long n)
{
    report_write_units_header(f, c, fam);
    report_write_unit_rows(f, c, fam, results, n);
}
