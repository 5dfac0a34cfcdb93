/* dss_lane.h - the DSS physics and its calibration model for one reading,
 * as inline functions: the scalar API (dss_optics.c, dss_centroid.c,
 * dss_sensor.c, dss_model.c) and the vectorised batches (dss_readings.c,
 * dss_batch.c: one reading per vector lane) are the same code.  The
 * formulas are documented in dss_sensor.h, dss_optics.h, dss_centroid.h,
 * dss_rotation.h and dss_model.h.  Everything is passed and returned by
 * value so that GCC vectorises a loop calling these (vmath.h). */
#ifndef SUNMC_DSS_LANE_H
#define SUNMC_DSS_LANE_H

#include "dss_model.h"
#include "dss_sensor.h"
#include "vmath.h"

/* Field angles are kept below this while inverting the glass formula (90
 * deg minus a margin), and the Newton iteration stops at this step. */
#define DSS_FIELD_THETA_MAX_RAD 1.5
#define DSS_FIELD_TOL_RAD 1e-13
#define DSS_FIELD_MAX_ITER 50

typedef struct {
    double x, y, z;
} dss_v3;

/* The rotary table's rotation R(b1, b2) = dss_zxy(b1, b2, 0) element by
 * element (dss_rotation.c with c3 = 0: cos 0 = 1, sin 0 = 0). */
typedef struct {
    double r00, r01, r02, r10, r11, r12, r20, r21, r22;
} dss_lane_table;

VM_INLINE dss_lane_table dss_lane_table_of(double b1, double b2)
{
    double cx = cos(b1), sx = sin(b1), cy = cos(b2), sy = sin(b2);
    dss_lane_table t = {cy, sy * sx, -sy * cx, 0.0, cx, sx, sy, -(cy * sx), cy * cx};
    return t;
}

VM_INLINE dss_v3 dss_lane_table_mul(dss_lane_table t, dss_v3 v)
{
    dss_v3 w = {t.r00 * v.x + t.r01 * v.y + t.r02 * v.z, t.r10 * v.x + t.r11 * v.y + t.r12 * v.z,
                t.r20 * v.x + t.r21 * v.y + t.r22 * v.z};
    return w;
}

