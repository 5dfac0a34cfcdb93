/* psd_model.h - the calibration models of the four-channel sensor.
 *
 * Physical model (psd_model.c): the sensor of psd_sensor.h with fitted
 * aperture offsets dx, dy, height error dh, mount rotations tilt_x,
 * tilt_y, rot_z (zxy, rotation.h), gains of channels 2-4 relative to
 * channel 1 and the four dark signals (in the data's unit; they absorb the
 * lab's uniform background, which adds to every channel alike).  A reading
 * m[4] gives the dark-corrected signals s_k = (m_k - dark_k) / gain_k and
 * their ratios (x, y) (psd_ratios), which do not depend on the sun's
 * intensity; the model predicts them from the geometry, and compensation
 * inverts that by Newton's method in (tan alpha, tan beta) of the table
 * top.  The fit has two stages (psd_phys_fit): the four channels with each
 * reading's light projected out (psd_fitchan.c), then the ratios, whose
 * residuals are the ratio differences divided by the sensitivity (ratio
 * per unit of tan) of the fitted height, i.e. about radians of that sensor;
 * the Jacobian carries the height's change of that scale.
 *
 * Polynomial model (psd_poly.c): the field's method: the ratios of the raw
 * channels (no dark correction), and tan(alpha), tan(beta) of the truth
 * fitted as polynomials in (x, y) of total degree <= order by linear least
 * squares; form fss20 is the 20-term 5th-order form of aeroztark's
 * FSScalibration (order 5 without the x^2 y^2 term).
 */
#ifndef SUNMC_PSD_MODEL_H
#define SUNMC_PSD_MODEL_H

#include "fit.h"
#include "lab_spline.h"
#include "lab_table.h"
#include "psd_sensor.h"

#include <stddef.h>

enum {
    PSD_P_DX = 0, PSD_P_DY, PSD_P_DH, PSD_P_TX, PSD_P_TY, PSD_P_RZ,
    PSD_P_G2, PSD_P_G3, PSD_P_G4, PSD_P_D1, PSD_P_D2, PSD_P_D3, PSD_P_D4,
    PSD_NP
};
#define PSD_NP_GEOMETRY 6
#define PSD_NEWTON_MAX_ITER 40
#define PSD_NEWTON_TOL 1e-13
#define PSD_FIT_MAX_ITER 1000
/* The ratios' fit's first damping (fit.h, mu0): from the channels' answer, or cold. */
#define PSD_FIT_MU0_WARM 1e-7
#define PSD_FIT_MU0_COLD 1e-3
/* Residuals per row of the first fit stage: the four channels. */
#define PSD_RESIDUALS_PER_ROW 4

/* Parameter names with units (params.ini, units.tsv, reports) and the
 * factor from the internal unit (mm, rad, ratio, data unit) to them. */
extern const char *const psd_param_names[PSD_NP];
extern const double psd_param_scale[PSD_NP];

typedef struct {
    psd_sensor s;                    /* the fitted geometry (gain, dark unused) */
    double gain[PSD_CHANNELS];       /* relative; gain[0] = 1 */
    double dark[PSD_CHANNELS];       /* data unit */
    double sens;                     /* nominal ratio per unit tan */
} psd_phys;

/* The physical model of design d with parameters p (internal units). */
void psd_phys_set(psd_phys *m, const psd_design *d, const double p[PSD_NP]);

/* Dark-corrected ratios of reading r[4]; SUNMC_EDOM where they are not finite. */
int psd_phys_observed(const psd_phys *m, const double r[4], double *x, double *y);
/* Predicted ratios for the table top's sun vector ut. */
int psd_phys_predicted(const psd_phys *m, const double ut[3], double *x, double *y);
/* The table top's sun vector ut whose predicted ratios are (x, y).
 * SUNMC_EDOM when Newton's method does not converge (saturated spot). */
int psd_phys_invert(const psd_phys *m, double x, double y, double ut[3]);

/* Rows of a calibration: readings m[k][i], the table top's sun vectors
 * ut[3 i ..], weights w[i] (> 0 used). */
