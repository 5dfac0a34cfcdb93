/* dss_calib.c - fitting the DSS calibration models (see dss_calib.h). */
#include "dss_calib.h"
#include "rotation.h"
#include "dss_score.h"
#include "dss_sensor.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_math.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The physical fit's first damping (fit.h, mu0): GSL's 1e-3 walks the
 * damping down over the first steps; the DSS fit starts from the nominal
 * design, whose spots lie within a pixel or two of the unit's (its
 * deviations are small and the model nearly linear in them), so it starts
 * at the floor and takes Gauss-Newton steps from the first. */
#define DSS_FIT_MU0 1e-7

int dss_compensate(const dss_calibration *cal, double x_px, double y_px, double *alpha,
                   double *beta)
{
    if (cal->kind == DSS_MODEL_POLYNOMIAL) {
        return dss_poly_compensate(&cal->poly, x_px, y_px, alpha, beta);
    }
    if (DSS_MODEL_HAS_SPLINE(cal->kind))
        return dss_spline_compensate(cal, x_px, y_px, alpha, beta);
    return dss_model_compensate(&cal->phys, x_px, y_px, alpha, beta);
}

void dss_compensate_batch(const dss_calibration *cal, size_t n, const double *x_px,
                          const double *y_px, double *alpha, double *beta, int *status)
{
    if (cal->kind == DSS_MODEL_PHYSICAL) {
        dss_model_compensate_batch(&cal->phys, n, x_px, y_px, alpha, beta, status);
        return;
    }
    for (size_t i = 0; i < n; i++)
        status[i] = dss_compensate(cal, x_px[i], y_px[i], &alpha[i], &beta[i]);
}

void dss_compensate_pair_batch(const dss_calibration *cal, size_t n, const double *x_px,
                               const double *y_px, const double *x0_px, const double *y0_px,
                               double *alpha, double *beta, int *status, double *alpha0,
                               double *beta0, int *status0)
{
    if (cal->kind == DSS_MODEL_PHYSICAL) {
        dss_model_compensate_pair_batch(&cal->phys, n, x_px, y_px, x0_px, y0_px, alpha, beta,
                                        status, alpha0, beta0, status0);
        return;
    }
    dss_compensate_batch(cal, n, x_px, y_px, alpha, beta, status);
    dss_compensate_batch(cal, n, x0_px, y0_px, alpha0, beta0, status0);
}

int dss_calib_free_params(const dss_design *d, int fit_index, int fix_sun, int free_idx[DSS_NP])
{
    fix_sun |= d->mount == DSS_MOUNT_ALIGNED;
    int n = 0;
    for (int j = 0; j < DSS_NP; j++) {
        if (j == DSS_P_N && !fit_index)
            continue;
        if ((j == DSS_P_S1 || j == DSS_P_S2) && fix_sun)
            continue;
        if ((j == DSS_P_TX || j == DSS_P_TY) && !d->fit_tilt)
            continue;
        if (free_idx)
            free_idx[n] = j;
        n++;
    }
    return n;
}

void dss_calib_truth(const dss_calibration *cal, double b1, double b2, double *alpha,
                     double *beta)
{
    if (DSS_MODEL_HAS_PHYSICS(cal->kind))
        dss_model_truth(&cal->phys, b1, b2, alpha, beta);
    else
        table_truth(b1, b2, alpha, beta);
}

void dss_calib_truth_batch(const dss_calibration *cal, size_t k, const double *b1,
                           const double *b2, double *alpha, double *beta)
{
    if (DSS_MODEL_HAS_PHYSICS(cal->kind))
        dss_truth_batch(cal->phys.mount, cal->phys.v0, k, b1, b2, alpha, beta);
    else
        dss_table_truth_batch(k, b1, b2, alpha, beta);
}

double dss_calib_bytes(size_t n, int kind, int poly_order)
{
    double cols = 5.0 * (double)sizeof(double) * (double)n; /* b1, b2, x, y, weight */
    if (kind == DSS_MODEL_POLYNOMIAL) {
        size_t nt = (size_t)dss_poly_n_terms(poly_order);
        return cols + (double)sizeof(double) * (double)(nt + 1) * (double)n +
               fit_workspace_bytes(n, nt);
    }
    double spline = 0;
    if (DSS_MODEL_HAS_SPLINE(kind)) /* its rows, folds, and lab_spline_fit's three matrices */
        spline = (4.0 * sizeof(double) + sizeof(int)) * (double)n + lab_spline_ws_bytes(n);
    return cols + fit_workspace_bytes(2 * n, DSS_NP) + spline;
}

