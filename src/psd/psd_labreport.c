/* psd_labreport.c - the calibrate report of the four-channel sensor:
 * parameters and their standard errors (per point, psd_labfit.c),
 * residuals per band, the accuracy estimate, repeatability and the
 * cross-validation by beta line or by sweep. */
#include "psd_lab.h"
#include "status.h"
#include "units.h"

#include <gsl/gsl_linalg.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- cross-validation folds ---- */

/* Distinct values of column col (sorted into v), at most max; -1 beyond. */
static int distinct(const lab_columns *d, int col, double *v, int max)
{
    int n = 0;
    for (size_t i = 0; i < d->n; i++) {
        int j = 0;
        while (j < n && v[j] != d->v[col][i])
            j++;
        if (j < n)
            continue;
        if (n == max)
            return -1;
        int at = n++;
        while (at > 0 && v[at - 1] > d->v[col][i]) {
            v[at] = v[at - 1];
            at--;
        }
        v[at] = d->v[col][i];
    }
    return n;
}

typedef struct {
    psd_labcal *k;
    int by_line;                     /* folds: beta lines, else sweeps */
    int n_folds;
    double line[CALREPORT_MAX_FOLDS];
    int *fold;                       /* n: fold of each row */
    psd_cal keep;
} cv_ctx;

static int fold_of(const void *ctx, size_t i) { return ((const cv_ctx *)ctx)->fold[i]; }

/* The campaign ("# source:" block) all of fold f's rows belong to, or -1. */
static int fold_source(const cv_ctx *c, int f)
{
    const lab_columns *d = c->k->d;
    int s = -1;
    for (size_t i = 0; d->source && i < d->n; i++)
        if (c->fold[i] == f) {
            if (s >= 0 && d->source[i] != s)
                return -1;
            s = d->source[i];
        }
    return s;
}

static void fold_label(const void *ctx, int f, char *buf, size_t len)
{
    const cv_ctx *c = ctx;
    int s = c->by_line ? -1 : fold_source(c, f);
    if (c->by_line)
        snprintf(buf, len, "beta = %g deg", c->line[f]);
    else if (s >= 0)
        snprintf(buf, len, "%s", c->k->d->source_name[s]);
    else
        snprintf(buf, len, "sweep %d", f + 1);
}

static int refit(void *ctx, const double *held, double sum2[2], long n[2], double *cond)
{
    cv_ctx *c = ctx;
    psd_labcal *k = c->k;
    fit_result fr;
    int ok = psd_labcal_fit(k, &fr) == SUNMC_OK;
    *cond = k->fw && ok ? 1.0 / fr.rcond : NAN;
    sum2[0] = sum2[1] = 0;
    n[0] = n[1] = 0;
    for (size_t i = 0; ok && i < k->d->n; i++) {
        double e[3];
        int use = k->w[i] > 0, out = held[i] > 0;
        if ((!use && !out) || psd_labcal_row_error(k, i, e) != SUNMC_OK)
            continue;
        double s = e[0] * e[0] + e[1] * e[1];
        sum2[out ? 1 : 0] += s;
        n[out ? 1 : 0]++;
    }
    k->cal = c->keep;
    return ok;
}

/* Sweeps: a new one where the swept angle steps back by more than a tenth
 * of its range. */
static int sweeps(const lab_columns *d, int *fold)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < d->n; i++)
        for (int a = 0; a < 2; a++) {
            lo[a] = fmin(lo[a], d->v[a][i]);
            hi[a] = fmax(hi[a], d->v[a][i]);
        }
    int f = 0;
    for (size_t i = 0; i < d->n; i++) {
        if (i > 0)
            for (int a = 0; a < 2; a++)
                if (d->v[a][i - 1] - d->v[a][i] > 0.1 * (hi[a] - lo[a]) ||
                    d->v[a][i] - d->v[a][i - 1] > 0.9 * (hi[a] - lo[a])) {
                    f++;
                    break;
                }
        fold[i] = f % CALREPORT_MAX_FOLDS;
    }
    return f + 1 < CALREPORT_MAX_FOLDS ? f + 1 : CALREPORT_MAX_FOLDS;
}

/* Folds none of whose rows is weighted (a campaign calibrate dropped)
 * leave: their rows -1, the others renumbered (line[] with them, when
 * the folds are lines). */
static int weighted_folds(const psd_labcal *k, int *fold, int n_folds, double *line)
{
    int used[CALREPORT_MAX_FOLDS] = {0}, to[CALREPORT_MAX_FOLDS], n = 0;
    for (size_t i = 0; i < k->d->n; i++)
        if (fold[i] >= 0 && k->w[i] > 0)
            used[fold[i]] = 1;
    for (int f = 0; f < n_folds; f++) {
        to[f] = used[f] ? n : -1;
        if (used[f] && line)
            line[n] = line[f];
        n += used[f];
    }
    for (size_t i = 0; i < k->d->n; i++)
        fold[i] = fold[i] >= 0 ? to[fold[i]] : -1;
    return n;
}

