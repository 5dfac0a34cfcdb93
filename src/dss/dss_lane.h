/* dss_lane.h - the DSS physics and its calibration model for one reading,
 * as inline functions: the scalar API (optics.c, dss_centroid.c,
 * dss_sensor.c, dss_model.c) and the vectorised batches (dss_readings.c,
 * dss_model_batch.c: one reading per vector lane) are the same code.  The
 * formulas are documented in dss_sensor.h, optics.h, dss_centroid.h,
 * rotation.h and dss_model.h.  Everything is passed and returned by
 * value so that GCC vectorises a loop calling these (vmath.h). */
#ifndef SUNMC_DSS_LANE_H
#define SUNMC_DSS_LANE_H

#include "dss_model.h"
#include "dss_sensor.h"
#include "optics_lane.h"
#include "vmath.h"

/* ---- the physical sensor ---- */

/* The sun in the sensor frame at true table angles: u = M R(b) v_sun. */
VM_INLINE geo_v3 dss_lane_sun_at(const dss_sensor *s, geo_table R)
{
    return geo_mul(s->M, geo_table_mul(R, geo_v3_of(s->v_sun)));
}

VM_INLINE geo_v3 dss_lane_sun(const dss_sensor *s, double b1, double b2)
{
    return dss_lane_sun_at(s, geo_table_of(b1, b2));
}

/* S-curve biases (px) of a spot at (x_px, y_px) from a pixel centre: sin(2
 * pi k x) by the recurrence s_{k+1} = 2 cos(w) s_k - s_{k-1}
 * (dss_centroid.h), both axes in one loop, unrolled (GCC vectorises a
 * loop over lanes only if its body has no loop). */
VM_INLINE geo_xy dss_lane_scurve(const double amp_px[DSS_SCURVE_HARMONICS], double x_px,
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
    geo_xy b = {bx, by};
    return b;
}

/* The sun disc's gain 1 + dr / f on the spot's distance from the
 * pinhole's foot (dss_sensor.h, Sun disc) for a sun at s2 = sin^2 theta,
 * uz = cos theta, pinhole height H, glass t, n; c = dss_disc_coefficient.
 * With the factor s taken out of f and its derivatives:
 *   f / s = (H - t) / c + t / g,  g = sqrt(n^2 - s^2)   (= q, optics.h)
 *   dr / (c s) = 2 (H - t) / cz^3 + t ((1 - 2 n^2) / g^3 + 3 cz^2 n^2 / g^5). */
VM_INLINE double dss_lane_disc_gain(double c, double s2, double uz, double H, double t, double n)
{
    double g2 = n * n - s2, g = sqrt(g2), g3 = g2 * g;
    double q = (H - t) / uz + t / g;
    double d = 2.0 * (H - t) / (uz * uz * uz) +
               t * ((1.0 - 2.0 * n * n) / g3 + 3.0 * uz * uz * n * n / (g3 * g2));
    return 1.0 + c * d / q;
}

/* The field angle's inversion in its tangent T (one square root and two
 * divisions a step; no sine, cosine or arctangent): a spot at r from the
 * pinhole's foot has
 *   F(T) = gain f - r = T Q + C E P - r = 0,
 * with the glass formula f = T Q (optics.h) written in T, g = sqrt(n^2 +
 * (n^2 - 1) T^2) (= sqrt(n^2 - sin^2) / cos), A = H - t:
 *   Q = A + t / g,   f' = A + t n^2 / g^3,
 * and the sun disc's gain = 1 + C d / q (dss_lane_disc_gain, C =
 * dss_disc_coefficient, 0 for a point sun) as f gain = T Q + C E P with
 *   E = T (1 + T^2),   P = 2 A + t ((1 - 2 n^2) / g^3 + 3 n^2 / g^5)
 * (d / q = (1 + T^2) P / Q), g' = (n^2 - 1) T / g and so
 *   P' = -3 t (n^2 - 1) T ((1 - 2 n^2) / g^5 + 5 n^2 / g^7).
 * One Newton step from T: the next T (clamped to [0, T_max]), the step,
 * F' and done = the next iterate's error, |F''| step^2 / (2 F') (Newton's
 * bound with F'' at T; F'' is odd in T, so the bound is relative),
 * is below DSS_TAN_TOL / 2 of T -- trusted only for a step that stays
 * inside the clamp and is below DSS_TAN_STEP_MAX (1 + T), where F'' hardly
 * changes over it. */
#define DSS_TAN_TOL 1e-17
#define DSS_TAN_STEP_MAX 1e-4
typedef struct {
    double T, step, slope;
    int done;
} dss_lane_tan;

