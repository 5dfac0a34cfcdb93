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
 *  4. The extended model fits more harmonics of the fine period (4x, 1x,
 *     2x: ess_model_fine_terms).  A step can sample two of them alike (0.8
 *     deg with theta0 = 2 deg: the 1st and the 4th; 0.2 and 0.8 deg: the
 *     2nd and the 8th, which is why the 8th is not a free term).
 *     ess_alias_check_set() checks every harmonic in the model's order, each
 *     against what the harmonics before it already explain (its sampled
 *     (sin, cos) with their strong directions projected out), so the
 *     paper's 4x term is kept and an aliased later harmonic is regularised
 *     to 0 with all its incidence terms.
 *  5. At beta = 0 the sun simulator's tilt toward Y turns alpha as b = -c
 *     does; only the beta lines separate them, by 1 - cos(beta).  A
 *     workspace from ess_calib_alloc_fix(n, kind, 1) keeps the tilt fixed
 *     at cw->sun_y_rad (a measurement) and fits one parameter fewer.
 */
#ifndef SUNMC_ESS_CALIB_H
#define SUNMC_ESS_CALIB_H

#include "ess_model.h"
#include "fit.h"

#include <stddef.h>

/* Rows appended after the data rows: one prior per fine-code direction
 * (the paper's model; the extended one has two per fine-code term). */
#define ESS_CALIB_PRIOR_ROWS 2
/* Fine-code terms and harmonics of the largest model. */
#define ESS_MAX_FINE_TERMS 6
#define ESS_ALIAS_MAX_H 3

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

/* Every harmonic a model fits, in its order. */
typedef struct {
    int n_h;                         /* harmonics checked */
    int harmonic[ESS_ALIAS_MAX_H];   /* of the fine period: 4 (the paper's), 1, 2 */
    ess_alias h[ESS_ALIAS_MAX_H];    /* each one's directions (the first as ess_alias_check) */
    int n_weak;                      /* weak directions over all harmonics */
    int n_prior;                     /* prior rows in use: weak directions x their terms */
} ess_alias_set;

/* Check the harmonics of the fine-code terms of a model of kind `kind` on
 * the campaign's alpha values: the first harmonic as ess_alias_check
 * (omega = its angular frequency), each later one after projecting out
 * the strong directions of those before it.  work: 2 ESS_ALIAS_MAX_H + 2
 * arrays of vm_pad(n) doubles (only for a model of more than one
 * harmonic; NULL for the paper's). */
void ess_alias_check_set(const double *alpha_rad, size_t n, int kind, double theta0_rad,
                         double threshold, double *const *work, ess_alias_set *out);

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
    int kind;             /* the model fitted (enum ess_model_kind) */
    int n_prior_rows;     /* ess_calib_prior_rows(kind) */
    int fix_sun_y;        /* 1: the sun-simulator tilt stays at sun_y_rad, not fitted */
    double sun_y_rad;     /* its measured value (set before ess_calibrate) */
    int np_fit;           /* parameters fitted: ess_model_np(kind) - fix_sun_y */
    double *jfull;        /* fix_sun_y: the model's full Jacobian, fw->ld x np */
    fit_workspace *fw;    /* n + n_prior_rows residuals, np_fit parameters */
    ess_model model;      /* working model of the residual function */
    ess_alias_set alias;
    double *alias_work[2 * ESS_ALIAS_MAX_H + 2]; /* extended: ess_alias_check_set's */
    int *fold;            /* spline models: n, the folds that choose the smoothing */
    lab_spline_ws *sws;   /* spline models: their fits' workspace (nothing allocated per fit) */
} ess_calib_workspace;

/* The spline models' folds: ESS_SPLINE_FOLDS interleaved blocks of
 * ESS_SPLINE_FOLD_BLOCK points; the fewest usable points a spline takes. */
#define ESS_SPLINE_FOLDS 4
#define ESS_SPLINE_FOLD_BLOCK 8
#define ESS_SPLINE_MIN_ROWS 16
/* Fit m's spline (and table) to cw's points, m's physics already in it
 * (ess_spline.c).  SUNMC_OK, SUNMC_EINPUT (too few points), SUNMC_EFIT. */
int ess_spline_fit(ess_calib_workspace *cw, ess_model *m);

/* Prior rows of a model kind: two per fine-code term. */
int ess_calib_prior_rows(int kind);

/* Allocate for n data points (filled by the caller: only [0, n) of each
 * array; the pads stay 0) and the paper's model, or a model of kind
 * `kind`. NULL on failure. */
ess_calib_workspace *ess_calib_alloc(size_t n);
ess_calib_workspace *ess_calib_alloc_kind(size_t n, int kind);
/* The same with the sun-simulator tilt toward Y fixed (fix_sun_y = 1) at
 * cw->sun_y_rad instead of fitted (0: as ess_calib_alloc_kind). */
ess_calib_workspace *ess_calib_alloc_fix(size_t n, int kind, int fix_sun_y);
/* The model parameter (enum ess_param) of fitted parameter j of cw: the
 * fit's vector leaves out a fixed sun tilt. */
int ess_calib_param_of(const ess_calib_workspace *cw, int j);
/* About how many bytes ess_calib_alloc_kind(n, kind) takes. */
double ess_calib_bytes(size_t n, int kind);
void ess_calib_free(ess_calib_workspace *cw);

/* Fit the model to cw's data.  theta0_rad: fine-code period; roll_rad: the
 * measured (fixed) roll (and cw->sun_y_rad the measured sun tilt when
 * cw->fix_sun_y); alias_threshold: see ess_alias_check.  out receives
 * the fitted model (prepared), res the fit's outcome.  SUNMC_OK or
 * SUNMC_EFIT. */
int ess_calibrate(ess_calib_workspace *cw, double theta0_rad, double roll_rad,
                  double alias_threshold, int max_iter, ess_model *out, fit_result *res);

/* Residual RMS (rad) of model m over cw's data with weight > 0 (after
 * ess_calibrate on the same data: it uses the turntable matrices). */
double ess_calib_residual_rms(const ess_calib_workspace *cw, const ess_model *m);

#endif
