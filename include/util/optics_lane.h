/* optics_lane.h - the geometry every family shares, as inline functions
 * passed and returned by value so that GCC vectorises a loop calling them
 * (vmath.h): vectors, the two-axis table's rotation (rotation.h), a pinhole
 * over a detector with a plane-parallel cover glass (optics.h: the ray
 * trace, the closed form q and its inverse, the field angle).  The scalar
 * API (optics.c, rotation.c) and the families' vectorised batches are the
 * same code. */
#ifndef SUNMC_OPTICS_LANE_H
#define SUNMC_OPTICS_LANE_H

#include "rotation.h"
#include "vmath.h"

#include <math.h>

/* Field angles are kept below this while inverting the glass formula (90
 * deg minus a margin), and the Newton iteration stops at this step. */
#define OPTICS_FIELD_THETA_MAX_RAD 1.5
#define OPTICS_FIELD_TOL_RAD 1e-13
#define OPTICS_FIELD_MAX_ITER 50

typedef struct {
    double x, y, z;
} geo_v3;

/* The rotary table's rotation R(b1, b2) = rot_zxy(b1, b2, 0) element by
 * element (rotation.c with c3 = 0: cos 0 = 1, sin 0 = 0). */
typedef struct {
    double r00, r01, r02, r10, r11, r12, r20, r21, r22;
} geo_table;

VM_INLINE geo_table geo_table_trig(double cx, double sx, double cy, double sy)
{
    geo_table t = {cy, sy * sx, -sy * cx, 0.0, cx, sx, sy, -(cy * sx), cy * cx};
    return t;
}

/* The same from the angles; geo_table_trig of their cosines and sines
 * (cx = cos b1, sx = sin b1, cy = cos b2, sy = sin b2) where a table of
 * them is kept. */
VM_INLINE geo_table geo_table_of(double b1, double b2)
{
    return geo_table_trig(cos(b1), sin(b1), cos(b2), sin(b2));
}

VM_INLINE geo_v3 geo_table_mul(geo_table t, geo_v3 v)
{
    geo_v3 w = {t.r00 * v.x + t.r01 * v.y + t.r02 * v.z, t.r10 * v.x + t.r11 * v.y + t.r12 * v.z,
                t.r20 * v.x + t.r21 * v.y + t.r22 * v.z};
    return w;
}

/* m v and m^T v for a matrix shared by every lane. */
VM_INLINE geo_v3 geo_mul(const mat3 m, geo_v3 v)
{
    geo_v3 w = {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    return w;
}

VM_INLINE geo_v3 geo_mul_t(const mat3 m, geo_v3 v)
{
    geo_v3 w = {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
                m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
                m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
    return w;
}

VM_INLINE geo_v3 geo_v3_of(const double v[3])
{
    geo_v3 w = {v[0], v[1], v[2]};
    return w;
}

/* Refraction of direction d at the surface z = const with normal +z from
 * index n1 to n2 (vector Snell's law, optics.c). */
VM_INLINE geo_v3 geo_refract_up(geo_v3 d, double n1, double n2)
{
    double eta = n1 / n2;
    double cos_i = -d.z;
    double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    double k = eta * cos_i - sqrt(1.0 - sin2_t);
    geo_v3 o = {eta * d.x, eta * d.y, eta * d.z + k};
    return o;
}

/* Point p moved along d to the plane z = z_to. */
VM_INLINE geo_v3 geo_travel(geo_v3 p, geo_v3 d, double z_to)
{
    double s = (z_to - p.z) / d.z;
    geo_v3 o = {p.x + s * d.x, p.y + s * d.y, z_to};
    return o;
}

/* The spot (mm) of the ray through the pinhole along -u through the glass
 * (gap, thickness t, index n) on the detector z = 0 (optics_trace; the
 * caller checks u_z > 0 and the glass's fit). */
typedef struct {
    double x, y;
} geo_xy;

VM_INLINE geo_xy optics_lane_trace(geo_v3 u, const double pinhole_mm[3], double gap_mm,
                                     double t_mm, double n)
{
    geo_v3 d = {-u.x, -u.y, -u.z};
    geo_v3 p = geo_v3_of(pinhole_mm);
    p = geo_travel(p, d, gap_mm + t_mm);
    geo_v3 dg = geo_refract_up(d, 1.0, n);
    p = geo_travel(p, dg, gap_mm);
    geo_v3 da = geo_refract_up(dg, n, 1.0);
    p = geo_travel(p, da, 0.0);
    geo_xy o = {p.x, p.y};
    return o;
}

/* q of the closed form spot = (x0, y0) - (ux, uy) q and its partial
 * derivatives by ux, uy, uz (taken as independent), H, t and n
 * (optics.h); u_z > 0 and n > |u_xy| assumed. */
typedef struct {
    double q, ux, uy, uz, H, t, n;
} optics_lane_qd;

VM_INLINE optics_lane_qd optics_lane_q(geo_v3 u, double H_mm, double t_mm, double n)
{
    double s2 = u.x * u.x + u.y * u.y;
    double g2 = n * n - s2;
    double g = sqrt(g2);
    double g3 = g2 * g;
    optics_lane_qd o;
    o.q = (H_mm - t_mm) / u.z + t_mm / g;
    o.ux = t_mm * u.x / g3;
    o.uy = t_mm * u.y / g3;
    o.uz = -(H_mm - t_mm) / (u.z * u.z);
    o.H = 1.0 / u.z;
    o.t = -1.0 / u.z + 1.0 / g;
    o.n = -t_mm * n / g3;
    return o;
}

/* One Newton step of the field angle th of a spot at radial distance r_mm:
 * the inverse of r = (H - t) tan(theta) + t tan(theta_g) (optics.c),
 * clamped to [0, OPTICS_FIELD_THETA_MAX_RAD]; *step receives the step. */
VM_INLINE double optics_lane_field_step(double r_mm, double H_mm, double t_mm, double n, double th,
                                     double *step)
{
    double s = sin(th), c = cos(th);
    double g2 = n * n - s * s, g = sqrt(g2);
    double f = (H_mm - t_mm) * s / c + t_mm * s / g - r_mm;
    double df = (H_mm - t_mm) / (c * c) + t_mm * c * n * n / (g2 * g);
    *step = f / df;
    th -= *step;
    th = vm_select(th < 0.0, 0.0, th);
    return vm_select(th > OPTICS_FIELD_THETA_MAX_RAD, OPTICS_FIELD_THETA_MAX_RAD, th);
}

/* The start of that iteration: the pinhole-only angle with the glass's
 * paraxial height. */
VM_INLINE double optics_lane_field_start(double r_mm, double H_mm, double t_mm, double n)
{
    return atan(r_mm / (H_mm - t_mm + t_mm / n));
}

#endif
