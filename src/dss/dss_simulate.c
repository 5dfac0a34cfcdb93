/* dss_simulate.c - a DSS unit's validation readings: the Monte Carlo's own
 * dss_validation_reading on the same stream, grid and order. */
#include "dss_simulate.h"
#include "dss_rotation.h"
#include "family.h"
#include "rng.h"
#include "status.h"
#include "units.h"

#include <math.h>

static long val_axis_count(const sunmc_config *c)
{
    const dss_config *dc = dss_cfg(c);
    return grid_count(dc->val_b_min_deg, dc->val_b_max_deg, dc->val_b_step_deg,
                      dc->val_b_offset_deg);
}

size_t dss_validation_size(const sunmc_config *c)
{
    size_t n = (size_t)val_axis_count(c);
    return n * n;
}

void dss_validation_readings(const sunmc_config *c, const dss_unit *u, long unit, double *b1_rad,
                             double *b2_rad, double *x_px, double *y_px, double *truth_alpha_rad,
                             double *truth_beta_rad, int *seen)
{
    const dss_config *dc = dss_cfg(c);
    rng_stream r;
    unit_stream_init(&r, c, unit, RNG_STREAM_VAL_NOISE);
    long nb = val_axis_count(c);
    size_t i = 0;
    for (long j1 = 0; j1 < nb; j1++)
        for (long j2 = 0; j2 < nb; j2++, i++) {
            double b1 =
                (dc->val_b_min_deg + dc->val_b_offset_deg + (double)j1 * dc->val_b_step_deg) *
                RAD_PER_DEG;
            double b2 =
                (dc->val_b_min_deg + dc->val_b_offset_deg + (double)j2 * dc->val_b_step_deg) *
                RAD_PER_DEG;
            double x, y;
            b1_rad[i] = b1;
            b2_rad[i] = b2;
            seen[i] = dss_validation_reading(c, u, &r, b1, b2, &x, &y, &truth_alpha_rad[i],
                                             &truth_beta_rad[i]) == SUNMC_OK;
            x_px[i] = seen[i] ? x : NAN;
            y_px[i] = seen[i] ? y : NAN;
        }
}
