/* root.c - bisection of an increasing function (root.h). */
#include "root.h"

#include <math.h>

double root_bisect_increasing(root_fn g, const void *ctx, double lo, double hi)
{
    for (;;) {
        double mid = lo + 0.5 * (hi - lo);
        if (mid <= lo || mid >= hi)
            return fabs(g(lo, ctx)) <= fabs(g(hi, ctx)) ? lo : hi;
        double gm = g(mid, ctx);
        if (gm == 0.0)
            return mid;
        if (gm > 0.0)
            hi = mid;
        else
            lo = mid;
    }
}