typedef struct {
    size_t n;
    const double *m[PSD_CHANNELS];
    const double *ut;
    const double *w;
    const psd_design *design;
    psd_phys work;                   /* scratch of the fit */
    double *scratch;                 /* room for 8 n doubles (the fit's ratios) */
    /* The fit's variables are p[j] / xscale[j] (set by psd_phys_fit), so
     * that the Jacobian's columns are of one size; its covariance is in
     * those units. */
    double xscale[PSD_NP];
    double sig1;                     /* channel 1's signal per unit photocurrent (psd_phys_start) */
    /* psd_phys_fit's first stage (psd_phys_fit_channels): a workspace of
     * PSD_RESIDUALS_PER_ROW n residuals and psd_phys_free_channels
     * parameters, or NULL to start the ratios' fit from p itself. */
    fit_workspace *fw_channels;
    /* spline and hybrid models: the smoothing (> 0: fixed), else chosen by
     * the folds fold[i] < n_folds (NULL: rows in PSD_SPLINE_AUTO_FOLDS
     * interleaved folds) */
    double smooth;
    int table_log;                   /* table: nodes 2^table_log + 1 (> 0: fixed), else by the folds */
    /* the spline models' thread workspace (lab_spline.h) and room for n
     * fold indices; NULL: allocated for the fit (calibrate) */
    lab_spline_ws *sws;
    int *fold_buf;
    const int *fold;
    int n_folds;
} psd_rows;

/* Start values: the nominal geometry, and per channel dark and gain from a
 * straight-line fit of the readings to the nominal photocurrents. */
void psd_phys_start(psd_rows *d, double p[PSD_NP]);
/* The parameters fitted (indices into p, into free[PSD_NP]); the tilts
 * about X and Y only when fit_tilt (otherwise they stay at p's value: on
 * a campaign of a few tens of degrees they move the spot as the aperture
 * offsets do, to first order), and not the one combination the ratios
 * cannot see (psd_model.c: dark4 or gain3).  Returns their count. */
int psd_phys_free(const psd_design *d, int fit_tilt, int *free);
/* Fit p (start values in, solution out) with fw (2 n residuals,
 * psd_phys_free's count of parameters): first, when d->fw_channels is
 * set, psd_phys_fit_channels from p (its solution the start when it
 * converges), then the ratios (x, y), the held dark combination at that
 * start's value.  SUNMC_OK or SUNMC_EFIT (res says why). */
int psd_phys_fit(fit_workspace *fw, psd_rows *d, int fit_tilt, double p[PSD_NP],
                 fit_result *res);

/* The first stage (psd_fitchan.c): the four channel signals themselves.
 * Row r's dark-corrected channels m_k - dark_k are predicted as P_r gain_k
 * i_k (i_k the geometry's photocurrents of unit light) with P_r the light
 * that reached the sensor at that reading, which a lab does not know (lamp
 * drift, a beam not uniform over the table's travel): the least-squares
 * P_r for the other parameters (variable projection).  Every dark signal
 * is visible to the four channels (the corner layouts' i1 i2 / (i3 i4) is
 * fixed by the geometry), and no solution lets the gains run away while
 * both ratios sit in a corner, so it converges from a start far from the
 * unit (a nominal height off by a factor 3, darks of the wrong sign)
 * where the ratios' fit does not.  fw: PSD_RESIDUALS_PER_ROW n residuals,
 * psd_phys_free_channels(fit_tilt) parameters. */
int psd_phys_fit_channels(fit_workspace *fw, psd_rows *d, int fit_tilt, double p[PSD_NP],
                          fit_result *res);
static inline int psd_phys_free_channels(int fit_tilt)
{
    return fit_tilt ? PSD_NP : PSD_NP - 2;
}

