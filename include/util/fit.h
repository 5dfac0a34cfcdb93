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

typedef struct {
    size_t n, p;
    gsl_multifit_nlinear_workspace *w;
    gsl_vector *x0;
    gsl_matrix *covar; /* p x p */
} fit_workspace;

/* Residual function and Jacobian as gsl_multifit_nlinear wants them. */
typedef int (*fit_f)(const gsl_vector *x, void *params, gsl_vector *f);
typedef int (*fit_df)(const gsl_vector *x, void *params, gsl_matrix *J);

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
int fit_solve(fit_workspace *fw, fit_f f, fit_df df, void *params, double *x, int max_iter,
              fit_result *res);

/* Covariance (J^T J)^-1 at the last solution into fw->covar (unscaled). */
int fit_covariance(fit_workspace *fw);

/* A words-for-humans reason for a GSL status / info code. */
const char *fit_reason(const fit_result *res);

#endif
