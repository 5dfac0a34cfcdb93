/* tolerance.c - the four tolerance distributions. */
#include "tolerance.h"

#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdio.h>

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

double tolerance_from_normal(const tolerance *t, double truncation_sigmas, double z)
{
    switch (t->dist) {
    case DIST_FIXED:
        return t->value;
    case DIST_UNIFORM:
        return t->value * (2.0 * gsl_cdf_ugaussian_P(z) - 1.0);
    case DIST_NORMAL:
        return t->value * z;
    case DIST_TRUNCNORMAL: {
        double lo = gsl_cdf_ugaussian_P(-truncation_sigmas);
        double hi = gsl_cdf_ugaussian_P(truncation_sigmas);
        double x = gsl_cdf_ugaussian_Pinv(lo + (hi - lo) * gsl_cdf_ugaussian_P(z));
        return t->value * fmax(-truncation_sigmas, fmin(truncation_sigmas, x));
    }
    }
    return 0.0;
}

void tolerance_range(const tolerance *t, double truncation_sigmas, double *lo, double *hi)
{
    double reach = t->value;
    if (t->dist == DIST_FIXED) {
        *lo = *hi = t->value;
        return;
    }
    if (t->dist == DIST_TRUNCNORMAL)
        reach = truncation_sigmas * t->value;
    else if (t->dist == DIST_NORMAL)
        reach = TOLERANCE_NORMAL_REACH_SIGMAS * t->value;
    *lo = -fabs(reach);
    *hi = fabs(reach);
}

void tolerance_range_text(const tolerance *t, double truncation_sigmas, char *buf, size_t len)
{
    double lo, hi;
    tolerance_range(t, truncation_sigmas, &lo, &hi);
    switch (t->dist) {
    case DIST_FIXED:
        snprintf(buf, len, "fixed, %+g", t->value);
        break;
    case DIST_UNIFORM:
        snprintf(buf, len, "uniform, +-%g", hi);
        break;
    case DIST_NORMAL:
        snprintf(buf, len, "normal, unbounded; +-%g sigma = +-%g", TOLERANCE_NORMAL_REACH_SIGMAS,
                 hi);
        break;
    default:
        snprintf(buf, len, "truncnormal, +-%g sigma = +-%g", truncation_sigmas, hi);
    }
}

