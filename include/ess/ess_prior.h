/* ess_prior.h - the ESS calibration's priors from a pilot of units drawn
 * from the config's tolerances (core's prior.h says what and why). */
#ifndef SUNMC_ESS_PRIOR_H
#define SUNMC_ESS_PRIOR_H

#include "config.h"
#include "ess_calib.h"
#include "prior.h"

/* One data row's reading noise (arcsec): the four-quadrant phase of fine
 * rows read with relative noise sigma (theta0 / (2 pi) sigma / sqrt 2 in
 * angle) with the encoder's, averaged over campaign.repeats. */
double ess_reading_noise_arcsec(const sunmc_config *c);

/* The pilot of config c at the table angles of cw (the Monte Carlo's
 * campaign, or a lab's data rows): calibration.prior_units units of
 * prior_pilot_seed(c) read there without noise, each fitted without priors
 * (in a workspace of its own, so cw is untouched), into p (cw's fit-vector
 * order, model units: rad; a and c dimensionless).  SUNMC_EINPUT with a
 * message when too few fits converge, SUNMC_ENOMEM. */
int ess_prior_pilot(const sunmc_config *c, const ess_calib_workspace *cw, calib_prior *p,
                    char *err, size_t errlen);

/* calibration.priors = tolerances: the pilot at cw's table angles (set
 * them first), then its priors set on cw's fit for every later
 * ess_calibrate; off: cw's priors cleared.  p receives the priors (np = 0
 * when off, and when fewer than two of the pilot's units can be fitted: a
 * config whose units mostly cannot be; the caller says so where it
 * reports).  SUNMC_ENOMEM. */
int ess_prior_apply(const sunmc_config *c, ess_calib_workspace *cw, calib_prior *p, char *err,
                    size_t errlen);

#endif
