/* lab_check.c - lab data a calibration must not be run on, and fits that
 * converged on data they did not explain (lab.h: lab_check_data,
 * lab_check_fit).  Both families get them through their lab hooks. */
#include "family.h"
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

/* The ways lab data are commonly garbled, tried against the design: a
 * sign, swapped columns, a unit.  Each with what it says of the data and
 * what to do. */
enum {
    LAB_FLIP_ALL_OUT = 1, /* every output's sign */
    LAB_FLIP_OUT,     /* output column col's sign */
    LAB_FLIP_IN,      /* table-angle column col's sign */
    LAB_SWAP_IN,
    LAB_SWAP_OUT,
    LAB_SCALE_OUT,    /* every output times factor */
    LAB_SCALE_IN      /* every table angle times factor */
};

/* A table angle in arcmin read as degrees: 60 times too large. */
#define LAB_ARCMIN_PER_DEG 60.0
#define LAB_MAX_HYP 24

typedef struct {
    int kind, col;
    double factor;
    char text[CALREPORT_TEXT_MAX / 4];
    const char *advice;
} lab_hyp;

static int add_hyp(lab_hyp *h, int n, int kind, int col, double factor, const char *advice,
                   const char *fmt, const char *arg)
{
    if (n >= LAB_MAX_HYP)
        return n;
    h[n].kind = kind;
    h[n].col = col;
    h[n].factor = factor;
    h[n].advice = advice;
    snprintf(h[n].text, sizeof h[n].text, fmt, arg);
    return n + 1;
}

/* The hypotheses to try for lab's columns, in order (the first that fits
 * is named): signs, swaps, then units. */
static int hypotheses(const family_lab *lab, const sunmc_config *c, const lab_columns *d,
                      lab_hyp *h)
{
    int ni = lab->cal_n_inputs, no = d->n_cols - 1 - ni, n = 0;
    const char *cols = "check the columns";
    n = add_hyp(h, n, LAB_FLIP_ALL_OUT, 0, 1, cols, "with every output's sign flipped%s", "");
    for (int j = 0; no > 1 && j < no; j++)
        n = add_hyp(h, n, LAB_FLIP_OUT, j, 1, cols, "with column '%s' sign-flipped",
                    col_name(lab, ni + j));
    for (int k = 0; k < ni; k++)
        n = add_hyp(h, n, LAB_FLIP_IN, k, 1, cols, "with column '%s' sign-flipped",
                    col_name(lab, k));
    if (ni == 2)
        n = add_hyp(h, n, LAB_SWAP_IN, 0, 1, cols, "with the two table-angle columns swapped%s",
                    "");
    if (no == 2)
        n = add_hyp(h, n, LAB_SWAP_OUT, 0, 1, cols, "with the two output columns swapped%s", "");
    double f[LAB_MAX_HYP];
    const char *what[LAB_MAX_HYP];
    int nu = lab->cal_output_units ? lab->cal_output_units(c, f, what, LAB_MAX_HYP) : 0;
    for (int u = 0; u < nu; u++)
        n = add_hyp(h, n, LAB_SCALE_OUT, 0, f[u],
                    "convert the output columns to the unit their names state",
                    "with the outputs read as %s", what[u]);
    n = add_hyp(h, n, LAB_SCALE_IN, 0, 1.0 / LAB_ARCMIN_PER_DEG,
                "convert the table angles to degrees", "with the table angles read as %s",
                "arcmin");
    return n;
}

/* Row i as hypothesis h (NULL: as it is) reads it: table angles in[],
 * outputs out[]. */
static void garbled_row(const family_lab *lab, const lab_columns *d, size_t i, const lab_hyp *h,
                        double *in, double *out)
{
    int ni = lab->cal_n_inputs, no = d->n_cols - 1 - ni;
    for (int k = 0; k < ni; k++)
        in[k] = d->v[k][i];
    for (int j = 0; j < no; j++)
        out[j] = d->v[ni + j][i];
    if (!h)
        return;
    double t;
    switch (h->kind) {
    case LAB_FLIP_ALL_OUT:
        for (int j = 0; j < no; j++)
            out[j] = -out[j];
        break;
    case LAB_FLIP_OUT:
        out[h->col] = -out[h->col];
        break;
    case LAB_FLIP_IN:
        in[h->col] = -in[h->col];
        break;
    case LAB_SWAP_IN:
        t = in[0], in[0] = in[1], in[1] = t;
        break;
    case LAB_SWAP_OUT:
        t = out[0], out[0] = out[1], out[1] = t;
        break;
    case LAB_SCALE_OUT:
        for (int j = 0; j < no; j++)
            out[j] *= h->factor;
        break;
    case LAB_SCALE_IN:
        for (int k = 0; k < ni; k++)
            in[k] *= h->factor;
        break;
    }
}

