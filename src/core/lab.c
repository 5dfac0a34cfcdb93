/* lab.c - the lab commands' shared pipeline: CSV columns, params.ini's
 * header, the cross-validation skeleton, a calibration's files and the
 * compensated CSV (lab.h). */
#include "lab.h"
#include "fold_outliers.h"
#include "lab_accuracy.h"
#include "csv.h"
#include "tsvnum.h"
#include "output.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *const lab_sim_files[LAB_SIM_FILES] = {"campaign.csv", "truth.csv", "validation.csv"};

/* Columns names[0..n-2] (required) and names[n-1] = "weight" (optional,
 * default 1, must not be negative) of t into freshly allocated v[k]. */
static int read_columns(const csv_table *t, const char *path, const char *const *names, int n,
                        double **v, char *err, size_t errlen)
{
    int st = SUNMC_OK;
    for (int k = 0; k < n && st == SUNMC_OK; k++) {
        int col;
        st = csv_column(t, names[k], k < n - 1, &col, err, errlen);
        if (st != SUNMC_OK)
            break;
        v[k] = malloc((t->n_rows + 1) * sizeof(double));
        if (!v[k])
            st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
        else if (col >= 0)
            st = csv_doubles(t, col, v[k], err, errlen);
        else
            for (size_t i = 0; i < t->n_rows; i++)
                v[k][i] = 1.0;
    }
    for (size_t i = 0; i < t->n_rows && st == SUNMC_OK; i++)
        if (v[n - 1][i] < 0)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                            "%s:%d: column 'weight': %g is negative (1 / relative variance; 0 "
                            "drops the row)",
                            path, t->line[i], v[n - 1][i]);
    return st;
}

int lab_columns_read(const char *path, const char *const *names, size_t min_rows,
                     const char *why, lab_columns *d, char *err, size_t errlen)
{
    memset(d, 0, sizeof *d);
    d->path = path;
    while (names[d->n_cols])
        d->n_cols++;
    if (d->n_cols > LAB_MAX_COLUMNS)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: more than %d lab columns", path,
                          LAB_MAX_COLUMNS);
    csv_table *t;
    int st = csv_read(path, &t, err, errlen);
    if (st != SUNMC_OK)
        return st;
    st = read_columns(t, path, names, d->n_cols, d->v, err, errlen);
    if (st == SUNMC_OK)
        st = csv_require_rows(t, min_rows, why, err, errlen);
    if (st == SUNMC_OK) {
        d->n = t->n_rows;
        d->line = malloc((t->n_rows + 1) * sizeof *d->line);
        if (!d->line)
            st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
        else
            memcpy(d->line, t->line, t->n_rows * sizeof *d->line);
    }
    csv_free(t);
    if (st == SUNMC_OK)
        st = lab_columns_sources(d, err, errlen);
    return st;
}

void lab_columns_free(lab_columns *d)
{
    for (int k = 0; k < LAB_MAX_COLUMNS; k++)
        free(d->v[k]);
    free(d->line);
    free(d->source);
    for (int s = 0; s < d->n_sources; s++)
        free(d->source_name[s]);
    free(d->source_name);
    memset(d, 0, sizeof *d);
}

int lab_params_header(params_file *p, const char *data, const char *config, size_t rows,
                      const calreport *rep, char *err, size_t errlen)
{
    unsigned long long h;
    int st = params_file_fnv1a64(data, &h, err, errlen);
    if (st != SUNMC_OK)
        return st;
    char hex[32];
    snprintf(hex, sizeof hex, "%016llx", h);
    st = params_set_text(p, "calibration", "sunmc_version", SUNMC_VERSION, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "sensor", rep->sensor, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "model", rep->model, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "data_file", data, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "data_fnv1a64", hex,
                             "FNV-1a 64 of the data file's bytes");
    if (st == SUNMC_OK)
        st = params_set_double(p, "calibration", "data_rows", (double)rows, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "config", config, NULL);
    if (st == SUNMC_OK)
        st = params_set_double(p, "calibration", "residual_sigma_arcsec", rep->sigma_arcsec,
                               "in-sample");
    if (st == SUNMC_OK && rep->n_folds > 0)
        st = params_set_double(p, "calibration", "crossval_rms_arcsec", rep->cv_rms_out_arcsec,
                               "held-out error: the honest accuracy estimate");
    if (st != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "cannot record the data file or config name in params.ini (too long, "
                          "or holds '#')");
    return SUNMC_OK;
}

/* ---- cross-validation ---- */

