/* tolerance.c - the four tolerance distributions. */
#include "tolerance.h"

#include <math.h>

/* Rejection of a truncated normal needs at most a few draws for cuts >= 0.5
 * sigma; the cap only guards against a pathological config. */
#define TRUNCNORMAL_MAX_TRIES 1000

double tolerance_draw(const tolerance *t, double truncation_sigmas, rng_stream *r)
{
    switch (t->dist) {
    case DIST_FIXED:
        return t->value;
    case DIST_UNIFORM:
        return t->value * (2.0 * rng_uniform(r) - 1.0);
    case DIST_NORMAL:
        return t->value * rng_normal(r);
    case DIST_TRUNCNORMAL:
        for (int i = 0; i < TRUNCNORMAL_MAX_TRIES; i++) {
            double z = rng_normal(r);
            if (fabs(z) <= truncation_sigmas)
                return t->value * z;
        }
        return 0.0;
    }
    return 0.0;
}

tolerance tolerance_nominal(void)
{
    tolerance t = {0.0, DIST_FIXED};
    return t;
}