/* m v and m^T v for a matrix shared by every lane. */
VM_INLINE dss_v3 dss_lane_mul(const mat3 m, dss_v3 v)
{
    dss_v3 w = {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    return w;
}

VM_INLINE dss_v3 dss_lane_mul_t(const mat3 m, dss_v3 v)
{
    dss_v3 w = {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
                m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
                m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
    return w;
}

VM_INLINE dss_v3 dss_lane_v3_of(const double v[3])
{
    dss_v3 w = {v[0], v[1], v[2]};
    return w;
}

/* ---- the physical sensor ---- */

/* The sun in the sensor frame at true table angles: u = M R(b) v0. */
VM_INLINE dss_v3 dss_lane_sun(const dss_sensor *s, double b1, double b2)
{
    return dss_lane_mul(s->M, dss_lane_table_mul(dss_lane_table_of(b1, b2),
                                                 dss_lane_v3_of(s->v0)));
}

/* Refraction of direction d at the surface z = const with normal +z from
 * index n1 to n2 (vector Snell's law, dss_optics.c). */
VM_INLINE dss_v3 dss_lane_refract_up(dss_v3 d, double n1, double n2)
{
    double eta = n1 / n2;
    double cos_i = -d.z;
    double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    double k = eta * cos_i - sqrt(1.0 - sin2_t);
    dss_v3 o = {eta * d.x, eta * d.y, eta * d.z + k};
    return o;
}

/* Point p moved along d to the plane z = z_to. */
VM_INLINE dss_v3 dss_lane_travel(dss_v3 p, dss_v3 d, double z_to)
{
    double s = (z_to - p.z) / d.z;
    dss_v3 o = {p.x + s * d.x, p.y + s * d.y, z_to};
    return o;
}

/* The spot (mm) of the ray through the pinhole along -u through the glass
 * (gap, thickness t, index n) on the detector z = 0 (dss_optics_trace; the
 * caller checks u_z > 0 and the glass's fit). */
typedef struct {
    double x, y;
} dss_lane_xy;

VM_INLINE dss_lane_xy dss_lane_trace(dss_v3 u, const double pinhole_mm[3], double gap_mm,
                                     double t_mm, double n)
{
    dss_v3 d = {-u.x, -u.y, -u.z};
    dss_v3 p = dss_lane_v3_of(pinhole_mm);
    p = dss_lane_travel(p, d, gap_mm + t_mm);
    dss_v3 dg = dss_lane_refract_up(d, 1.0, n);
    p = dss_lane_travel(p, dg, gap_mm);
    dss_v3 da = dss_lane_refract_up(dg, n, 1.0);
    p = dss_lane_travel(p, da, 0.0);
    dss_lane_xy o = {p.x, p.y};
    return o;
}

/* S-curve biases (px) of a spot at (x_px, y_px) from a pixel centre: sin(2
 * pi k x) by the recurrence s_{k+1} = 2 cos(w) s_k - s_{k-1}
 * (dss_centroid.h), both axes in one loop, unrolled (GCC vectorises a
 * loop over lanes only if its body has no loop). */
VM_INLINE dss_lane_xy dss_lane_scurve(const double amp_px[DSS_SCURVE_HARMONICS], double x_px,
                                      double y_px)
{
    double wx = 2.0 * M_PI * x_px, cx2 = 2.0 * cos(wx);
    double wy = 2.0 * M_PI * y_px, cy2 = 2.0 * cos(wy);
    double sx_prev = 0.0, sx = sin(wx), bx = 0.0;
    double sy_prev = 0.0, sy = sin(wy), by = 0.0;
#pragma GCC unroll 64
    for (int k = 1; k <= DSS_SCURVE_HARMONICS; k++) {
        bx += amp_px[k - 1] * sx;
        by += amp_px[k - 1] * sy;
        double sx_next = cx2 * sx - sx_prev, sy_next = cy2 * sy - sy_prev;
        sx_prev = sx;
        sx = sx_next;
        sy_prev = sy;
        sy = sy_next;
    }
    dss_lane_xy b = {bx, by};
    return b;
}

/* The plane-parallel glass may sit anywhere under the pinhole (dss_optics.h);
 * it is traced lying on the detector. */
#define DSS_GLASS_GAP_MM 0.0

/* The noiseless measured spot (px) for sun direction u, and whether it is
 * seen (the sun in front, the spot's disc wholly on the detector). */
typedef struct {
    double x, y;
    int ok;
} dss_lane_spot;

VM_INLINE dss_lane_spot dss_lane_sensor_spot(const dss_sensor *s, dss_v3 u)
{
    double H = s->pinhole_mm[2], t = s->glass_t_mm;
    int fits = t >= 0.0 && DSS_GLASS_GAP_MM + t <= H;
    dss_lane_xy sp = dss_lane_trace(u, s->pinhole_mm, DSS_GLASS_GAP_MM, t, s->glass_n);
    double lim = s->half_side_mm - 0.5 * s->spot_px * s->pixel_mm;
    dss_lane_spot o;
    o.ok = (u.z > 0.0) & fits & (fabs(sp.x) <= lim) & (fabs(sp.y) <= lim);
    o.x = sp.x / s->pixel_mm;
    o.y = sp.y / s->pixel_mm;
    dss_lane_xy b =
        dss_lane_scurve(s->scurve_amp_px, o.x - s->pixel_phase_px, o.y - s->pixel_phase_px);
    o.x += vm_keep(s->s_curve, b.x);
    o.y += vm_keep(s->s_curve, b.y);
    return o;
}

/* The truth angles of a table at (b1, b2) under the sun simulator v
 * (dss_truth_angles): the angles of R(b) v when mounted, eq. 3-4 when
 * aligned. */
VM_INLINE double dss_lane_truth_beta(double b1, double b2);

typedef struct {
    double alpha, beta;
} dss_lane_ab;

VM_INLINE dss_lane_ab dss_lane_truth(int mount, dss_v3 v, double b1, double b2)
{
    dss_v3 w = dss_lane_table_mul(dss_lane_table_of(b1, b2), v);
    int mounted = mount != DSS_MOUNT_ALIGNED;
    dss_lane_ab o = {vm_select(mounted, atan2(w.x, w.z), -b2),
                     vm_select(mounted, atan2(w.y, w.z), dss_lane_truth_beta(b1, b2))};
    return o;
}

/* The table's truth angles of eq. 3-4 (dss_table_truth). */
VM_INLINE double dss_lane_truth_beta(double b1, double b2)
{
    return atan(tan(b1) / cos(b2));
}

/* ---- the calibration model ---- */

/* q of the closed form spot = (x0, y0) - (ux, uy) q and its partial
 * derivatives by ux, uy, uz (taken as independent), H, t and n
 * (dss_optics.h); u_z > 0 and n > |u_xy| assumed. */
typedef struct {
    double q, ux, uy, uz, H, t, n;
} dss_lane_q;

VM_INLINE dss_lane_q dss_lane_optics_q(dss_v3 u, double H_mm, double t_mm, double n)
{
    double s2 = u.x * u.x + u.y * u.y;
    double g2 = n * n - s2;
    double g = sqrt(g2);
    double g3 = g2 * g;
    dss_lane_q o;
    o.q = (H_mm - t_mm) / u.z + t_mm / g;
    o.ux = t_mm * u.x / g3;
    o.uy = t_mm * u.y / g3;
    o.uz = -(H_mm - t_mm) / (u.z * u.z);
    o.H = 1.0 / u.z;
    o.t = -1.0 / u.z + 1.0 / g;
    o.n = -t_mm * n / g3;
    return o;
}

/* The model's spot (px) at table rotation R and its derivatives by the
 * parameters (dss_model_spot).  ok = 0 where the sun is behind the sensor
 * or totally reflected. */
typedef struct {
    double x0, y0, H, t, c1, c2, c3, n, s1, s2;
} dss_lane_par;

typedef struct {
    double x, y;
    int ok;
    dss_lane_par jx, jy;
} dss_lane_model;

/* d spot / d c_k from du/dc_k = dM_k R v0 + M R dv0_k and d spot / d u. */
VM_INLINE double dss_lane_dc(const dss_model *m, int k, dss_lane_table R, dss_v3 w, dss_v3 dsdu)
{
    dss_v3 t1 = dss_lane_mul(m->dM[k], w);
    dss_v3 t3 = dss_lane_mul(m->M, dss_lane_table_mul(R, dss_lane_v3_of(m->dv0[k])));
    return dsdu.x * (t1.x + t3.x) + dsdu.y * (t1.y + t3.y) + dsdu.z * (t1.z + t3.z);
}

/* d spot / d s_k (the sun simulator's angles, k = 3, 4 of dv0) from
 * du/ds_k = M R dv0_k (0 when the lab is aligned: dv0_k = 0). */
VM_INLINE double dss_lane_ds(const dss_model *m, int k, dss_lane_table R, dss_v3 dsdu)
{
    dss_v3 t3 = dss_lane_mul(m->M, dss_lane_table_mul(R, dss_lane_v3_of(m->dv0[k])));
    return dsdu.x * t3.x + dsdu.y * t3.y + dsdu.z * t3.z;
}

VM_INLINE dss_lane_model dss_lane_model_spot(const dss_model *m, dss_lane_table R, int want_j)
{
    dss_v3 w = dss_lane_table_mul(R, dss_lane_v3_of(m->v0));
    dss_v3 u = dss_lane_mul(m->M, w);
    double H = m->p[DSS_P_H], t = m->p[DSS_P_T], n = m->p[DSS_P_N];
    dss_lane_model e;
    e.ok = (u.z > 0.0) & (n * n > u.x * u.x + u.y * u.y);
    dss_lane_q g = dss_lane_optics_q(u, H, t, n);
    double q = g.q;
    double inv_pix = 1.0 / m->pixel_mm;
    e.x = (m->p[DSS_P_X0] - u.x * q) * inv_pix;
    e.y = (m->p[DSS_P_Y0] - u.y * q) * inv_pix;
    if (!want_j)
        return e;
    double gx = g.ux, gy = g.uy, gz = g.uz, gH = g.H, gt = g.t, gn = g.n;
    e.jx.x0 = inv_pix;
    e.jx.y0 = 0.0;
    e.jy.x0 = 0.0;
    e.jy.y0 = inv_pix;
    e.jx.H = -u.x * gH * inv_pix;
    e.jy.H = -u.y * gH * inv_pix;
    e.jx.t = -u.x * gt * inv_pix;
    e.jy.t = -u.y * gt * inv_pix;
    e.jx.n = -u.x * gn * inv_pix;
    e.jy.n = -u.y * gn * inv_pix;
    /* d spot_a / d u_j = -(delta_aj q + u_a dq/du_j) */
    dss_v3 dx = {-(q + u.x * gx) * inv_pix, -(0.0 + u.x * gy) * inv_pix,
                 -(0.0 + u.x * gz) * inv_pix};
    dss_v3 dy = {-(0.0 + u.y * gx) * inv_pix, -(q + u.y * gy) * inv_pix,
                 -(0.0 + u.y * gz) * inv_pix};
    e.jx.c1 = dss_lane_dc(m, 0, R, w, dx);
    e.jy.c1 = dss_lane_dc(m, 0, R, w, dy);
    e.jx.c2 = dss_lane_dc(m, 1, R, w, dx);
    e.jy.c2 = dss_lane_dc(m, 1, R, w, dy);
    e.jx.c3 = dss_lane_dc(m, 2, R, w, dx);
    e.jy.c3 = dss_lane_dc(m, 2, R, w, dy);
    e.jx.s1 = dss_lane_ds(m, 3, R, dx);
    e.jy.s1 = dss_lane_ds(m, 3, R, dy);
    e.jx.s2 = dss_lane_ds(m, 4, R, dx);
    e.jy.s2 = dss_lane_ds(m, 4, R, dy);
    return e;
}

/* One Newton step of the field angle th of a spot at radial distance r_mm:
 * the inverse of r = (H - t) tan(theta) + t tan(theta_g) (dss_optics.c),
 * clamped to [0, DSS_FIELD_THETA_MAX_RAD]; *step receives the step. */
VM_INLINE double dss_lane_field_step(double r_mm, double H_mm, double t_mm, double n, double th,
                                     double *step)
{
    double s = sin(th), c = cos(th);
    double g2 = n * n - s * s, g = sqrt(g2);
    double f = (H_mm - t_mm) * s / c + t_mm * s / g - r_mm;
    double df = (H_mm - t_mm) / (c * c) + t_mm * c * n * n / (g2 * g);
    *step = f / df;
    th -= *step;
    th = vm_select(th < 0.0, 0.0, th);
    return vm_select(th > DSS_FIELD_THETA_MAX_RAD, DSS_FIELD_THETA_MAX_RAD, th);
}

/* The start of that iteration: the pinhole-only angle with the glass's
 * paraxial height. */
VM_INLINE double dss_lane_field_start(double r_mm, double H_mm, double t_mm, double n)
{
    return atan(r_mm / (H_mm - t_mm + t_mm / n));
}

/* The calibrated angles of a spot whose field angle th and azimuth
 * (dx, dy) / r from the pinhole's foot are known: u taken back through
 * M, w = M^T u.  As mounted: w's angles (the sun in the mount's frame).
 * Aligned: the table solved for R(b) v0 = w (dss_table_solve), the truth
 * angles of that b (eq. 3-4).  ok = 0 where no table angle gives it. */
typedef struct {
    double alpha, beta;
    int ok;
} dss_lane_angles;

VM_INLINE dss_lane_angles dss_lane_model_angles(const dss_model *m, double dx, double dy,
                                                double r, double th, double v_phi)
{
    double s = sin(th);
    int off = r > 0.0;
    double rr = vm_select(off, r, 1.0);
    dss_v3 u = {vm_keep(off, dx / rr * s), vm_keep(off, dy / rr * s), vm_select(off, cos(th), 1.0)};
    dss_v3 w = dss_lane_mul_t(m->M, u);
    /* Rx(b1) v = Ry(-b2) w; Rx keeps the x component */
    double rho = hypot(w.x, w.z);
    dss_lane_angles o;
    o.ok = rho > fabs(m->v0[0]);
    double phi = atan2(w.x, w.z);
    double b2 = asin(m->v0[0] / vm_select(o.ok, rho, 1.0)) - phi;
    double c = cos(-b2), sn = sin(-b2);
    double q1 = 0.0 * w.x + 1.0 * w.y + 0.0 * w.z;
    double q2 = sn * w.x + 0.0 * w.y + c * w.z;
    double b1 = atan2(q1, q2) - v_phi;
    int mounted = m->mount != DSS_MOUNT_ALIGNED;
    o.ok = (mounted & (w.z > 0.0)) | ((!mounted) & o.ok);
    o.alpha = vm_select(mounted, atan2(w.x, w.z), -b2);
    o.beta = vm_select(mounted, atan2(w.y, w.z), dss_lane_truth_beta(b1, b2));
    return o;
}

/* The angle (rad) between the directions of angles (a, b) and of the unit
 * vector v: dss_vector_of and dss_angle_between. */
VM_INLINE dss_v3 dss_lane_vector_of(double tan_a, double tan_b)
{
    double n = sqrt(1.0 + tan_a * tan_a + tan_b * tan_b);
    dss_v3 u = {tan_a / n, tan_b / n, 1.0 / n};
    return u;
}

VM_INLINE double dss_lane_angle_between(dss_v3 u, dss_v3 v)
{
    double cx = u.y * v.z - u.z * v.y;
    double cy = u.z * v.x - u.x * v.z;
    double cz = u.x * v.y - u.y * v.x;
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), u.x * v.x + u.y * v.y + u.z * v.z);
}

#endif