/* Fold k: hold its rows out (held = their weights, weight = 0), refit the
 * rest and score both parts into sum2[2], cnt[2] (in-sample, held out). */
static void one_fold(calreport *rep, int k, double *weight, const double *saved, double *held,
                     size_t n, const lab_folds *f, void *ctx, double sum2[2], long cnt[2])
{
    calreport_fold *fo = &rep->fold[rep->n_folds++];
    f->label(ctx, k, fo->label, sizeof fo->label);
    size_t left = 0;
    fo->n_out = 0;
    for (size_t i = 0; i < n; i++) {
        int out = f->fold_of(ctx, i) == k;
        held[i] = out ? saved[i] : 0.0;
        weight[i] = out ? 0.0 : saved[i];
        fo->n_out += held[i] > 0;
        left += weight[i] > 0;
    }
    fo->cond = NAN;
    fo->ok = fo->n_out > 0 && left > f->min_fit_rows && f->refit(ctx, held, sum2, cnt, &fo->cond);
    fo->rms_in_arcsec = fo->rms_out_arcsec = NAN;
    if (!fo->ok)
        return;
    fo->rms_in_arcsec = cnt[0] ? sqrt(sum2[0] / (double)cnt[0]) * ARCSEC_PER_RAD : NAN;
    fo->rms_out_arcsec = cnt[1] ? sqrt(sum2[1] / (double)cnt[1]) * ARCSEC_PER_RAD : NAN;
}

/* The pooled estimates of the folds' sums: in-sample over every fold,
 * held out with and without the outlying parts (fold_outliers.h). */
static void pool_folds(calreport *rep, const unsigned char *outlier, double (*sum2)[2],
                       long (*cnt)[2])
{
    double in2 = 0, out2[CALREPORT_MAX_FOLDS];
    long n_in = 0, n_out[CALREPORT_MAX_FOLDS];
    unsigned char out[CALREPORT_MAX_FOLDS];
    rep->cv_n_outliers = 0;
    for (int k = 0; k < rep->n_folds; k++) {
        int ok = rep->fold[k].ok; /* a failed refit's sums are 0 */
        in2 += ok ? sum2[k][0] : 0.0;
        n_in += ok ? cnt[k][0] : 0;
        out2[k] = ok ? sum2[k][1] : 0.0;
        n_out[k] = ok ? cnt[k][1] : 0;
        out[k] = outlier ? outlier[k] : 0;
        rep->fold[k].outlier = out[k];
        rep->cv_n_outliers += out[k];
    }
    if (n_in)
        rep->cv_rms_in_arcsec = sqrt(in2 / (double)n_in) * ARCSEC_PER_RAD;
    if (rep->n_folds > 0)
        rep->cv_rms_out_arcsec = fold_outliers_pool(out2, n_out, rep->n_folds, out,
                                                    ARCSEC_PER_RAD, &rep->cv_rms_out_all_arcsec);
}

void lab_cross_validate(calreport *rep, double *weight, size_t n, const lab_folds *f, void *ctx)
{
    double *saved = malloc((n + 1) * sizeof *saved), *held = malloc((n + 1) * sizeof *held);
    if (!saved || !held) {
        free(saved);
        free(held);
        snprintf(rep->cv_note, sizeof rep->cv_note, "out of memory");
        return;
    }
    memcpy(saved, weight, n * sizeof *saved);
    double sum2[CALREPORT_MAX_FOLDS][2] = {{0}};
    long cnt[CALREPORT_MAX_FOLDS][2] = {{0}};
    for (int k = 0; k < f->n_folds && k < CALREPORT_MAX_FOLDS; k++)
        one_fold(rep, k, weight, saved, held, n, f, ctx, sum2[k], cnt[k]);
    memcpy(weight, saved, n * sizeof *saved);
    free(saved);
    free(held);
    pool_folds(rep, f->outlier, sum2, cnt);
    calreport_check_fold_outliers(rep);
    calreport_check_crossval(rep, CALREPORT_CV_RATIO_WARN);
    calreport_check_fold_condition(rep, CALREPORT_FOLD_COND_WARN);
}

/* ---- a calibration's files ---- */

#define LAB_CAL_FILES 4 /* params.ini, residuals.tsv, bands.tsv, crossval.tsv */

/* params.ini's [prior] section: each parameter's prior mean and sigma (the
 * user's statement of what was known before the campaign), when the fit
 * had priors. */
