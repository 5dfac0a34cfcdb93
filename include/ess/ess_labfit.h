/* ess_labfit.h - calibrating a real ESS from turntable data (`sunmc
 * calibrate` of an ESS): the fit itself is ess_calibrate (ess_calib.h),
 * the very code path of the Monte Carlo; this adds what a lab needs around
 * it: gross-error checks, standard errors and correlations, the residual
 * per band in the angle domain, the parameter covariance propagated to the
 * compensated angle, cross-validation by beta line, and params.ini.
 *
 * Angle-domain error of a reading: the compensated output minus the
 * incidence that the fitted installation predicts at the recorded table
 * angles, i.e. what the Monte Carlo's validation measures against the truth.
 */
#ifndef SUNMC_ESS_LABFIT_H
#define SUNMC_ESS_LABFIT_H

#include "calreport.h"
#include "ess_config.h"
#include "ess_calib.h"
#include "ess_model.h"
#include "params_io.h"

#include <stdio.h>

/* Model names written to params.ini: the paper's, the extended one. */
#define ESS_CALFIT_MODEL "ess_eq12_finecode"
#define ESS_CALFIT_MODEL_EXT "ess_extended"
#define ESS_CALFIT_MODEL_SPLINE "ess_spline"
#define ESS_CALFIT_MODEL_HYBRID "ess_hybrid"
#define ESS_CALFIT_MODEL_TABLE "ess_table"
/* params.ini [fixed] key of a measured sun-simulator tilt toward Y
 * (calibration.sun_y = measured; [parameters] then has no fit_sun_y_arcsec). */
#define ESS_SUN_Y_MEASURED_KEY "sun_y_measured_arcsec"

/* The params.ini name of a model kind (enum ess_model_kind). */
const char *ess_labfit_model_name(int kind);

/* Step of the field grid on which the covariance is propagated. */
#define ESS_FIELD_STEP_DEG 0.1

typedef struct {
    ess_model m;                    /* fitted model (prepared) */
    double cov[ESS_NP_MAX][ESS_NP_MAX]; /* scaled parameter covariance, internal units (rad) */
    double s2;                      /* residual variance, rad^2 */
    int n_gross;                    /* rows dropped by the half-period check */
} ess_labfit_result;

/* Calibrate from cw's data: alpha_rad, beta_rad, raw_rad as recorded and
 * weight (1 / relative variance; 0 drops a row).  line[n] is each row's line
 * in the data file for messages (may be NULL).  Rows whose output is off the
 * table alpha by more than half a fine period get weight 0 (as in the Monte
 * Carlo).  Roll: calibration.roll_measured_arcsec of c.  Fills res and rep.
 * SUNMC_EINPUT (message in err) when n_used <= ESS_NP; a failed fit is not an
 * error (rep->fit_ok = 0, with a warning). */
int ess_labfit_run(const sunmc_config *c, ess_calib_workspace *cw, const int *line,
                   ess_labfit_result *res, calreport *rep, char *err, size_t errlen);

/* The distinct beta lines (rad) of cw's rows with weight > 0, in file
 * order, into betas: their count, or -1 when there are more than max. */
int ess_beta_lines(const ess_calib_workspace *cw, double *betas, int max);
/* The index of beta_rad among betas[nb] (within 1e-9 rad), or -1. */
int ess_beta_line_of(const double *betas, int nb, double beta_rad);

/* The model comparison of `calibrate` (ess_calmodels.c): the paper's and
 * the extended model refitted with each beta line of cw's data held out
 * (cw's weights after the gross-error check; cw itself is not touched),
 * scored on it point by point, into rep->models with the recommendation.
 * SUNMC_ENOMEM (message in err) when the work arrays cannot be had. */
int ess_labfit_compare(const sunmc_config *c, const ess_calib_workspace *cw, calreport *rep,
                       char *err, size_t errlen);

/* Derivative of the compensated angle with respect to the parameters
 * p[m->np] (internal units), at the reading that incidence alpha_rad
 * produces under m (implicit differentiation of the structural model; only
 * a, b, c and the fine-code terms are non-zero: the installation does not
 * enter compensation). */
void ess_compensate_gradient(const ess_model *m, double alpha_rad, double h[ESS_NP_MAX]);

/* Standard deviation (rad) of the compensated angle at incidence alpha_rad
 * from the parameter covariance cov (internal units): sqrt(h^T cov h). */
double ess_labfit_sigma(const ess_model *m, const double cov[ESS_NP_MAX][ESS_NP_MAX],
                        double alpha_rad);

/* Angle-domain error (rad) of reading raw_rad at recorded table angles:
 * compensate(raw) - incidence under m's installation.  SUNMC_EDOM when the
 * reading cannot be compensated. */
int ess_angle_error(const ess_model *m, double alpha_rad, double beta_rad, double raw_rad,
                    double *err_rad);

/* TSV: every row of the data with its residual (raw - predicted) and
 * angle-domain error in arcsec; line[] may be NULL. */
int ess_labfit_write_residuals(FILE *f, const ess_calib_workspace *cw, const int *line,
                               const ess_model *m);

/* TSV: alpha_deg, sigma_arcsec of the compensated angle across
 * [alpha_min_deg, alpha_max_deg] in steps of ESS_FIELD_STEP_DEG. */
int ess_labfit_write_field(FILE *f, const ess_labfit_result *res, double alpha_min_deg,
                           double alpha_max_deg);

/* params.ini content: [design] theta0_deg, [parameters] (with standard
 * errors from rep, may be NULL), [fixed] roll and d, [derived] k_deg, t_rad. */
int ess_params_fill(params_file *p, const ess_labfit_result *res, const calreport *rep,
                    double theta0_deg);

/* The model a params.ini describes (checks sensor and model names).
 * Messages "FILE:LINE: ..." / "FILE: missing key ...". */
int ess_params_load(const params_file *p, ess_model *m, char *err, size_t errlen);

#endif
