/* ess_series.h - short series for the ESS kernels' small angles, as
 * inline functions of one vector lane: an arctangent, a tangent, and the
 * cosine and sine of x + d from those of x (the addition formulas with
 * sin d and cos d - 1 by their series), where a libmvec call would cost
 * more than the few multiply-adds.  Each states the range it is exact in
 * (to double precision); callers check it. */
#ifndef SUNMC_ESS_SERIES_H
#define SUNMC_ESS_SERIES_H

#include "vmath.h"

/* For a kernel whose series these are: multiply-adds fused where the CPU
 * has FMA (the x86-64-v3 clone), half the operations and one rounding
 * instead of two (as fit.c's dot products). */
#define ESS_CONTRACT __attribute__((optimize("fp-contract=fast")))

/* atan(e) for |e| <= 1e-2: its series to e^9 / 9, the first term left
 * out below 1e-22 |e|. */
VM_INLINE double ess_lane_atan_small(double e)
{
    double e2 = e * e;
    return e + e * e2 * (-1.0 / 3.0 + e2 * (1.0 / 5.0 + e2 * (-1.0 / 7.0 + e2 * (1.0 / 9.0))));
}

/* atan(e) for |e| <= 1/4: its series to e^25 / 25, the first term left
 * out (e^27 / 27) below 2^-53 |e| / 4.  Horner in e^2 from the small
 * end. */
VM_INLINE double ess_lane_atan_quarter(double e)
{
    double e2 = e * e;
    double p = 1.0 / 25.0;
    p = -1.0 / 23.0 + e2 * p;
    p = 1.0 / 21.0 + e2 * p;
    p = -1.0 / 19.0 + e2 * p;
    p = 1.0 / 17.0 + e2 * p;
    p = -1.0 / 15.0 + e2 * p;
    p = 1.0 / 13.0 + e2 * p;
    p = -1.0 / 11.0 + e2 * p;
    p = 1.0 / 9.0 + e2 * p;
    p = -1.0 / 7.0 + e2 * p;
    p = 1.0 / 5.0 + e2 * p;
    p = -1.0 / 3.0 + e2 * p;
    return e + e * e2 * p;
}

/* tan(h) for |h| <= 1e-2: its series to h^9, the first term left out
 * below 1e-23 |h|. */
VM_INLINE double ess_lane_tan_small(double h)
{
    double h2 = h * h;
    return h + h * h2 * (1.0 / 3.0 + h2 * (2.0 / 15.0 + h2 * (17.0 / 315.0 + h2 * (62.0 / 2835.0))));
}

typedef struct {
    double c, s;
} ess_lane_cs;

/* cos(x + d), sin(x + d) from c = cos x, sn = sin x, sd = sin d and cm1
 * = cos d - 1 (the addition formulas, the small parts added last). */
VM_INLINE ess_lane_cs ess_lane_turn_by(double c, double sn, double sd, double cm1)
{
    ess_lane_cs o = {c + (c * cm1 - sn * sd), sn + (sn * cm1 + c * sd)};
    return o;
}

/* cos(x + d), sin(x + d) from c = cos x, sn = sin x for |d| <= 0.25: sin d
 * and cos d - 1 by their series (to d^11 and d^12; the first terms left
 * out are below 3e-18 and 4e-20). */
VM_INLINE ess_lane_cs ess_lane_turn(double c, double sn, double d)
{
    double d2 = d * d;
    double sd = d + d * d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0 + d2 * (-1.0 / 5040.0 +
                    d2 * (1.0 / 362880.0 + d2 * (-1.0 / 39916800.0)))));
    double cm1 = d2 * (-0.5 + d2 * (1.0 / 24.0 + d2 * (-1.0 / 720.0 + d2 * (1.0 / 40320.0 +
                     d2 * (-1.0 / 3628800.0 + d2 * (1.0 / 479001600.0))))));
    return ess_lane_turn_by(c, sn, sd, cm1);
}

/* The same for |d| <= 0.1: to d^9 and d^10 (the first terms left out
 * are below 3e-19 and 3e-21). */
VM_INLINE ess_lane_cs ess_lane_turn_near(double c, double sn, double d)
{
    double d2 = d * d;
    double sd = d + d * d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0 + d2 * (-1.0 / 5040.0 +
                    d2 * (1.0 / 362880.0))));
    double cm1 = d2 * (-0.5 + d2 * (1.0 / 24.0 + d2 * (-1.0 / 720.0 + d2 * (1.0 / 40320.0 +
                     d2 * (-1.0 / 3628800.0)))));
    return ess_lane_turn_by(c, sn, sd, cm1);
}

/* The same for |d| <= 1: to d^17 and d^18 (the first terms left out are
 * below 9e-18 and 5e-19). */
VM_INLINE ess_lane_cs ess_lane_turn_wide(double c, double sn, double d)
{
    double d2 = d * d;
    double sd = d + d * d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0 + d2 * (-1.0 / 5040.0 +
                    d2 * (1.0 / 362880.0 + d2 * (-1.0 / 39916800.0 + d2 * (1.0 / 6227020800.0 +
                    d2 * (-1.0 / 1307674368000.0 + d2 * (1.0 / 355687428096000.0))))))));
    double cm1 = d2 * (-0.5 + d2 * (1.0 / 24.0 + d2 * (-1.0 / 720.0 + d2 * (1.0 / 40320.0 +
                     d2 * (-1.0 / 3628800.0 + d2 * (1.0 / 479001600.0 + d2 * (-1.0 / 87178291200.0 +
                     d2 * (1.0 / 20922789888000.0 + d2 * (-1.0 / 6402373705728000.0)))))))));
    return ess_lane_turn_by(c, sn, sd, cm1);
}

#endif
