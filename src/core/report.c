/* report.c - statistics over units: the accumulator and the summary rows
 * (report.h); the files are written by report_write.c. */
#include "report.h"
#include "campaign.h"
#include "sampling.h"
#include "stats_blocks.h"
#include "thermal.h"
#include "verdict.h"
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

int report_n_rows(const sunmc_config *c)
{
    const sensor_family *fam = c->family;
    return fam->n_angles(c) * c->bands_deg.n * n_sets(c);
}

int report_n_lab_rows(const sunmc_config *c)
{
    const sensor_family *fam = c->family;
    return fam->n_angles(c) * c->bands_deg.n;
}

int report_primary_row(const sunmc_config *c, int angle, int band)
{
    const sensor_family *fam = c->family;
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
    stats_moments mf;    /* the model-form part, units with the pass */
    /* their after mean square in three parts: noise, estimation, model form */
    stats_ratio_acc floor_part[3];
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
    long n, gross, alias, failed;
    campaign_info campaign;
    /* set-major: the lab's, each operating temperature, the worst over them */
    band_cell cell[(UNIT_MAX_TEMPS + 2) * UNIT_MAX_ANGLES * CONFIG_BANDS_MAX];
    /* the spec's verdict per set and angle: passes, and a design's blocks */
    long spec_pass[(UNIT_MAX_TEMPS + 2) * UNIT_MAX_ANGLES];
    long points[CONFIG_BANDS_MAX]; /* validation points per band, the most of any unit */
    stats_blocks spec_b[(UNIT_MAX_TEMPS + 2) * UNIT_MAX_ANGLES];
};

