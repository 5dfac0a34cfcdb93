/* prior.h - Gaussian priors of a calibration's parameters from what the lab
 * knows before its campaign (calibration.priors = tolerances, issue 25).
 *
 * The prior of each fitted parameter is its distribution over the units the
 * config's tolerances describe: a pilot of calibration.prior_units units,
 * drawn like the Monte Carlo's units but from a seed of their own
 * (prior_pilot_seed), each simulated on the config's campaign without
 * reading noise and fitted without priors.  The mean and standard deviation
 * of each parameter over the pilot are its prior; the mount's and the sun
 * simulator's tolerances (and measured values, when the config measures
 * them) are in the pilot's draws, so they are in the prior.  In the Monte
 * Carlo the truth is drawn from the same tolerances, so the prior is honest
 * there; for a lab's data it is the config's statement, printed in the
 * report and written to params.ini.
 *
 * The fit adds one residual row per parameter, weight sigma_row / sigma_j
 * (fit_prior_set): sigma_row is one data row's reading noise in the
 * residuals' unit, so with no reading noise the priors weigh nothing and the
 * fit is the plain one.  The pilot depends only on the config and run.seed:
 * every thread, shard and rank computes the same priors.
 */
#ifndef SUNMC_PRIOR_H
#define SUNMC_PRIOR_H

#include "config.h"
#include "fit.h"

#include <stdint.h>

#define PRIOR_MAX_P 64

typedef struct {
    int np;              /* parameters (the fit vector's order) */
    long units;          /* pilot units whose fit converged */
    double mean[PRIOR_MAX_P];
    double sigma[PRIOR_MAX_P];  /* over the pilot, floored at PRIOR_SIGMA_FLOOR */
    double weight[PRIOR_MAX_P]; /* sigma_row / sigma: fit_prior_set's */
    double sum2[PRIOR_MAX_P];   /* accumulation (Welford) */
    int unseen[PRIOR_MAX_P];    /* 1: no pilot fit moved it from its start (the campaign
                                   does not see it): held there, not determined */
    double sigma_row;    /* one data row's noise, residual units */
} calib_prior;

/* The smallest prior sigma (parameter units): a parameter that no
 * tolerance moves is held at its pilot value, not at infinite weight. */
#define PRIOR_SIGMA_FLOOR 1e-9

/* The seed of the pilot's draws: run.seed's own, distinct from the units'
 * and from sensitivity's second sample. */
uint64_t prior_pilot_seed(const sunmc_config *c);

/* Start a pilot of np parameters (SUNMC_EINPUT when np > PRIOR_MAX_P). */
int calib_prior_reset(calib_prior *p, int np);
/* Add one pilot unit's fitted parameters x[np]. */
void calib_prior_add(calib_prior *p, const double *x);
/* Means, sigmas and weights for a data row's noise sigma_row (>= 0).
 * SUNMC_EINPUT (with a message) when fewer than 2 pilot units converged. */
int calib_prior_finish(calib_prior *p, double sigma_row, char *err, size_t errlen);

/* Give a pilot's outcome to the fit: pilot_status SUNMC_OK sets p's priors
 * on fw (fit_prior_set); SUNMC_EINPUT (fewer than two pilot units could be
 * fitted: a config whose units mostly cannot be) leaves fw without priors
 * and p empty (np = 0), which the caller reports; any other status is
 * returned.  SUNMC_OK, or the failing status. */
int calib_prior_install(fit_workspace *fw, calib_prior *p, int pilot_status, char *err,
                        size_t errlen);

#endif
