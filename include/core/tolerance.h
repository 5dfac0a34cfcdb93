/* tolerance.h - drawing one deviation from a tolerance's distribution. */
#ifndef SUNMC_TOLERANCE_H
#define SUNMC_TOLERANCE_H

#include "config.h"
#include "rng.h"

/* One draw of tolerance t, in the unit of its key: fixed -> t->value;
 * uniform -> U(-value, value); normal -> N(0, value^2); truncnormal ->
 * N(0, value^2) redrawn until within +-truncation_sigmas*value. */
double tolerance_draw(const tolerance *t, double truncation_sigmas, rng_stream *r);

/* A tolerance with every deviation switched off (fixed 0). */
tolerance tolerance_nominal(void);

#endif
