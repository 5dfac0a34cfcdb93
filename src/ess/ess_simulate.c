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
    const ess_config *ec = ess_cfg(c);
    /* The same draws, in the same order, as ess_unit_campaign. */
    long na = grid_count(ec->cal_alpha_min_deg, ec->cal_alpha_max_deg, ec->cal_alpha_step_deg, 0);
    rng_stream r;
    unit_stream_init(&r, c, unit, RNG_STREAM_CAL_NOISE);
    size_t i = 0;
    for (int k = 0; k < ec->cal_beta_deg.n; k++)
        for (long j = 0; j < na; j++, i++) {
            double a = (ec->cal_alpha_min_deg + (double)j * ec->cal_alpha_step_deg) * RAD_PER_DEG;
            double b = ec->cal_beta_deg.v[k] * RAD_PER_DEG;
            seen[i] = ess_campaign_reading(c, u, &r, a, b, &alpha_true_rad[i], &beta_true_rad[i],
                                           &incidence_rad[i], &raw_rad[i]);
        }
}

size_t ess_validation_size(const sunmc_config *c)
{
    const ess_config *ec = ess_cfg(c);
    return (size_t)grid_count(ec->val_alpha_min_deg, ec->val_alpha_max_deg, ec->val_alpha_step_deg,
                              ec->val_alpha_offset_deg) *
           (size_t)ec->val_beta_deg.n;
}

void ess_validation_readings(const sunmc_config *c, const ess_unit *u, long unit,
                             double *alpha_rad, double *beta_rad, double *raw_rad,
                             double *truth_rad, int *status)
{
    const ess_config *ec = ess_cfg(c);
    /* The same grid, draws and checks as ess_family's unit_run. */
    rng_stream r;
    unit_stream_init(&r, c, unit, RNG_STREAM_VAL_NOISE);
    long na = grid_count(ec->val_alpha_min_deg, ec->val_alpha_max_deg, ec->val_alpha_step_deg,
                         ec->val_alpha_offset_deg);
    size_t i = 0;
    for (int k = 0; k < ec->val_beta_deg.n; k++)
        for (long j = 0; j < na; j++, i++) {
            alpha_rad[i] = (ec->val_alpha_min_deg + ec->val_alpha_offset_deg +
                            (double)j * ec->val_alpha_step_deg) *
                           RAD_PER_DEG;
            beta_rad[i] = ec->val_beta_deg.v[k] * RAD_PER_DEG;
            status[i] = ess_validation_reading(c, u, &r, alpha_rad[i], beta_rad[i], &raw_rad[i],
                                               &truth_rad[i]);
        }
}