/* ---- polynomial (psd_poly.c) ---- */
#define PSD_POLY_MAX_ORDER 5
#define PSD_POLY_MAX_TERMS 21
typedef struct {
    int order, form, nt;
    double scale;                    /* x and y enter the terms as x / scale (conditioning) */
    int ex[PSD_POLY_MAX_TERMS], ey[PSD_POLY_MAX_TERMS]; /* term k = x^ex y^ey */
    double ca[PSD_POLY_MAX_TERMS], cb[PSD_POLY_MAX_TERMS]; /* tan alpha, tan beta */
} psd_poly;

/* The terms of order and form (enum psd_poly_form); returns their count. */
int psd_poly_init(psd_poly *q, int order, int form);
/* Raw ratios of reading r[4] (no dark correction) for detector d. */
int psd_poly_ratios(const psd_design *d, const double r[4], double *x, double *y);
/* Weighted least squares of the rows (work: room for nt (nt + 1) doubles).
 * SUNMC_EFIT when the normal matrix is singular. */
int psd_poly_fit(psd_poly *q, const psd_rows *d, double *work);
/* Compensated sun angles (rad) of reading r. */
int psd_poly_eval(const psd_poly *q, const psd_design *d, const double r[4], double *alpha,
                  double *beta);

/* ---- a fitted calibration of any model ---- */
typedef struct {
    int model;                       /* enum psd_model */
    const psd_design *design;
    double p[PSD_NP];                /* physical (and hybrid): internal units */
    psd_phys phys;
    psd_poly poly;
    lab_spline spline;               /* spline: tan alpha, tan beta of the raw ratios;
                                        hybrid: the physical model's error in them;
                                        table: the spline its nodes sample */
    lab_table table;                 /* table: tan alpha, tan beta of the raw ratios */
} psd_cal;

/* ---- spline, table and hybrid (psd_spline.c) ----
 * spline: core's penalised B-spline (lab_spline.h) of tan alpha and tan
 * beta over the raw ratios (x, y), as the polynomial; hybrid: the physical
 * model, and a spline of its error (true minus physical tan alpha, tan
 * beta) over its own (tan alpha, tan beta), zero where the physics is
 * exact.  One input per output (dims 1) when every row lies on an axis
 * (single-axis sweeps: alpha = 0 or beta = 0), else both (dims 2).
 * table: core's look-up table (lab_table.h) of tan alpha and tan beta over
 * the raw ratios, its nodes the spline's values, its step chosen by the
 * same folds. */
#define PSD_SPLINE_AUTO_FOLDS 4
/* Fewest rows a spline is fitted to (two breakpoints' worth). */
#define PSD_SPLINE_MIN_ROWS 8
/* The models' names as calibration.model gives them (enum psd_model). */
extern const char *const psd_model_names[PSD_N_MODELS];
/* Fit k->spline (and k->table for the table model) to the rows (the
 * physical part of a hybrid already in k); work: 4 n doubles.  SUNMC_EFIT
 * when it cannot be fitted. */
int psd_spline_fit(psd_cal *k, const psd_rows *d, double *work);
/* The spline's inputs of reading r: the raw ratios (spline, table), the physical
 * model's tan alpha, tan beta (hybrid).  SUNMC_EDOM where there are none. */
int psd_spline_inputs(const psd_cal *k, const double r[4], double x[2]);
/* The fitted spline's (table's) outputs t at inputs x: SUNMC_EDOM outside
 * the calibrated field. */
int psd_spline_eval(const psd_cal *k, const double x[2], double t[2]);
/* The table's nodes as log2 of its steps (nodes = 2^log + 1). */
int psd_table_log(const lab_table *t);

/* The nominal calibration of design d (no fit): the design's geometry,
 * equal gains, the nominal dark signal dark_fs (data in fractions of full
 * scale, as the Monte Carlo writes them). */
void psd_cal_nominal(psd_cal *k, const psd_design *d);
/* The sun angles (rad, table top: tan alpha = u_x/u_z, tan beta =
 * u_y/u_z) of reading r[4].  SUNMC_EDOM where it cannot be read. */
int psd_cal_angles(const psd_cal *k, const double r[4], double *alpha, double *beta);

#endif
