/* dss_prior.h - the DSS physical calibration's priors from a pilot of units
 * drawn from the config's tolerances (core's prior.h says what and why).
 * The polynomial model has no physical prior: for it the priors are off. */
#ifndef SUNMC_DSS_PRIOR_H
#define SUNMC_DSS_PRIOR_H

#include "config.h"
#include "dss_calib.h"
#include "prior.h"

/* One spot coordinate's reading noise (px): the centroid noise and the
 * table encoder's at the detector centre (h / pitch px per rad), averaged
 * over campaign.repeats. */
double dss_reading_noise_px(const sunmc_config *c);

/* The campaign's table angles of config c (b1 slowest), n =
 * dss_campaign_size(c) of each. */
void dss_campaign_angles(const sunmc_config *c, double *b1_rad, double *b2_rad);

/* calibration.priors = tolerances and the physical model: the pilot
 * (calibration.prior_units units of prior_pilot_seed(c) read without noise
 * at cw's table angles, set them first; each fitted without priors in a
 * workspace of its own), then its priors set on cw's fit for every later
 * dss_calibrate; otherwise cw's priors cleared.  p receives them (np = 0:
 * none).  SUNMC_ENOMEM; when fewer than two of the
 * pilot's units can be fitted (a config whose units mostly cannot be), no
 * priors (p->np = 0, SUNMC_OK): the caller says so where it reports. */
int dss_prior_apply(const sunmc_config *c, dss_calib_workspace *cw, calib_prior *p, char *err,
                    size_t errlen);

#endif
