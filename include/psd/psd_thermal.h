/* psd_thermal.h - a four-channel unit at another temperature than the lab's.
 *
 * dT = T - environment.calibration_temp_c.  What moves (docs/temperature.md):
 *  - the aperture's height h with the spacer (environment.spacer_cte_ppm_k),
 *  - the cover glass's thickness (glass_cte_ppm_k) and index (glass_dn_dt_ppm_k),
 *  - each channel's dark signal by 2^(dT / environment.dark_doubling_k)
 *    (0: no drift),
 *  - each channel's gain by (1 + environment.responsivity_tc_ppm_k dT).
 * At dT = 0 the sensor is the same bits.
 */
#ifndef SUNMC_PSD_THERMAL_H
#define SUNMC_PSD_THERMAL_H

#include "config.h"
#include "psd_sensor.h"

/* Sensor s (built at the lab's temperature) as it is at temp_c, into out. */
void psd_sensor_at_temp(const sunmc_config *c, const psd_sensor *s, double temp_c,
                        psd_sensor *out);

#endif
