/* dss_calfit.h - calibrating a real DSS from rotary-table data (`sunmc
 * calibrate --sensor dss`): the fit is dss_calibrate (dss_calib.h), the
 * Monte Carlo's code path; this adds the report (standard errors and
 * correlations of the physical model, residual per angle and band,
 * cross-validation by grid quadrant) and params.ini for `compensate`.
 *
 * Residual of a reading: compensated (alpha, beta) minus the recorded
 * table's truth angles (dss_table_truth), arcsec, banded on the field angle
 * atan(hypot(tan alpha, tan beta)) as in the Monte Carlo.
 */
#ifndef SUNMC_DSS_CALFIT_H
#define SUNMC_DSS_CALFIT_H

#include "calreport.h"
#include "config.h"
#include "dss_calib.h"
#include "params_io.h"

#include <stdio.h>

/* Model names written to params.ini. */
#define DSS_CALFIT_MODEL_PHYSICAL "dss_physical"
#define DSS_CALFIT_MODEL_POLYNOMIAL "dss_polynomial"

/* Fit cw (data and weights filled by the caller; allocated with c's model)
 * and fill cal and rep.  SUNMC_EINPUT (message in err) when the usable
 * readings do not outnumber the parameters; a failed fit is not an error
 * (rep->fit_ok = 0, with a warning). */
int dss_calfit_run(const sunmc_config *c, dss_calib_workspace *cw, dss_calibration *cal,
                   calreport *rep, char *err, size_t errlen);

/* TSV: each reading with its compensated angles and errors (arcsec). */
int dss_calfit_write_residuals(FILE *f, const dss_calib_workspace *cw, const int *line,
                               const dss_calibration *cal);

/* params.ini content of a calibration ([model] section). */
int dss_params_fill(params_file *p, const dss_calibration *cal, const calreport *rep);

/* The calibration a params.ini describes ("FILE:LINE: ..." messages). */
int dss_params_load(const params_file *p, dss_calibration *cal, char *err, size_t errlen);

#endif
