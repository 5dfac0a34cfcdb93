/* ess_simulate.h - one simulated ESS unit's data as a lab records them
 * (`sunmc simulate`): the truth behind its calibration campaign and the
 * validation readings the Monte Carlo scores it on.
 *
 * Both are built on the Monte Carlo's own per-reading functions
 * (ess_campaign_reading, ess_validation_reading in ess_unit.c) with the same
 * streams and order, so the files `simulate` writes are exactly what unit
 * `unit` of `sunmc run` sees.
 */
#ifndef SUNMC_ESS_SIMULATE_H
#define SUNMC_ESS_SIMULATE_H

#include "ess_config.h"
#include "ess_unit.h"

#include <stddef.h>

/* Truth behind each of the ess_campaign_size(c) campaign points of unit
 * `unit` (same order as ess_unit_campaign): the table's true angles (the
 * recorded ones plus encoder error), the true incidence alpha in the sensor
 * frame, the averaged raw output (equal to ess_unit_campaign's), and seen[i]
 * = 0 when the sun was not seen.  All angles in rad; arrays of n. */
void ess_campaign_truth(const sunmc_config *c, const ess_unit *u, long unit,
                        double *alpha_true_rad, double *beta_true_rad, double *incidence_rad,
                        double *raw_rad, int *seen);

/* Number of validation grid points of config c (alphas x betas). */
size_t ess_validation_size(const sunmc_config *c);

/* The validation readings of unit `unit`, as ess_family's unit_run makes
 * them: table angles, raw output and true incidence (rad), and status[i]:
 * 0 valid, 1 sun not seen, 2 gross error (off the truth by more than half a
 * fine period; the Monte Carlo leaves these out).  Arrays of
 * ess_validation_size(c). */
void ess_validation_readings(const sunmc_config *c, const ess_unit *u, long unit,
                             double *alpha_rad, double *beta_rad, double *raw_rad,
                             double *truth_rad, int *status);


#endif