VM_INLINE dss_lane_tan dss_lane_tan_step(double r, double A, double t, double n, double C,
                                         double T_max, double T)
{
    double n2 = n * n, m2 = n2 - 1.0, T2 = T * T, a = 1.0 - 2.0 * n2;
    double ig = 1.0 / sqrt(n2 + m2 * T2), ig2 = ig * ig;
    double ig3 = ig2 * ig, ig5 = ig3 * ig2, ig7 = ig5 * ig2, ig9 = ig7 * ig2;
    double P = 2.0 * A + t * (a * ig3 + 3.0 * n2 * ig5);
    double Pt = -3.0 * t * m2 * (a * ig5 + 5.0 * n2 * ig7); /* P' / T */
    double P2 = Pt + 3.0 * t * m2 * m2 * T2 * (5.0 * a * ig7 + 35.0 * n2 * ig9);
    double E = T * (1.0 + T2), E1 = 1.0 + 3.0 * T2;
    double F = T * (A + t * ig) + C * E * P - r;
    double F1 = A + t * n2 * ig3 + C * (E1 * P + E * T * Pt);
    double F2 = -3.0 * t * n2 * m2 * T * ig5 + C * (6.0 * T * P + 2.0 * E1 * T * Pt + E * P2);
    dss_lane_tan o;
    o.slope = F1;
    o.step = F / F1;
    double next = T - o.step;
    int inside = (next >= 0.0) & (next <= T_max);
    o.done = inside & (fabs(o.step) <= DSS_TAN_STEP_MAX * (1.0 + T)) &
             (fabs(F2) * o.step * o.step <= DSS_TAN_TOL * F1 * T);
    next = vm_select(next < 0.0, 0.0, next);
    o.T = vm_select(next > T_max, T_max, next);
    return o;
}

/* The start: the pinhole-only angle with the glass's paraxial height,
 * clamped to T_max. */
VM_INLINE double dss_lane_tan_start(double r, double H, double t, double n, double T_max)
{
    double T = r / (H - t + t / n);
    return vm_select(T > T_max, T_max, T);
}

/* The plane-parallel glass may sit anywhere under the pinhole (optics.h);
 * it is traced lying on the detector. */
#define DSS_GLASS_GAP_MM 0.0

/* The noiseless measured spot (px) for sun direction u, and whether it is
 * seen (the sun in front, the spot's disc wholly on the detector). */
typedef struct {
    double x, y;
    int ok;
} dss_lane_spot;

/* The spot p0 (mm, on z = 0) carried along the sun's ray to the tilted
 * detector (dss_sensor.h, Detector tilt), in the detector's axes: q = D p0,
 * the ray's direction w = D u, the point q - w q_z / w_z. */
VM_INLINE geo_xy dss_lane_tilt(const mat3 D, geo_xy p0, geo_v3 w)
{
    double qx = D[0][0] * p0.x + D[0][1] * p0.y;
    double qy = D[1][0] * p0.x + D[1][1] * p0.y;
    double qz = D[2][0] * p0.x + D[2][1] * p0.y;
    double s = qz / w.z;
    geo_xy o = {qx - w.x * s, qy - w.y * s};
    return o;
}