int psd_labcal_folds(const psd_labcal *k, int *fold, double line[CALREPORT_MAX_FOLDS],
                     int *by_line)
{
    int nl = distinct(k->d, 1, line, CALREPORT_MAX_FOLDS);
    *by_line = nl >= 2;
    if (!*by_line)
        return weighted_folds(k, fold, sweeps(k->d, fold), NULL);
    /* each beta line in turn; from 4 lines on, the outermost two are
     * never held out (a refit without them would extrapolate, which a
     * calibration's user does not do) */
    int edge = nl >= 4, n_folds = nl - 2 * edge;
    for (int f = 0; f < n_folds; f++)
        line[f] = line[f + edge];
    for (size_t i = 0; i < k->d->n; i++) {
        fold[i] = -1;
        for (int f = 0; f < n_folds; f++)
            if (line[f] == k->d->v[1][i])
                fold[i] = f;
    }
    return weighted_folds(k, fold, n_folds, line);
}

static void cross_validate(psd_labcal *k, calreport *rep, size_t min_rows)
{
    cv_ctx c = {.k = k, .keep = k->cal};
    c.fold = (int *)(void *)k->err; /* the errors are refilled after the folds */
    c.n_folds = psd_labcal_folds(k, c.fold, c.line, &c.by_line);
    if (c.n_folds < 2) {
        snprintf(rep->cv_note, sizeof rep->cv_note,
                 "one beta line and one sweep: nothing to hold out");
        return;
    }
    const calreport_models *cm = &rep->models;
    lab_folds folds = {.n_folds = c.n_folds, .min_fit_rows = min_rows, .fold_of = fold_of,
                       .label = fold_label, .refit = refit,
                       .outlier = cm->n_fold_outliers > 0 ? cm->fold_outlier : NULL};
    lab_cross_validate(rep, k->w, k->d->n, &folds, &c);
    k->cal = c.keep;
    psd_labcal_errors(k);
}

/* ---- the report ---- */

/* (J^T J)^-1 into fw->covar from the SVD of the Jacobian at the solution
 * (fw->J): J^T J itself squares a condition number of 1e7 or more, which
 * its Cholesky factorisation does not survive.  SUNMC_EFIT when J is rank
 * deficient. */
static int jacobian_covariance(fit_workspace *fw)
{
    size_t n = fw->n, p = fw->p;
    gsl_matrix *a = gsl_matrix_alloc(n, p), *v = gsl_matrix_alloc(p, p);
    gsl_vector *s = gsl_vector_alloc(p), *w = gsl_vector_alloc(p);
    int st = a && v && s && w ? SUNMC_OK : SUNMC_ENOMEM;
    for (size_t j = 0; j < p && st == SUNMC_OK; j++)
        for (size_t i = 0; i < n; i++)
            gsl_matrix_set(a, i, j, fw->J[j * fw->ld + i]);
    if (st == SUNMC_OK && gsl_linalg_SV_decomp(a, v, s, w) != GSL_SUCCESS)
        st = SUNMC_EFIT;
    if (st == SUNMC_OK && !(gsl_vector_get(s, p - 1) > 1e-14 * gsl_vector_get(s, 0)))
        st = SUNMC_EFIT;
    for (size_t i = 0; i < p && st == SUNMC_OK; i++)
        for (size_t j = 0; j < p; j++) {
            double c = 0;
            for (size_t q = 0; q < p; q++) {
                double sq = gsl_vector_get(s, q);
                c += gsl_matrix_get(v, i, q) * gsl_matrix_get(v, j, q) / (sq * sq);
            }
            gsl_matrix_set(fw->covar, i, j, c);
        }
    gsl_matrix_free(a);
    gsl_matrix_free(v);
    gsl_vector_free(s);
    gsl_vector_free(w);
    return st;
}

