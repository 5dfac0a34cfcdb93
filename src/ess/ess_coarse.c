/* ess_coarse.c - the Gray-coded coarse rows and the coarse/fine combination.
 *
 * Cells are coarse_resolution wide, numbered k = 0 .. 2^n - 1 from
 * -2^(n-1) res upward; the cell boundaries are etched at eta = H tan(angle)
 * like every row.  Row j carries bit (n-1-j) of gray(k) = k ^ (k >> 1) and
 * reads it at its own position, so near a boundary rows may disagree: the
 * Gray code then decodes to one of the two neighbouring cells, never further.
 */
#include "ess_lane.h"

/* The arithmetic is inline in ess_lane.h, shared with the vectorised
 * batch (ess_sensor_output_chunk). */
VM_NOSAN double ess_coarse_read(const ess_sensor *s, const double psi_rad[])
{
    ess_lane_coarse acc = {0.0, 0.0};
    for (int j = 0; j < s->n_coarse; j++)
        acc = ess_lane_coarse_row(s, ess_lane_row_bit(s, j), psi_rad[j], acc);
    return ess_lane_coarse_angle(s, acc);
}

VM_NOSAN double ess_combine(double coarse_rad, double fine_phase, double theta0_rad)
{
    return ess_lane_combine(coarse_rad, fine_phase, theta0_rad);
}