report_acc *report_acc_new(const sunmc_config *c)
{
    const sensor_family *fam = c->family;
    report_acc *a = calloc(1, sizeof *a);
    if (!a)
        return NULL;
    a->c = c;
    a->fam = fam;
    a->na = fam->n_angles(c);
    a->nb = c->bands_deg.n;
    a->nt = thermal_n_temps(c);
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
    for (int i = 0; i < a->na * n_sets(c); i++)
        stats_blocks_init(&a->spec_b[i]);
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

/* A unit's model-form part mf (NaN: no pass) and its after mean square
 * in three parts, when its systematic part is known too. */
static void cell_add_floor(band_cell *s, double aft, double sys, double mf)
{
    if (!isfinite(mf) || !isfinite(sys))
        return;
    double a2 = aft * aft, s2 = sys * sys, m2 = mf * mf;
    stats_moments_add(&s->mf, mf);
    stats_ratio_acc_add(&s->floor_part[0], a2 - s2, a2);
    stats_ratio_acc_add(&s->floor_part[1], s2 - m2, a2);
    stats_ratio_acc_add(&s->floor_part[2], m2, a2);
}

/* One unit's RMS before, after, its systematic and model-form parts (NaN:
 * none) in a cell, the unit in sampling block `block` (-1: independent
 * units); a unit without a fit only counts in the yield's denominator (a
 * fail). */
static int cell_add(band_cell *s, long block, int fit_ok, double bef, double aft, double sys,
                    double mf, int pass)
{
    int usable = fit_ok && isfinite(bef) && isfinite(aft);
    pass = pass && usable;
    if (block >= 0)
        stats_blocks_add(&s->b_pass, block, pass ? 1.0 : 0.0);
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
    s->pass += pass;
    s->worse += aft > bef;
    if (isfinite(sys))
        stats_moments_add(&s->sys, sys);
    cell_add_floor(s, aft, sys, mf);
    return SUNMC_OK;
}

/* Whether ur meets the spec in band b alone at set (verdict.h). */
static int band_pass(const report_acc *acc, const unit_result *ur, int a, int b, int set)
{
    verdict v;
    verdict_band(acc->c, ur, a, b, set, &v);
    return v.pass;
}

/* A unit's cells at the operating temperatures and the worst over them. */
static int thermal_add(report_acc *acc, const unit_result *ur, int a, int b)
{
    int ok = ur->fit_status == UNIT_FIT_OK, nab = acc->na * acc->nb, i = a * acc->nb + b;
    long blk = sampling_block_of(acc->c, ur->unit);
    for (int t = 0; t < acc->nt; t++)
        if (cell_add(&acc->cell[(1 + t) * nab + i], blk, ok, ur->rms_before_t[t][a][b],
                     ur->rms_after_t[t][a][b], NAN, NAN, band_pass(acc, ur, a, b, t)) != SUNMC_OK)
            return SUNMC_ENOMEM;
    return cell_add(&acc->cell[(1 + acc->nt) * nab + i], blk, ok,
                    thermal_worst(ur->rms_before_t, acc->nt, a, b),
                    thermal_worst(ur->rms_after_t, acc->nt, a, b), NAN, NAN,
                    band_pass(acc, ur, a, b, VERDICT_WORST));
}

/* A unit's verdict under the spec for each angle and set. */
static void spec_add(report_acc *acc, const unit_result *ur)
{
    long blk = sampling_block_of(acc->c, ur->unit);
    int ns = n_sets(acc->c);
    for (int set = 0; set < ns; set++)
        for (int a = 0; a < acc->na; a++) {
            verdict v;
            int vs = set == 0 ? VERDICT_LAB : set <= acc->nt ? set - 1 : VERDICT_WORST;
            verdict_unit(acc->c, ur, a, vs, &v);
            acc->spec_pass[set * acc->na + a] += v.pass;
            if (blk >= 0)
                stats_blocks_add(&acc->spec_b[set * acc->na + a], blk, v.pass ? 1.0 : 0.0);
        }
}

int report_acc_add(report_acc *acc, const unit_result *results, long n)
{
    for (long u = 0; u < n; u++) {
        const unit_result *ur = &results[u];
        acc->n++;
        acc->gross += ur->gross_val;
        acc->alias += ur->alias_weak > 0;
        acc->failed += ur->fit_status != UNIT_FIT_OK;
        for (int b = 0; b < acc->nb; b++)
            if (ur->points[b] > acc->points[b])
                acc->points[b] = ur->points[b];
        spec_add(acc, ur);
        for (int a = 0; a < acc->na; a++)
            for (int b = 0; b < acc->nb; b++)
                if (cell_add(&acc->cell[a * acc->nb + b], sampling_block_of(acc->c, ur->unit),
                             ur->fit_status == UNIT_FIT_OK,
                             ur->rms_before[a][b], ur->rms_after[a][b], ur->rms_after_sys[a][b],
                             ur->rms_after_mf[a][b],
                             band_pass(acc, ur, a, b, VERDICT_LAB)) != SUNMC_OK ||
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

const char *report_yield_interval_name(const sunmc_config *c)
{
    static const char *const names[] = {"Wilson score", "Clopper-Pearson",
                                        "one-sided Clopper-Pearson lower bound"};
    return names[c->yield_interval >= 0 && c->yield_interval < 3 ? c->yield_interval : 0];
}

/* A design's yield interval (method, level) of yield over n units whose
 * passes in blocks are b: at the effective count n / deff when the blocks
 * vary more than independent units would (deff > 1), else left as it is
 * (never narrower than independent units'). */
static void design_yield_interval(const stats_blocks *b, double yield, long n, int method,
                                  double level, stats_interval *ci)
{
    double deff = n > 0 ? stats_blocks_deff(b, yield, n) : 1.0;
    if (deff > 1.0) {
        long n_eff = (long)floor((double)n / deff);
        n_eff = n_eff < 1 ? 1 : n_eff;
        yield_interval(method, lround(yield * (double)n_eff), n_eff, level, ci);
    }
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
    design_yield_interval(&s->b_pass, r->yield, n, method, level, &r->yield_ci);
    size_t k = (size_t)s->after.n;
    if (k > 0 && quantiles)
        stats_blocks_quantile_ci(s->after_v, s->block_v, k, REPORT_PERCENTILE, level,
                                 &r->rms_after_p95_ci, err, sizeof err);
}

/* The model-form part and the after mean square's three parts, with
 * independent units' intervals (under a sampling design too: the pass's
 * units, every N-th, do not form the design's blocks). */
static void floor_statistics(const band_cell *s, double level, summary_row *r)
{
    char err[SUNMC_ERRLEN];
    double *v[3] = {&r->share_noise, &r->share_estimation, &r->share_model_form};
    stats_interval *ci[3] = {&r->share_noise_ci, &r->share_estimation_ci,
                             &r->share_model_form_ci};
    r->mf_units = s->mf.n;
    stats_moments_t(&s->mf, level, &r->rms_after_mf_mean, &r->rms_after_mf_mean_ci, err,
                    sizeof err);
    for (int k = 0; k < 3; k++)
        stats_ratio_acc_t(&s->floor_part[k], level, v[k], ci[k], err, sizeof err);
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
    floor_statistics(s, level, r);
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
        r->rms_after_mf_mean_ci = r->share_noise_ci = r->share_estimation_ci = none;
        r->share_model_form_ci = none;
        r->improvement_mean_ci = r->yield_ci = r->rms_after_p95_ci = r->worse_ci = none;
    }
}

/* The spec's yield of set-and-angle cell i into r, with its interval (a
 * design's: at the effective count, as a band's yield). */
static void spec_statistics(const report_acc *acc, int i, summary_row *r)
{
    const sunmc_config *c = acc->c;
    long n = acc->n, pass = acc->spec_pass[i];
    double conf = c->confidence;
    r->spec_yield = n > 0 ? (double)pass / (double)n : NAN;
    r->spec_yield_ci = (stats_interval){NAN, NAN};
    if (!(conf > 0.0 && conf < 1.0))
        return;
    yield_interval(c->yield_interval, pass, n, conf, &r->spec_yield_ci);
    if (c->sampling != CONFIG_SAMPLING_RANDOM)
        design_yield_interval(&acc->spec_b[i], r->spec_yield, n, c->yield_interval, conf,
                              &r->spec_yield_ci);
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
        spec_statistics(acc, set * acc->na + a, r);
        r->band_points = acc->points[b];
    }
}

/* The estimates with an interval, by name, and where their interval is. */
static const struct {
    const char *name;
    size_t ci;
} report_stats[] = {
    {"yield", offsetof(summary_row, spec_yield_ci)}, /* the spec's verdict (verdict.h) */
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
        spec_statistics(acc, a, &r);
        const stats_interval *ci = (const stats_interval *)((const char *)&r + report_stats[stat].ci);
        double half = 0.5 * (ci->hi - ci->lo);
        if (!(half >= 0))
            return NAN;
        h = fmax(h, half);
    }
    return h;
}

int report_summarize(const sunmc_config *c, const unit_result *results,
                     long n, summary_row *rows)
{
    report_acc *acc = report_acc_new(c);
    int st = acc ? report_acc_add(acc, results, n) : SUNMC_ENOMEM;
    if (st == SUNMC_OK)
        report_acc_rows(acc, rows);
    report_acc_free(acc);
    return st;
}

/* ---- numbers and labels the tables and reports share ---- */

int report_format_number(char *buf, size_t len, double v, int d)
{
    return isfinite(v) ? snprintf(buf, len, "%.*f", d, v) : snprintf(buf, len, "-");
}

void report_band_head(const sensor_family *fam, char *buf, size_t len)
{
    snprintf(buf, len, "%s deg", fam && fam->band_name ? fam->band_name : "|angle|");
}
