/* ess_calib.c - alias detection and the ESS calibration fit. */
#include "ess_calib.h"
#include "status.h"
#include "vmath.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_math.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

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

/* The 2x2 covariance [ss sc; sc cc] of a harmonic's sampled (sin, cos):
 * closed-form eigen-decomposition, directions below threshold weak. */
static void alias_eigen(double ss, double sc, double cc, double threshold, ess_alias *out)
{
    double tr = ss + cc, det = ss * cc - sc * sc;
    double disc = sqrt(fmax(tr * tr / 4.0 - det, 0.0));
    double l[2] = {tr / 2.0 - disc, tr / 2.0 + disc};
    out->n_weak = 0;
    for (int j = 0; j < 2; j++) {
        double vx, vy;
        if (fabs(sc) > 1e-14) {
            /* (l - cc, sc) and (sc, l - ss) both solve [ss sc; sc cc] v = l v:
             * the longer one, since one of them vanishes to rounding noise
             * when v is near an axis */
            vx = l[j] - cc;
            vy = sc;
            if (hypot(sc, l[j] - ss) > hypot(vx, vy)) {
                vx = sc;
                vy = l[j] - ss;
            }
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
    alias_eigen(ss, sc, cc, threshold, out);
}

/* Mean of x[0..n) times x[0..n) against y: (1/n) sum x y. */
static double mean_dot(const double *x, const double *y, size_t n)
{
    double sum = 0;
    for (size_t i = 0; i < n; i++)
        sum += x[i] * y[i];
    return sum / (double)n;
}

/* sin and cos of omega alpha over all n angles, centred. */
static void centred_phases(const double *alpha_rad, size_t n, double omega, double *s, double *c)
{
    for (size_t i0 = 0; i0 < n; i0 += ALIAS_CHUNK) {
        size_t k = n - i0 < ALIAS_CHUNK ? n - i0 : ALIAS_CHUNK;
        phase_chunk(k, alpha_rad + i0, omega, s + i0, c + i0);
    }
    double ms = 0, mc = 0;
    for (size_t i = 0; i < n; i++) {
        ms += s[i];
        mc += c[i];
    }
    ms /= (double)n;
    mc /= (double)n;
    for (size_t i = 0; i < n; i++) {
        s[i] -= ms;
        c[i] -= mc;
    }
}

/* Append the strong directions of harmonic a (its centred s, c) to the
 * basis, each scaled to a mean square of 1. */
static void basis_add(const ess_alias *a, const double *s, const double *c, size_t n,
                      double *const *basis, int *nb)
{
    for (int j = 0; j < 2; j++) {
        if (a->weak[j])
            continue;
        double *b = basis[*nb];
        for (size_t i = 0; i < n; i++)
            b[i] = a->evec[j][0] * s[i] + a->evec[j][1] * c[i];
        double nrm = sqrt(mean_dot(b, b, n));
        for (size_t i = 0; i < n; i++)
            b[i] /= nrm;
        (*nb)++;
    }
}

/* The distinct harmonics of a model's fine-code terms, in their order. */
static int model_harmonics(int kind, int harmonic[ESS_ALIAS_MAX_H])
{
    int nt, nh = 0;
    const ess_fine_term *t = ess_model_fine_terms(kind, &nt);
    for (int k = 0; k < nt; k++) {
        int seen = 0;
        for (int j = 0; j < nh; j++)
            seen |= harmonic[j] == t[k].harmonic;
        if (!seen && nh < ESS_ALIAS_MAX_H)
            harmonic[nh++] = t[k].harmonic;
    }
    return nh;
}

void ess_alias_check_set(const double *alpha_rad, size_t n, int kind, double theta0_rad,
                         double threshold, double *const *work, ess_alias_set *out)
{
    double w1 = 2.0 * M_PI / theta0_rad;
    out->n_h = model_harmonics(kind, out->harmonic);
    ess_alias_check(alpha_rad, n, out->harmonic[0] * w1, threshold, &out->h[0]);
    out->n_weak = out->h[0].n_weak;
    if (out->n_h > 1) {
        /* work: the basis (2 per harmonic), then the candidate's s and c */
        double *const *basis = work;
        double *s = work[2 * ESS_ALIAS_MAX_H], *c = work[2 * ESS_ALIAS_MAX_H + 1];
        int nb = 0;
        centred_phases(alpha_rad, n, out->harmonic[0] * w1, s, c);
        basis_add(&out->h[0], s, c, n, basis, &nb);
        for (int h = 1; h < out->n_h; h++) {
            centred_phases(alpha_rad, n, out->harmonic[h] * w1, s, c);
            for (int k = 0; k < nb; k++) {
                double ps = mean_dot(s, basis[k], n), pc = mean_dot(c, basis[k], n);
                for (size_t i = 0; i < n; i++) {
                    s[i] -= ps * basis[k][i];
                    c[i] -= pc * basis[k][i];
                }
            }
            alias_eigen(mean_dot(s, s, n), mean_dot(s, c, n), mean_dot(c, c, n), threshold,
                        &out->h[h]);
            out->n_weak += out->h[h].n_weak;
            basis_add(&out->h[h], s, c, n, basis, &nb);
        }
    }
    /* prior rows: each weak direction of a harmonic, for each of its terms */
    int nt;
    const ess_fine_term *t = ess_model_fine_terms(kind, &nt);
    out->n_prior = 0;
    for (int k = 0; k < nt; k++)
        for (int h = 0; h < out->n_h; h++)
            if (out->harmonic[h] == t[k].harmonic)
                out->n_prior += out->h[h].n_weak;
}

/* Arrays of n doubles a workspace holds: 7 columns and the 9 of the table;
 * the extended model's alias check adds its work arrays. */
#define ESS_CALIB_ARRAYS 16
#define ESS_ALIAS_ARRAYS (2 * ESS_ALIAS_MAX_H + 2)

int ess_calib_prior_rows(int kind)
{
    int nt;
    ess_model_fine_terms(kind, &nt);
    return 2 * nt;
}

double ess_calib_bytes(size_t n, int kind)
{
    int arrays = ESS_CALIB_ARRAYS + (kind == ESS_MODEL_EXTENDED ? ESS_ALIAS_ARRAYS : 0);
    return (double)sizeof(ess_calib_workspace) + (double)sizeof(double) * arrays * (double)n +
           fit_workspace_bytes(n + (size_t)ess_calib_prior_rows(kind), (size_t)ess_model_np(kind)) +
           (ESS_MODEL_HAS_SPLINE(kind) ? lab_spline_ws_bytes(n) + (double)(n + 1) * sizeof(int)
                                       : 0.0);
}

ess_calib_workspace *ess_calib_alloc(size_t n)
{
    return ess_calib_alloc_kind(n, ESS_MODEL_PAPER);
}

ess_calib_workspace *ess_calib_alloc_kind(size_t n, int kind)
{
    return ess_calib_alloc_fix(n, kind, 0);
}

ess_calib_workspace *ess_calib_alloc_fix(size_t n, int kind, int fix_sun_y)
{
    ess_calib_workspace *cw = calloc(1, sizeof *cw);
    if (!cw)
        return NULL;
    cw->n = n;
    cw->kind = kind;
    cw->fix_sun_y = fix_sun_y != 0;
    cw->np_fit = ess_model_np(kind) - cw->fix_sun_y;
    cw->n_prior_rows = ess_calib_prior_rows(kind);
    int ok = 1;
    double **arrays[] = {&cw->alpha_rad, &cw->beta_rad, &cw->raw_rad, &cw->weight, &cw->sw,
                         &cw->scratch[0], &cw->scratch[1]};
    for (size_t k = 0; k < sizeof arrays / sizeof *arrays; k++)
        ok &= (*arrays[k] = vm_alloc(n)) != NULL;
    cw->table.n = n;
    for (int k = 0; k < 9; k++)
        ok &= (cw->table.m[k] = vm_alloc(n)) != NULL;
    for (int k = 0; k < ESS_ALIAS_ARRAYS && kind == ESS_MODEL_EXTENDED; k++)
        ok &= (cw->alias_work[k] = vm_alloc(n)) != NULL;
    cw->fw = fit_workspace_alloc(n + (size_t)cw->n_prior_rows, (size_t)cw->np_fit);
    if (cw->fw && cw->fix_sun_y)
        ok &= (cw->jfull = vm_alloc(cw->fw->ld * (size_t)ess_model_np(kind))) != NULL;
    if (ESS_MODEL_HAS_SPLINE(kind)) {
        ok &= (cw->fold = malloc((n + 1) * sizeof *cw->fold)) != NULL;
        ok &= (cw->sws = lab_spline_ws_alloc(n)) != NULL;
    }
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
    for (int k = 0; k < ESS_ALIAS_ARRAYS; k++)
        free(cw->alias_work[k]);
    free(cw->jfull);
    free(cw->fold);
    lab_spline_ws_free(cw->sws);
    fit_workspace_free(cw->fw);
    free(cw);
}

int ess_calib_param_of(const ess_calib_workspace *cw, int j)
{
    return cw->fix_sun_y && j >= ESS_P_SUN_Y ? j + 1 : j;
}

static void load_params(ess_calib_workspace *cw, const double *x)
{
    for (int j = 0; j < cw->np_fit; j++)
        cw->model.p[ess_calib_param_of(cw, j)] = x[j];
    ess_model_prepare(&cw->model);
}

/* The alias result of the harmonic of fine-code term t. */
static const ess_alias *term_alias(const ess_calib_workspace *cw, const ess_fine_term *t)
{
    for (int h = 1; h < cw->alias.n_h; h++)
        if (cw->alias.harmonic[h] == t->harmonic)
            return &cw->alias.h[h];
    return &cw->alias.h[0];
}

static double prior_weight(const ess_calib_workspace *cw, const ess_alias *a, int j)
{
    return a->weak[j] ? sqrt((double)cw->n) : 0.0;
}

/* Residuals and Jacobian together (fit_fdf): the data rows in one
 * vectorised pass, then the prior rows: direction j of fine-code term k at
 * row n + 2 k + j.  With the sun tilt fixed the model's full Jacobian goes
 * to cw->jfull and the fitted parameters' columns are copied into J. */
static int residual_fdf(const double *x, void *params, double *f, double *Jfit, size_t ld)
{
    ess_calib_workspace *cw = params;
    load_params(cw, x);
    double *J = cw->fix_sun_y ? cw->jfull : Jfit;
    ess_model_batch(&cw->model, &cw->table, cw->raw_rad, cw->sw, f, J, ld);
    int nt;
    const ess_fine_term *terms = ess_model_fine_terms(cw->kind, &nt);
    for (int r = 0; r < cw->n_prior_rows; r++) {
        const ess_fine_term *t = &terms[r / 2];
        const ess_alias *a = term_alias(cw, t);
        int j = r % 2;
        double w = prior_weight(cw, a, j);
        size_t row = cw->n + (size_t)r;
        f[row] = w * (a->evec[j][0] * cw->model.p[t->p_sin] + a->evec[j][1] * cw->model.p[t->p_cos]);
        for (int k = 0; k < cw->model.np; k++)
            J[(size_t)k * ld + row] = 0.0;
        J[(size_t)t->p_sin * ld + row] = w * a->evec[j][0];
        J[(size_t)t->p_cos * ld + row] = w * a->evec[j][1];
    }
    if (cw->fix_sun_y)
        for (int j = 0; j < cw->np_fit; j++)
            memcpy(Jfit + (size_t)j * ld, J + (size_t)ess_calib_param_of(cw, j) * ld,
                   ld * sizeof *J);
    return GSL_SUCCESS;
}

int ess_calibrate(ess_calib_workspace *cw, double theta0_rad, double roll_rad,
                  double alias_threshold, int max_iter, ess_model *out, fit_result *res)
{
    ess_model_init_kind(&cw->model, cw->kind, theta0_rad, roll_rad);
    if (cw->fix_sun_y) {
        cw->model.p[ESS_P_SUN_Y] = cw->sun_y_rad;
        cw->model.sun_y_fixed = 1;
        ess_model_prepare(&cw->model);
    }
    if (cw->kind == ESS_MODEL_SPLINE || cw->kind == ESS_MODEL_TABLE) {
        /* no physics fitted: the nominal model gives the truth, the spline
         * the angle (no Jacobian: rcond 1, the penalty keeps it regular) */
        *out = cw->model;
        memset(res, 0, sizeof *res);
        res->rcond = 1.0;
        int st = ess_spline_fit(cw, out);
        res->status = st == SUNMC_OK ? GSL_SUCCESS : GSL_EFAILED;
        return st == SUNMC_OK ? SUNMC_OK : SUNMC_EFIT;
    }
    cw->table.n = cw->n;
    ess_table_fill(&cw->table, cw->alpha_rad, cw->beta_rad);
    for (size_t i = 0; i < vm_pad(cw->n); i++)
        cw->sw[i] = i < cw->n && cw->weight[i] > 0 ? sqrt(cw->weight[i]) : 0.0;
    ess_alias_check_set(cw->alpha_rad, cw->n, cw->kind, theta0_rad, alias_threshold,
                        cw->alias_work, &cw->alias);
    double x[ESS_NP_MAX];
    for (int j = 0; j < cw->np_fit; j++)
        x[j] = cw->model.p[ess_calib_param_of(cw, j)];
    int st = fit_solve(cw->fw, residual_fdf, cw, x, max_iter, res);
    ess_model_init_kind(out, cw->kind, theta0_rad, roll_rad);
    out->p[ESS_P_SUN_Y] = cw->model.p[ESS_P_SUN_Y];
    out->sun_y_fixed = cw->fix_sun_y;
    for (int j = 0; j < cw->np_fit; j++)
        out->p[ess_calib_param_of(cw, j)] = x[j];
    ess_model_prepare(out);
    if (st == SUNMC_OK && cw->kind == ESS_MODEL_HYBRID && ess_spline_fit(cw, out) != SUNMC_OK)
        st = SUNMC_EFIT;
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
