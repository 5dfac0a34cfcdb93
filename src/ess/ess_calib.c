/* ess_calib.c - alias detection and the ESS calibration fit. */
#include "ess_calib.h"
#include "status.h"
#include "vmath.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_math.h>
#include <math.h>
#include <stdlib.h>

/* Eigenvalue of a perfectly spread (sin, cos) sampling. */
#define ALIAS_FULL_EIGENVALUE 0.5
/* Angles per vectorised pass of the alias check. */
#define ALIAS_CHUNK 256

/* sin and cos of omega alpha for k <= ALIAS_CHUNK angles (padded lanes). */
VM_KERNEL static void phase_chunk(size_t k, const double *alpha_rad, double omega, double *s,
                                  double *c)
{
    _Alignas(VM_ALIGN) double a[ALIAS_CHUNK];
    size_t kp = vm_pad(k);
    for (size_t i = 0; i < kp; i++)
        a[i] = i < k ? alpha_rad[i] : 0.0;
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        s[i] = sin(omega * a[i]);
        c[i] = cos(omega * a[i]);
    }
}

void ess_alias_check(const double *alpha_rad, size_t n, double omega, double threshold,
                     ess_alias *out)
{
    _Alignas(VM_ALIGN) double sn[ALIAS_CHUNK], cs[ALIAS_CHUNK];
    double ms = 0, mc = 0, ss = 0, cc = 0, sc = 0;
    for (size_t i0 = 0; i0 < n; i0 += ALIAS_CHUNK) {
        size_t k = n - i0 < ALIAS_CHUNK ? n - i0 : ALIAS_CHUNK;
        phase_chunk(k, alpha_rad + i0, omega, sn, cs);
        for (size_t i = 0; i < k; i++) {
            ms += sn[i];
            mc += cs[i];
        }
    }
    ms /= (double)n;
    mc /= (double)n;
    for (size_t i0 = 0; i0 < n; i0 += ALIAS_CHUNK) {
        size_t k = n - i0 < ALIAS_CHUNK ? n - i0 : ALIAS_CHUNK;
        phase_chunk(k, alpha_rad + i0, omega, sn, cs);
        for (size_t i = 0; i < k; i++) {
            double si = sn[i] - ms, ci = cs[i] - mc;
            ss += si * si;
            cc += ci * ci;
            sc += si * ci;
        }
    }
    ss /= (double)n;
    cc /= (double)n;
    sc /= (double)n;
    /* Symmetric 2x2 [ss sc; sc cc]: closed-form eigen-decomposition. */
    double tr = ss + cc, det = ss * cc - sc * sc;
    double disc = sqrt(fmax(tr * tr / 4.0 - det, 0.0));
    double l[2] = {tr / 2.0 - disc, tr / 2.0 + disc};
    out->n_weak = 0;
    for (int j = 0; j < 2; j++) {
        double vx, vy;
        if (fabs(sc) > 1e-14) {
            vx = l[j] - cc;
            vy = sc;
        } else if ((ss <= cc) == (j == 0)) {
            vx = 1;
            vy = 0;
        } else {
            vx = 0;
            vy = 1;
        }
        double nrm = hypot(vx, vy);
        out->evec[j][0] = vx / nrm;
        out->evec[j][1] = vy / nrm;
        out->eig_norm[j] = l[j] / ALIAS_FULL_EIGENVALUE;
        out->weak[j] = out->eig_norm[j] < threshold;
        out->n_weak += out->weak[j];
    }
}

/* Arrays of n doubles a workspace holds: 7 columns and the 9 of the table. */
#define ESS_CALIB_ARRAYS 16

double ess_calib_bytes(size_t n)
{
    return (double)sizeof(ess_calib_workspace) +
           (double)sizeof(double) * ESS_CALIB_ARRAYS * (double)n +
           fit_workspace_bytes(n + ESS_CALIB_PRIOR_ROWS, ESS_NP);
}

