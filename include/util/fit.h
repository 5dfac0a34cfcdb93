/* fit.h - one nonlinear least-squares engine for every calibration model:
 * Levenberg-Marquardt on the normal equations with the model's analytic
 * Jacobian.
 *
 * The algorithm is that of GSL's gsl_multifit_nlinear trust-region driver
 * with the Levenberg-Marquardt subproblem, More's diagonal scaling,
 * Nielsen's damping update and GSL's convergence tests (step below xtol,
 * scaled gradient below gtol), solved like GSL's Cholesky solver, with two
 * differences that make it several times faster for these problems (n of
 * 1,000 to 4,000 residuals, 8 parameters):
 *  - residuals and Jacobian come from one call per parameter vector (the
 *    model's work at each point is shared), and every pass over the n rows
 *    (J^T J, J^T f, |f|) is one vectorised loop: the iteration itself never
 *    touches an n x p matrix again;
 *  - the damping starts where GSL's does (1e-3 of the largest scaled
 *    diagonal) but falls tenfold per good step (GSL: threefold at most)
 *    down to a floor of 1e-7: the calibration problems are nearly linear,
 *    so the fit converges in a few iterations instead of spending eight on
 *    walking the damping down;
 *  - besides GSL's tests it stops when a full Gauss-Newton step would lower
 *    the cost by less than 1e-12 of it (info 3): GSL's tests wait for the
 *    steps to reach rounding noise, which takes several more evaluations.
 * Linear algebra (the p x p Cholesky factors, condition, inverse) is GSL's.
 *
 * A fit_workspace is allocated once per thread for a fixed problem size
 * (n residuals, p parameters) and reused for every unit: fit_solve does not
 * allocate.  Both the Monte Carlo and `sunmc calibrate` go through here.
 */
#ifndef SUNMC_FIT_H
#define SUNMC_FIT_H

#include <gsl/gsl_matrix.h>
#include <gsl/gsl_permutation.h>
#include <gsl/gsl_vector.h>
#include <stddef.h>

/* Residuals f[n] and Jacobian J (column-major: J[j * ld + i] = d f_i /
 * d x_j) at x[p], computed together: most of their work (the model at each
 * point) is shared.  f and every column of J have room for ld >= n values,
 * ld a multiple of VM_PAD (vmath.h), so a vectorised fdf may run its loops
 * over padded counts; rows from n on are ignored.  Returns GSL_SUCCESS or a
 * GSL error code. */
typedef int (*fit_fdf)(const double *x, void *params, double *f, double *J, size_t ld);

typedef struct {
    size_t n, p;
    size_t ld;                 /* rows of f and of each column of J */
    double *f, *J;             /* at the current x */
    double *f_trial, *J_trial; /* at the trial x */
    double *x, *x_trial, *dx, *g, *diag, *work; /* p each */
    gsl_matrix *JTJ;           /* J^T J at the current x */
    gsl_matrix *fac;           /* its (damped) factorisation */
    gsl_permutation *perm;
    gsl_vector *rhs, *step, *work3p;
    gsl_matrix *covar;         /* p x p */
    /* Gaussian priors (fit_prior_set): p extra residual rows
     * prior_w[j] (x[j] - prior_mean[j]); all weights 0 when off. */
    double *prior_mean, *prior_w;
    int prior_on;
    /* The first iteration's damping, relative to the largest scaled
     * diagonal of J^T J: fit_workspace_alloc sets GSL's 1e-3.  A fit that
     * starts next to its solution (a second stage from a first stage's
     * answer) may set it as low as the floor, 1e-7, and skip the steps that
     * only walk the damping down; the solution is the same. */
    double mu0;
} fit_workspace;

typedef struct {
    int status;          /* GSL status of the driver (GSL_SUCCESS, GSL_EMAXITER, ...) */
    int info;            /* convergence reason: 1 small step, 2 small gradient (GSL's),
                          * 3 a further step would not lower the cost (fit.c) */
    size_t iterations;
    double chisq;        /* sum of squared residuals at the solution (data rows only) */
    double chisq_prior;  /* the prior rows' share of the cost at the solution (0 when off) */
    double rcond;        /* reciprocal condition number of J at the solution
                          * (sqrt of the 1-norm estimate for J^T J) */
} fit_result;

/* Allocate for n residuals and p parameters.  NULL on failure. */
fit_workspace *fit_workspace_alloc(size_t n, size_t p);

/* About how many bytes fit_workspace_alloc(n, p) takes (memory checks and
 * their messages). */
double fit_workspace_bytes(size_t n, size_t p);
void fit_workspace_free(fit_workspace *fw);

/* Minimise |f(x)|^2 from the start x[p]; x receives the solution.  Returns
 * SUNMC_OK when it converged, SUNMC_EFIT otherwise (res says why). */
int fit_solve(fit_workspace *fw, fit_fdf fdf, void *params, double *x, int max_iter,
              fit_result *res);

/* Covariance (J^T J)^-1 at the last solution into fw->covar (unscaled). */
int fit_covariance(fit_workspace *fw);

/* fit_covariance when the data rows' variance s2 estimated from the
 * residuals differs from sigma_row^2, the one the priors' weights assumed
 * (fit_prior_set): k = s2 / sigma_row^2.  covar = (J^T J + k W^2)^-1, so
 * s2 covar = (J^T J / s2 + Sigma_prior^-1)^-1, the posterior covariance
 * with the prior's own variances kept.  k = 1 is fit_covariance. */
int fit_covariance_rescaled(fit_workspace *fw, double k);

/* Gaussian priors on the parameters, as p residual rows appended to the
 * model's n: row j is weight[j] (x[j] - mean[j]), so in the data's residual
 * units weight[j] = sigma_row / sigma_j (a data row's noise over the
 * prior's standard deviation of parameter j); weight 0 leaves x[j] free.
 * They enter J^T J (so fit_covariance's inverse is the posterior's, in
 * units of the data rows' variance), J^T f and the cost; res->chisq stays
 * the data rows' sum.  Kept for every fit_solve until fit_prior_clear.
 * Weights must be finite and >= 0: SUNMC_EINPUT otherwise. */
int fit_prior_set(fit_workspace *fw, const double *mean, const double *weight);
void fit_prior_clear(fit_workspace *fw);

/* A words-for-humans reason for a GSL status / info code. */
const char *fit_reason(const fit_result *res);

#endif
