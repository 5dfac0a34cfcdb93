/* fit.c - Levenberg-Marquardt on the normal equations (see fit.h). */
#include "fit.h"
#include "status.h"
#include "vmath.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_math.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FIT_XTOL 1e-12
#define FIT_GTOL 1e-12
/* Converged when a full Gauss-Newton step would lower the cost by less than
 * this fraction of it: the parameters are then within about 1e-12 of the
 * optimum relative to their statistical spread, and further steps only
 * trade rounding noise (GSL's own tests wait for that noise to vanish and
 * spend several evaluations on it). */
#define FIT_DTOL 1e-12
/* A start whose cost |f|^2 is below this is exact to rounding in any
 * quantity of order one (residuals of 1e-11 over 10^4 points): no step
 * lowering it is the solution, whatever the gradient's rounding. */
#define FIT_F2_EXACT 1e-16
/* Damping, relative to the largest scaled diagonal of J^T J: Nielsen's
 * start (GSL's nielsen_init); on an accepted step it falls by Nielsen's
 * factor but at least FIT_MU_FALL, down to FIT_MU_MIN.  The floor keeps
 * what the data do not determine (a degenerate campaign) where the start
 * put it, as GSL's damping does; with it the well-determined directions
 * still converge as under Gauss-Newton. */
#define FIT_MU0 1.0e-3
#define FIT_MU_FALL 0.1
#define FIT_MU_MIN 1.0e-7
/* Consecutive rejected steps before giving up (GSL's trust region). */
#define FIT_MAX_BAD_STEPS 15
/* Most parameters a fit may have. */
#define FIT_MAX_P 64

double fit_workspace_bytes(size_t n, size_t p)
{
    /* f, J, their trial copies; the p x p matrices and vectors are small. */
    return (double)sizeof(double) * (2.0 * (double)vm_pad(n) * (double)(p + 1) +
                                     4.0 * (double)p * (double)p + 16.0 * (double)p);
}

fit_workspace *fit_workspace_alloc(size_t n, size_t p)
{
    if (n < p || p == 0 || p > FIT_MAX_P)
        return NULL;
    fit_workspace *fw = calloc(1, sizeof *fw);
    if (!fw)
        return NULL;
    fw->n = n;
    fw->p = p;
    fw->ld = vm_pad(n);
    fw->mu0 = FIT_MU0;
    int ok = (fw->f = vm_alloc(fw->ld)) && (fw->J = vm_alloc(fw->ld * p)) &&
             (fw->f_trial = vm_alloc(fw->ld)) && (fw->J_trial = vm_alloc(fw->ld * p));
    double **pv[] = {&fw->x,    &fw->x_trial, &fw->dx,         &fw->g,
                     &fw->diag, &fw->work,    &fw->prior_mean, &fw->prior_w};
    for (size_t k = 0; k < sizeof pv / sizeof *pv; k++)
        ok = ok && (*pv[k] = calloc(p, sizeof(double))) != NULL;
    fw->JTJ = gsl_matrix_alloc(p, p);
    fw->fac = gsl_matrix_alloc(p, p);
    fw->perm = gsl_permutation_alloc(p);
    fw->rhs = gsl_vector_alloc(p);
    fw->step = gsl_vector_alloc(p);
    fw->work3p = gsl_vector_alloc(3 * p);
    fw->covar = gsl_matrix_alloc(p, p);
    if (!ok || !fw->JTJ || !fw->fac || !fw->perm || !fw->rhs || !fw->step || !fw->work3p ||
        !fw->covar) {
        fit_workspace_free(fw);
        return NULL;
    }
    return fw;
}

void fit_workspace_free(fit_workspace *fw)
{
    if (!fw)
        return;
    double *arrays[] = {fw->f,       fw->J,  fw->f_trial, fw->J_trial, fw->x,
                        fw->x_trial, fw->dx, fw->g,       fw->diag,    fw->work,
                        fw->prior_mean, fw->prior_w};
    for (size_t k = 0; k < sizeof arrays / sizeof *arrays; k++)
        free(arrays[k]);
    /* GSL's free functions accept NULL */
    gsl_matrix_free(fw->JTJ);
    gsl_matrix_free(fw->fac);
    gsl_matrix_free(fw->covar);
    gsl_permutation_free(fw->perm);
    gsl_vector_free(fw->rhs);
    gsl_vector_free(fw->step);
    gsl_vector_free(fw->work3p);
    free(fw);
}