dss_calib_workspace *dss_calib_alloc(const dss_design *d, size_t n, int kind, int poly_order,
                                     int fit_index)
{
    return dss_calib_alloc_fix(d, n, kind, poly_order, fit_index, 0);
}

dss_calib_workspace *dss_calib_alloc_config(const dss_config *dc, size_t n)
{
    return dss_calib_alloc_fix(&dc->design, n, dc->cal_model, dc->poly_order,
                               dc->fit_glass_index, dc->sun_mode == DSS_SUN_MEASURED);
}

dss_calib_workspace *dss_calib_alloc_fix(const dss_design *d, size_t n, int kind, int poly_order,
                                         int fit_index, int fix_sun)
{
    if (kind == DSS_MODEL_POLYNOMIAL && (poly_order < 1 || poly_order > DSS_POLY_MAX_ORDER))
        return NULL;
    dss_calib_workspace *cw = calloc(1, sizeof *cw);
    if (!cw)
        return NULL;
    cw->n = n;
    cw->design = *d;
    cw->kind = kind;
    cw->poly_order = poly_order;
    cw->b1_rad = vm_alloc(n);
    cw->b2_rad = vm_alloc(n);
    cw->x_px = vm_alloc(n);
    cw->y_px = vm_alloc(n);
    cw->weight = vm_alloc(n);
    int ok = cw->b1_rad && cw->b2_rad && cw->x_px && cw->y_px && cw->weight;
    if (ok && kind == DSS_MODEL_POLYNOMIAL) {
        size_t nt = (size_t)dss_poly_n_terms(poly_order);
        cw->basis = calloc(n * nt, sizeof(double));
        cw->target = calloc(n, sizeof(double));
        cw->fw = n > nt ? fit_workspace_alloc(n, nt) : NULL;
        ok = cw->basis && cw->target && cw->fw;
    } else if (ok) {
        cw->fix_sun = fix_sun && d->mount == DSS_MOUNT_AS_MOUNTED;
        cw->n_free = dss_calib_free_params(d, fit_index, cw->fix_sun, cw->free_idx);
        /* rows 2i, 2i + 1 of every padded point: the pads' rows stay 0 */
        cw->fw = 2 * n > (size_t)cw->n_free
                     ? fit_workspace_alloc(2 * vm_pad(n), (size_t)cw->n_free)
                     : NULL;
        if (cw->fw)
            cw->fw->mu0 = DSS_FIT_MU0;
        cw->table.n = n;
        for (int k = 0; k < 9; k++)
            ok &= (cw->table.m[k] = vm_alloc(n)) != NULL;
        ok &= (cw->sw = vm_alloc(n)) != NULL;
        ok &= (cw->jscratch = vm_alloc(2 * vm_pad(n))) != NULL;
        ok &= cw->fw != NULL;
    }
    if (ok && DSS_MODEL_HAS_SPLINE(kind)) {
        cw->sx = malloc((4 * n + 1) * sizeof *cw->sx);
        cw->fold = malloc((n + 1) * sizeof *cw->fold);
        cw->sws = lab_spline_ws_alloc(n);
        ok = cw->sx && cw->fold && cw->sws;
    }
    if (!ok) {
        dss_calib_free(cw);
        return NULL;
    }
    return cw;
}

void dss_calib_free(dss_calib_workspace *cw)
{
    if (!cw)
        return;
    free(cw->b1_rad);
    free(cw->b2_rad);
    free(cw->x_px);
    free(cw->y_px);
    free(cw->weight);
    free(cw->basis);
    free(cw->target);
    free(cw->sx);
    free(cw->fold);
    lab_spline_ws_free(cw->sws);
    for (int k = 0; k < 9; k++)
        free(cw->table.m[k]);
    free(cw->sw);
    free(cw->jscratch);
    fit_workspace_free(cw->fw);
    free(cw);
}

/* ---- physical model ---- */

static void load_params(dss_calib_workspace *cw, const double *x)
{
    for (int k = 0; k < cw->n_free; k++)
        cw->work.p[cw->free_idx[k]] = x[k];
    dss_model_prepare(&cw->work);
}

/* Spot residuals and their Jacobian together (fit_fdf): rows 2i, 2i + 1,
 * every point in one vectorised pass over the cached table rotations. */