static int params_priors(params_file *pf, const calreport *rep)
{
    int st = SUNMC_OK;
    char key[CALREPORT_NAME_MAX + 8];
    if (rep->prior_on)
        st = params_set_double(pf, "prior", "pilot_units", (double)rep->prior_units,
                               "calibration.priors = tolerances: units of the pilot");
    for (int j = 0; rep->prior_on && j < rep->np && st == SUNMC_OK; j++) {
        snprintf(key, sizeof key, "%s_mean", rep->name[j]);
        st = params_set_double(pf, "prior", key, rep->prior_mean[j], NULL);
        snprintf(key, sizeof key, "%s_sigma", rep->name[j]);
        if (st == SUNMC_OK)
            st = params_set_double(pf, "prior", key, rep->prior_sigma[j], NULL);
    }
    return st;
}

int lab_write_calibration(const family_lab *lab, const void *cal, const sunmc_config *c,
                          const calreport *rep, const char *data, const char *config,
                          size_t rows, const char *out_dir, char *err, size_t errlen)
{
    params_file *pf = malloc(sizeof *pf);
    if (!pf)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    params_init(pf);
    int st = lab_params_header(pf, data, config, rows, rep, err, errlen);
    if (st == SUNMC_OK &&
        (lab->params_fill(cal, c, rep, pf) != SUNMC_OK || params_priors(pf, rep) != SUNMC_OK))
        st = sunmc_fail(err, errlen, SUNMC_EINPUT, "params.ini: too many entries");
    const char *names[OUT_MAX_FILES] = {"params.ini", "residuals.tsv", "bands.tsv",
                                        "crossval.tsv"};
    int n = LAB_CAL_FILES;
    while (lab->extra_files && lab->extra_files[n - LAB_CAL_FILES] && n < OUT_MAX_FILES - 2)
        names[n] = lab->extra_files[n - LAB_CAL_FILES], n++;
    int n_family = n, drift = rep->drift.n >= 2;
    if (lab->cal_models_tsv)
        names[n++] = "models.tsv";
    if (drift)
        names[n++] = "campaigns.tsv";
    FILE *f[OUT_MAX_FILES] = {NULL};
    out_set os;
    if (st == SUNMC_OK)
        st = out_begin(&os, out_dir, err, errlen);
    if (st == SUNMC_OK) {
        st = out_open_all(&os, names, f, n, err, errlen);
        if (st == SUNMC_OK) {
            params_write(f[0], pf, lab->params_title);
            lab->write_residuals(cal, f[1]);
            calreport_write_bands(f[2], rep);
            calreport_write_folds(f[3], rep);
            for (int k = LAB_CAL_FILES; k < n_family; k++)
                lab->write_extra(cal, c, k - LAB_CAL_FILES, f[k]);
            if (lab->cal_models_tsv)
                calreport_write_models(f[n_family], &rep->models);
            if (drift)
                lab_drift_write(f[n - 1], &rep->drift);
            st = out_commit(&os, err, errlen);
        } else {
            out_abort(&os);
        }
    }
    free(pf);
    return st;
}

/* ---- compensate ---- */

/* Refusal when t already has one of the columns `added`. */
static int comp_no_dup(const char *const *added, const csv_table *t, const char *raw_path,
                       char *err, size_t errlen)
{
    int st = SUNMC_OK;
    for (int k = 0; added && added[k] && st == SUNMC_OK; k++) {
        int dup;
        st = csv_column(t, added[k], 0, &dup, err, errlen);
        if (st == SUNMC_OK && dup >= 0)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: the input already has a column '%s'",
                            raw_path, t->header_line, added[k]);
    }
    return st;
}

/* Column indices of lab->raw_columns in t (cols), then of the optional
 * columns when t has them all (*n_opt of them, else 0), and a refusal when
 * t already has a column compensate adds. */
static int comp_columns(const family_lab *lab, const csv_table *t, const char *raw_path,
                        int *cols, int *n_raw, int *n_opt, char *err, size_t errlen)
{
    int st = SUNMC_OK;
    *n_raw = *n_opt = 0;
    for (; lab->raw_columns[*n_raw] && st == SUNMC_OK; (*n_raw)++)
        st = csv_column(t, lab->raw_columns[*n_raw], 1, &cols[*n_raw], err, errlen);
    int all = lab->opt_columns != NULL, k = 0;
    for (; lab->opt_columns && lab->opt_columns[k] && st == SUNMC_OK; k++) {
        st = csv_column(t, lab->opt_columns[k], 0, &cols[*n_raw + k], err, errlen);
        all &= cols[*n_raw + k] >= 0;
    }
    *n_opt = all ? k : 0;
    if (st == SUNMC_OK)
        st = comp_no_dup(lab->comp_columns, t, raw_path, err, errlen);
    if (st == SUNMC_OK && *n_opt)
        st = comp_no_dup(lab->opt_comp_columns, t, raw_path, err, errlen);
    return st;
}