/* Sum of a[i] b[i] over i < n: four vector accumulators of four lanes
 * (16 partial sums, so the adds do not wait on each other; fused
 * multiply-adds on a CPU with FMA), added pairwise at the end, then the
 * last n mod 16 terms.  The order is fixed, so the sum is the same bits
 * on every call, thread and shard on one kernel path. */
typedef double fit_v4 __attribute__((vector_size(32)));
VM_KERNEL __attribute__((optimize("fp-contract=fast"))) static double
dot(const double *restrict a, const double *restrict b, size_t n)
{
    fit_v4 s0 = {0}, s1 = {0}, s2 = {0}, s3 = {0};
    size_t n16 = n / 16 * 16;
    for (size_t i = 0; i < n16; i += 16) {
        fit_v4 a0, a1, a2, a3, b0, b1, b2, b3;
        memcpy(&a0, a + i, sizeof a0);
        memcpy(&a1, a + i + 4, sizeof a1);
        memcpy(&a2, a + i + 8, sizeof a2);
        memcpy(&a3, a + i + 12, sizeof a3);
        memcpy(&b0, b + i, sizeof b0);
        memcpy(&b1, b + i + 4, sizeof b1);
        memcpy(&b2, b + i + 8, sizeof b2);
        memcpy(&b3, b + i + 12, sizeof b3);
        s0 += a0 * b0;
        s1 += a1 * b1;
        s2 += a2 * b2;
        s3 += a3 * b3;
    }
    fit_v4 t = (s0 + s1) + (s2 + s3);
    double tail = 0.0;
    for (size_t i = n16; i < n; i++)
        tail += a[i] * b[i];
    return ((t[0] + t[1]) + (t[2] + t[3])) + tail;
}

/* The prior rows' cost at x: sum of (w_j (x_j - mean_j))^2. */
static double prior_cost(const fit_workspace *fw, const double *x)
{
    double s = 0.0;
    for (size_t j = 0; fw->prior_on && j < fw->p; j++) {
        double r = fw->prior_w[j] * (x[j] - fw->prior_mean[j]);
        s += r * r;
    }
    return s;
}

/* The prior rows' part of J^T J (diagonal w^2) and of J^T f. */
static void prior_normal_equations(fit_workspace *fw)
{
    for (size_t j = 0; fw->prior_on && j < fw->p; j++) {
        double w2 = fw->prior_w[j] * fw->prior_w[j];
        *gsl_matrix_ptr(fw->JTJ, j, j) += w2;
        fw->g[j] += w2 * (fw->x[j] - fw->prior_mean[j]);
    }
}

/* J^T J and g = J^T f at the current point, the prior rows included;
 * returns the cost |f|^2 + the prior's. */
static double normal_equations(fit_workspace *fw)
{
    size_t n = fw->n, p = fw->p, ld = fw->ld;
    for (size_t j = 0; j < p; j++) {
        const double *cj = fw->J + j * ld;
        for (size_t k = 0; k <= j; k++) {
            double s = dot(cj, fw->J + k * ld, n);
            gsl_matrix_set(fw->JTJ, j, k, s);
            gsl_matrix_set(fw->JTJ, k, j, s);
        }
        fw->g[j] = dot(cj, fw->f, n);
    }
    prior_normal_equations(fw);
    return dot(fw->f, fw->f, n) + prior_cost(fw, fw->x);
}

/* More's scaling: D_j = max(D_j, |J_j|), a zero column counting as 1. */
static void scale_update(fit_workspace *fw)
{
    for (size_t j = 0; j < fw->p; j++) {
        double norm = sqrt(gsl_matrix_get(fw->JTJ, j, j));
        if (norm == 0.0)
            norm = 1.0;
        fw->diag[j] = GSL_MAX(fw->diag[j], norm);
    }
}