/* Rows (with weight > 0) whose outputs the design cannot read at their
 * table angles under hypothesis h (NULL: as they are); *first is the
 * first of them, *used the rows looked at. */
static long count_inconsistent(const family_lab *lab, const lab_predictor *lp, const lab_columns *d,
                               const lab_hyp *h, long *used, size_t *first)
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
        garbled_row(lab, d, i, h, in, out);
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

/* "; is it this sensor's data, in the units its columns name (a_deg, ...)?" */
static void generic_hint(const family_lab *lab, const lab_columns *d, char *buf, size_t len)
{
    size_t used = (size_t)snprintf(buf, len, "; is it this sensor's data, in the units its "
                                             "columns name (");
    for (int k = 0; k < d->n_cols - 1 && used < len; k++)
        used += (size_t)snprintf(buf + used, len - used, "%s%s", k ? ", " : "", col_name(lab, k));
    if (used < len)
        snprintf(buf + used, len - used, ")?");
}

/* The first inconsistent row as it is, told (what the design reads there)
 * into err with the likely cause: the first hypothesis under which the
 * rows fit, else the columns' units to check. */
static int refuse_inconsistent(const family_lab *lab, const sunmc_config *c,
                               const lab_predictor *lp, const lab_columns *d, long bad, long used,
                               size_t first, char *err, size_t errlen)
{
    char hint[CALREPORT_TEXT_MAX];
    generic_hint(lab, d, hint, sizeof hint);
    lab_hyp h[LAB_MAX_HYP];
    int nh = hypotheses(lab, c, d, h);
    /* every hypothesis that fits is named: a flipped table angle and a
     * flipped output can be the same data (DSS b1 and y_px) */
    size_t used_h = 0;
    const char *advice = NULL;
    long fit = 0;
    for (int i = 0; i < nh && used_h < sizeof hint; i++) {
        long u2;
        size_t f2;
        long b2 = count_inconsistent(lab, lp, d, &h[i], &u2, &f2);
        if (too_many(b2, u2))
            continue;
        used_h += (size_t)snprintf(hint + (advice ? used_h : 0),
                                   sizeof hint - (advice ? used_h : 0), "%s%s",
                                   advice ? ", or " : "; ", h[i].text);
        if (!advice)
            fit = u2 - b2;
        advice = advice ? advice : h[i].advice;
    }
    if (advice && used_h < sizeof hint)
        snprintf(hint + used_h, sizeof hint - used_h, ", %ld of them would fit: %s", fit, advice);
    double in[LAB_MAX_COLUMNS], out[LAB_MAX_COLUMNS], pred[LAB_MAX_COLUMNS],
        allowed[LAB_MAX_COLUMNS];
    garbled_row(lab, d, first, NULL, in, out);
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
    long bad = count_inconsistent(lab, lp, d, NULL, &used, &first);
    int st = too_many(bad, used)
                 ? refuse_inconsistent(lab, c, lp, d, bad, used, first, err, errlen)
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
    size_t kept = rep->n_used + rep->n_set_aside;
    size_t dropped = offered > kept ? offered - kept : 0;
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

/* Drop the rows marked in drop[] (d->n of them, 1: drop): the file
 * without them, the rest in their order.  A repeated row left at weight 0
 * would still count in the priors' pilot, the campaign's size and the
 * cross-validation's folds. */
static void drop_marked(lab_columns *d, const unsigned char *drop)
{
    size_t k = 0;
    for (size_t i = 0; i < d->n; i++) {
        if (drop[i])
            continue;
        for (int c = 0; c < d->n_cols; c++)
            d->v[c][k] = d->v[c][i];
        d->line[k] = d->line[i];
        k++;
    }
    d->n = k;
}

int lab_duplicates(lab_columns *d, int mode, char *note, size_t notelen, char *err,
                   size_t errlen)
{
    note[0] = '\0';
    size_t *ix = malloc((d->n + 1) * sizeof *ix);
    unsigned char *drop = calloc(d->n + 1, 1);
    if (!ix || !drop) {
        free(ix);
        free(drop);
        return -sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    }
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
            drop[dup] = 1; /* the mean of equal rows is the row: once */
        n++;
    }
    if (st == SUNMC_OK && mode == LAB_DUP_AVERAGE && n)
        drop_marked(d, drop);
    free(ix);
    free(drop);
    if (st == SUNMC_OK && n && used < notelen)
        snprintf(note + used, notelen - used, "%s", n > LAB_DUP_SHOWN ? ", ..." : "");
    return st == SUNMC_OK ? (int)n : -st;
}

