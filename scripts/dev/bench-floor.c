/* bench-floor.c - the transcendental floor of an ESS type A unit: a program that
 * makes exactly the vector math calls one unit of the paper model made
 * (configs/ess_type_a.ini, one thread, before issue 27) and nothing else,
 * in the same vector loops (include/util/vmath.h: libmvec, AVX2 where the
 * CPU has it, chosen at run time as the kernels choose it).
 *
 * Counted per unit (lane evaluations, padding lanes included: an
 * LD_PRELOAD counter around libmvec's entry points, 200 minus 100 units):
 * sin 66,979, cos 85,459, tan 7,632, atan 55,504, log 18,480,
 * atan2 16,899: 250,953 (the 250,968 within a unit's varying
 * number of fit iterations).  Arguments span the ranges the unit's calls
 * see (angles of a few radians, fine-code phases up to ~200 rad, tangents
 * within +-2, logs of uniforms).
 *
 * Usage: bench-floor [UNITS]  (default 1000); prints the units and a
 * checksum so that the calls cannot be optimised away.  scripts/dev/bench.sh
 * divides sunmc's one-thread CPU time per unit by this one's. */
#include "vmath.h"

#include <stdio.h>
#include <stdlib.h>

#define FLOOR_CHUNK 64

enum { F_SIN, F_COS, F_TAN, F_ATAN, F_LOG, F_ATAN2, F_N };
static const long floor_calls[F_N] = {66979, 85459, 7632, 55504, 18480, 16899};

/* One vector loop of n (a multiple of VM_PAD, at most FLOOR_CHUNK) calls
 * of function f; returns a sum. */
VM_KERNEL static double floor_chunk(int f, int n, const double *x, const double *y)
{
    _Alignas(VM_ALIGN) double out[FLOOR_CHUNK];
    switch (f) {
    case F_SIN:
        VM_SIMD for (int i = 0; i < n; i++) out[i] = sin(x[i]);
        break;
    case F_COS:
        VM_SIMD for (int i = 0; i < n; i++) out[i] = cos(x[i]);
        break;
    case F_TAN:
        VM_SIMD for (int i = 0; i < n; i++) out[i] = tan(0.01 * x[i]);
        break;
    case F_ATAN:
        VM_SIMD for (int i = 0; i < n; i++) out[i] = atan(y[i]);
        break;
    case F_LOG:
        VM_SIMD for (int i = 0; i < n; i++) out[i] = log(0.5 + 0.2 * y[i]);
        break;
    default:
        VM_SIMD for (int i = 0; i < n; i++) out[i] = atan2(y[i], x[i]);
        break;
    }
    double s = 0.0;
    for (int i = 0; i < n; i++)
        s += out[i];
    return s;
}

int main(int argc, char **argv)
{
    long units = argc > 1 ? atol(argv[1]) : 1000;
    if (units <= 0) {
        fprintf(stderr, "usage: bench-floor [UNITS > 0]\n");
        return 2;
    }
    _Alignas(VM_ALIGN) double x[FLOOR_CHUNK], y[FLOOR_CHUNK];
    for (int i = 0; i < FLOOR_CHUNK; i++) {
        x[i] = -3.0 + 6.0 * i / FLOOR_CHUNK + (i % 8 == 0 ? 150.0 : 0.0);
        y[i] = -2.0 + 4.0 * i / FLOOR_CHUNK;
    }
    double sum = 0.0;
    long calls = 0;
    for (long u = 0; u < units; u++)
        for (int f = 0; f < F_N; f++)
            for (long c = 0; c < floor_calls[f]; c += FLOOR_CHUNK) {
                long left = floor_calls[f] - c;
                int n = left < FLOOR_CHUNK ? (int)vm_pad((size_t)left) : FLOOR_CHUNK;
                x[c / FLOOR_CHUNK % FLOOR_CHUNK] += 1e-9; /* a fresh argument each loop */
                sum += floor_chunk(f, n, x, y);
                calls += n;
            }
    printf("units\t%ld\tcalls_per_unit\t%ld\tchecksum\t%.6g\n", units, calls / units, sum);
    return 0;
}