/* The largest scaled diagonal of J^T J: max_j |J_j|^2 / D_j^2. */
static double scaled_diagonal_max(const fit_workspace *fw)
{
    double max = 0.0;
    for (size_t j = 0; j < fw->p; j++) {
        double u = sqrt(gsl_matrix_get(fw->JTJ, j, j)) / fw->diag[j];
        max = GSL_MAX(max, u);
    }
    return max * max;
}

/* Solve (J^T J + mu D^2) v = -g into fw->dx (modified Cholesky, as GSL's
 * Cholesky solver, so a J^T J that rounding left indefinite still works). */
static int lm_step(fit_workspace *fw, double mu)
{
    size_t p = fw->p;
    gsl_matrix_memcpy(fw->fac, fw->JTJ);
    for (size_t j = 0; j < p; j++) {
        *gsl_matrix_ptr(fw->fac, j, j) += mu * fw->diag[j] * fw->diag[j];
        gsl_vector_set(fw->rhs, j, -fw->g[j]);
    }
    int st = gsl_linalg_mcholesky_decomp(fw->fac, fw->perm, NULL);
    if (st == GSL_SUCCESS)
        st = gsl_linalg_mcholesky_solve(fw->fac, fw->perm, fw->rhs, fw->step);
    for (size_t j = 0; j < p && st == GSL_SUCCESS; j++)
        fw->dx[j] = gsl_vector_get(fw->step, j);
    return st;
}

/* Predicted reduction of the LM step v = dx (More 1978 eq. 4.4, as GSL):
 * (|J v|^2 + 2 mu |D v|^2) / |f|^2. */
static double predicted_reduction(const fit_workspace *fw, double mu, double f2)
{
    size_t p = fw->p;
    double jv2 = 0.0, dv2 = 0.0;
    for (size_t j = 0; j < p; j++) {
        double s = 0.0;
        for (size_t k = 0; k < p; k++)
            s += gsl_matrix_get(fw->JTJ, j, k) * fw->dx[k];
        jv2 += fw->dx[j] * s;
        dv2 += (fw->diag[j] * fw->dx[j]) * (fw->diag[j] * fw->dx[j]);
    }
    return (jv2 + 2.0 * mu * dv2) / f2;
}

typedef struct {
    fit_fdf fdf;
    void *params;
    double mu;  /* damping */
    double mu_min;
    long nu;    /* Nielsen's factor for the next rejection */
    double f2;  /* |f|^2 at the current point */
} lm_state;

/* Swap the trial point in as the current one and update g, J^T J, D. */
static void lm_accept(fit_workspace *fw, lm_state *s)
{
    double *t;
    t = fw->f, fw->f = fw->f_trial, fw->f_trial = t;
    t = fw->J, fw->J = fw->J_trial, fw->J_trial = t;
    t = fw->x, fw->x = fw->x_trial, fw->x_trial = t;
    s->f2 = normal_equations(fw);
    scale_update(fw);
}

/* One iteration: find a step that lowers the cost (GSL's trust_iterate
 * with the LM subproblem).  GSL_SUCCESS, GSL_ENOPROG or an error. */
static int lm_iterate(fit_workspace *fw, lm_state *s)
{
    size_t p = fw->p;
    for (int bad = 0;;) {
        int st = lm_step(fw, s->mu);
        if (st != GSL_SUCCESS)
            return st;
        for (size_t j = 0; j < p; j++)
            fw->x_trial[j] = fw->x[j] + fw->dx[j];
        st = s->fdf(fw->x_trial, s->params, fw->f_trial, fw->J_trial, fw->ld);
        if (st != GSL_SUCCESS)
            return st;
        double f2t = dot(fw->f_trial, fw->f_trial, fw->n) + prior_cost(fw, fw->x_trial);
        double rho = -1.0;
        if (f2t < s->f2) {
            double pred = predicted_reduction(fw, s->mu, s->f2);
            rho = pred > 0.0 ? (1.0 - f2t / s->f2) / pred : -1.0;
        }
        if (rho > 0.0) {
            lm_accept(fw, s);
            double b = 2.0 * rho - 1.0;
            s->mu = GSL_MAX(s->mu * GSL_MAX(FIT_MU_FALL, 1.0 - b * b * b), s->mu_min);
            s->nu = 2;
            return GSL_SUCCESS;
        }
        s->mu *= (double)s->nu;
        s->nu <<= 1;
        if (++bad > FIT_MAX_BAD_STEPS)
            return GSL_ENOPROG;
    }
}

