/* tolerance.h - drawing one deviation from a tolerance's distribution. */
#ifndef SUNMC_TOLERANCE_H
#define SUNMC_TOLERANCE_H

#include "config.h"
#include "rng.h"

/* One draw of tolerance t, in the unit of its key: fixed -> t->value;
 * uniform -> U(-value, value); normal -> N(0, value^2); truncnormal ->
 * N(0, value^2) redrawn until within +-truncation_sigmas*value. */
double tolerance_draw(const tolerance *t, double truncation_sigmas, rng_stream *r);

/* The draw of tolerance t whose standard normal score is z (the Gaussian
 * copula: P(draw <= x) = Phi(z) for the distribution's CDF), in the unit of
 * its key: fixed -> value; uniform -> value (2 Phi(z) - 1); normal ->
 * value z; truncnormal -> value Phi^-1(Phi(-c) + (Phi(c) - Phi(-c)) Phi(z)),
 * c = truncation_sigmas.  A standard normal z gives t's distribution. */
double tolerance_from_normal(const tolerance *t, double truncation_sigmas, double z);

/* How far a normal (untruncated) tolerance is taken to reach when a config
 * is checked for physically impossible draws: 6 sigma (a draw beyond it has
 * probability 2e-9, one in 500 million units). */
#define TOLERANCE_NORMAL_REACH_SIGMAS 6.0

/* The range of tolerance t's draws, in the unit of its key: fixed
 * [value, value]; uniform [-value, value]; truncnormal +-truncation_sigmas *
 * value; normal +-TOLERANCE_NORMAL_REACH_SIGMAS * value. */
void tolerance_range(const tolerance *t, double truncation_sigmas, double *lo, double *hi);

/* "uniform, +-2", "truncnormal, +-3 sigma = +-6", "normal, +-6 sigma = +-12"
 * or "fixed, +2": how tolerance t's range above comes about, for messages. */
void tolerance_range_text(const tolerance *t, double truncation_sigmas, char *buf, size_t len);

#endif
