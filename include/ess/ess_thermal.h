/* ess_thermal.h - an ESS unit at another temperature than the lab's.
 *
 * The campaign and the fit are at environment.calibration_temp_c, the
 * validation at environment.operating_temp_c; dT = operating - calibration.
 * What moves (docs/temperature.md):
 *  - the spacer: the slit-to-dial distance H + dH grows by (H + dH) a_s dT
 *    (environment.spacer_cte_ppm_k);
 *  - the dial: its code pitch grows by a_m dT (environment.mask_cte_ppm_k).
 *    The sensor reads tan(alpha) = x / H: every code edge x scaled by
 *    (1 + a_m dT) reads as H divided by it, so both are one effective height
 *        H_T = (H + dH) (1 + a_s dT) / (1 + a_m dT).
 *  - the slit moves with the slit plate and the dial alike (no relative
 *    shift to first order), the etching rule was set at H.
 * With dH = H a dT alone the error is -(dH / 2H) sin(2 alpha) (ESS paper
 * eq. of the height error; test_thermal_derivations).  Photocell responsivity and dark
 * current are not modelled (the fine code is a ratio of its rows; their
 * common change cancels, their mismatch is not in the paper's model). */
#ifndef SUNMC_ESS_THERMAL_H
#define SUNMC_ESS_THERMAL_H

#include "config.h"
#include "ess_sensor.h"

/* Unit deviations d (at the lab's temperature) as they are at the
 * operating temperature: out = d with dH_um moved as above; out = d (the
 * same bits) when the two temperatures are equal. */
void ess_deviations_at_temp(const sunmc_config *c, const ess_deviations *d, double temp_c,
                            ess_deviations *out);

#endif
