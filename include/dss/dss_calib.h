/* dss_calib.h - calibrating a DSS from rotary-table data: the physical model
 * (dss_model.h) or the 2-D polynomial (dss_poly.h), both fitted with the
 * shared fit.h engine (Levenberg-Marquardt, analytic Jacobian).  One code
 * path for the Monte Carlo and for `sunmc calibrate`.
 *
 * Data: n readings of (recorded table angles b1, b2 in rad; measured spot
 * x, y in px from the detector centre; weight = 1/variance scale, 0 drops
 * the reading).  The caller fills the arrays of an allocated workspace.
 *
 * Physical model: residuals are the spot's (x, y) in px, 2n rows, weighted.
 * Fitted: dx, dy, dh, glass thickness, glass index (unless
 * calibration.fit_glass_index = off), the mount c1-c3, as mounted, the
 * sun simulator's sun_b1, sun_b2 and, with calibration.fit_detector_tilt =
 * on, the detector's tilt tx, ty (nearly collinear with c1 + dy and c2 + dx:
 * |r| ~0.99 on this campaign; dss_labfit.c names the cause).  The table
 * below is the paper's model's.  Identifiability, from the Jacobian at
 * the nominal unit over the default campaign (b1, b2 in -60..60 deg step
 * 5, 581 seen readings; columns normalised; tests/unit/dss/test_dss_calib.c
 * recomputes it):
 *
 *     singular value  direction (largest components)
 *     1.73            dh, t, n together (the spot's scale)
 *     1.67, 1.66      dy, c1, sun_b1 and dx, c2, sun_b2 together (a shift)
 *     1.00            c3 alone
 *     0.48, 0.41      principal point against the tilts: dx vs c2 + sun_b2,
 *                     dy vs c1
 *     0.21            sun_b1 against c1 and dy
 *     0.155           t against n
 *     0.128           c2 against sun_b2
 *     0.013           dh against t and n
 *
 * So: the principal point and the tilts separate (a shift is constant over
 * the field, a tilt grows as sec^2 of the field angle); c3 is a rotation
 * about the detector normal, which no other parameter makes; the mount's
 * tilt and the sun simulator's separate because the table's two axes do
 * not commute: at the centre both shift the spot alike, but R(b) moves a
 * tilt of v_sun differently from one of the mount, by O(b) at the edge.
 * With 0.01 px of centroid noise the standard errors are 0.2-0.5" for
 * c1, c2, sun_b1, sun_b2, 0.13" for c3, 0.001 px for dx, dy: nothing the
 * default campaign cannot determine is left free.  On a narrow campaign
 * the tilt-vs-simulator pair goes first (+-10 deg: 15-40"): the report's
 * correlation warning and its propagated uncertainty say so; measure the
 * sun simulator's direction there (calibration.sun = measured: a workspace
 * with fix_sun holds sun_b1, sun_b2 at cw->sun_rad, two parameters fewer)
 * or use the aligned procedure.  The one weak direction is the height against
 * the glass: height, glass thickness and index act on the radial spot
 * distance r through, with s = sin(theta),
 * r = (H - t + t/n) s + (H - t + t/n^3) s^3 / 2 + O(s^5): only the higher
 * orders tell all three
 * apart (correlations H-n 0.992, H-t 0.984, t-n 0.954).  The three are
 * still fitted by default: their individual estimates are poor (the per-unit
 * corr_max_abs in units.tsv is ~0.99) but the spot map they predict is not,
 * and holding n at its design value (calibration.fit_glass_index = off, t
 * then an effective thickness) leaves a bias: noise-free, after-calibration
 * RMS 0.45" (alpha, 0-60 deg) for dn uniform +-0.005 against 0.00" fitted;
 * with 0.01 px centroid noise 3.27" against 3.23" (200 units, dss.ini).
 * The per-unit largest |correlation| and its pair are reported
 * (dss_calib_correlation).
 *
 * Polynomial model: alpha and beta corrections are two linear least-squares
 * problems with the same design matrix, solved one after the other on the
 * same workspace (the Levenberg-Marquardt engine solves a linear problem in
 * a few iterations); targets are the recorded table's truth angles (eq. 3-4)
 * minus the on-board angles.
 */
#ifndef SUNMC_DSS_CALIB_H
#define SUNMC_DSS_CALIB_H

#include "dss_config.h"
#include "dss_model.h"
#include "dss_poly.h"
#include "fit.h"
#include "lab_spline.h"
#include "lab_table.h"

