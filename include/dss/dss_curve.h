/* dss_curve.h - the DSS implementation of the family's curve hooks
 * (family.h): one unit's error over a 2-D grid of sun angles (alpha, beta),
 * before and after its own calibration.  Used by `sunmc curve` to redraw the
 * DSS paper's error maps (Figs. 2-5).
 *
 * The map's axes are the sun angles of the DSS paper's figures, i.e. the
 * truth (alpha0, beta0) of eq. 3-4, not the table angles: a grid point
 * (alpha, beta) is reached with the table at b2 = -alpha,
 * b1 = atan(tan beta cos b2) (the inverse of table_truth).  Both axes
 * take the validation grid's values: validation.b_min_deg + b_offset_deg +
 * j b_step_deg up to b_max_deg.  Points whose spot leaves the detector are
 * not seen (SUNMC_EDOM; NaN in curve.tsv). */
#ifndef SUNMC_DSS_CURVE_H
#define SUNMC_DSS_CURVE_H

#include "dss_config.h"
#include "family.h"

#include <stddef.h>

/* {"alpha_deg", "beta_deg"} */
extern const char *const dss_curve_axis_names[2];

/* Values (deg) of axis 0 (alpha) or 1 (beta): the validation b grid, the same
 * for both.  Returns the count; writes at most max values (values_deg may be
 * NULL when max is 0). */
long dss_curve_axis(const sunmc_config *c, int axis, double *values_deg, long max);

/* Workspace for one unit of c (campaign of dss_campaign_size(c) readings,
 * c's calibration model).  NULL with a message in err on failure. */
void *dss_curve_alloc(const sunmc_config *c, char *err, size_t errlen);
void dss_curve_free(void *cv);

/* Draw unit `unit`'s deviations as the Monte Carlo does, multiply each by
 * dev_sign (+1, or -1 for the mirror unit), build it, simulate its campaign
 * (c's noise) and fit it; *fit_ok = 1 when the fit converged. */
int dss_curve_prepare(const sunmc_config *c, long unit, double dev_sign, void *cv, int *fit_ok);

/* Noiseless reading (S-curve bias included when on) at sun angles
 * alpha_deg, beta_deg: before[a] = on-board - truth, after[a] = compensated
 * - truth in arcsec, for a = alpha, beta, total (the angle between the
 * measured and true sun vectors, >= 0); after[] NaN when the fit failed.
 * SUNMC_EDOM when the spot is not on the detector there. */
int dss_curve_eval(const sunmc_config *c, const void *cv, double alpha_deg, double beta_deg,
                   double before[UNIT_MAX_ANGLES], double after[UNIT_MAX_ANGLES]);

#endif