/* The Newton decrement g^T (J^T J)^-1 g: the cost decrease of a full
 * Gauss-Newton step from the current point; -1 if J^T J is singular. */
static double newton_decrement(fit_workspace *fw)
{
    if (lm_step(fw, 0.0) != GSL_SUCCESS)
        return -1.0;
    double d = 0.0;
    for (size_t j = 0; j < fw->p; j++)
        d -= fw->g[j] * fw->dx[j];
    return d;
}

/* GSL's gradient test at the current point: max_i |max(x_i, 1) g_i| <=
 * gtol max(|f|^2 / 2, 1). */
static int gradient_small(const fit_workspace *fw, const lm_state *s)
{
    double gnorm = 0.0;
    for (size_t j = 0; j < fw->p; j++)
        gnorm = GSL_MAX(gnorm, fabs(GSL_MAX(fw->x[j], 1.0) * fw->g[j]));
    return gnorm <= FIT_GTOL * GSL_MAX(0.5 * s->f2, 1.0);
}

/* GSL's tests: every |dx_i| <= xtol (xtol + |x_i|) (info 1), or
 * max_i |max(x_i, 1) g_i| <= gtol max(|f|^2 / 2, 1) (info 2); and a full
 * Gauss-Newton step would lower the cost by less than FIT_DTOL of it
 * (info 3).  fw->dx keeps the step just taken. */
static int converged(fit_workspace *fw, const lm_state *s, int *info)
{
    int small = 1;
    for (size_t j = 0; j < fw->p && small; j++)
        small = fabs(fw->dx[j]) < FIT_XTOL * FIT_XTOL + FIT_XTOL * fabs(fw->x[j]);
    if (small) {
        *info = 1;
        return 1;
    }
    if (gradient_small(fw, s)) {
        *info = 2;
        return 1;
    }
    double keep[FIT_MAX_P];
    memcpy(keep, fw->dx, fw->p * sizeof *keep);
    double d = newton_decrement(fw);
    memcpy(fw->dx, keep, fw->p * sizeof *keep);
    if (d >= 0.0 && d <= FIT_DTOL * s->f2) {
        *info = 3;
        return 1;
    }
    return 0;
}

/* GSL's driver: iterate until converged; no step at all on the first
 * iteration is GSL_EMAXITER -- unless the start already passes the
 * gradient test or its cost is below FIT_F2_EXACT (a perfect unit's data
 * fitted from the nominal model: its residuals are zero or rounding, and no
 * step can lower them; the gradient of rounding residuals times a large
 * Jacobian need not pass the test), which is the solution, 0 iterations. */
static int lm_drive(fit_workspace *fw, lm_state *s, int max_iter, fit_result *res)
{
    size_t iter = 0;
    int st, done = 0;
    do {
        st = lm_iterate(fw, s);
        if (st == GSL_ENOPROG && iter == 0 && (gradient_small(fw, s) || s->f2 <= FIT_F2_EXACT)) {
            res->info = 2;
            res->iterations = 0;
            return GSL_SUCCESS;
        }
        if (st == GSL_ENOPROG && iter == 0) {
            res->info = st;
            res->iterations = 1;
            return GSL_EMAXITER;
        }
        if (st != GSL_SUCCESS && st != GSL_ENOPROG) {
            res->iterations = iter;
            return st;
        }
        ++iter;
        done = converged(fw, s, &res->info);
    } while (!done && iter < (size_t)max_iter);
    res->iterations = iter;
    return done ? GSL_SUCCESS : GSL_EMAXITER;
}