static void report_parameters(psd_labcal *k, calreport *rep, const psd_point_stats *ps)
{
    const psd_config *p = psd_cfg(k->c);
    if (p->cal_model == PSD_MODEL_TABLE) {
        static const char *const names[] = {"nodes", "step_x", "step_y", "bytes"};
        const lab_table *t = &k->cal.table;
        const double v[] = {t->nodes, lab_table_step(t, 0), lab_table_step(t, 1),
                            (double)lab_table_bytes(t)};
        calreport_set_values(rep, names, v, 4);
        return;
    }
    if (p->cal_model == PSD_MODEL_SPLINE) {
        static const char *const names[] = {"smoothing", "edf_alpha", "edf_beta"};
        const double v[] = {k->cal.spline.smooth, k->cal.spline.edf[0], k->cal.spline.edf[1]};
        calreport_set_values(rep, names, v, 3);
        return;
    }
    if (p->cal_model == PSD_MODEL_POLYNOMIAL) {
        rep->np = 2 * k->cal.poly.nt;
        for (int t = 0; t < k->cal.poly.nt; t++)
            for (int a = 0; a < 2; a++) {
                int i = 2 * t + a;
                snprintf(rep->name[i], CALREPORT_NAME_MAX, "%s_x%dy%d", a ? "tanb" : "tana",
                         k->cal.poly.ex[t], k->cal.poly.ey[t]);
                rep->value[i] = a ? k->cal.poly.cb[t] : k->cal.poly.ca[t];
                rep->se[i] = NAN;
            }
        return;
    }
    int free[PSD_NP];
    rep->np = psd_phys_free(&p->design, p->fit_tilt, free);
    double scale[PSD_NP];
    for (int q = 0; q < rep->np; q++) {
        snprintf(rep->name[q], CALREPORT_NAME_MAX, "%s", psd_param_names[free[q]]);
        rep->value[q] = k->cal.p[free[q]] * psd_param_scale[free[q]];
        rep->se[q] = NAN;
        scale[q] = psd_param_scale[free[q]] * k->rows.xscale[free[q]];
    }
    rep->cond_jacobian = 1.0 / k->fr.rcond;
    /* per point: the points' mean residuals, each point one observation */
    double chi2 = (double)ps->points * (ps->mean_rms_rad[0] * ps->mean_rms_rad[0] +
                                        ps->mean_rms_rad[1] * ps->mean_rms_rad[1]);
    double s2 = ps->per_point * chi2 / (double)rep->dof;
    int fcs = jacobian_covariance(k->fw);
    if (rep->dof > 0 && fcs == SUNMC_OK &&
        calreport_covariance(rep, k->fw->covar, s2, scale) == SUNMC_OK) {
        static const calreport_corr_cause causes[] = {
            {{"dx_um", "tilt_y_arcsec", NULL},
             "a tilt of the mount about Y moves the spot as an aperture offset along X does",
             "keep calibration.fit_tilt = off (the offsets take the tilt up), or widen the "
             "campaign's alpha range"},
            {{"dy_um", "tilt_x_arcsec", NULL},
             "a tilt of the mount about X moves the spot as an aperture offset along Y does",
             "keep calibration.fit_tilt = off, or widen the campaign's beta range"},
            {{"dh_um", "dark1_raw", "dark2_raw", "dark3_raw", "dark4_raw"},
             "a dark signal common to the four channels changes the ratios' scale as the "
             "aperture height does; only the signal's change over the field separates them",
             "measure the dark signals with the sun off and subtract them, or widen the "
             "campaign to larger angles"},
        };
        calreport_check_correlations_explained(rep, CALREPORT_CORR_WARN, causes,
                                               (int)(sizeof causes / sizeof causes[0]));
    }
}

static void report_bands(psd_labcal *k, calreport *rep, const psd_point_stats *ps)
{
    const sunmc_config *c = k->c;
    rep->n_angles = 2;
    rep->angle_name[0] = "alpha";
    rep->angle_name[1] = "beta";
    rep->bands = c->bands_deg;
    for (int a = 0; a < 2; a++) {
        band_acc acc;
        band_acc_reset(&acc);
        for (size_t i = 0; i < k->d->n; i++)
            if (k->w[i] > 0 && isfinite(k->err[3 * i]))
                band_acc_add(&acc, &c->bands_deg,
                             acos(fmin(k->ut[3 * i + 2], 1.0)) * DEG_PER_RAD,
                             k->err[3 * i + (size_t)a]);
        band_acc_rms(&acc, &c->bands_deg, ARCSEC_PER_RAD, rep->resid_rms[a]);
        for (int b = 0; b < c->bands_deg.n; b++) {
            rep->band_n[a][b] = acc.n[b];
            rep->cal_sigma_rms[a][b] = rep->cal_sigma_max[a][b] = NAN;
        }
        calreport_predict(rep, a, rep->dof > 0 ? sqrt(2.0 * (double)ps->points / rep->dof) : NAN);
    }
}

