/* ess_calib.h - fitting the ESS calibration model (ess_model.h) to turntable
 * data: one code path for the Monte Carlo and for `sunmc calibrate`.
 *
 * Identifiability (each handled here):
 *  1. (a, b, c, d) only matter up to a common scale: d = 1.
 *  2. a = d, b = -c is tan(alpha + delta), exactly the installation roll:
 *     the roll is fixed at its measured value (roll_rad), never fitted.
 *  3. The fine-code term has period theta0/4 (0.5 deg).  A campaign whose
 *     alpha step samples it at one phase (1 deg) or two opposite phases
 *     (0.25 deg) cannot resolve (ks, kc), or one direction of it.
 *     ess_alias_check() finds the unresolved directions from the sampled
 *     phases; ess_calibrate() regularises them to 0 with prior rows of
 *     weight sqrt(n) instead of returning a wild fit, and reports it.
 */
#ifndef SUNMC_ESS_CALIB_H
#define SUNMC_ESS_CALIB_H

#include "ess_model.h"
#include "fit.h"

#include <stddef.h>

/* Rows appended after the data rows: one prior per fine-code direction. */
#define ESS_CALIB_PRIOR_ROWS 2

typedef struct {
    int n_weak;            /* directions regularised: 0, 1 or 2 */
    double eig_norm[2];    /* eigenvalues of the centred (sin, cos) Gram, / 0.5 */
    double evec[2][2];     /* evec[j] = unit eigenvector j in (ks, kc) */
    int weak[2];           /* 1 when direction j is regularised */
} ess_alias;

/* Inspect the campaign's turntable alpha values (rad, n of them) for the
 * fine-code term of angular frequency omega (1/rad): the 2x2 covariance of
 * (sin omega alpha, cos omega alpha), whose eigenvalues are 0.5 each for a
 * well-spread sampling.  A direction whose eigenvalue / 0.5 is below
 * threshold is weak. */
void ess_alias_check(const double *alpha_rad, size_t n, double omega, double threshold,
                     ess_alias *out);

typedef struct {
    size_t n;             /* data points; every array holds vm_pad(n) (vmath.h) */
    double *alpha_rad;    /* turntable inner-frame angle, n */
    double *beta_rad;     /* turntable outer-frame angle, n */
    double *raw_rad;      /* sensor output, n */
    double *weight;       /* 1 / variance scale; 0 drops a point (gross error) */
    /* filled by ess_calibrate */
    double *sw;           /* sqrt(weight), 0 for a dropped point */
    ess_table table;      /* turntable matrices */
    double *scratch[2];   /* per-point work arrays */
    fit_workspace *fw;    /* n + ESS_CALIB_PRIOR_ROWS residuals, ESS_NP parameters */
    ess_model model;      /* working model of the residual function */
    ess_alias alias;
} ess_calib_workspace;

/* Allocate for n data points (filled by the caller: only [0, n) of each
 * array; the pads stay 0). NULL on failure. */
ess_calib_workspace *ess_calib_alloc(size_t n);
/* About how many bytes ess_calib_alloc(n) takes. */
double ess_calib_bytes(size_t n);
void ess_calib_free(ess_calib_workspace *cw);

/* Fit the model to cw's data.  theta0_rad: fine-code period; roll_rad: the
 * measured (fixed) roll; alias_threshold: see ess_alias_check.  out receives
 * the fitted model (prepared), res the fit's outcome.  SUNMC_OK or
 * SUNMC_EFIT. */
int ess_calibrate(ess_calib_workspace *cw, double theta0_rad, double roll_rad,
                  double alias_threshold, int max_iter, ess_model *out, fit_result *res);

/* Residual RMS (rad) of model m over cw's data with weight > 0 (after
 * ess_calibrate on the same data: it uses the turntable matrices). */
double ess_calib_residual_rms(const ess_calib_workspace *cw, const ess_model *m);

#endif