/* The raw columns of t as numbers, v[k][i]. */
static int comp_values(const csv_table *t, const int *cols, int n_raw, double **v, char *err,
                       size_t errlen)
{
    int st = SUNMC_OK;
    for (int k = 0; k < n_raw && st == SUNMC_OK; k++) {
        v[k] = malloc((t->n_rows + 1) * sizeof *v[k]);
        st = v[k] ? csv_doubles(t, cols[k], v[k], err, errlen)
                  : sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    }
    return st;
}

const char *const lab_reading_text[LAB_N_READING] = {
    [LAB_READING_OK] = "compensated",
    [LAB_NO_SIGNAL] = "no signal (no spot, or channels at or below the dark level)",
    [LAB_NEGATIVE_SUM] = "negative sum (the dark-corrected channels add up below 0)",
    [LAB_OUTSIDE_DETECTOR] = "outside the detector",
    [LAB_OUTSIDE_RANGE] = "outside the output's range",
    [LAB_NO_INVERSE] = "no inverse (the model cannot be inverted there)",
    [LAB_OUTSIDE_FIELD] = "outside the calibrated field (the model would extrapolate)"};

void lab_comp_summary(const lab_comp_stats *s, char *buf, size_t len)
{
    size_t k = (size_t)snprintf(buf, len, "%ld row%s not compensated", s->failed,
                                s->failed == 1 ? "" : "s");
    const char *sep = ": ";
    for (int c = LAB_READING_OK + 1; c < LAB_N_READING && k < len; c++)
        if (s->by_cause[c]) {
            k += (size_t)snprintf(buf + k, len - k, "%s%ld %s", sep, s->by_cause[c],
                                  lab_reading_text[c]);
            sep = ", ";
        }
}

/* One reading: LAB_READING_OK and its angles in comp, or why not. */
static int comp_one(const family_lab *lab, const void *model, const double *raw, double *comp,
                    int n_comp)
{
    int why = lab->reading_check ? lab->reading_check(model, raw) : LAB_READING_OK;
    if (why < LAB_READING_OK || why >= LAB_N_READING)
        why = LAB_NO_INVERSE;
    if (why != LAB_READING_OK)
        return why;
    if (lab->compensate(model, raw, comp) != SUNMC_OK)
        return LAB_NO_INVERSE;
    for (int k = 0; k < n_comp; k++)
        if (!isfinite(comp[k]))
            return LAB_NO_INVERSE;
    return LAB_READING_OK;
}

/* ",v" in degrees ("-": tsvnum.h) */
static void comp_put(FILE *out, const char *sep, double rad)
{
    char num[64];
    tsv_num_fmt(num, sizeof num, "%.15g", rad * DEG_PER_RAD);
    fprintf(out, "%s%s", sep, num);
}

/* Where the truth of compensated angle k comes from: tsrc[k] >= 0 an input
 * column, -2 - j the family's added column opt_comp_columns[j], -1 none
 * (then acc->found = 0).  Refused when acc->required and there is none. */
static int comp_truth(const family_lab *lab, const csv_table *t, int n_opt, lab_accuracy *acc,
                      int *tsrc, const char *raw_path, char *err, size_t errlen)
{
    static const char prefix[] = "compensated_";
    int k = 0, st = SUNMC_OK;
    for (; k < acc->n_comp; k++) {
        const char *x = lab->comp_columns[k];
        snprintf(acc->truth[k], sizeof acc->truth[k], "truth_%s",
                 strncmp(x, prefix, sizeof prefix - 1) ? x : x + sizeof prefix - 1);
    }
    for (k = 0; k < acc->n_comp; k++) {
        if ((st = csv_column(t, acc->truth[k], 0, &tsrc[k], err, errlen)) != SUNMC_OK)
            return st;
        for (int j = 0; tsrc[k] < 0 && n_opt && lab->opt_comp_columns && lab->opt_comp_columns[j]; j++)
            if (strcmp(lab->opt_comp_columns[j], acc->truth[k]) == 0)
                tsrc[k] = -2 - j;
        if (tsrc[k] == -1)
            break;
    }
    acc->found = k == acc->n_comp;
    if (!acc->found && acc->required)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: no truth columns (%s%s%s) to score the compensated angles against",
                          raw_path, t->header_line, acc->truth[0], acc->n_comp > 1 ? ", " : "",
                          acc->n_comp > 1 ? acc->truth[1] : "");
    return SUNMC_OK;
}

