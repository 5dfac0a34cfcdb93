/* dss_labfit.h - calibrating a real DSS from rotary-table data (`sunmc
 * calibrate` of a DSS): the fit is dss_calibrate (dss_calib.h), the
 * Monte Carlo's code path; this adds the report (standard errors and
 * correlations of the physical model, residual per angle and band,
 * cross-validation by grid quadrant) and params.ini for `compensate`.
 *
 * Residual of a reading: compensated (alpha, beta) minus the recorded
 * table's truth angles (table_truth), arcsec, banded on the field angle
 * atan(hypot(tan alpha, tan beta)) as in the Monte Carlo.
 */
#ifndef SUNMC_DSS_LABFIT_H
#define SUNMC_DSS_LABFIT_H

#include "calreport.h"
#include "dss_config.h"
#include "dss_calib.h"
#include "params_io.h"

#include <stdio.h>

/* Model names written to params.ini. */
#define DSS_CALFIT_MODEL_PHYSICAL "dss_physical"
#define DSS_CALFIT_MODEL_POLYNOMIAL "dss_polynomial"
#define DSS_CALFIT_MODEL_SPLINE "dss_spline"
#define DSS_CALFIT_MODEL_HYBRID "dss_hybrid"
#define DSS_CALFIT_MODEL_TABLE "dss_table"
/* params.ini's model line of each calibration.model (enum dss_model_kind). */
extern const char *const dss_calfit_models[DSS_N_MODELS];

/* Fit cw (data and weights filled by the caller; allocated with c's model)
 * and fill cal and rep.  SUNMC_EINPUT (message in err) when the usable
 * readings do not outnumber the parameters; a failed fit is not an error
 * (rep->fit_ok = 0, with a warning). */
int dss_labfit_run(const sunmc_config *c, dss_calib_workspace *cw, dss_calibration *cal,
                   calreport *rep, char *err, size_t errlen);

/* Propagated calibration uncertainty at table angles (b1, b2) rad: the
 * standard deviations sigma_rad[0] (alpha) and sigma_rad[1] (beta), rad, of
 * the compensated angles of the spot model m predicts there, from the
 * covariance cov (n_free x n_free, row-major, of the parameters free_idx[]
 * (dss_param indices) in m's internal units, already scaled by the residual
 * variance).  The derivative with respect to the parameters is by the
 * implicit function theorem: the model's analytic d spot / d p and a
 * central-difference 2 x 2 d spot / d b and d (alpha, beta) / d b.
 * SUNMC_EDOM when the spot cannot be formed or the map is singular there. */
int dss_labfit_sigma(const dss_model *m, const double *cov, const int *free_idx, int n_free,
                     double b1, double b2, double sigma_rad[2]);

/* TSV: each reading with its compensated angles and errors (arcsec). */
/* Row i's compensated angles (a, b; NaN where it has none: weight 0, no
 * inverse) and its truth (a0, b0), rad; SUNMC_EDOM when no angles. */
int dss_labfit_row(const dss_calib_workspace *cw, const dss_calibration *cal, size_t i,
                   double *a, double *b, double *a0, double *b0);
int dss_labfit_write_residuals(FILE *f, const dss_calib_workspace *cw, const int *line,
                               const dss_calibration *cal);

/* params.ini content of a calibration ([model] section). */
int dss_params_fill(params_file *p, const dss_calibration *cal, const calreport *rep);

/* The calibration a params.ini describes ("FILE:LINE: ..." messages). */
int dss_params_load(const params_file *p, dss_calibration *cal, char *err, size_t errlen);

/* The model comparison of `calibrate` (dss_calmodels.c): every model
 * refitted on folds of the campaign's b1 lines, into rep->models with the
 * recommendation. */
void dss_labfit_compare(const sunmc_config *c, const dss_calib_workspace *cw, calreport *rep);

#endif
