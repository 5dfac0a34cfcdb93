/* ess_coarse.c - the Gray-coded coarse rows and the coarse/fine combination.
 *
 * Cells are coarse_resolution wide, numbered k = 0 .. 2^n - 1 from
 * -2^(n-1) res upward; the cell boundaries are etched at eta = H tan(angle)
 * like every row.  Row j carries bit (n-1-j) of gray(k) = k ^ (k >> 1) and
 * reads it at its own position, so near a boundary rows may disagree: the
 * Gray code then decodes to one of the two neighbouring cells, never further.
 */
#include "ess_sensor.h"

#include <math.h>

double ess_coarse_read(const ess_sensor *s, const double psi_rad[])
{
    int n = s->n_coarse;
    long ncell = 1L << n;
    double origin = -(double)(ncell / 2) * s->coarse_res_rad;
    unsigned long gray = 0;
    for (int j = 0; j < n; j++) {
        long k = (long)floor((psi_rad[j] - origin) / s->coarse_res_rad);
        if (k < 0)
            k = 0;
        if (k >= ncell)
            k = ncell - 1;
        unsigned long g = (unsigned long)k ^ ((unsigned long)k >> 1);
        int bit = n - 1 - j;
        gray |= g & (1UL << bit);
    }
    unsigned long k = gray;
    for (unsigned long shift = gray >> 1; shift; shift >>= 1)
        k ^= shift;
    return origin + ((double)k + 0.5) * s->coarse_res_rad;
}

double ess_combine(double coarse_rad, double fine_phase, double theta0_rad)
{
    double fine = fine_phase / (2.0 * M_PI) * theta0_rad;
    return fine + theta0_rad * round((coarse_rad - fine) / theta0_rad);
}
