/* deviation.c - one unit's deviations from a family's deviation list. */
#include "deviation.h"
#include "family.h"
#include "rng.h"
#include "sampling.h"
#include "tolerance.h"

#include <gsl/gsl_cdf.h>
#include <math.h>

/* The unit's own standard normal score of draw j of a tolerance: from its
 * stream, or under a sampling design the quantile of its design
 * coordinate (sampling.h; k: the draw's place in the list). */
static double unit_score(const sunmc_config *c, uint64_t sseed, long unit, uint32_t id, int j,
                         int k, rng_stream *r)
{
    if (c->sampling == CONFIG_SAMPLING_RANDOM)
        return rng_normal(r);
    return gsl_cdf_ugaussian_Pinv(sampling_uniform(c, sseed, unit, id, j, k, r));
}

/* A tolerance with a lot share rho: score z = sqrt(rho) z_lot + sqrt(1 -
 * rho) z_unit, z_lot from the lot's stream (seed, unit / lot_size), z_unit
 * from the unit's; z is standard normal, so the draw keeps t's
 * distribution, and two units of a lot correlate by rho (their scores). */
static void draw_with_lot(const tolerance *t, const sunmc_config *c, uint64_t seed, long unit,
                          uint32_t stream, rng_stream *r, int count, int k0, double *out)
{
    rng_stream rl;
    uint32_t lid = RNG_STREAM_LOT + stream;
    long lot_size = c->lot_size > 0 ? c->lot_size : 1;
    rng_stream_init(&rl, unit_stream_seed(c, seed, lid), (uint64_t)(unit / lot_size), lid);
    double a = sqrt(t->lot), b = sqrt(1.0 - t->lot);
    for (int i = 0; i < count; i++) {
        uint32_t id = RNG_STREAM_TOLERANCE + stream;
        double zu = unit_score(c, unit_stream_seed(c, seed, id), unit, id, i, k0 + i, r);
        double z = a * rng_normal(&rl) + b * zu;
        out[i] = tolerance_from_normal(t, c->truncation_sigmas, z);
    }
}

void deviations_sample(const deviation_spec *list, int n, const sunmc_config *c, uint64_t seed,
                       long unit, void *dev)
{
    for (int e = 0, k = 0; e < n; k += list[e].count, e++) {
        const tolerance *t = (const tolerance *)(const void *)(c->fam.bytes + list[e].tol_offset);
        double *out = (double *)(void *)((char *)dev + list[e].dev_offset);
        rng_stream r;
        uint32_t id = RNG_STREAM_TOLERANCE + list[e].stream;
        uint64_t sseed = unit_stream_seed(c, seed, id);
        rng_stream_init(&r, sseed, (uint64_t)unit, id);
        if (t->lot > 0 && t->dist != DIST_FIXED) {
            draw_with_lot(t, c, seed, unit, list[e].stream, &r, list[e].count, k, out);
            continue;
        }
        for (int i = 0; i < list[e].count; i++)
            out[i] = c->sampling == CONFIG_SAMPLING_RANDOM || t->dist == DIST_FIXED
                         ? tolerance_draw(t, c->truncation_sigmas, &r)
                         : tolerance_from_normal(t, c->truncation_sigmas,
                                                 unit_score(c, sseed, unit, id, i, k + i, &r));
    }
}

int deviations_values(const deviation_spec *list, int n, const void *dev, double *out, int max)
{
    int k = 0;
    for (int e = 0; e < n; e++) {
        const double *v = (const double *)(const void *)((const char *)dev + list[e].dev_offset);
        for (int i = 0; i < list[e].count; i++, k++)
            if (k < max)
                out[k] = v[i];
    }
    return k;
}

int deviations_columns(const deviation_spec *list, int n, const char **names, int max)
{
    int k = 0;
    for (int e = 0; e < n; e++)
        for (int i = 0; i < list[e].count; i++, k++)
            if (k < max)
                names[k] = list[e].columns[i];
    return k;
}

void deviations_scale(const deviation_spec *list, int n, void *dev, double s)
{
    for (int e = 0; e < n; e++) {
        double *v = (double *)(void *)((char *)dev + list[e].dev_offset);
        for (int i = 0; i < list[e].count; i++)
            v[i] *= s;
    }
}

void deviations_set_values(const deviation_spec *list, int n, const double *values, void *dev)
{
    int k = 0;
    for (int e = 0; e < n; e++) {
        double *v = (double *)(void *)((char *)dev + list[e].dev_offset);
        for (int i = 0; i < list[e].count; i++)
            v[i] = values[k++];
    }
}

double deviations_reach(const deviation_spec *spec, const sunmc_config *c)
{
    const tolerance *t = (const tolerance *)(const void *)(c->fam.bytes + spec->tol_offset);
    double lo, hi;
    tolerance_range(t, c->truncation_sigmas, &lo, &hi);
    return fmax(fabs(lo), fabs(hi));
}
