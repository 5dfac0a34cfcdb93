/* ess_slit.c - where the slit image crosses a code row (see ess_sensor.h).
 *
 * x is measured from the slit's tilt pivot (design.tilt_pivot_mm; the
 * sensor stores each row's x so).  The slit is the line
 * p(l) = (l cos dphi, dd + l sin dphi, H + dH).  A ray
 * through p travelling along -s meets the dial (z = 0) at
 * (l cos dphi - Hr u, dd + l sin dphi - Hr v), u = s_x/s_z, v = s_y/s_z.
 * At the row x = x_r: l cos dphi = x_r + Hr u, and the dial coordinate,
 * counted so that the nominal reading is +H tan(alpha), is
 *     eta = Hr v - dd - (x_r + Hr u) tan dphi.
 */
#include "ess_lane.h"

/* The formula is ess_lane_eta (ess_lane.h), shared with the batch. */
VM_NOSAN double ess_slit_eta_mm(const ess_sensor *s, double x_mm, double u, double v)
{
    return ess_lane_eta(s, x_mm, u, v);
}
