/* dss_simulate.h - one simulated DSS unit's validation readings as a lab
 * records them (`sunmc simulate`): exactly the readings the Monte Carlo's
 * dss_family unit_run validates unit `unit` on.
 *
 * It calls the Monte Carlo's own dss_validation_reading (dss_unit.h) on the
 * stream RNG_STREAM_VAL_NOISE of (seed, unit), over the same grid in the
 * same order (tests/test_calibrate.c compares with run's units.tsv).
 */
#ifndef SUNMC_DSS_SIMULATE_H
#define SUNMC_DSS_SIMULATE_H

#include "dss_config.h"
#include "dss_unit.h"

#include <stddef.h>

/* Number of validation grid points of config c (b1 x b2). */
size_t dss_validation_size(const sunmc_config *c);

/* The validation readings of unit `unit` (arrays of dss_validation_size(c),
 * b1 varying slowest): table angles b1_rad, b2_rad (the table stands at
 * exactly these), the measured spot x_px, y_px (px from the detector centre,
 * one reading with centroid noise; NaN with seen[i] = 0 when there is no
 * spot, which `run` leaves out), and the truth angles (eq. 3-4) rad. */
void dss_validation_readings(const sunmc_config *c, const dss_unit *u, long unit, double *b1_rad,
                             double *b2_rad, double *x_px, double *y_px, double *truth_alpha_rad,
                             double *truth_beta_rad, int *seen);

#endif