VM_INLINE dss_lane_spot dss_lane_sensor_spot(const dss_sensor *s, geo_v3 u)
{
    double H = s->pinhole_mm[2], t = s->glass_t_mm;
    int fits = t >= 0.0 && DSS_GLASS_GAP_MM + t <= H;
    geo_xy sp = optics_lane_trace(u, s->pinhole_mm, DSS_GLASS_GAP_MM, t, s->glass_n);
    double lim = s->half_side_mm - 0.5 * s->spot_px * s->pixel_mm;
    double k = dss_lane_disc_gain(s->disc_c_rad2, u.x * u.x + u.y * u.y, u.z, H, t, s->glass_n);
    int disc = s->disc_c_rad2 != 0.0;
    sp.x = vm_select(disc, s->pinhole_mm[0] + k * (sp.x - s->pinhole_mm[0]), sp.x);
    sp.y = vm_select(disc, s->pinhole_mm[1] + k * (sp.y - s->pinhole_mm[1]), sp.y);
    geo_v3 w = geo_mul(s->D, u);
    sp = dss_lane_tilt(s->D, sp, w);
    dss_lane_spot o;
    /* the tube closes where T tan(theta) >= d */
    int open = s->tube_ratio * s->tube_ratio * (u.x * u.x + u.y * u.y) < u.z * u.z;
    o.ok = (u.z > 0.0) & (w.z > 0.0) & fits & open & (fabs(sp.x) <= lim) & (fabs(sp.y) <= lim);
    o.x = sp.x / s->pixel_mm;
    o.y = sp.y / s->pixel_mm;
    geo_xy b =
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

/* For a mount mode known outside the loop (so that only its own calls are
 * made): as mounted, the angles of w = R v; aligned, eq. 3-4. */
VM_INLINE dss_lane_ab dss_lane_truth_mounted(geo_table R, geo_v3 v)
{
    geo_v3 w = geo_table_mul(R, v);
    dss_lane_ab o = {atan2(w.x, w.z), atan2(w.y, w.z)};
    return o;
}

VM_INLINE dss_lane_ab dss_lane_truth_aligned(double b1, double b2)
{
    dss_lane_ab o = {-b2, dss_lane_truth_beta(b1, b2)};
    return o;
}

/* The table's truth angles of eq. 3-4 (table_truth). */
VM_INLINE double dss_lane_truth_beta(double b1, double b2)
{
    return atan(tan(b1) / cos(b2));
}

/* ---- the calibration model ---- */

/* The model's spot (px) at table rotation R and its derivatives by the
 * parameters (dss_model_spot).  ok = 0 where the sun is behind the sensor
 * or totally reflected. */
typedef struct {
    double x0, y0, H, t, c1, c2, c3, n, s1, s2, tx, ty;
} dss_lane_par;

typedef struct {
    double x, y;
    int ok;
    dss_lane_par jx, jy;
} dss_lane_model;

/* d spot / d c_k from du/dc_k = dM_k R v0 + M R dv0_k and d spot / d u. */
VM_INLINE double dss_lane_dc(const dss_model *m, int k, geo_table R, geo_v3 w, geo_v3 dsdu)
{
    geo_v3 t1 = geo_mul(m->dM[k], w);
    geo_v3 t3 = geo_mul(m->M, geo_table_mul(R, geo_v3_of(m->dv0[k])));
    return dsdu.x * (t1.x + t3.x) + dsdu.y * (t1.y + t3.y) + dsdu.z * (t1.z + t3.z);
}

/* d spot / d s_k (the sun simulator's angles, k = 3, 4 of dv0) from
 * du/ds_k = M R dv0_k (0 when the lab is aligned: dv0_k = 0). */
VM_INLINE double dss_lane_ds(const dss_model *m, int k, geo_table R, geo_v3 dsdu)
{
    geo_v3 t3 = geo_mul(m->M, geo_table_mul(R, geo_v3_of(m->dv0[k])));
    return dsdu.x * t3.x + dsdu.y * t3.y + dsdu.z * t3.z;
}

/* disc: 1 (the sun disc on), 0 (off: its gain is 1, not computed) or -1
 * (either: computed and selected). */
/* du / d p_k of a rotation parameter (k = 0-2: c1-c3, 3, 4: s1, s2):
 * dM_k w + M R dv0_k (the first term for c only). */
VM_INLINE geo_v3 dss_lane_du(const dss_model *m, int k, geo_table R, geo_v3 w)
{
    geo_v3 t3 = geo_mul(m->M, geo_table_mul(R, geo_v3_of(m->dv0[k])));
    if (k < 3) {
        geo_v3 t1 = geo_mul(m->dM[k], w);
        t3.x += t1.x;
        t3.y += t1.y;
        t3.z += t1.z;
    }
    return t3;
}

/* The tilted detector's spot of a parameter's derivative: the untilted
 * (jx, jy) px and du (0 for a parameter that does not turn the sun) taken
 * through s = q - wv r (dss_lane_tilt): ds_a = C_a . (dp0, 0) - r C_a . du
 * with C_aj = D_aj - wv_a D_2j / wv_z. */
VM_INLINE void dss_lane_tilt_j(const double C[2][3], double r, double inv_pix, geo_v3 du,
                               double *jx, double *jy)
{
    double x = *jx, y = *jy;
    *jx = C[0][0] * x + C[0][1] * y - r * (C[0][0] * du.x + C[0][1] * du.y + C[0][2] * du.z) * inv_pix;
    *jy = C[1][0] * x + C[1][1] * y - r * (C[1][0] * du.x + C[1][1] * du.y + C[1][2] * du.z) * inv_pix;
}

/* d s / d tilt_i (dD = dD_i): dq = dD p0, dwv = dD u,
 * ds_a = dq_a - wv_a dq_z / wv_z - r (dwv_a - wv_a dwv_z / wv_z). */
VM_INLINE geo_xy dss_lane_tilt_dtheta(const mat3 dD, geo_xy p0, geo_v3 u, geo_v3 wv, double r)
{
    double dq[3], dw[3];
    for (int a = 0; a < 3; a++) {
        dq[a] = dD[a][0] * p0.x + dD[a][1] * p0.y;
        dw[a] = dD[a][0] * u.x + dD[a][1] * u.y + dD[a][2] * u.z;
    }
    geo_xy o = {dq[0] - wv.x * dq[2] / wv.z - r * (dw[0] - wv.x * dw[2] / wv.z),
                dq[1] - wv.y * dq[2] / wv.z - r * (dw[1] - wv.y * dw[2] / wv.z)};
    return o;
}

/* The model's untilted spot p0 (mm) carried to its tilted detector, and
 * the Jacobian e's untilted columns through it (dss_lane_tilt_j). */
VM_INLINE void dss_lane_model_tilt(const dss_model *m, geo_table R, geo_v3 w, geo_v3 u,
                                   geo_xy p0, int want_j, dss_lane_model *e)
{
    double inv_pix = 1.0 / m->pixel_mm;
    geo_v3 wv = geo_mul(m->D, u);
    geo_xy sp = dss_lane_tilt(m->D, p0, wv);
    e->ok = e->ok & (wv.z > 0.0);
    e->x = sp.x * inv_pix;
    e->y = sp.y * inv_pix;
    if (!want_j)
        return;
    double r = (m->D[2][0] * p0.x + m->D[2][1] * p0.y) / wv.z;
    double C[2][3];
    for (int j = 0; j < 3; j++) {
        C[0][j] = m->D[0][j] - wv.x * m->D[2][j] / wv.z;
        C[1][j] = m->D[1][j] - wv.y * m->D[2][j] / wv.z;
    }
    geo_v3 z = {0.0, 0.0, 0.0};
    dss_lane_tilt_j(C, r, inv_pix, z, &e->jx.x0, &e->jy.x0);
    dss_lane_tilt_j(C, r, inv_pix, z, &e->jx.y0, &e->jy.y0);
    dss_lane_tilt_j(C, r, inv_pix, z, &e->jx.H, &e->jy.H);
    dss_lane_tilt_j(C, r, inv_pix, z, &e->jx.t, &e->jy.t);
    dss_lane_tilt_j(C, r, inv_pix, z, &e->jx.n, &e->jy.n);
    dss_lane_tilt_j(C, r, inv_pix, dss_lane_du(m, 0, R, w), &e->jx.c1, &e->jy.c1);
    dss_lane_tilt_j(C, r, inv_pix, dss_lane_du(m, 1, R, w), &e->jx.c2, &e->jy.c2);
    dss_lane_tilt_j(C, r, inv_pix, dss_lane_du(m, 2, R, w), &e->jx.c3, &e->jy.c3);
    dss_lane_tilt_j(C, r, inv_pix, dss_lane_du(m, 3, R, w), &e->jx.s1, &e->jy.s1);
    dss_lane_tilt_j(C, r, inv_pix, dss_lane_du(m, 4, R, w), &e->jx.s2, &e->jy.s2);
    geo_xy gx = dss_lane_tilt_dtheta(m->dD[0], p0, u, wv, r);
    geo_xy gy = dss_lane_tilt_dtheta(m->dD[1], p0, u, wv, r);
    e->jx.tx = gx.x * inv_pix;
    e->jy.tx = gx.y * inv_pix;
    e->jx.ty = gy.x * inv_pix;
    e->jy.ty = gy.y * inv_pix;
}

/* tilt: 1 (the model's detector tilt on: m->tilt) or 0 (off: not computed,
 * its Jacobian columns 0). */
VM_INLINE dss_lane_model dss_lane_model_spot_tilt(const dss_model *m, geo_table R, int want_j,
                                                  int disc, int tilt)
{
    geo_v3 w = geo_table_mul(R, geo_v3_of(m->v0));
    geo_v3 u = geo_mul(m->M, w);
    double H = m->p[DSS_P_H], t = m->p[DSS_P_T], n = m->p[DSS_P_N];
    dss_lane_model e;
    e.ok = (u.z > 0.0) & (n * n > u.x * u.x + u.y * u.y);
    optics_lane_qd g = optics_lane_q(u, H, t, n);
    /* the sun's disc scales the spot's distance from the pinhole's foot;
     * the Jacobian takes the gain as constant (its derivatives are ~1e-5 of
     * the terms kept) */
    double k = 1.0;
    if (disc) {
        k = dss_lane_disc_gain(m->disc_c_rad2, u.x * u.x + u.y * u.y, u.z, H, t, n);
        k = vm_select(m->disc_c_rad2 != 0.0, k, 1.0);
    }
    double q = g.q * k;
    double inv_pix = 1.0 / m->pixel_mm;
    geo_xy p0 = {m->p[DSS_P_X0] - u.x * q, m->p[DSS_P_Y0] - u.y * q};
    e.x = p0.x * inv_pix;
    e.y = p0.y * inv_pix;
    if (!want_j) {
        if (tilt)
            dss_lane_model_tilt(m, R, w, u, p0, 0, &e);
        return e;
    }
    double gx = k * g.ux, gy = k * g.uy, gz = k * g.uz, gH = k * g.H, gt = k * g.t, gn = k * g.n;
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
    geo_v3 dx = {-(q + u.x * gx) * inv_pix, -(0.0 + u.x * gy) * inv_pix,
                 -(0.0 + u.x * gz) * inv_pix};
    geo_v3 dy = {-(0.0 + u.y * gx) * inv_pix, -(q + u.y * gy) * inv_pix,
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
    e.jx.tx = 0.0;
    e.jy.tx = 0.0;
    e.jx.ty = 0.0;
    e.jy.ty = 0.0;
    if (tilt)
        dss_lane_model_tilt(m, R, w, u, p0, 1, &e);
    return e;
}

VM_INLINE dss_lane_model dss_lane_model_spot_as(const dss_model *m, geo_table R, int want_j,
                                                int disc)
{
    return dss_lane_model_spot_tilt(m, R, want_j, disc, 0);
}

VM_INLINE dss_lane_model dss_lane_model_spot(const dss_model *m, geo_table R, int want_j)
{
    return dss_lane_model_spot_tilt(m, R, want_j, -1, m->tilt);
}

/* The calibrated angles of a spot whose field angle th and azimuth
 * (dx, dy) / r from the pinhole's foot are known: u taken back through
 * M, w = M^T u.  As mounted: w's angles (the sun in the mount's frame).
 * Aligned: the table solved for R(b) v0 = w (table_solve), the truth
 * angles of that b (eq. 3-4).  ok = 0 where no table angle gives it. */
typedef struct {
    double alpha, beta;
    int ok;
} dss_lane_angles;

/* w = M^T u of the sun at field angle theta and azimuth (dx, dy) / r,
 * u = (dx / r s_th, dy / r s_th, c_th): sin and cos of theta, or any
 * positive multiple of them (tan theta and 1). */
VM_INLINE geo_v3 dss_lane_model_w(const dss_model *m, double dx, double dy, double r, double s_th,
                                  double c_th)
{
    int off = r > 0.0;
    double rr = vm_select(off, r, 1.0);
    geo_v3 u = {vm_keep(off, dx / rr * s_th), vm_keep(off, dy / rr * s_th),
                vm_select(off, c_th, 1.0)};
    return geo_mul_t(m->M, u);
}

/* As mounted: w's angles. */
VM_INLINE dss_lane_angles dss_lane_angles_mounted(geo_v3 w)
{
    dss_lane_angles o;
    o.ok = w.z > 0.0;
    o.alpha = atan2(w.x, w.z);
    o.beta = atan2(w.y, w.z);
    return o;
}

/* Aligned: the table solved for R(b) v0 = w, the truth angles of that b;
 * v_phi = atan2(v0_y, v0_z). */
VM_INLINE dss_lane_angles dss_lane_angles_aligned(const dss_model *m, geo_v3 w, double v_phi)
{
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
    o.alpha = -b2;
    o.beta = dss_lane_truth_beta(b1, b2);
    return o;
}

/* The angle (rad) between the directions of angles (a, b) and of the unit
 * vector v: sun_vector_of and angle_between. */
VM_INLINE geo_v3 dss_lane_vector_of(double tan_a, double tan_b)
{
    double n = sqrt(1.0 + tan_a * tan_a + tan_b * tan_b);
    geo_v3 u = {tan_a / n, tan_b / n, 1.0 / n};
    return u;
}

VM_INLINE double dss_lane_angle_between(geo_v3 u, geo_v3 v)
{
    double cx = u.y * v.z - u.z * v.y;
    double cy = u.z * v.x - u.x * v.z;
    double cz = u.x * v.y - u.y * v.x;
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), u.x * v.x + u.y * v.y + u.z * v.z);
}

#endif
