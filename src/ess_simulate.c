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
    double enc = c->encoder_arcsec * RAD_PER_ARCSEC;
    rng_stream r;
    rng_stream_init(&r, (uint64_t)c->seed, (uint64_t)unit, RNG_STREAM_CAL_NOISE);
    size_t i = 0;
    for (int k = 0; k < c->cal_beta_deg.n; k++)
        for (long j = 0; j < na; j++, i++) {
            double a = (c->cal_alpha_min_deg + (double)j * c->cal_alpha_step_deg) * RAD_PER_DEG;
            double b = c->cal_beta_deg.v[k] * RAD_PER_DEG;
            double a_true = a + enc * rng_normal(&r);
            double b_true = b + enc * rng_normal(&r);
            double sum = 0, truth = 0;
            int ok = 1;
            for (int rep = 0; rep < c->cal_repeats; rep++) {
                double noise[ESS_FINE_ROWS], raw;
                ess_row_noise(c, &r, noise);
                if (ess_unit_read(u, a_true, b_true, noise, &raw, &truth) != SUNMC_OK)
                    ok = 0;
                else
                    sum += raw;
            }
            alpha_true_rad[i] = a_true;
            beta_true_rad[i] = b_true;
            incidence_rad[i] = truth;
            raw_rad[i] = ok ? sum / c->cal_repeats : 0.0;
            seen[i] = ok;
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
    double half_period = 0.5 * c->ess.theta0_deg * RAD_PER_DEG;
    size_t i = 0;
    for (int k = 0; k < c->val_beta_deg.n; k++)
        for (long j = 0; j < na; j++, i++) {
            double a = (c->val_alpha_min_deg + c->val_alpha_offset_deg +
                        (double)j * c->val_alpha_step_deg) * RAD_PER_DEG;
            double b = c->val_beta_deg.v[k] * RAD_PER_DEG;
            double noise[ESS_FINE_ROWS], raw = 0, truth = 0;
            ess_row_noise(c, &r, noise);
            alpha_rad[i] = a;
            beta_rad[i] = b;
            if (ess_unit_read(u, a, b, noise, &raw, &truth) != SUNMC_OK)
                status[i] = ESS_READING_UNSEEN;
            else if (fabs(raw - truth) > half_period)
                status[i] = ESS_READING_GROSS;
            else
                status[i] = ESS_READING_OK;
            raw_rad[i] = raw;
            truth_rad[i] = truth;
        }
}
