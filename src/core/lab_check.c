/* lab_check.c - lab data a calibration must not be run on, and fits that
 * converged on data they did not explain (lab.h: lab_check_data,
 * lab_check_fit).  Both families get them through their lab hooks. */
#include "lab.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Largest |value| a table angle in radians can have. */
#define LAB_RADIANS_MAX (2.0 * M_PI)
/* A configured range this wide (deg) is told apart from its radians. */
#define LAB_RADIANS_MIN_SPAN_DEG 10.0
/* The residual floor of the noise test (arcsec): a noise-free config. */
#define LAB_NOISE_FLOOR_ARCSEC 1.0

static const char *col_name(const family_lab *lab, int k) { return lab->cal_columns[k]; }

static int weight_col(const lab_columns *d) { return d->n_cols - 1; }

/* A weight this many times the median is refused: weights are relative
 * precisions (1 / variance), and no lab knows one reading 10^6 times
 * better than its typical one; such a weight is a lever on the fit. */
#define LAB_WEIGHT_MAX_RATIO 1e6

static int cmp_double(const void *a, const void *b);

/* Median of the weights > 0 (0 when there are none); w_pos is scratch of
 * d->n doubles. */
static double positive_median(const lab_columns *d, double *w_pos)
{
    size_t n = 0;
    for (size_t i = 0; i < d->n; i++)
        if (d->v[weight_col(d)][i] > 0)
            w_pos[n++] = d->v[weight_col(d)][i];
    if (n == 0)
        return 0;
    qsort(w_pos, n, sizeof *w_pos, cmp_double);
    return n % 2 ? w_pos[n / 2] : 0.5 * (w_pos[n / 2 - 1] + w_pos[n / 2]);
}

/* Weights refused when they cannot be relative precisions (non-finite, all
 * zero, one past LAB_WEIGHT_MAX_RATIO times the median), else scaled so
 * that the median of the used rows' weights is 1: a residual of weight 1 is
 * then a typical row's, which one heavy row cannot move. */
static int normalise_weights(lab_columns *d, char *err, size_t errlen)
{
    double *w = d->v[weight_col(d)];
    for (size_t i = 0; i < d->n; i++)
        if (!isfinite(w[i]))
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s:%d: column 'weight': %g is not a finite number", d->path,
                              d->line[i], w[i]);
    double *scratch = malloc((d->n + 1) * sizeof *scratch);
    if (!scratch)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", d->path);
    double med = positive_median(d, scratch);
    free(scratch);
    if (!(med > 0))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: column 'weight' is 0 in every row (0 drops a row): no row "
                          "is left to fit",
                          d->path, d->n ? d->line[0] : 0);
    for (size_t i = 0; i < d->n; i++)
        if (w[i] > LAB_WEIGHT_MAX_RATIO * med)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s:%d: column 'weight': %g is more than %g times the median "
                              "weight %g: weights are relative precisions (1 / variance), "
                              "not a lever; give this reading its real variance",
                              d->path, d->line[i], w[i], LAB_WEIGHT_MAX_RATIO, med);
    for (size_t i = 0; i < d->n; i++)
        w[i] /= med;
    return SUNMC_OK;
}

/* Range of column k over the rows with weight > 0. */
static void column_range(const lab_columns *d, int k, double *lo, double *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (size_t i = 0; i < d->n; i++)
        if (d->v[weight_col(d)][i] > 0) {
            *lo = fmin(*lo, d->v[k][i]);
            *hi = fmax(*hi, d->v[k][i]);
        }
}

static int check_radians(const family_lab *lab, const sunmc_config *c, const lab_columns *d,
                         char *err, size_t errlen)
{
    for (int k = 0; k < lab->cal_n_inputs && lab->cal_campaign_range; k++) {
        double clo, chi, lo, hi;
        lab->cal_campaign_range(c, k, &clo, &chi);
        column_range(d, k, &lo, &hi);
        double span_cfg = chi - clo, span = hi - lo, span_as_deg = span * DEG_PER_RAD;
        if (!(span_cfg >= LAB_RADIANS_MIN_SPAN_DEG) ||
            !(fmax(fabs(lo), fabs(hi)) <= LAB_RADIANS_MAX))
            continue;
        if (span <= 0.2 * span_cfg && span_as_deg >= 0.5 * span_cfg &&
            span_as_deg <= 1.5 * span_cfg)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s:%d: column '%s' spans %.6g..%.6g, which read as radians is "
                              "%.4g..%.4g deg, the configured campaign's %.4g..%.4g deg: the "
                              "angles look like radians; convert every angle column to degrees",
                              d->path, d->line[0], col_name(lab, k), lo, hi, lo * DEG_PER_RAD,
                              hi * DEG_PER_RAD, clo, chi);
    }
    return SUNMC_OK;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Each table angle must take enough distinct values; data too short for
 * the model at all are left to the family's own message (cal_run). */