static int phys_fdf(const double *x, void *params, double *f, double *J, size_t ld)
{
    dss_calib_workspace *cw = params;
    load_params(cw, x);
    double *col[DSS_NP];
    for (int j = 0; j < DSS_NP; j++)
        col[j] = cw->jscratch;
    for (int k = 0; k < cw->n_free; k++)
        col[cw->free_idx[k]] = J + (size_t)k * ld;
    dss_model_batch(&cw->work, &cw->table, cw->x_px, cw->y_px, cw->sw, f, col);
    return GSL_SUCCESS;
}

static size_t usable(const dss_calib_workspace *cw)
{
    size_t k = 0;
    for (size_t i = 0; i < cw->n; i++)
        k += cw->weight[i] > 0;
    return k;
}

static int calibrate_physical(dss_calib_workspace *cw, int max_iter, dss_calibration *out,
                              fit_result *res)
{
    dss_model_init(&cw->work, &cw->design);
    if (cw->fix_sun) {
        cw->work.p[DSS_P_S1] = cw->sun_rad[0];
        cw->work.p[DSS_P_S2] = cw->sun_rad[1];
        dss_model_prepare(&cw->work);
    }
    out->kind = DSS_MODEL_PHYSICAL;
    out->phys = cw->work;
    out->sun_measured = cw->fix_sun;
    if (2 * usable(cw) < (size_t)cw->n_free + 1) {
        memset(res, 0, sizeof *res);
        res->status = GSL_EINVAL;
        return SUNMC_EINPUT;
    }
    dss_table_fill(&cw->table, cw->b1_rad, cw->b2_rad);
    for (size_t i = 0; i < vm_pad(cw->n); i++)
        cw->sw[i] = i < cw->n && cw->weight[i] > 0 ? sqrt(cw->weight[i]) : 0.0;
    double x[DSS_NP];
    for (int k = 0; k < cw->n_free; k++)
        x[k] = cw->work.p[cw->free_idx[k]];
    int st = fit_solve(cw->fw, phys_fdf, cw, x, max_iter, res);
    if (st == SUNMC_OK) {
        for (int k = 0; k < cw->n_free; k++)
            out->phys.p[cw->free_idx[k]] = x[k];
        dss_model_prepare(&out->phys);
    }
    return st;
}

/* ---- polynomial model ---- */

/* Residuals and Jacobian (the design matrix) of the current axis (fit_fdf). */
static int poly_fdf(const double *x, void *params, double *f, double *J, size_t ld)
{
    dss_calib_workspace *cw = params;
    size_t nt = cw->fw->p;
    for (size_t i = 0; i < cw->n; i++) {
        const double *t = cw->basis + i * nt;
        double sw = cw->weight[i] > 0 ? sqrt(cw->weight[i]) : 0.0;
        double r = 0.0;
        if (sw > 0) {
            for (size_t k = 0; k < nt; k++)
                r += x[k] * t[k];
            r = sw * (r - cw->target[i]);
        }
        f[i] = r;
        for (size_t k = 0; k < nt; k++)
            J[k * ld + i] = sw > 0 ? sw * t[k] : 0.0;
    }
    return GSL_SUCCESS;
}

static int calibrate_poly(dss_calib_workspace *cw, int max_iter, dss_calibration *out,
                          fit_result *res)
{
    const dss_design *d = &cw->design;
    dss_poly *p = &out->poly;
    out->kind = DSS_MODEL_POLYNOMIAL;
    dss_onboard ob;
    dss_onboard_init(&ob, d);
    dss_poly_init(p, cw->poly_order, &ob, d->fov_deg * RAD_PER_DEG);
    size_t nt = (size_t)p->n_terms;
    if (usable(cw) < nt + 1) {
        memset(res, 0, sizeof *res);
        res->status = GSL_EINVAL;
        return SUNMC_EINPUT;
    }
    /* A reading the on-board formula cannot read is left out (weight 0 in
     * poly_fdf through a zero basis row and target). */
    for (size_t i = 0; i < cw->n; i++) {
        double *t = cw->basis + i * nt, am, bm;
        memset(t, 0, nt * sizeof *t);
        if (cw->weight[i] > 0 &&
            dss_onboard_angles(&p->onboard, cw->x_px[i], cw->y_px[i], &am, &bm) == SUNMC_OK)
            dss_poly_basis(p->order, am / p->scale_rad, bm / p->scale_rad, t);
    }
    int status = SUNMC_OK;
    for (int axis = 0; axis < 2; axis++) {
        for (size_t i = 0; i < cw->n; i++) {
            double am, bm, a0, b0;
            cw->target[i] = 0.0;
            if (!(cw->weight[i] > 0) ||
                dss_onboard_angles(&p->onboard, cw->x_px[i], cw->y_px[i], &am, &bm) != SUNMC_OK)
                continue;
            table_truth(cw->b1_rad[i], cw->b2_rad[i], &a0, &b0);
            cw->target[i] = axis == 0 ? a0 - am : b0 - bm;
        }
        double x[DSS_POLY_MAX_TERMS] = {0};
        fit_result r;
        int st = fit_solve(cw->fw, poly_fdf, cw, x, max_iter, &r);
        double *c = axis == 0 ? p->ca : p->cb;
        for (size_t k = 0; k < nt; k++)
            c[k] = st == SUNMC_OK ? x[k] : 0.0;
        /* Report the worse fit: a failed one, else the worse conditioned. */
        size_t iters = axis == 0 ? r.iterations
                                 : (r.iterations > res->iterations ? r.iterations : res->iterations);
        if (axis == 0 || (status == SUNMC_OK && (st != SUNMC_OK || r.rcond < res->rcond)))
            *res = r;
        res->iterations = iters;
        if (st != SUNMC_OK && status == SUNMC_OK)
            status = st;
    }
    return status;
}

