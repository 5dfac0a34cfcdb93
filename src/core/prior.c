/* prior.c - Gaussian priors of a calibration from its pilot (prior.h). */
#include "prior.h"
#include "status.h"

#include <math.h>
#include <string.h>

/* XOR into run.seed: a pilot stream no unit of any command draws from. */
#define PRIOR_PILOT_SEED_XOR 0x9E3779B97F4A7C15ULL

uint64_t prior_pilot_seed(const sunmc_config *c)
{
    return (uint64_t)c->seed ^ PRIOR_PILOT_SEED_XOR;
}

int calib_prior_install(fit_workspace *fw, calib_prior *p, int pilot_status, char *err,
                        size_t errlen)
{
    if (pilot_status == SUNMC_EINPUT) {
        calib_prior_reset(p, 0);
        return SUNMC_OK;
    }
    if (pilot_status != SUNMC_OK)
        return pilot_status;
    if (fit_prior_set(fw, p->mean, p->weight) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "prior: weights not finite");
    return SUNMC_OK;
}

int calib_prior_reset(calib_prior *p, int np)
{
    memset(p, 0, sizeof *p);
    if (np < 0 || np > PRIOR_MAX_P)
        return SUNMC_EINPUT;
    p->np = np;
    return SUNMC_OK;
}

void calib_prior_add(calib_prior *p, const double *x)
{
    p->units++;
    for (int j = 0; j < p->np; j++) {
        double d = x[j] - p->mean[j];
        p->mean[j] += d / (double)p->units;
        p->sum2[j] += d * (x[j] - p->mean[j]);
    }
}

int calib_prior_finish(calib_prior *p, double sigma_row, char *err, size_t errlen)
{
    if (p->units < 2)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "calibration.priors = tolerances: only %ld of the pilot's units could "
                          "be fitted; the priors need at least 2 (raise "
                          "calibration.prior_units, or set calibration.priors = off)",
                          p->units);
    if (!(sigma_row >= 0 && isfinite(sigma_row)))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "prior: reading noise %g is not a noise",
                          sigma_row);
    p->sigma_row = sigma_row;
    for (int j = 0; j < p->np; j++) {
        p->unseen[j] = !(p->sum2[j] > 0);
        p->sigma[j] = fmax(sqrt(p->sum2[j] / (double)(p->units - 1)), PRIOR_SIGMA_FLOOR);
        p->weight[j] = sigma_row / p->sigma[j];
    }
    return SUNMC_OK;
}