/* rcond of J from J^T J at the current point (GSL's Cholesky solver). */
static double jacobian_rcond(fit_workspace *fw)
{
    double rc;
    gsl_matrix_memcpy(fw->fac, fw->JTJ);
    if (gsl_linalg_mcholesky_decomp(fw->fac, fw->perm, NULL) != GSL_SUCCESS ||
        gsl_linalg_mcholesky_rcond(fw->fac, fw->perm, &rc, fw->work3p) != GSL_SUCCESS)
        return GSL_NAN;
    return sqrt(rc);
}

int fit_solve(fit_workspace *fw, fit_fdf fdf, void *params, double *x, int max_iter,
              fit_result *res)
{
    size_t p = fw->p;
    lm_state s = {.fdf = fdf, .params = params, .nu = 2};
    res->iterations = 0;
    res->info = 0;
    res->chisq = GSL_NAN;
    res->chisq_prior = 0.0;
    res->rcond = GSL_NAN;
    for (size_t j = 0; j < p; j++) {
        fw->x[j] = x[j];
        fw->diag[j] = 0.0;
    }
    int st = fdf(fw->x, params, fw->f, fw->J, fw->ld);
    if (st == GSL_SUCCESS) {
        s.f2 = normal_equations(fw);
        scale_update(fw);
        s.mu = fw->mu0 * scaled_diagonal_max(fw);
        s.mu_min = FIT_MU_MIN * scaled_diagonal_max(fw);
        st = lm_drive(fw, &s, max_iter, res);
    }
    res->status = st;
    for (size_t j = 0; j < p; j++)
        x[j] = fw->x[j];
    res->chisq = dot(fw->f, fw->f, fw->n);
    res->chisq_prior = prior_cost(fw, fw->x);
    res->rcond = jacobian_rcond(fw);
    if (st != GSL_SUCCESS || !gsl_finite(res->chisq))
        return SUNMC_EFIT;
    for (size_t j = 0; j < p; j++)
        if (!gsl_finite(x[j]))
            return SUNMC_EFIT;
    return SUNMC_OK;
}

int fit_covariance(fit_workspace *fw)
{
    return fit_covariance_rescaled(fw, 1.0);
}

int fit_covariance_rescaled(fit_workspace *fw, double k)
{
    gsl_matrix_memcpy(fw->covar, fw->JTJ);
    for (size_t j = 0; fw->prior_on && j < fw->p; j++)
        *gsl_matrix_ptr(fw->covar, j, j) += (k - 1.0) * fw->prior_w[j] * fw->prior_w[j];
    if (gsl_linalg_cholesky_decomp1(fw->covar) != GSL_SUCCESS ||
        gsl_linalg_cholesky_invert(fw->covar) != GSL_SUCCESS)
        return SUNMC_EFIT;
    return SUNMC_OK;
}

int fit_prior_set(fit_workspace *fw, const double *mean, const double *weight)
{
    int on = 0;
    for (size_t j = 0; j < fw->p; j++) {
        if (!(isfinite(weight[j]) && weight[j] >= 0.0 && isfinite(mean[j])))
            return SUNMC_EINPUT;
        on |= weight[j] > 0.0;
    }
    for (size_t j = 0; j < fw->p; j++) {
        fw->prior_mean[j] = mean[j];
        fw->prior_w[j] = weight[j];
    }
    fw->prior_on = on;
    return SUNMC_OK;
}

void fit_prior_clear(fit_workspace *fw)
{
    fw->prior_on = 0;
    for (size_t j = 0; j < fw->p; j++)
        fw->prior_w[j] = 0.0;
}

const char *fit_reason(const fit_result *res)
{
    if (res->status == GSL_SUCCESS)
        return res->info == 1   ? "converged: step below tolerance"
               : res->info == 2 ? "converged: gradient below tolerance"
                                : "converged: a further step would lower the cost by < 1e-12";
    if (res->status == GSL_EMAXITER)
        return "did not converge within calibration.max_iterations";
    if (res->status == GSL_ENOPROG)
        return "no further progress possible (singular or flat problem)";
    return gsl_strerror(res->status);
}