static int check_distinct(const family_lab *lab, const sunmc_config *c, const lab_columns *d,
                          char *err, size_t errlen)
{
    char why[CALREPORT_TEXT_MAX];
    size_t usable = 0;
    for (size_t i = 0; i < d->n; i++)
        usable += d->v[weight_col(d)][i] > 0;
    if (lab->cal_min_rows && usable < lab->cal_min_rows(c, why, sizeof why))
        return SUNMC_OK;
    double *v = malloc((d->n + 1) * sizeof *v);
    if (!v)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", d->path);
    int st = SUNMC_OK;
    for (int k = 0; k < lab->cal_n_inputs && lab->cal_min_distinct && st == SUNMC_OK; k++) {
        size_t m = 0;
        for (size_t i = 0; i < d->n; i++)
            if (d->v[weight_col(d)][i] > 0)
                v[m++] = d->v[k][i];
        qsort(v, m, sizeof *v, cmp_double);
        int distinct = m > 0;
        for (size_t i = 1; i < m; i++)
            distinct += v[i] - v[i - 1] > 1e-9 * fmax(1.0, fabs(v[i]));
        if (distinct < lab->cal_min_distinct[k])
            st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                            "%s:%d: column '%s' takes %d distinct value%s%s%.6g), the fit needs "
                            "at least %d: the data cannot determine the model (is it the right "
                            "column?)",
                            d->path, d->line[d->n - 1], col_name(lab, k), distinct,
                            distinct == 1 ? "" : "s", distinct == 1 ? " (every row at " : " (from ",
                            m ? v[0] : NAN, lab->cal_min_distinct[k]);
    }
    free(v);
    return st;
}

/* The ways lab data are commonly garbled, tried against the design. */
enum { LAB_AS_IS, LAB_SIGN_FLIPPED, LAB_INPUTS_SWAPPED, LAB_OUTPUTS_SWAPPED, LAB_N_HYP };

static const char *const hypothesis_text[LAB_N_HYP] = {
    "", "with every output's sign flipped", "with the two table-angle columns swapped",
    "with the two output columns swapped"};

/* Row i as hypothesis h reads it: table angles in[], outputs out[]; 0 when
 * h does not apply to this family's columns. */
static int garbled_row(const family_lab *lab, const lab_columns *d, size_t i, int h, double *in,
                       double *out)
{
    int ni = lab->cal_n_inputs, no = d->n_cols - 1 - ni;
    for (int k = 0; k < ni; k++)
        in[k] = d->v[k][i];
    for (int j = 0; j < no; j++)
        out[j] = d->v[ni + j][i];
    double *swap = h == LAB_INPUTS_SWAPPED && ni == 2 ? in : h == LAB_OUTPUTS_SWAPPED && no == 2
                                                                 ? out
                                                                 : NULL;
    if (swap) {
        double t = swap[0];
        swap[0] = swap[1];
        swap[1] = t;
    } else if (h == LAB_SIGN_FLIPPED) {
        for (int j = 0; j < no; j++)
            out[j] = -out[j];
    } else if (h != LAB_AS_IS) {
        return 0;
    }
    return 1;
}

/* Rows (with weight > 0) whose outputs the design cannot read at their
 * table angles under hypothesis h (-1: h does not apply); *first is the
 * first of them, *used the rows looked at. */
static long count_inconsistent(const family_lab *lab, const lab_predictor *lp, const lab_columns *d,
                               int h, long *used, size_t *first)
{
    double in[LAB_MAX_COLUMNS], out[LAB_MAX_COLUMNS], pred[LAB_MAX_COLUMNS],
        allowed[LAB_MAX_COLUMNS];
    int no = d->n_cols - 1 - lab->cal_n_inputs;
    long bad = 0;
    *used = 0;
    *first = 0;
    for (size_t i = 0; i < d->n; i++) {
        if (!(d->v[weight_col(d)][i] > 0))
            continue;
        if (!garbled_row(lab, d, i, h, in, out))
            return -1;
        (*used)++;
        int ok = lab_predict(lp, in, pred, allowed) == SUNMC_OK;
        for (int j = 0; ok && j < no; j++)
            ok = fabs(out[j] - pred[j]) <= allowed[j];
        if (!ok && bad++ == 0)
            *first = i;
    }
    return bad;
}

