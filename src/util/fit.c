/* fit.c - the gsl_multifit_nlinear wrapper shared by all calibration models. */
#include "fit.h"
#include "status.h"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <stdlib.h>
#include <string.h>

#define FIT_XTOL 1e-12
#define FIT_GTOL 1e-12
#define FIT_FTOL 0.0
#define FIT_COVAR_EPS 1e-12

fit_workspace *fit_workspace_alloc(size_t n, size_t p)
{
    if (n < p || p == 0)
        return NULL;
    fit_workspace *fw = calloc(1, sizeof *fw);
    if (!fw)
        return NULL;
    gsl_multifit_nlinear_parameters params = gsl_multifit_nlinear_default_parameters();
    params.trs = gsl_multifit_nlinear_trs_lm;
    params.scale = gsl_multifit_nlinear_scale_more;
    params.solver = gsl_multifit_nlinear_solver_qr;
    fw->n = n;
    fw->p = p;
    fw->w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &params, n, p);
    fw->x0 = gsl_vector_alloc(p);
    fw->covar = gsl_matrix_alloc(p, p);
    fw->cache_x = malloc(p * sizeof(double));
    fw->cache_f = malloc(n * sizeof(double));
    fw->cache_J = malloc(n * p * sizeof(double));
    if (!fw->w || !fw->x0 || !fw->covar || !fw->cache_x || !fw->cache_f || !fw->cache_J) {
        fit_workspace_free(fw);
        return NULL;
    }
    return fw;
}

void fit_workspace_free(fit_workspace *fw)
{
    if (!fw)
        return;
    if (fw->w)
        gsl_multifit_nlinear_free(fw->w);
    if (fw->x0)
        gsl_vector_free(fw->x0);
    if (fw->covar)
        gsl_matrix_free(fw->covar);
    free(fw->cache_x);
    free(fw->cache_f);
    free(fw->cache_J);
    free(fw);
}

/* Evaluate f and J together at x unless the cache holds x already. */
static int fit_eval(const gsl_vector *x, fit_workspace *fw)
{
    size_t p = fw->p;
    int hit = fw->cache_valid;
    for (size_t j = 0; j < p && hit; j++)
        hit = gsl_vector_get(x, j) == fw->cache_x[j];
    if (hit)
        return GSL_SUCCESS;
    for (size_t j = 0; j < p; j++)
        fw->cache_x[j] = gsl_vector_get(x, j);
    fw->cache_valid = 0;
    int st = fw->fdf(fw->cache_x, fw->fdf_params, fw->cache_f, fw->cache_J);
    fw->cache_valid = st == GSL_SUCCESS;
    return st;
}

static int fit_f(const gsl_vector *x, void *ctx, gsl_vector *f)
{
    fit_workspace *fw = ctx;
    int st = fit_eval(x, fw);
    if (st != GSL_SUCCESS)
        return st;
    for (size_t i = 0; i < fw->n; i++)
        gsl_vector_set(f, i, fw->cache_f[i]);
    return GSL_SUCCESS;
}

static int fit_df(const gsl_vector *x, void *ctx, gsl_matrix *J)
{
    fit_workspace *fw = ctx;
    int st = fit_eval(x, fw);
    if (st != GSL_SUCCESS)
        return st;
    for (size_t i = 0; i < fw->n; i++)
        memcpy(gsl_matrix_ptr(J, i, 0), fw->cache_J + i * fw->p, fw->p * sizeof(double));
    return GSL_SUCCESS;
}

int fit_solve(fit_workspace *fw, fit_fdf fdf, void *params, double *x, int max_iter,
              fit_result *res)
{
    gsl_multifit_nlinear_fdf gfdf;
    gfdf.f = fit_f;
    gfdf.df = fit_df;
    gfdf.fvv = NULL;
    gfdf.n = fw->n;
    gfdf.p = fw->p;
    gfdf.params = fw;
    fw->fdf = fdf;
    fw->fdf_params = params;
    fw->cache_valid = 0;
    for (size_t i = 0; i < fw->p; i++)
        gsl_vector_set(fw->x0, i, x[i]);

    res->iterations = 0;
    res->info = 0;
    res->chisq = GSL_NAN;
    res->rcond = GSL_NAN;
    int st = gsl_multifit_nlinear_init(fw->x0, &gfdf, fw->w);
    if (st == GSL_SUCCESS)
        st = gsl_multifit_nlinear_driver((size_t)max_iter, FIT_XTOL, FIT_GTOL, FIT_FTOL, NULL, NULL,
                                         &res->info, fw->w);
    res->status = st;
    res->iterations = gsl_multifit_nlinear_niter(fw->w);
    gsl_vector *xs = gsl_multifit_nlinear_position(fw->w);
    gsl_vector *fr = gsl_multifit_nlinear_residual(fw->w);
    for (size_t i = 0; i < fw->p; i++)
        x[i] = gsl_vector_get(xs, i);
    double chisq = GSL_NAN;
    if (gsl_blas_ddot(fr, fr, &chisq) != GSL_SUCCESS)
        chisq = GSL_NAN;
    res->chisq = chisq;
    double rc;
    if (gsl_multifit_nlinear_rcond(&rc, fw->w) == GSL_SUCCESS)
        res->rcond = rc;
    if (st != GSL_SUCCESS || !gsl_finite(chisq))
        return SUNMC_EFIT;
    for (size_t i = 0; i < fw->p; i++)
        if (!gsl_finite(x[i]))
            return SUNMC_EFIT;
    return SUNMC_OK;
}

int fit_covariance(fit_workspace *fw)
{
    gsl_matrix *J = gsl_multifit_nlinear_jac(fw->w);
    int st = gsl_multifit_nlinear_covar(J, FIT_COVAR_EPS, fw->covar);
    return st == GSL_SUCCESS ? SUNMC_OK : SUNMC_EFIT;
}

const char *fit_reason(const fit_result *res)
{
    if (res->status == GSL_SUCCESS)
        return res->info == 1 ? "converged: step below tolerance"
                              : "converged: gradient below tolerance";
    if (res->status == GSL_EMAXITER)
        return "did not converge within calibration.max_iterations";
    if (res->status == GSL_ENOPROG)
        return "no further progress possible (singular or flat problem)";
    return gsl_strerror(res->status);
}
