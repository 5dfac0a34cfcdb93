/* optics.h - where the sun spot falls: a pinhole over a detector with a
 * plane-parallel cover glass between them, traced with Snell's law.
 *
 * Frame: the sensor frame (DSS: b of dss_sensor.h); the detector is the plane z = 0,
 * lengths in mm.  The pinhole is at (x0, y0, H); the glass of thickness t
 * and index n fills gap <= z <= gap + t (gap + t <= H).  u is the unit vector
 * toward the sun (u[2] > 0); light travels along -u.
 *
 * Closed form.  In air the ray crosses tan(theta) = s/uz of lateral distance
 * per unit height (s = |u_xy| = sin theta); inside the glass sin(theta_g) =
 * s/n, so tan(theta_g) = s / sqrt(n^2 - s^2).  The spot is therefore
 *     spot = (x0, y0) - (ux, uy) q,   q = (H - t)/uz + t / sqrt(n^2 - s^2),
 * independent of the gap: a plane-parallel plate shifts the ray by the same
 * amount wherever it sits between pinhole and detector (so there is no gap
 * key).  optics_trace does the ray trace with the vector form of Snell's
 * law; the calibration model uses optics_q; a test checks they agree.
 */
#ifndef SUNMC_OPTICS_H
#define SUNMC_OPTICS_H

#include <stddef.h>

/* Trace the ray through pinhole_mm[3] = (x0, y0, H) along -u through the
 * glass (gap_mm, t_mm, index n) to the detector: spot_mm[2].  SUNMC_EDOM when
 * the sun is at or below the horizon, or the glass does not fit under the
 * pinhole. */
int optics_trace(const double u[3], const double pinhole_mm[3], double gap_mm, double t_mm,
                     double n, double spot_mm[2]);

/* q of the closed form (mm per unit of u_xy) and, if grad != NULL, its
 * partial derivatives: grad[0..2] by (ux, uy, uz) taken as independent,
 * grad[3] by H, grad[4] by t, grad[5] by n.  u[2] > 0 and n > s assumed. */
#define OPTICS_NGRAD 6
double optics_q(const double u[3], double H_mm, double t_mm, double n,
                    double grad[OPTICS_NGRAD]);

/* Field angle theta (rad) of a spot at radial distance r_mm from the pinhole's
 * foot: the inverse of r = (H - t) tan(theta) + t tan(theta_g), by Newton's
 * method (r is monotonic in theta).  SUNMC_EDOM if it does not converge. */
int optics_field_angle(double r_mm, double H_mm, double t_mm, double n, double *theta);

#endif