static void comp_rows(const family_lab *lab, const void *model, const csv_table *t,
                      double *const *v, int n_raw, int n_opt, FILE *out, lab_comp_stats *s,
                      lab_accuracy *acc, const int *tsrc, double *const *tv)
{
    for (int j = 0; j < t->n_cols; j++)
        fprintf(out, "%s,", t->names[j]);
    int n_comp = 0, n_opt_comp = 0, n_opt_in = 0;
    for (; lab->comp_columns[n_comp]; n_comp++)
        fprintf(out, "%s%s", n_comp ? "," : "", lab->comp_columns[n_comp]);
    while (lab->opt_columns && lab->opt_columns[n_opt_in])
        n_opt_in++;
    for (; n_opt && lab->opt_comp_columns && lab->opt_comp_columns[n_opt_comp]; n_opt_comp++)
        fprintf(out, ",%s", lab->opt_comp_columns[n_opt_comp]);
    fprintf(out, "\n");
    for (size_t i = 0; i < t->n_rows; i++) {
        for (int j = 0; j < t->n_cols; j++)
            fprintf(out, "%s,", t->field[i * (size_t)t->n_cols + (size_t)j]);
        double raw[LAB_MAX_COLUMNS], comp[LAB_MAX_COLUMNS];
        for (int k = 0; k < n_raw + n_opt_in; k++)
            raw[k] = k < n_raw + n_opt ? v[k][i] : NAN;
        for (int k = 0; k < LAB_MAX_COLUMNS; k++)
            comp[k] = NAN;
        int why = comp_one(lab, model, raw, comp, n_comp);
        for (int k = 0; k < n_comp; k++)
            comp_put(out, k ? "," : "", why == LAB_READING_OK ? comp[k] : NAN);
        for (int k = n_comp; k < n_comp + n_opt_comp; k++)
            comp_put(out, ",", comp[k]);
        fprintf(out, "\n");
        if (acc && acc->found) {
            double truth[2], got[2];
            for (int k = 0; k < acc->n_comp; k++) {
                truth[k] = tsrc[k] >= 0 ? tv[k][i] / DEG_PER_RAD : comp[n_comp - 2 - tsrc[k]];
                got[k] = why == LAB_READING_OK ? comp[k] : NAN;
            }
            if (lab_accuracy_add(acc, got, truth) != SUNMC_OK)
                s->acc_nomem = 1;
        }
        if (why != LAB_READING_OK) {
            s->by_cause[why]++;
            if (!s->failed++)
                s->first_failed_line = t->line[i];
        }
    }
}

int lab_compensate_csv(const family_lab *lab, const void *model, const char *raw_path,
                       FILE *out, lab_comp_stats *s, lab_accuracy *acc, char *err,
                       size_t errlen)
{
    memset(s, 0, sizeof *s);
    csv_table *t = NULL;
    int st = csv_read(raw_path, &t, err, errlen);
    int cols[LAB_MAX_COLUMNS], n_raw = 0, n_opt = 0, tsrc[2] = {-1, -1};
    double *v[LAB_MAX_COLUMNS] = {NULL}, *tv[2] = {NULL};
    if (st == SUNMC_OK && t->n_rows == 0)
        st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: no data rows", raw_path);
    if (st == SUNMC_OK)
        st = comp_columns(lab, t, raw_path, cols, &n_raw, &n_opt, err, errlen);
    if (st == SUNMC_OK)
        st = comp_values(t, cols, n_raw + n_opt, v, err, errlen);
    if (st == SUNMC_OK && acc)
        st = comp_truth(lab, t, n_opt, acc, tsrc, raw_path, err, errlen);
    for (int k = 0; st == SUNMC_OK && acc && acc->found && k < acc->n_comp; k++)
        if (tsrc[k] >= 0) /* the input's truth columns as numbers, each checked */
            st = comp_values(t, &tsrc[k], 1, &tv[k], err, errlen);
    if (st == SUNMC_OK)
        comp_rows(lab, model, t, v, n_raw, n_opt, out, s, acc, tsrc, tv);
    if (st == SUNMC_OK && s->acc_nomem)
        st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the accuracy summary");
    for (int k = 0; k < LAB_MAX_COLUMNS; k++)
        free(v[k]);
    free(tv[0]);
    free(tv[1]);
    csv_free(t);
    return st;
}
