/* dss_optics.c - pinhole and cover-glass ray trace (see dss_optics.h). */
#include "dss_optics.h"
#include "status.h"

#include <math.h>

#define NEWTON_MAX_ITER 50
#define NEWTON_TOL_RAD 1e-13
/* Field angles are kept below this while iterating (90 deg minus a margin). */
#define THETA_MAX_RAD 1.5

/* Refract unit direction d at a surface with unit normal nrm (pointing back
 * against d) going from index n1 to n2 (vector Snell's law). */
static void refract(const double d[3], const double nrm[3], double n1, double n2, double out[3])
{
    double eta = n1 / n2;
    double cos_i = -(d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2]);
    double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    double k = eta * cos_i - sqrt(1.0 - sin2_t);
    for (int i = 0; i < 3; i++)
        out[i] = eta * d[i] + k * nrm[i];
}

/* Move point p along direction d to the plane z = z_to. */
static void travel(double p[3], const double d[3], double z_to)
{
    double s = (z_to - p[2]) / d[2];
    p[0] += s * d[0];
    p[1] += s * d[1];
    p[2] = z_to;
}

int dss_optics_trace(const double u[3], const double pinhole_mm[3], double gap_mm, double t_mm,
                     double n, double spot_mm[2])
{
    if (!(u[2] > 0.0) || gap_mm < 0.0 || t_mm < 0.0 || gap_mm + t_mm > pinhole_mm[2])
        return SUNMC_EDOM;
    const double up[3] = {0.0, 0.0, 1.0};
    double d[3] = {-u[0], -u[1], -u[2]}, dg[3], da[3];
    double p[3] = {pinhole_mm[0], pinhole_mm[1], pinhole_mm[2]};
    travel(p, d, gap_mm + t_mm);
    refract(d, up, 1.0, n, dg);
    travel(p, dg, gap_mm);
    refract(dg, up, n, 1.0, da);
    travel(p, da, 0.0);
    spot_mm[0] = p[0];
    spot_mm[1] = p[1];
    return SUNMC_OK;
}

double dss_optics_q(const double u[3], double H_mm, double t_mm, double n,
                    double grad[DSS_OPTICS_NGRAD])
{
    double s2 = u[0] * u[0] + u[1] * u[1];
    double g2 = n * n - s2;
    double g = sqrt(g2);
    double q = (H_mm - t_mm) / u[2] + t_mm / g;
    if (grad) {
        double g3 = g2 * g;
        grad[0] = t_mm * u[0] / g3;
        grad[1] = t_mm * u[1] / g3;
        grad[2] = -(H_mm - t_mm) / (u[2] * u[2]);
        grad[3] = 1.0 / u[2];
        grad[4] = -1.0 / u[2] + 1.0 / g;
        grad[5] = -t_mm * n / g3;
    }
    return q;
}

int dss_optics_field_angle(double r_mm, double H_mm, double t_mm, double n, double *theta)
{
    /* Start from the pinhole-only angle with the glass's paraxial height. */
    double th = atan(r_mm / (H_mm - t_mm + t_mm / n));
    for (int it = 0; it < NEWTON_MAX_ITER; it++) {
        double s = sin(th), c = cos(th);
        double g2 = n * n - s * s, g = sqrt(g2);
        double f = (H_mm - t_mm) * s / c + t_mm * s / g - r_mm;
        double df = (H_mm - t_mm) / (c * c) + t_mm * c * n * n / (g2 * g);
        double step = f / df;
        th -= step;
        if (th < 0.0)
            th = 0.0;
        if (th > THETA_MAX_RAD)
            th = THETA_MAX_RAD;
        if (fabs(step) < NEWTON_TOL_RAD) {
            *theta = th;
            return SUNMC_OK;
        }
    }
    return SUNMC_EDOM;
}
