/* root.h - the root of an increasing function by bisection, to the last bit.
 *
 * For inverses whose Newton-type iteration cannot meet its step test (a
 * slope near 0 lets rounding keep the step above the tolerance): bisection
 * ends at adjacent doubles whatever the slope. */
#ifndef SUNMC_UTIL_ROOT_H
#define SUNMC_UTIL_ROOT_H

/* g(x) with its parameters in ctx. */
typedef double (*root_fn)(double x, const void *ctx);

/* The root of g, strictly increasing on [lo, hi] with g(lo) <= 0 <= g(hi)
 * (the caller's bracket, not checked): an x where g is exactly 0, else,
 * once lo and hi are adjacent doubles, whichever has the smaller |g|. */
double root_bisect_increasing(root_fn g, const void *ctx, double lo, double hi);

#endif
