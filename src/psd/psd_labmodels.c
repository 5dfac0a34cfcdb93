/* psd_labmodels.c - `sunmc calibrate`'s model comparison for the
 * four-channel sensor (issue 39): the physical, polynomial, spline, hybrid
 * and table models, each refitted on the same cross-validation folds as the
 * calibration (beta lines or sweeps) and scored on the held-out rows, for
 * a single reading and for the mean of a point's repeats; the lowest
 * held-out error is recommended, and when the physical model's is far
 * above the best empirical one's, the report says the physics does not
 * describe this sensor. */
#include "psd_lab.h"
#include "fold_outliers.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The physical model's held-out error above this many times the best
 * empirical model's: its physics does not describe the sensor. */
#define PSD_PHYSICS_FAR 1.5
/* A model with more parameters is recommended over one with fewer only
 * when its held-out error is lower by more than this fraction. */
#define PSD_COMPARE_GAIN 0.05

static const int compared[PSD_N_MODELS] = {PSD_MODEL_PHYSICAL, PSD_MODEL_POLYNOMIAL,
                                           PSD_MODEL_SPLINE, PSD_MODEL_HYBRID, PSD_MODEL_TABLE};

/* Sums of one model's refits: in-sample, held-out rows (per fold),
 * held-out points. */
typedef struct {
    double in2, out2[CALREPORT_MAX_FOLDS];
    long n_in, n_out[CALREPORT_MAX_FOLDS];
    double *pt;       /* 3 per point: held-out alpha and beta error sums, count */
    int *pt_fold;     /* per point: the fold that held it out */
} cv_sums;

/* Refit k on the rows of k0 outside fold f and add its errors. */
static int one_fold(psd_labcal *k, const psd_labcal *k0, const int *fold, int f, cv_sums *s)
{
    size_t n = k0->d->n;
    for (size_t i = 0; i < n; i++)
        k->w[i] = fold[i] == f ? 0.0 : k0->w[i];
    fit_result fr;
    if (psd_labcal_fit(k, &fr) != SUNMC_OK)
        return 0;
    for (size_t i = 0; i < n; i++) {
        double e[3];
        if (!(k0->w[i] > 0) || psd_labcal_row_error(k, i, e) != SUNMC_OK)
            continue;
        double e2 = e[0] * e[0] + e[1] * e[1];
        if (fold[i] != f) {
            s->in2 += e2;
            s->n_in++;
            continue;
        }
        s->out2[f] += e2;
        s->n_out[f]++;
        s->pt_fold[k0->point[i]] = f;
        double *p = s->pt + 3 * k0->point[i];
        p[0] += e[0];
        p[1] += e[1];
        p[2] += 1.0;
    }
    return 1;
}

/* The held-out estimates of s's sums into x: for a single reading and for
 * a point's mean, the folds marked in out[] left out (fold_outliers.h). */
static void pool_model(const psd_labcal *k0, const cv_sums *s, int n_folds,
                       const unsigned char *out, calreport_model *x)
{
    long n_out = 0;
    x->n_outliers = 0;
    for (int f = 0; f < n_folds; f++) {
        n_out += s->n_out[f];
        x->n_outliers += out[f];
    }
    x->n_out = n_out;
    x->rms_in_arcsec = s->n_in ? sqrt(s->in2 / (double)s->n_in) * ARCSEC_PER_RAD : NAN;
    x->rms_out_arcsec = fold_outliers_pool(s->out2, s->n_out, n_folds, out, ARCSEC_PER_RAD,
                                           &x->rms_out_all_arcsec);
    double m2 = 0;
    long np = 0;
    for (long g = 0; g < k0->n_points; g++) {
        const double *p = s->pt + 3 * g;
        if (p[2] > 0 && !out[s->pt_fold[g]]) {
            m2 += (p[0] * p[0] + p[1] * p[1]) / (p[2] * p[2]);
            np++;
        }
    }
    x->rms_out_mean_arcsec = np ? sqrt(m2 / (double)np) * ARCSEC_PER_RAD : NAN;
}

/* The repeat campaigns unlike the others, on the folds of the model with
 * the lowest held-out error over every fold (the one that describes the
 * data: under one that does not, any campaign can look odd); none when
 * the folds are lines across the field (lab.h, lab_folds). */
static void judge_folds(calreport_models *cm, const cv_sums *s, int n_folds, int repeats)
{
    static const unsigned char none[CALREPORT_MAX_FOLDS];
    cm->judge = -1;
    double best = INFINITY;
    for (int m = 0; m < cm->n; m++) {
        double all;
        fold_outliers_pool(s[m].out2, s[m].n_out, n_folds, none, 1.0, &all);
        if (cm->m[m].ok && all < best) {
            best = all;
            cm->judge = m;
        }
    }
    if (!repeats || cm->judge < 0) {
        cm->judge = -1;
        return;
    }
    const cv_sums *j = &s[cm->judge];
    for (int f = 0; f < n_folds; f++)
        cm->judge_fold_arcsec[f] =
            j->n_out[f] ? sqrt(j->out2[f] / (double)j->n_out[f]) * ARCSEC_PER_RAD : NAN;
    cm->n_fold_outliers = fold_outliers_mark(cm->judge_fold_arcsec, n_folds, cm->fold_outlier,
                                             &cm->judge_median_arcsec);
}

