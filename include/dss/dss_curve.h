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

#include "family.h"

/* The hooks (family.h's family_curve), reached as dss_family.curve. */
extern const family_curve dss_curve;

#endif