static int too_many(long bad, long used)
{
    return used > 0 && (double)bad > LAB_MAX_INCONSISTENT * (double)used;
}

/* The first inconsistent row under h = LAB_AS_IS, told (what the design
 * reads there) into err with the likely cause. */
static int refuse_inconsistent(const family_lab *lab, const lab_predictor *lp,
                               const lab_columns *d, long bad, long used, size_t first,
                               char *err, size_t errlen)
{
    char hint[CALREPORT_TEXT_MAX] = "; is it this sensor's data, in degrees and pixels?";
    for (int h = 1; h < LAB_N_HYP; h++) {
        long u2;
        size_t f2;
        long b2 = count_inconsistent(lab, lp, d, h, &u2, &f2);
        if (b2 >= 0 && !too_many(b2, u2)) {
            snprintf(hint, sizeof hint, "; %s, %ld of them would fit: check the columns",
                     hypothesis_text[h], u2 - b2);
            break;
        }
    }
    double in[LAB_MAX_COLUMNS], out[LAB_MAX_COLUMNS], pred[LAB_MAX_COLUMNS],
        allowed[LAB_MAX_COLUMNS];
    garbled_row(lab, d, first, LAB_AS_IS, in, out);
    int ni = lab->cal_n_inputs;
    char what[CALREPORT_TEXT_MAX] = "the design sees no sun there";
    if (lab_predict(lp, in, pred, allowed) == SUNMC_OK)
        snprintf(what, sizeof what, "%s = %.6g where the design reads %.6g +- %.3g",
                 col_name(lab, ni), out[0], pred[0], allowed[0]);
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "%s:%d: at %s = %.6g, %s = %.6g: %s (within the config's tolerances); %ld "
                      "of %ld rows are inconsistent with their table angles%s",
                      d->path, d->line[first], col_name(lab, 0), in[0],
                      col_name(lab, ni > 1 ? 1 : 0), in[ni > 1 ? 1 : 0], what, bad, used, hint);
}

static int check_consistent(const family_lab *lab, const sunmc_config *c, const lab_columns *d,
                            char *err, size_t errlen)
{
    if (!lab->cal_unit_build)
        return SUNMC_OK;
    lab_predictor *lp = lab_predict_alloc(lab, c, err, errlen);
    if (!lp)
        return SUNMC_ENOMEM;
    long used;
    size_t first;
    long bad = count_inconsistent(lab, lp, d, LAB_AS_IS, &used, &first);
    int st = too_many(bad, used) ? refuse_inconsistent(lab, lp, d, bad, used, first, err, errlen)
                                 : SUNMC_OK;
    lab_predict_free(lp);
    return st;
}

int lab_check_data(const family_lab *lab, const sunmc_config *c, lab_columns *d, char *err,
                   size_t errlen)
{
    int st = normalise_weights(d, err, errlen);
    if (st == SUNMC_OK)
        st = check_radians(lab, c, d, err, errlen);
    if (st == SUNMC_OK)
        st = check_consistent(lab, c, d, err, errlen);
    if (st == SUNMC_OK)
        st = check_distinct(lab, c, d, err, errlen);
    return st;
}

