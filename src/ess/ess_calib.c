/* ess_calib.c - alias detection and the ESS calibration fit. */
#include "ess_calib.h"
#include "status.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdlib.h>

/* Eigenvalue of a perfectly spread (sin, cos) sampling. */
#define ALIAS_FULL_EIGENVALUE 0.5

void ess_alias_check(const double *alpha_rad, size_t n, double omega, double threshold,
                     ess_alias *out)
{
    double ms = 0, mc = 0, ss = 0, cc = 0, sc = 0;
    for (size_t i = 0; i < n; i++) {
        ms += sin(omega * alpha_rad[i]);
        mc += cos(omega * alpha_rad[i]);
    }
    ms /= (double)n;
    mc /= (double)n;
    for (size_t i = 0; i < n; i++) {
        double s = sin(omega * alpha_rad[i]) - ms, c = cos(omega * alpha_rad[i]) - mc;
        ss += s * s;
        cc += c * c;
        sc += s * c;
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

ess_calib_workspace *ess_calib_alloc(size_t n)
{
    ess_calib_workspace *cw = calloc(1, sizeof *cw);
    if (!cw)
        return NULL;
    cw->n = n;
    cw->alpha_rad = calloc(n, sizeof(double));
    cw->beta_rad = calloc(n, sizeof(double));
    cw->raw_rad = calloc(n, sizeof(double));
    cw->weight = calloc(n, sizeof(double));
    cw->table = calloc(n, sizeof(mat3));
    cw->fw = fit_workspace_alloc(n + ESS_CALIB_PRIOR_ROWS, ESS_NP);
    if (!cw->alpha_rad || !cw->beta_rad || !cw->raw_rad || !cw->weight || !cw->table || !cw->fw) {
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
    free(cw->table);
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

/* Residuals and Jacobian together (fit_fdf). */
static int residual_fdf(const double *x, void *params, double *f, double *J)
{
    ess_calib_workspace *cw = params;
    load_params(cw, x);
    for (size_t i = 0; i < cw->n; i++) {
        double *Ji = J + i * ESS_NP;
        if (cw->weight[i] > 0) {
            double sw = sqrt(cw->weight[i]), g[ESS_NP];
            double r = ess_model_predict_m(&cw->model, (const double(*)[3])cw->table[i], g);
            f[i] = sw * (r - cw->raw_rad[i]);
            for (int j = 0; j < ESS_NP; j++)
                Ji[j] = sw * g[j];
        } else {
            f[i] = 0.0;
            for (int j = 0; j < ESS_NP; j++)
                Ji[j] = 0.0;
        }
    }
    for (int j = 0; j < ESS_CALIB_PRIOR_ROWS; j++) {
        double w = prior_weight(cw, j);
        double *Jr = J + (cw->n + (size_t)j) * ESS_NP;
        f[cw->n + (size_t)j] = w * (cw->alias.evec[j][0] * cw->model.p[ESS_P_KS] +
                                    cw->alias.evec[j][1] * cw->model.p[ESS_P_KC]);
        for (int k = 0; k < ESS_NP; k++)
            Jr[k] = 0.0;
        Jr[ESS_P_KS] = w * cw->alias.evec[j][0];
        Jr[ESS_P_KC] = w * cw->alias.evec[j][1];
    }
    return GSL_SUCCESS;
}

int ess_calibrate(ess_calib_workspace *cw, double theta0_rad, double roll_rad,
                  double alias_threshold, int max_iter, ess_model *out, fit_result *res)
{
    ess_model_init(&cw->model, theta0_rad, roll_rad);
    for (size_t i = 0; i < cw->n; i++)
        ess_turntable_matrix(cw->alpha_rad[i], cw->beta_rad[i], cw->table[i]);
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
    double sum = 0;
    size_t k = 0;
    for (size_t i = 0; i < cw->n; i++)
        if (cw->weight[i] > 0) {
            double r = ess_model_predict(m, cw->alpha_rad[i], cw->beta_rad[i], NULL) - cw->raw_rad[i];
            sum += r * r;
            k++;
        }
    return k ? sqrt(sum / (double)k) : GSL_NAN;
}
