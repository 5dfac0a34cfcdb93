/* ess_curve.h - the ESS implementation of the family's curve hooks
 * (family.h): one unit's error vs incidence alpha, before and after its own
 * calibration, one series per outer-frame angle beta, on the validation grid
 * (validation.alpha_* and validation.beta_deg).  Used by `sunmc curve` to
 * redraw ESS paper Fig. 3, 5-7 and 11. */
#ifndef SUNMC_ESS_CURVE_H
#define SUNMC_ESS_CURVE_H

#include "family.h"

/* The hooks (family.h's family_curve), reached as ess_family.curve. */
extern const family_curve ess_curve;

#endif
