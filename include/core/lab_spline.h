/* lab_spline.h - the family-neutral empirical calibration model
 * (calibration.model = spline, issue 39): each output of a calibration
 * (the tangent of an angle, say) as a penalised cubic B-spline of the
 * family's calibrated reading (the PSD's ratios), a P-spline in the manner
 * of Eilers & Marx (1996): uniform knots over the calibrated field, a
 * penalty on the second differences of neighbouring coefficients.
 *
 *   dims 1: output j is a spline of input j alone (single-axis sweeps);
 *           with `cross` (two outputs), plus a coarse spline of the other
 *           input (LAB_SPLINE_CROSS_BREAK breakpoints, pinned to 0 at its
 *           field's low end): an additive model, output j = f_j(x_j) +
 *           g_j(x_other), whose g takes up the cross-talk of the other
 *           axis a single-axis sweep moves (kenscl's ADPD2140: its alpha
 *           ratio moves by a tenth of its travel along a beta sweep);
 *   dims 2: every output is a tensor-product spline of inputs 0 and 1,
 *           penalised along each input.
 *
 * The penalty leaves straight lines (planes for dims 2) free, so a linear
 * response is reproduced at any smoothing, and a cubic at none.  Its
 * weight, the smoothing, is chosen from LAB_SPLINE_N_SMOOTH values by the
 * pooled held-out error of the caller's cross-validation folds
 * (lab_spline_choose); the effective degrees of freedom (the trace of the
 * hat matrix) say how many parameters it amounts to.
 *
 * The calibrated field is what the data visited: each input within the
 * range of the used rows, and for dims 2 a cell of the knot grid that held
 * at least one of them.  A reading outside it is an extrapolation the
 * calibration cannot stand behind: lab_spline_eval refuses it (SUNMC_EDOM).
 *
 * Basis: order 4 on uniform clamped knots (gsl_bspline_knots_uniform's),
 * evaluated by the Cox-de Boor recursion in place; the penalised normal equations
 * (X^T W X + lambda D^T D) c = X^T W y by Cholesky (gsl_linalg), every
 * status checked. */
#ifndef SUNMC_LAB_SPLINE_H
#define SUNMC_LAB_SPLINE_H

#include "params_io.h"

#include <stddef.h>

#define LAB_SPLINE_ORDER 4                      /* cubic */
#define LAB_SPLINE_MAX_OUT 2
#define LAB_SPLINE_MAX_BREAK1 300               /* breakpoints per input, dims 1 */
#define LAB_SPLINE_MAX_BREAK2 11                /* dims 2 */
#define LAB_SPLINE_MIN_BREAK 2
/* dims 1 with cross: the other input's breakpoints (its cross-talk is
 * smooth: 11 leave kenscl's held-out error where 300 do). */
#define LAB_SPLINE_CROSS_BREAK 11
/* its coefficients: one per basis function but the pinned first */
#define LAB_SPLINE_CROSS_COEF (LAB_SPLINE_CROSS_BREAK + LAB_SPLINE_ORDER - 3)
/* Data rows per coefficient the knot count aims at (before the penalty). */
#define LAB_SPLINE_ROWS_PER_COEF 4
#define LAB_SPLINE_MAX_COEF1 (LAB_SPLINE_MAX_BREAK1 + LAB_SPLINE_ORDER - 2 + LAB_SPLINE_CROSS_COEF)
#define LAB_SPLINE_MAX_COEF2 ((LAB_SPLINE_MAX_BREAK2 + LAB_SPLINE_ORDER - 2) * \
                              (LAB_SPLINE_MAX_BREAK2 + LAB_SPLINE_ORDER - 2))
#define LAB_SPLINE_MAX_COEF \
    (LAB_SPLINE_MAX_COEF1 > LAB_SPLINE_MAX_COEF2 ? LAB_SPLINE_MAX_COEF1 : LAB_SPLINE_MAX_COEF2)
#define LAB_SPLINE_MAX_CELLS ((LAB_SPLINE_MAX_BREAK2 - 1) * (LAB_SPLINE_MAX_BREAK2 - 1))
/* The smoothing grid: lambda = 10^(LAB_SPLINE_LOG_SMOOTH_MIN + k / 2) times
 * the ratio of the data's and the penalty's traces, k < LAB_SPLINE_N_SMOOTH. */
