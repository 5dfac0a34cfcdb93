/* ess_score.h - a calibrated ESS unit's validation scores (ess_score.c). */
#ifndef SUNMC_ESS_SCORE_H
#define SUNMC_ESS_SCORE_H

#include "ess_unit.h"
#include "family.h"

/* Score unit readings v with the unit's fitted model m into res
 * (ess_score.c): RMS per report band before and after calibration, and
 * the systematic part of after (the same readings without noise; NaN
 * under c->no_systematic).  Unseen readings are left out, gross ones
 * counted in res->gross_val and left out; res->fit_status says whether m
 * is good (not: before only), and a reading m cannot compensate fails
 * the unit's fit (UNIT_FIT_FAILED) and ends the after sums.  ob (NULL:
 * none) compensates through the on-board form (calibration.onboard,
 * lab_onboard.h) prepared with m instead of m itself. */
struct lab_onboard;
void ess_score_validation(const sunmc_config *c, const ess_model *m, const struct lab_onboard *ob,
                          const ess_val_readings *v, unit_result *res);

#endif