void lab_check_fit(const family_lab *lab, const sunmc_config *c, const lab_columns *d,
                   calreport *rep)
{
    if (!rep->fit_ok)
        return;
    size_t zero = 0;
    for (size_t i = 0; i < d->n; i++)
        zero += !(d->v[weight_col(d)][i] > 0);
    size_t offered = d->n - zero;
    size_t dropped = offered > rep->n_used ? offered - rep->n_used : 0;
    double noise = lab->cal_noise_arcsec ? lab->cal_noise_arcsec(c) : 0;
    double limit = c->max_residual_ratio * fmax(noise, LAB_NOISE_FLOOR_ARCSEC);
    /* The weights are scaled to a median of 1 (normalise_weights): sigma
     * is a typical row's, which one heavy row cannot move (scaled to the
     * largest weight, one row of weight 100 showed 1522" for a 150"
     * residual, and weight 1e6 0.344" for a 357" misfit). */
    double typical = rep->sigma_arcsec;
    rep->sigma_typical_arcsec = typical;
    if (offered && (double)dropped > c->max_dropped_fraction * (double)offered)
        snprintf(rep->refused, sizeof rep->refused,
                 "%zu of %zu rows were dropped as gross errors, more than "
                 "calibration.max_dropped_fraction = %g: the data are not this sensor's readings "
                 "(a flipped sign, swapped columns, another unit)",
                 dropped, offered, c->max_dropped_fraction);
    else if (!(rep->cond_jacobian <= LAB_MAX_CONDITION))
        snprintf(rep->refused, sizeof rep->refused,
                 "the Jacobian is rank-deficient (condition number %.3g, at most %g): the data "
                 "do not determine the model's parameters (too few distinct angles?)",
                 rep->cond_jacobian, LAB_MAX_CONDITION);
    else if (!(typical <= limit))
        snprintf(rep->refused, sizeof rep->refused,
                 "the residual %.4g arcsec (of a row of the median weight) is more than "
                 "calibration.max_residual_ratio = %g times the reading noise of the config "
                 "(%.3g arcsec, at least %g): the model does not describe these data",
                 typical, c->max_residual_ratio, noise, LAB_NOISE_FLOOR_ARCSEC);
    if (rep->refused[0])
        rep->fit_ok = 0;
}

void lab_check_measured(const family_lab *lab, const config_state *st, calreport *rep)
{
    for (const lab_measured_key *m = lab->cal_measured; m && m->name; m++) {
        const config_key *k = config_find_in(st->cfg.family, m->section, m->name);
        const char *origin = k ? config_origin_of(st, k) : NULL;
        if (!origin || strcmp(origin, "default") != 0)
            continue;
        char value[CONFIG_STR_MAX];
        config_format_value(k, &st->cfg, value, sizeof value);
        calreport_warn(rep, m->action, "%s.%s is left at its default (%s %s): %s", m->section,
                       m->name, value, k->unit, m->why);
    }
}

/* Row order by every column, for finding exact duplicates. */
static const lab_columns *dup_ctx;

static int cmp_rows(const void *a, const void *b)
{
    size_t i = *(const size_t *)a, j = *(const size_t *)b;
    for (int k = 0; k < dup_ctx->n_cols; k++) {
        double x = dup_ctx->v[k][i], y = dup_ctx->v[k][j];
        if (x != y)
            return (x > y) - (x < y);
    }
    return (i > j) - (i < j);
}

static int same_row(const lab_columns *d, size_t i, size_t j)
{
    for (int k = 0; k < d->n_cols; k++)
        if (d->v[k][i] != d->v[k][j])
            return 0;
    return 1;
}

int lab_duplicates(lab_columns *d, int mode, char *note, size_t notelen, char *err,
                   size_t errlen)
{
    note[0] = '\0';
    size_t *ix = malloc((d->n + 1) * sizeof *ix);
    if (!ix)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    for (size_t i = 0; i < d->n; i++)
        ix[i] = i;
    dup_ctx = d;
    qsort(ix, d->n, sizeof *ix, cmp_rows);
    long n = 0;
    size_t used = 0;
    int st = SUNMC_OK;
    size_t first = d->n ? ix[0] : 0; /* the earliest row of the current group */
    for (size_t r = 1; r < d->n && st == SUNMC_OK; r++) {
        size_t dup = ix[r];
        if (!same_row(d, first, dup)) {
            first = dup;
            continue;
        }
        if (!(d->v[weight_col(d)][dup] > 0))
            continue;
        if (mode == LAB_DUP_REFUSE)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                            "%s:%d: repeats line %d exactly (every column): a reading logged "
                            "twice is not two readings; remove it, or --duplicates=average "
                            "counts it once, --duplicates=keep as independent",
                            d->path, d->line[dup], d->line[first]);
        if (n < LAB_DUP_SHOWN && used < notelen)
            used += (size_t)snprintf(note + used, notelen - used, "%s%d = %d", n ? ", " : "",
                                     d->line[dup], d->line[first]);
        if (mode == LAB_DUP_AVERAGE)
            d->v[weight_col(d)][dup] = 0; /* the mean of equal rows is the row: once */
        n++;
    }
    free(ix);
    if (st == SUNMC_OK && n && used < notelen)
        snprintf(note + used, notelen - used, "%s", n > LAB_DUP_SHOWN ? ", ..." : "");
    return st == SUNMC_OK ? (int)n : -st;
}
