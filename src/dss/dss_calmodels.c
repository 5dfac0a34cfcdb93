/* dss_calmodels.c - `sunmc calibrate` of a DSS: its five calibration
 * models (physical, polynomial, spline, hybrid, table) compared on the
 * same folds (issue 39).  The folds are the campaign's b1 lines, every
 * DSS_COMPARE_FOLDS-th together: each fold's rows lie between the others'
 * (the report's own cross-validation holds out quadrants, which an
 * empirical model can only extrapolate into).  Every model is refitted
 * without each fold (the same data, weights, priors and fit as its own
 * calibration) and scored on the fold's readings: the RMS of the alpha and
 * beta errors' root sum square, rows outside a spline's field not scored.
 * The recommendation is core's (calreport_models_recommend). */
#include "dss_labfit.h"
#include "dss_prior.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DSS_COMPARE_FOLDS 4
/* A model with more parameters is recommended over one with fewer only
 * when its held-out error is lower by more than this fraction. */
#define DSS_COMPARE_GAIN 0.05
/* The physical model's held-out error above this many times the best
 * other model's: its physics does not describe the sensor. */
#define DSS_PHYSICS_FAR 1.5

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* fold[i]: the rank of row i's b1 among the distinct b1 values, modulo
 * DSS_COMPARE_FOLDS.  Returns the number of distinct lines (-1: no memory). */
static int line_folds(const dss_calib_workspace *cw, int *fold)
{
    double *v = malloc((cw->n + 1) * sizeof *v);
    if (!v)
        return -1;
    memcpy(v, cw->b1_rad, cw->n * sizeof *v);
    qsort(v, cw->n, sizeof *v, cmp_double);
    size_t nd = 0;
    for (size_t i = 0; i < cw->n; i++)
        if (nd == 0 || v[i] != v[nd - 1])
            v[nd++] = v[i];
    for (size_t i = 0; i < cw->n; i++) {
        const double *at = bsearch(&cw->b1_rad[i], v, nd, sizeof *v, cmp_double);
        fold[i] = (int)((at - v) % DSS_COMPARE_FOLDS);
    }
    free(v);
    return (int)nd;
}

/* Parameters of a fitted model: the physical's, the polynomial's terms per
 * angle, a spline's effective degrees of freedom, a table's node values. */
static int model_np(const dss_calib_workspace *w, const dss_calibration *k)
{
    int edf = (int)lround(k->spline.edf[0] + k->spline.edf[1]);
    switch (k->kind) {
    case DSS_MODEL_POLYNOMIAL: return 2 * k->poly.n_terms;
    case DSS_MODEL_SPLINE: return edf;
    case DSS_MODEL_HYBRID: return w->n_free + edf;
    case DSS_MODEL_TABLE: return (int)(lab_table_bytes(&k->table) / sizeof(float));
    default: return w->n_free;
    }
}

/* Model `kind` refitted without each fold of cw's rows, into x. */
static int score_model(const sunmc_config *c0, const dss_calib_workspace *cw, const int *fold,
                       int kind, calreport_model *x)
{
    memset(x, 0, sizeof *x);
    snprintf(x->name, sizeof x->name, "%s", dss_model_names[kind]);
    sunmc_config *c = malloc(sizeof *c);
    if (!c)
        return SUNMC_ENOMEM;
    *c = *c0;
    dss_cfg(c)->cal_model = kind;
    dss_calib_workspace *w = dss_calib_alloc_config(dss_cfg(c), cw->n);
    char err[SUNMC_ERRLEN];
    calib_prior prior;
    int st = w ? SUNMC_OK : SUNMC_ENOMEM;
    if (st == SUNMC_OK) {
        memcpy(w->b1_rad, cw->b1_rad, cw->n * sizeof *w->b1_rad);
        memcpy(w->b2_rad, cw->b2_rad, cw->n * sizeof *w->b2_rad);
        memcpy(w->x_px, cw->x_px, cw->n * sizeof *w->x_px);
        memcpy(w->y_px, cw->y_px, cw->n * sizeof *w->y_px);
        memcpy(w->sun_rad, cw->sun_rad, sizeof w->sun_rad);
        st = dss_prior_apply(c, w, &prior, err, sizeof err);
    }
    double in2 = 0, out2 = 0;
    long n_in = 0;
    x->ok = st == SUNMC_OK;
    for (int f = 0; f < DSS_COMPARE_FOLDS && x->ok; f++) {
        for (size_t i = 0; i < cw->n; i++)
            w->weight[i] = fold[i] == f ? 0.0 : cw->weight[i];
        dss_calibration k;
        fit_result fr;
        if (dss_calibrate(w, c->max_iterations, &k, &fr) != SUNMC_OK) {
            x->ok = 0;
            break;
        }
        x->np = model_np(w, &k);
        for (size_t i = 0; i < cw->n; i++) {
            double a, b, a0, b0;
            if (!(cw->weight[i] > 0) ||
                dss_compensate(&k, cw->x_px[i], cw->y_px[i], &a, &b) != SUNMC_OK)
                continue;
            dss_calib_truth(&k, cw->b1_rad[i], cw->b2_rad[i], &a0, &b0);
            double e2 = (a - a0) * (a - a0) + (b - b0) * (b - b0);
            if (fold[i] == f) {
                out2 += e2;
                x->n_out++;
            } else {
                in2 += e2;
                n_in++;
            }
        }
    }
    x->rms_in_arcsec = n_in ? sqrt(in2 / (double)n_in) * ARCSEC_PER_RAD : NAN;
    x->rms_out_arcsec = x->n_out ? sqrt(out2 / (double)x->n_out) * ARCSEC_PER_RAD : NAN;
    x->rms_out_all_arcsec = x->rms_out_arcsec; /* interleaved folds: no campaign to judge */
    x->ok &= x->n_out > 0;
    dss_calib_free(w);
    free(c);
    return st == SUNMC_ENOMEM ? st : SUNMC_OK;
}

void dss_labfit_compare(const sunmc_config *c, const dss_calib_workspace *cw, calreport *rep)
{
    calreport_models *cm = &rep->models;
    memset(cm, 0, sizeof *cm);
    int *fold = malloc((cw->n + 1) * sizeof *fold);
    int lines = fold ? line_folds(cw, fold) : -1;
    if (lines < 0) {
        snprintf(cm->note, sizeof cm->note, "no model comparison: out of memory");
        free(fold);
        return;
    }
    if (lines < DSS_COMPARE_FOLDS) {
        snprintf(cm->note, sizeof cm->note,
                 "no model comparison: %d b1 lines, fewer than its %d folds of lines", lines,
                 DSS_COMPARE_FOLDS);
        free(fold);
        return;
    }
    for (int m = 0; m < DSS_N_MODELS; m++) {
        if (score_model(c, cw, fold, m, &cm->m[m]) != SUNMC_OK) {
            snprintf(cm->note, sizeof cm->note, "no model comparison: out of memory");
            cm->n = 0;
            free(fold);
            return;
        }
        cm->n++;
    }
    cm->used = dss_cfg(c)->cal_model;
    free(fold);
    calreport_models_recommend(cm, DSS_COMPARE_GAIN, DSS_PHYSICS_FAR);
}