/* The spline's effective degrees of freedom, or 0. */
static double spline_edf(const psd_labcal *k)
{
    int m = k->cal.model;
    return PSD_MODEL_HAS_SPLINE(m) ? k->cal.spline.edf[0] + k->cal.spline.edf[1] : 0.0;
}

/* Fit model to every row of k0 (the smoothing chosen on the folds), then
 * hold out each fold in turn into x. */
static int score_model(const psd_labcal *k0, int model, const int *fold, int n_folds,
                       double per_point, calreport_model *x, cv_sums *s)
{
    memset(x, 0, sizeof *x);
    snprintf(x->name, sizeof x->name, "%s", psd_model_names[model]);
    sunmc_config *c = malloc(sizeof *c);
    if (!c)
        return SUNMC_ENOMEM;
    *c = *k0->c;
    ((psd_config *)(void *)c->fam.bytes)->cal_model = model;
    char err[SUNMC_ERRLEN];
    size_t n = k0->d->n;
    psd_labcal *k = psd_labcal_alloc(c, k0->d, err, sizeof err);
    s->pt = calloc(3 * (size_t)k0->n_points + 1, sizeof *s->pt);
    s->pt_fold = calloc((size_t)k0->n_points + 1, sizeof *s->pt_fold);
    int *sf = malloc((n + 1) * sizeof *sf);
    if (!k || !s->pt || !s->pt_fold || !sf) {
        psd_labcal_free(k);
        free(sf);
        free(c);
        return SUNMC_ENOMEM;
    }
    memcpy(sf, fold, n * sizeof *sf);
    k->spline_fold = sf;
    k->spline_n_folds = n_folds;
    memcpy(k->w, k0->w, n * sizeof *k->w);
    fit_result fr;
    x->ok = psd_labcal_fit(k, &fr) == SUNMC_OK;
    k->spline_smooth = x->ok && spline_edf(k) > 0 ? k->cal.spline.smooth : 0.0;
    k->table_log = x->ok && model == PSD_MODEL_TABLE ? psd_table_log(&k->cal.table) : 0;
    x->edf = spline_edf(k);
    /* a table's parameters are its stored node values */
    x->np = (PSD_MODEL_HAS_PHYSICS(model) ? (int)k->fw->p : 0) +
            (model == PSD_MODEL_POLYNOMIAL ? 2 * k->cal.poly.nt : 0) +
            (model == PSD_MODEL_TABLE ? (int)(lab_table_bytes(&k->cal.table) / sizeof(float))
                                      : (int)lround(x->edf));
    for (int f = 0; f < n_folds && x->ok; f++)
        x->ok = one_fold(k, k0, fold, f, s);
    long held = 0;
    for (int f = 0; f < n_folds; f++)
        held += s->n_out[f];
    x->ok &= held > 0;
    x->per_point = per_point;
    psd_labcal_free(k);
    free(c);
    return SUNMC_OK;
}

void psd_labcal_compare(const psd_labcal *k0, calreport *rep)
{
    calreport_models *cm = &rep->models;
    memset(cm, 0, sizeof *cm);
    int *fold = malloc((k0->d->n + 1) * sizeof *fold), by_line;
    double line[CALREPORT_MAX_FOLDS];
    if (!fold) {
        snprintf(cm->note, sizeof cm->note, "no model comparison: out of memory");
        return;
    }
    int n_folds = psd_labcal_folds(k0, fold, line, &by_line);
    psd_point_stats ps;
    psd_labcal_point_stats(k0, k0->w, &ps);
    if (n_folds < 2) {
        snprintf(cm->note, sizeof cm->note,
                 "no model comparison: one beta line and one sweep, nothing to hold out");
        free(fold);
        return;
    }
    cm->used = 0;
    cm->judge = -1;
    cv_sums *s = calloc(PSD_N_MODELS, sizeof *s);
    int st = s ? SUNMC_OK : SUNMC_ENOMEM;
    for (int m = 0; m < PSD_N_MODELS && st == SUNMC_OK; m++) {
        if (compared[m] == psd_cfg(k0->c)->cal_model)
            cm->used = m;
        st = score_model(k0, compared[m], fold, n_folds, ps.per_point, &cm->m[m], &s[m]);
        cm->n += st == SUNMC_OK;
    }
    if (st == SUNMC_OK) {
        judge_folds(cm, s, n_folds, !by_line);
        for (int m = 0; m < cm->n; m++)
            pool_model(k0, &s[m], n_folds, cm->fold_outlier, &cm->m[m]);
    }
    for (int m = 0; s && m < PSD_N_MODELS; m++) {
        free(s[m].pt);
        free(s[m].pt_fold);
    }
    free(s);
    free(fold);
    if (st != SUNMC_OK) {
        snprintf(cm->note, sizeof cm->note, "no model comparison: out of memory");
        cm->n = 0;
        cm->judge = -1;
        cm->n_fold_outliers = 0;
        return;
    }
    calreport_models_recommend(cm, PSD_COMPARE_GAIN, PSD_PHYSICS_FAR);
}
