/* ess_simulate.c - replaying one unit's campaign and validation readings. */
#include "ess_simulate.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <math.h>

void ess_campaign_truth(const sunmc_config *c, const ess_unit *u, long unit,
                        double *alpha_true_rad, double *beta_true_rad, double *incidence_rad,
                        double *raw_rad, int *seen)
{
    /* The same draws, in the same order, as ess_unit_campaign. */
    long na = grid_count(c->cal_alpha_min_deg, c->cal_alpha_max_deg, c->cal_alpha_step_deg, 0);
    rng_stream r;
    rng_stream_init(&r, (uint64_t)c->seed, (uint64_t)unit, RNG_STREAM_CAL_NOISE);
    size_t i = 0;
    for (int k = 0; k < c->cal_beta_deg.n; k++)
        for (long j = 0; j < na; j++, i++) {
            double a = (c->cal_alpha_min_deg + (double)j * c->cal_alpha_step_deg) * RAD_PER_DEG;
            double b = c->cal_beta_deg.v[k] * RAD_PER_DEG;
            seen[i] = ess_campaign_reading(c, u, &r, a, b, &alpha_true_rad[i], &beta_true_rad[i],
                                           &incidence_rad[i], &raw_rad[i]);
        }
}

size_t ess_validation_size(const sunmc_config *c)
{
    return (size_t)grid_count(c->val_alpha_min_deg, c->val_alpha_max_deg, c->val_alpha_step_deg,
                              c->val_alpha_offset_deg) *
           (size_t)c->val_beta_deg.n;
}

void ess_validation_readings(const sunmc_config *c, const ess_unit *u, long unit,
                             double *alpha_rad, double *beta_rad, double *raw_rad,
                             double *truth_rad, int *status)
{
    /* The same grid, draws and checks as ess_family's unit_run. */
    rng_stream r;
    rng_stream_init(&r, (uint64_t)c->seed, (uint64_t)unit, RNG_STREAM_VAL_NOISE);
    long na = grid_count(c->val_alpha_min_deg, c->val_alpha_max_deg, c->val_alpha_step_deg,
                         c->val_alpha_offset_deg);
    size_t i = 0;
    for (int k = 0; k < c->val_beta_deg.n; k++)
        for (long j = 0; j < na; j++, i++) {
            alpha_rad[i] = (c->val_alpha_min_deg + c->val_alpha_offset_deg +
                            (double)j * c->val_alpha_step_deg) * RAD_PER_DEG;
            beta_rad[i] = c->val_beta_deg.v[k] * RAD_PER_DEG;
            status[i] = ess_validation_reading(c, u, &r, alpha_rad[i], beta_rad[i], &raw_rad[i],
                                               &truth_rad[i]);
        }
}
