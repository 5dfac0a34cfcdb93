/* fit.h - one nonlinear least-squares engine for every calibration model:
 * gsl_multifit_nlinear (Levenberg-Marquardt, trust region) with the model's
 * analytic Jacobian.
 *
 * A fit_workspace is allocated once per thread for a fixed problem size
 * (n residuals, p parameters) and reused for every unit: fit_solve does not
 * allocate.  Both the Monte Carlo and `sunmc calibrate` go through here.
 */
#ifndef SUNMC_FIT_H
#define SUNMC_FIT_H

#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_vector.h>

/* Residuals f[n] and Jacobian J[n * p] (row-major, J[i * p + j] = d f_i /
 * d x_j) at x[p], computed together: most of their work (the model at each
 * point) is shared.  Returns GSL_SUCCESS or a GSL error code. */
typedef int (*fit_fdf)(const double *x, void *params, double *f, double *J);

typedef struct {
    size_t n, p;
    gsl_multifit_nlinear_workspace *w;
    gsl_vector *x0;
    gsl_matrix *covar; /* p x p */
    /* Last evaluation, keyed on its parameter vector: GSL asks for f and
     * then J at the same x; both come from one fdf call. */
    fit_fdf fdf;
    void *fdf_params;
    double *cache_x, *cache_f, *cache_J;
    int cache_valid;
} fit_workspace;

typedef struct {
    int status;          /* GSL status of the driver (GSL_SUCCESS, GSL_EMAXITER, ...) */
    int info;            /* GSL convergence reason: 1 small step, 2 small gradient */
    size_t iterations;
    double chisq;        /* sum of squared residuals at the solution */
    double rcond;        /* reciprocal condition number of J at the solution */
} fit_result;

/* Allocate for n residuals and p parameters.  NULL on failure. */
fit_workspace *fit_workspace_alloc(size_t n, size_t p);
void fit_workspace_free(fit_workspace *fw);

/* Minimise |f(x)|^2 from the start x[p]; x receives the solution.  Returns
 * SUNMC_OK when GSL converged, SUNMC_EFIT otherwise (res says why). */
int fit_solve(fit_workspace *fw, fit_fdf fdf, void *params, double *x, int max_iter,
              fit_result *res);

/* Covariance (J^T J)^-1 at the last solution into fw->covar (unscaled). */
int fit_covariance(fit_workspace *fw);

/* A words-for-humans reason for a GSL status / info code. */
const char *fit_reason(const fit_result *res);

#endif