#define LAB_SPLINE_LOG_SMOOTH_MIN (-6.0)
#define LAB_SPLINE_N_SMOOTH 25
/* Coefficients per params.ini value (c<output>_<block> = "v v v ..."). */
#define LAB_SPLINE_COEF_PER_KEY 16

typedef struct {
    int dims, n_out;
    int cross;                          /* dims 1, two outputs: the other input's term */
    int nbreak;                         /* breakpoints per input */
    double lo[2], hi[2];                /* the calibrated field per input */
    double smooth;                      /* the penalty's relative weight */
    double edf[LAB_SPLINE_MAX_OUT];     /* effective degrees of freedom per output */
    unsigned char cell[LAB_SPLINE_MAX_CELLS]; /* dims 2: cells the data visited */
    int n_coef;                         /* per output */
    double coef[LAB_SPLINE_MAX_OUT][LAB_SPLINE_MAX_COEF];
} lab_spline;

/* Rows of a fit: inputs x[k][i] (k < dims), outputs y[j][i] (j < n_out),
 * weights w[i] (rows with w <= 0 or a value not finite are left out);
 * cross: dims 1 and two outputs only (the header's additive model). */
typedef struct {
    size_t n;
    int dims, n_out, cross;
    const double *x[2];
    const double *y[LAB_SPLINE_MAX_OUT];
    const double *w;
} lab_spline_data;

/* Fit d with relative smoothing smooth (the knots from the used rows'
 * count and range) into s; edf filled when want_edf.  SUNMC_EINPUT (dims
 * or n_out out of range, fewer used rows than coefficients' worth, an
 * input that does not vary) or SUNMC_EFIT (a singular system), with err. */
int lab_spline_fit(lab_spline *s, const lab_spline_data *d, double smooth, int want_edf,
                   char *err, size_t errlen);

/* Outputs y[j] at reading x[k]: SUNMC_OK, or SUNMC_EDOM outside the
 * calibrated field (y left NaN). */
int lab_spline_eval(const lab_spline *s, const double *x, double *y);

/* The smoothing by cross-validation: for each value of the grid, fit the
 * rows of every fold but one (fold[i] < 0: always fitted) and score the
 * held-out rows inside the refit's field; the smoothing of the least
 * pooled held-out RMS (of the outputs' differences) wins, and s is fitted
 * to every row with it (edf filled).  *cv_rms: that RMS (NaN when no fold
 * could be scored: s is then fitted at the grid's middle), *n_outside: held-out
 * rows outside their refit's field (not scored). */
int lab_spline_choose(lab_spline *s, const lab_spline_data *d, const int *fold, int n_folds,
                      double *cv_rms, long *n_outside, char *err, size_t errlen);

/* A workspace for fits of up to n rows: the normal equations at their
 * largest (LAB_SPLINE_MAX_COEF^2, three of them) and the folds' weights.
 * Allocated once per thread; the _ws calls then allocate nothing (the
 * Monte Carlo fits every unit through them).  The calls without _ws
 * allocate one for the call. */
typedef struct lab_spline_ws lab_spline_ws;
lab_spline_ws *lab_spline_ws_alloc(size_t n);
void lab_spline_ws_free(lab_spline_ws *w);
/* Its weights' buffer (n + 1 doubles), NULL when n is more than it takes. */
double *lab_spline_ws_weights(lab_spline_ws *w, size_t n);
int lab_spline_fit_ws(lab_spline *s, const lab_spline_data *d, double smooth, int want_edf,
                      lab_spline_ws *w, char *err, size_t errlen);
/* lab_spline_choose on w (d->n at most its n: SUNMC_EINPUT otherwise). */
int lab_spline_choose_ws(lab_spline *s, const lab_spline_data *d, const int *fold, int n_folds,
                         lab_spline_ws *w, double *cv_rms, long *n_outside, char *err,
                         size_t errlen);
/* Bytes of lab_spline_ws_alloc(n). */
double lab_spline_ws_bytes(size_t n);

/* params.ini: s into section (its keys: dims, outputs, cross (written
 * only when on; absent reads as off), breakpoints,
 * smoothing, edf_<j>, lo_<k>, hi_<k>, field_<row> (dims 2), c<j>_<block>),
 * and read back strictly: every key known, every count in range, every
 * value a number ("FILE:LINE: ..."). */
int lab_spline_params_fill(const lab_spline *s, params_file *p, const char *section);
int lab_spline_params_load(const params_file *p, const char *section, lab_spline *s, char *err,
                           size_t errlen);

#endif