int dss_calibrate(dss_calib_workspace *cw, int max_iter, dss_calibration *out, fit_result *res)
{
    memset(out, 0, sizeof *out);
    if (cw->kind == DSS_MODEL_POLYNOMIAL)
        return calibrate_poly(cw, max_iter, out, res);
    if (cw->kind == DSS_MODEL_SPLINE || cw->kind == DSS_MODEL_TABLE) {
        out->kind = cw->kind;
        return dss_spline_fit(cw, out, res);
    }
    int st = calibrate_physical(cw, max_iter, out, res);
    if (cw->kind != DSS_MODEL_HYBRID)
        return st;
    out->kind = DSS_MODEL_HYBRID;
    fit_result rs;
    if (st == SUNMC_OK)
        st = dss_spline_fit(cw, out, &rs);
    return st;
}

double dss_calib_residual_rms(const dss_calib_workspace *cw, const dss_calibration *cal)
{
    _Alignas(VM_ALIGN) double a[DSS_CHUNK], b[DSS_CHUNK], a0[DSS_CHUNK], b0[DSS_CHUNK];
    _Alignas(VM_ALIGN) double e[DSS_CHUNK];
    int st[DSS_CHUNK];
    double sum = 0.0;
    size_t k = 0;
    /* chunks of the padded arrays (vm_pad(n) values each) */
    for (size_t i0 = 0; i0 < cw->n; i0 += DSS_CHUNK) {
        size_t m = cw->n - i0 < DSS_CHUNK ? cw->n - i0 : DSS_CHUNK;
        dss_compensate_batch(cal, vm_pad(m), cw->x_px + i0, cw->y_px + i0, a, b, st);
        dss_calib_truth_batch(cal, m, cw->b1_rad + i0, cw->b2_rad + i0, a0, b0);
        dss_total_error_chunk(m, a, b, a0, b0, e);
        for (size_t q = 0; q < m; q++) {
            if (!(cw->weight[i0 + q] > 0) || st[q] != SUNMC_OK)
                continue;
            sum += e[q] * e[q];
            k++;
        }
    }
    return k ? sqrt(sum / (double)k) : GSL_NAN;
}

int dss_calib_correlation(dss_calib_workspace *cw, double *max_abs, int *i, int *j)
{
    *max_abs = GSL_NAN;
    *i = *j = -1;
    if (fit_covariance(cw->fw) != SUNMC_OK)
        return SUNMC_EFIT;
    const gsl_matrix *C = cw->fw->covar;
    size_t p = cw->fw->p;
    double best = -1.0;
    for (size_t a = 0; a < p; a++)
        for (size_t b = a + 1; b < p; b++) {
            double den = sqrt(gsl_matrix_get(C, a, a) * gsl_matrix_get(C, b, b));
            double r = den > 0 ? fabs(gsl_matrix_get(C, a, b)) / den : GSL_NAN;
            if (r > best) {
                best = r;
                *i = DSS_MODEL_HAS_PHYSICS(cw->kind) ? cw->free_idx[a] : (int)a;
                *j = DSS_MODEL_HAS_PHYSICS(cw->kind) ? cw->free_idx[b] : (int)b;
            }
        }
    if (best < 0)
        return SUNMC_EFIT;
    *max_abs = best;
    return SUNMC_OK;
}