/* Another table convention the data fit markedly better (psd_labconv.c). */
void psd_labcal_report_conventions(const psd_labcal *k, calreport *rep)
{
    psd_conv_check cc;
    if (psd_labcal_conventions(k, &cc) != SUNMC_OK || !cc.better)
        return;
    char now[64];
    if (isfinite(cc.rms_configured_arcsec))
        snprintf(now, sizeof now, "leaves %.0f arcsec", cc.rms_configured_arcsec);
    else
        snprintf(now, sizeof now, "fails or cannot read a tenth of the rows");
    calreport_warn(rep,
                   "check how the table's angles were recorded (which axis is which, which "
                   "way each turns) and set the campaign keys so, or swap the columns",
                   "the data fit markedly better under another table convention: the physical "
                   "model, fitted in-sample to %ld rows, %s as configured (%s) and leaves %.0f "
                   "arcsec under %s (%d conventions tried)",
                   cc.rows, now, cc.configured, cc.rms_best_arcsec, cc.best, cc.tried);
}

void psd_labcal_report(psd_labcal *k, calreport *rep)
{
    const psd_config *p = psd_cfg(k->c);
    psd_point_stats ps;
    psd_labcal_point_stats(k, k->w, &ps);
    rep->n_rows = k->d->n;
    rep->n_used = (size_t)ps.rows;
    int phys = PSD_MODEL_HAS_PHYSICS(p->cal_model);
    int spl = PSD_MODEL_HAS_SPLINE(p->cal_model);
    int np = phys ? (int)k->fw->p : p->cal_model == PSD_MODEL_POLYNOMIAL ? k->cal.poly.nt : 0;
    double edf = spl ? k->cal.spline.edf[0] + k->cal.spline.edf[1] : 0.0;
    rep->dof = 2 * (int)ps.points - (phys ? np : 2 * np) - (int)lround(edf);
    double chi2 = (double)ps.points * (ps.mean_rms_rad[0] * ps.mean_rms_rad[0] +
                                       ps.mean_rms_rad[1] * ps.mean_rms_rad[1]);
    rep->sigma_arcsec = rep->dof > 0 ? sqrt(chi2 / rep->dof) * ARCSEC_PER_RAD : NAN;
    report_parameters(k, rep, &ps);
    report_bands(k, rep, &ps);
    if (ps.per_point > 1.0)
        calreport_warn(rep,
                       "nothing to do: this is the floor no calibration goes below; average "
                       "repeats in flight to lower it",
                       "repeatability: %.4g rows per point; a single reading scatters %.4g "
                       "arcsec per axis about its point's mean (%.4g arcsec for the mean of "
                       "a point's rows); the residual and the standard errors count each "
                       "point once (%ld points), not each row",
                       ps.per_point, ps.repeat_rad * ARCSEC_PER_RAD,
                       ps.repeat_rad / sqrt(ps.per_point) * ARCSEC_PER_RAD, ps.points);
    if (spl)
        calreport_warn(rep, "nothing to do: compare the models' held-out errors (crossval.tsv)",
                       "the %s's spline: %d breakpoints per input (%s), smoothing %.3g chosen "
                       "by the held-out error of the folds below, %.1f and %.1f effective "
                       "degrees of freedom (alpha, beta); readings outside the calibrated "
                       "field are refused by compensate, not extrapolated",
                       p->cal_model == PSD_MODEL_HYBRID ? "correction" : "model",
                       k->cal.spline.nbreak,
                       k->cal.spline.dims == 1 ? "one per axis: single-axis sweeps"
                                               : "tensor product of both",
                       k->cal.spline.smooth, k->cal.spline.edf[0], k->cal.spline.edf[1]);
    if (p->cal_model == PSD_MODEL_TABLE)
        calreport_warn(rep, "nothing to do: compare the models' held-out errors (crossval.tsv)",
                       "the look-up table: %d nodes per input (steps %.4g and %.4g in the raw "
                       "ratios), the spline's values at its nodes, the step the coarsest within "
                       "%.0f %% of the best held-out error of the folds; %zu bytes as 32-bit "
                       "floats; readings outside its field are refused by compensate",
                       k->cal.table.nodes, lab_table_step(&k->cal.table, 0),
                       lab_table_step(&k->cal.table, 1), 100 * LAB_TABLE_STEP_TOL,
                       lab_table_bytes(&k->cal.table));
    if (k->dropped)
        calreport_warn(rep, "keep the data within the linear field, or check the table "
                            "convention (campaign.table_order and signs)",
                       "%zu rows could not be compensated by the fitted model (a saturated or "
                       "clipped spot: the ratios stop moving) and were left out of the fit",
                       k->dropped);
    psd_labcal_report_conventions(k, rep);
    size_t min_rows = (size_t)np + 1 + (size_t)lround(edf / 2);
    /* the comparison first: its best model judges the campaigns (fold_outliers.h) */
    psd_labcal_compare(k, rep);
    cross_validate(k, rep, min_rows);
}
