/* optics.c - pinhole and cover-glass ray trace (see optics.h); the
 * formulas are optics_lane.h's, shared with the vectorised batches. */
#include "optics.h"
#include "optics_lane.h"
#include "status.h"

#include <math.h>

VM_NOSAN int optics_trace(const double u[3], const double pinhole_mm[3], double gap_mm,
                              double t_mm, double n, double spot_mm[2])
{
    if (!(u[2] > 0.0) || gap_mm < 0.0 || t_mm < 0.0 || gap_mm + t_mm > pinhole_mm[2])
        return SUNMC_EDOM;
    geo_xy sp = optics_lane_trace(geo_v3_of(u), pinhole_mm, gap_mm, t_mm, n);
    spot_mm[0] = sp.x;
    spot_mm[1] = sp.y;
    return SUNMC_OK;
}

VM_NOSAN double optics_q(const double u[3], double H_mm, double t_mm, double n,
                             double grad[OPTICS_NGRAD])
{
    optics_lane_qd g = optics_lane_q(geo_v3_of(u), H_mm, t_mm, n);
    if (grad) {
        grad[0] = g.ux;
        grad[1] = g.uy;
        grad[2] = g.uz;
        grad[3] = g.H;
        grad[4] = g.t;
        grad[5] = g.n;
    }
    return g.q;
}

VM_NOSAN int optics_field_angle(double r_mm, double H_mm, double t_mm, double n,
                                    double *theta)
{
    double th = optics_lane_field_start(r_mm, H_mm, t_mm, n);
    for (int it = 0; it < OPTICS_FIELD_MAX_ITER; it++) {
        double step;
        th = optics_lane_field_step(r_mm, H_mm, t_mm, n, th, &step);
        if (fabs(step) < OPTICS_FIELD_TOL_RAD) {
            *theta = th;
            return SUNMC_OK;
        }
    }
    return SUNMC_EDOM;
}