/* Points of the config's campaign grid listed in a warning, at most. */
#define LAB_MISSING_SHOWN 6
/* The data follow the config's grid when this share of their rows sits on
 * it; only then are the grid's points without a row named. */
#define LAB_ON_GRID_SHARE 0.9
/* Table angles equal to a grid point within this (deg). */
#define LAB_GRID_TOL_DEG 1e-6

/* Whether a row of d sits at table angles (x, y) (deg); one of weight 0
 * counts (the lab measured the point: a DSS's "no spot"). */
static int has_row(const lab_columns *d, double x, double y)
{
    for (size_t i = 0; i < d->n; i++)
        if (fabs(d->v[0][i] - x) <= LAB_GRID_TOL_DEG &&
            fabs(d->v[1][i] - y) <= LAB_GRID_TOL_DEG)
            return 1;
    return 0;
}

/* Rows of d on the grid (g0[k], g1[k]) of n points, the grid's axes taken
 * as columns (0, 1) (swap = 0) or (1, 0); every row counts. */
static long rows_on_grid(const lab_columns *d, const double *g0, const double *g1, long n,
                         int swap)
{
    long on = 0;
    for (size_t i = 0; i < d->n; i++) {
        double x = d->v[swap][i], y = d->v[1 - swap][i];
        for (long k = 0; k < n; k++)
            if (fabs(g0[k] - x) <= LAB_GRID_TOL_DEG && fabs(g1[k] - y) <= LAB_GRID_TOL_DEG) {
                on++;
                break;
            }
    }
    return on;
}

void lab_check_grid(const family_lab *lab, const sunmc_config *c, const lab_columns *d,
                    calreport *rep)
{
    const family_grid *gr = c->family->grid;
    if (!gr || !gr->points || lab->cal_n_inputs != 2)
        return;
    long n = gr->points(c, FAMILY_GRID_CAMPAIGN, NULL, NULL, 0);
    double *g = n > 0 ? malloc(2 * (size_t)n * sizeof *g) : NULL;
    if (!g)
        return;
    gr->points(c, FAMILY_GRID_CAMPAIGN, g, g + n, n);
    long used = (long)d->n;
    long on0 = rows_on_grid(d, g, g + n, n, 0), on1 = rows_on_grid(d, g, g + n, n, 1);
    int swap = on1 > on0;
    long on = swap ? on1 : on0;
    if (used > 0 && (double)on >= LAB_ON_GRID_SHARE * (double)used) {
        char list[CALREPORT_TEXT_MAX / 2] = "";
        size_t len = 0;
        long missing = 0;
        for (long k = 0; k < n; k++) {
            double x = swap ? g[n + k] : g[k], y = swap ? g[k] : g[n + k];
            if (has_row(d, x, y))
                continue;
            if (missing++ < LAB_MISSING_SHOWN && len < sizeof list)
                len += (size_t)snprintf(list + len, sizeof list - len, "%s(%g, %g)",
                                        missing > 1 ? ", " : "", x, y);
        }
        if (missing)
            calreport_warn(rep,
                           "measure the missing points, or set the config's campaign keys to "
                           "the grid the lab ran",
                           "%ld of the config's %ld campaign points have no row in %s "
                           "((%s, %s) deg: %s%s): the fit sees less of the field than the "
                           "campaign the config describes",
                           missing, n, d->path, col_name(lab, 0), col_name(lab, 1), list,
                           missing > LAB_MISSING_SHOWN ? ", ..." : "");
    }
    free(g);
}