#include <stddef.h>

/* The values of calibration.model. */
enum dss_model_kind { DSS_MODEL_PHYSICAL = 0, DSS_MODEL_POLYNOMIAL = 1, DSS_MODEL_SPLINE = 2,
                      DSS_MODEL_HYBRID = 3, DSS_MODEL_TABLE = 4 };
#define DSS_N_MODELS 5
/* Does model k fit the physical model (alone, or under a correction)? */
#define DSS_MODEL_HAS_PHYSICS(k) ((k) == DSS_MODEL_PHYSICAL || (k) == DSS_MODEL_HYBRID)
/* Does model k fit core's spline (alone, under a table, or as a correction)? */
#define DSS_MODEL_HAS_SPLINE(k) \
    ((k) == DSS_MODEL_SPLINE || (k) == DSS_MODEL_HYBRID || (k) == DSS_MODEL_TABLE)
/* The models' names as calibration.model gives them. */
extern const char *const dss_model_names[DSS_N_MODELS];

/* A calibrated DSS: what `compensate` needs. */
typedef struct {
    int kind;          /* enum dss_model_kind */
    dss_model phys;    /* kind == DSS_MODEL_PHYSICAL */
    int sun_measured;  /* physical: sun_b1, sun_b2 are a measurement, not fitted */
    dss_poly poly;     /* kind == DSS_MODEL_POLYNOMIAL */
    /* spline, table: alpha, beta (rad) of the spot (x, y px); hybrid: the
     * physical model's error in them (dss_spline.c) */
    lab_spline spline;
    lab_table table;   /* kind == DSS_MODEL_TABLE: the spline at its nodes */
} dss_calibration;

/* Calibrated angles alpha, beta (rad) of a measured spot (px from the
 * detector centre).  SUNMC_EDOM when the physical model cannot invert it. */
int dss_compensate(const dss_calibration *cal, double x_px, double y_px, double *alpha,
                   double *beta);

/* The same for n spots at once (vectorised for the physical model; each
 * gives the bits it gives alone): status[i] = SUNMC_OK or SUNMC_EDOM. */
void dss_compensate_batch(const dss_calibration *cal, size_t n, const double *x_px,
                          const double *y_px, double *alpha, double *beta, int *status);

/* The same for n noisy spots (x, y) and the same spots without their noise
 * (x0, y0) (dss_model_compensate_pair_batch: the noise-free inversions
 * start from the noisy ones' solutions). */
void dss_compensate_pair_batch(const dss_calibration *cal, size_t n, const double *x_px,
                               const double *y_px, const double *x0_px, const double *y0_px,
                               double *alpha, double *beta, int *status, double *alpha0,
                               double *beta0, int *status0);

/* The truth (rad) a calibration assigns to recorded table angles (b1, b2)
 * rad: the physical model's (dss_model_truth, its fitted sun simulator when
 * as_mounted); eq. 3-4 for the polynomial, which assumes a perfect sun
 * simulator (it cannot tell a tilted one from the unit's own error). */
void dss_calib_truth(const dss_calibration *cal, double b1, double b2, double *alpha,
                     double *beta);

/* The same for k <= DSS_CHUNK table positions (padded arrays). */
void dss_calib_truth_batch(const dss_calibration *cal, size_t k, const double *b1,
                           const double *b2, double *alpha, double *beta);

/* The physical model's fitted parameters for design d (its mount),
 * fit_index and fix_sun (1: a measured sun simulator, not fitted), as
 * dss_param indices into free_idx (may be NULL); returns their count. */
int dss_calib_free_params(const dss_design *d, int fit_index, int fix_sun, int free_idx[DSS_NP]);

