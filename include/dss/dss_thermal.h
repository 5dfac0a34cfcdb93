/* dss_thermal.h - a DSS unit at another temperature than the lab's.
 *
 * dT = environment.operating_temp_c - calibration_temp_c.  What moves
 * (docs/temperature.md):
 *  - the spacer: the pinhole height h + dh by (h + dh) a_s dT;
 *  - the cover glass: its thickness t + dt by (t + dt) a_g dT, its index by
 *    (dn/dT) dT;
 *  - the detector: its pixel pitch p by p a_d dT.  Spots are read in pixels,
 *    so a pitch grown by (1 + a_d dT) is every length of the geometry (h, t,
 *    the pinhole's offsets dx, dy) divided by it at the design pitch.
 * The pinhole's offsets in mm and the mount do not move (the mask is thin
 * and centred); the disc coefficient and the spot size are kept. */
#ifndef SUNMC_DSS_THERMAL_H
#define SUNMC_DSS_THERMAL_H

#include "config.h"
#include "dss_sensor.h"

/* Deviations d as they are at the operating temperature; out = d (the same
 * bits) when the temperatures are equal. */
void dss_deviations_at_temp(const sunmc_config *c, const dss_deviations *d, double temp_c,
                            dss_deviations *out);

#endif
