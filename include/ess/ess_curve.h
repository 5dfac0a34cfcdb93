/* ess_curve.h - the ESS implementation of the family's curve hooks
 * (family.h): one unit's error vs incidence alpha, before and after its own
 * calibration, one series per outer-frame angle beta, on the validation grid
 * (validation.alpha_* and validation.beta_deg).  Used by `sunmc curve` to
 * redraw ESS paper Fig. 3, 5-7 and 11. */
#ifndef SUNMC_ESS_CURVE_H
#define SUNMC_ESS_CURVE_H

#include "ess_config.h"
#include "family.h"

#include <stddef.h>

/* {"alpha_deg", "beta_deg"} */
extern const char *const ess_curve_axis_names[2];

/* Axis 0: validation alphas (deg) alpha_min + offset + j step up to
 * alpha_max; axis 1: validation.beta_deg.  Returns the count; writes at
 * most max values. */
long ess_curve_axis(const sunmc_config *c, int axis, double *values_deg, long max);

/* Workspace for one unit of c (campaign of ess_campaign_size(c) points).
 * NULL with a message in err on failure. */
void *ess_curve_alloc(const sunmc_config *c, char *err, size_t errlen);
void ess_curve_free(void *cv);

/* Draw unit `unit`'s deviations (times dev_sign), build it, run its
 * campaign and fit it; *fit_ok = 1 when the fit converged. */
int ess_curve_prepare(const sunmc_config *c, long unit, double dev_sign, void *cv, int *fit_ok);

/* Noiseless reading at turntable (alpha, beta) in degrees: before[0] =
 * raw - truth, after[0] = compensated - truth (deg; NaN when the fit
 * failed).  SUNMC_EDOM when the sun is not seen or the coarse code picked
 * the wrong fine period. */
int ess_curve_eval(const sunmc_config *c, const void *cv, double alpha_deg, double beta_deg,
                   double before[UNIT_MAX_ANGLES], double after[UNIT_MAX_ANGLES]);

#endif