typedef struct {
    size_t n;             /* readings */
    double *b1_rad;       /* recorded table angle about X, n */
    double *b2_rad;       /* recorded table angle about Y, n */
    double *x_px;         /* measured spot x, n */
    double *y_px;         /* measured spot y, n */
    double *weight;       /* n; 0 drops a reading */
    /* (the five arrays above hold vm_pad(n) values, pads 0: vmath.h) */

    dss_design design;    /* the nominal design (start point, on-board formula) */
    int kind;             /* enum dss_model_kind */
    int poly_order;
    int n_free;           /* physical: parameters fitted */
    int free_idx[DSS_NP]; /* physical: their dss_param indices */
    int fix_sun;          /* physical, as_mounted: sun_b1, sun_b2 held at sun_rad */
    double sun_rad[2];    /* their measured values (set before dss_calibrate) */
    fit_workspace *fw;    /* physical: 2n x n_free; polynomial: n x n_terms */
    dss_model work;       /* physical: the residual function's model */
    dss_table table;      /* physical: the table rotation of each reading */
    double *sw;           /* physical: sqrt(weight), vm_pad(n) */
    double *jscratch;     /* physical: Jacobian column of a parameter held fixed */
    double *basis;        /* polynomial: n x n_terms design matrix */
    double *target;       /* polynomial: the current axis's targets, n */
    double *sx;           /* spline models: 4 n (inputs and targets) */
    int *fold;            /* spline models: n, the folds that choose the smoothing */
    lab_spline_ws *sws;   /* spline models: their fits' workspace (nothing allocated per fit) */
} dss_calib_workspace;

/* Allocate for n readings of design d and model `kind` (poly_order for the
 * polynomial; fit_index = 1 frees the glass index of the physical model).
 * NULL on failure (no memory, or no more residuals than parameters). */
dss_calib_workspace *dss_calib_alloc(const dss_design *d, size_t n, int kind, int poly_order,
                                     int fit_index);
/* The same with the sun simulator's direction fixed (fix_sun = 1, as
 * mounted only) at cw->sun_rad instead of fitted. */
dss_calib_workspace *dss_calib_alloc_fix(const dss_design *d, size_t n, int kind, int poly_order,
                                         int fit_index, int fix_sun);
/* dss_calib_alloc_fix for config dc's design and calibration keys. */
dss_calib_workspace *dss_calib_alloc_config(const dss_config *dc, size_t n);
void dss_calib_free(dss_calib_workspace *cw);
/* About how many bytes dss_calib_alloc takes for n readings of model kind. */
double dss_calib_bytes(size_t n, int kind, int poly_order);

/* Fit cw's model to cw's data.  out receives the calibration (the design's
 * nominal model if the fit failed), res the fit's outcome (for the
 * polynomial, of the worse of its two fits).  SUNMC_OK, SUNMC_EFIT, or
 * SUNMC_EINPUT when fewer usable readings than parameters. */
int dss_calibrate(dss_calib_workspace *cw, int max_iter, dss_calibration *out, fit_result *res);

/* ---- spline, table and hybrid (dss_spline.c) ----
 * spline: core's penalised B-spline (lab_spline.h) of alpha and beta
 * (the recorded table's eq. 3-4, as the polynomial) over the spot (x, y
 * px), a tensor product; table: core's look-up table of the same
 * (lab_table.h), the spline at its nodes; hybrid: the physical model
 * fitted first, and a spline of its error (its truth minus its angles)
 * over the spot, zero where the physics is exact.  The smoothing (and
 * the table's step) chosen by DSS_SPLINE_FOLDS interleaved folds of
 * DSS_SPLINE_FOLD_BLOCK readings. */
#define DSS_SPLINE_FOLDS 4
#define DSS_SPLINE_FOLD_BLOCK 8
/* Fewest usable readings a spline is fitted to. */
#define DSS_SPLINE_MIN_ROWS 16
/* Fit cal's spline (and table) to cw's readings (a hybrid's physical part
 * already in cal).  SUNMC_OK, SUNMC_EINPUT (too few readings), SUNMC_EFIT. */
int dss_spline_fit(dss_calib_workspace *cw, dss_calibration *cal, fit_result *res);
/* The spline model's angles of spot (x, y): SUNMC_EDOM outside its field
 * (or where a hybrid's physics has no angle). */
int dss_spline_compensate(const dss_calibration *cal, double x_px, double y_px, double *alpha,
                          double *beta);

/* RMS (rad) over the readings with weight > 0 of the angle between the
 * calibrated direction of the reading's spot and the recorded table's truth
 * direction; NaN when none. */
double dss_calib_residual_rms(const dss_calib_workspace *cw, const dss_calibration *cal);

/* Largest |correlation| between two fitted parameters at the last solution
 * (from (J^T J)^-1 of fit_covariance) and the pair: dss_param indices for
 * the physical model, monomial indices of the beta fit for the polynomial.
 * SUNMC_EFIT if the covariance cannot be formed. */
int dss_calib_correlation(dss_calib_workspace *cw, double *max_abs, int *i, int *j);

#endif