ess_calib_workspace *ess_calib_alloc(size_t n)
{
    ess_calib_workspace *cw = calloc(1, sizeof *cw);
    if (!cw)
        return NULL;
    cw->n = n;
    int ok = 1;
    double **arrays[] = {&cw->alpha_rad, &cw->beta_rad, &cw->raw_rad, &cw->weight, &cw->sw,
                         &cw->scratch[0], &cw->scratch[1]};
    for (size_t k = 0; k < sizeof arrays / sizeof *arrays; k++)
        ok &= (*arrays[k] = vm_alloc(n)) != NULL;
    cw->table.n = n;
    for (int k = 0; k < 9; k++)
        ok &= (cw->table.m[k] = vm_alloc(n)) != NULL;
    cw->fw = fit_workspace_alloc(n + ESS_CALIB_PRIOR_ROWS, ESS_NP);
    if (!ok || !cw->fw) {
        ess_calib_free(cw);
        return NULL;
    }
    return cw;
}

void ess_calib_free(ess_calib_workspace *cw)
{
    if (!cw)
        return;
    free(cw->alpha_rad);
    free(cw->beta_rad);
    free(cw->raw_rad);
    free(cw->weight);
    free(cw->sw);
    free(cw->scratch[0]);
    free(cw->scratch[1]);
    for (int k = 0; k < 9; k++)
        free(cw->table.m[k]);
    fit_workspace_free(cw->fw);
    free(cw);
}

static void load_params(ess_calib_workspace *cw, const double *x)
{
    for (int j = 0; j < ESS_NP; j++)
        cw->model.p[j] = x[j];
    ess_model_prepare(&cw->model);
}

static double prior_weight(const ess_calib_workspace *cw, int j)
{
    return cw->alias.weak[j] ? sqrt((double)cw->n) : 0.0;
}

/* Residuals and Jacobian together (fit_fdf): the data rows in one
 * vectorised pass, then the prior rows. */
static int residual_fdf(const double *x, void *params, double *f, double *J, size_t ld)
{
    ess_calib_workspace *cw = params;
    load_params(cw, x);
    ess_model_batch(&cw->model, &cw->table, cw->raw_rad, cw->sw, f, J, ld);
    for (int j = 0; j < ESS_CALIB_PRIOR_ROWS; j++) {
        double w = prior_weight(cw, j);
        size_t row = cw->n + (size_t)j;
        f[row] = w * (cw->alias.evec[j][0] * cw->model.p[ESS_P_KS] +
                      cw->alias.evec[j][1] * cw->model.p[ESS_P_KC]);
        for (int k = 0; k < ESS_NP; k++)
            J[(size_t)k * ld + row] = 0.0;
        J[(size_t)ESS_P_KS * ld + row] = w * cw->alias.evec[j][0];
        J[(size_t)ESS_P_KC * ld + row] = w * cw->alias.evec[j][1];
    }
    return GSL_SUCCESS;
}

int ess_calibrate(ess_calib_workspace *cw, double theta0_rad, double roll_rad,
                  double alias_threshold, int max_iter, ess_model *out, fit_result *res)
{
    ess_model_init(&cw->model, theta0_rad, roll_rad);
    cw->table.n = cw->n;
    ess_table_fill(&cw->table, cw->alpha_rad, cw->beta_rad);
    for (size_t i = 0; i < vm_pad(cw->n); i++)
        cw->sw[i] = i < cw->n && cw->weight[i] > 0 ? sqrt(cw->weight[i]) : 0.0;
    ess_alias_check(cw->alpha_rad, cw->n, cw->model.omega, alias_threshold, &cw->alias);
    double x[ESS_NP];
    for (int j = 0; j < ESS_NP; j++)
        x[j] = cw->model.p[j];
    int st = fit_solve(cw->fw, residual_fdf, cw, x, max_iter, res);
    ess_model_init(out, theta0_rad, roll_rad);
    for (int j = 0; j < ESS_NP; j++)
        out->p[j] = x[j];
    ess_model_prepare(out);
    return st;
}

double ess_calib_residual_rms(const ess_calib_workspace *cw, const ess_model *m)
{
    double *pred = cw->scratch[0];
    ess_model_predict_batch(m, &cw->table, pred);
    double sum = 0;
    size_t k = 0;
    for (size_t i = 0; i < cw->n; i++)
        if (cw->weight[i] > 0) {
            double r = pred[i] - cw->raw_rad[i];
            sum += r * r;
            k++;
        }
    return k ? sqrt(sum / (double)k) : GSL_NAN;
}
