/* dss_model_batch.c - the physical DSS model over many readings at once
 * (vectorised, one reading per lane, dss_lane.h): the fit's residuals and
 * Jacobian on the cached table rotations, and the compensation (Newton on
 * arrays for the field angle, then the table solve).  The one-reading
 * compensation is a chunk of one, so a spot gives the same bits however
 * it is asked for. */
#include "dss_lane.h"
#include "dss_model.h"
#include "status.h"
#include "vmath.h"

#include <float.h>
#include <math.h>
#include <string.h>

VM_KERNEL void dss_table_fill(dss_table *t, const double *b1_rad, const double *b2_rad)
{
    double *restrict m0 = t->m[0], *restrict m1 = t->m[1], *restrict m2 = t->m[2];
    double *restrict m3 = t->m[3], *restrict m4 = t->m[4], *restrict m5 = t->m[5];
    double *restrict m6 = t->m[6], *restrict m7 = t->m[7], *restrict m8 = t->m[8];
    VM_SIMD for (size_t i = 0; i < vm_pad(t->n); i++) {
        geo_table R = geo_table_of(b1_rad[i], b2_rad[i]);
        m0[i] = R.r00;
        m1[i] = R.r01;
        m2[i] = R.r02;
        m3[i] = R.r10;
        m4[i] = R.r11;
        m5[i] = R.r12;
        m6[i] = R.r20;
        m7[i] = R.r21;
        m8[i] = R.r22;
    }
}

/* dss_model_batch's loop, disc and tilt constants (dss_lane_model_spot_tilt);
 * the tilt's columns are written only with the tilt on. */
VM_INLINE void model_batch_loop(const dss_model *m, const dss_table *t, const double *x_px,
                                const double *y_px, const double *sw, double *f,
                                double *const col[DSS_NP], int disc, int tilt)
{
    const double *restrict m0 = t->m[0], *restrict m1 = t->m[1], *restrict m2 = t->m[2];
    const double *restrict m3 = t->m[3], *restrict m4 = t->m[4], *restrict m5 = t->m[5];
    const double *restrict m6 = t->m[6], *restrict m7 = t->m[7], *restrict m8 = t->m[8];
    double *jx0 = col[DSS_P_X0], *jy0 = col[DSS_P_Y0], *jh = col[DSS_P_H], *jt = col[DSS_P_T];
    double *jc1 = col[DSS_P_C1], *jc2 = col[DSS_P_C2], *jc3 = col[DSS_P_C3], *jn = col[DSS_P_N];
    double *js1 = col[DSS_P_S1], *js2 = col[DSS_P_S2];
    double *jtx = col[DSS_P_TX], *jty = col[DSS_P_TY];
    VM_SIMD for (size_t i = 0; i < vm_pad(t->n); i++) {
        geo_table R = {m0[i], m1[i], m2[i], m3[i], m4[i], m5[i], m6[i], m7[i], m8[i]};
        dss_lane_model e = dss_lane_model_spot_tilt(m, R, 1, disc, tilt);
        /* a dropped or unmodelled point gives 0, whatever the model says there */
        double w = sw[i];
        int use = (w > 0.0) & e.ok;
        f[2 * i] = vm_keep(use, w * (e.x - x_px[i]));
        f[2 * i + 1] = vm_keep(use, w * (e.y - y_px[i]));
        jx0[2 * i] = vm_keep(use, w * e.jx.x0);
        jx0[2 * i + 1] = vm_keep(use, w * e.jy.x0);
        jy0[2 * i] = vm_keep(use, w * e.jx.y0);
        jy0[2 * i + 1] = vm_keep(use, w * e.jy.y0);
        jh[2 * i] = vm_keep(use, w * e.jx.H);
        jh[2 * i + 1] = vm_keep(use, w * e.jy.H);
        jt[2 * i] = vm_keep(use, w * e.jx.t);
        jt[2 * i + 1] = vm_keep(use, w * e.jy.t);
        jc1[2 * i] = vm_keep(use, w * e.jx.c1);
        jc1[2 * i + 1] = vm_keep(use, w * e.jy.c1);
        jc2[2 * i] = vm_keep(use, w * e.jx.c2);
        jc2[2 * i + 1] = vm_keep(use, w * e.jy.c2);
        jc3[2 * i] = vm_keep(use, w * e.jx.c3);
        jc3[2 * i + 1] = vm_keep(use, w * e.jy.c3);
        jn[2 * i] = vm_keep(use, w * e.jx.n);
        jn[2 * i + 1] = vm_keep(use, w * e.jy.n);
        js1[2 * i] = vm_keep(use, w * e.jx.s1);
        js1[2 * i + 1] = vm_keep(use, w * e.jy.s1);
        js2[2 * i] = vm_keep(use, w * e.jx.s2);
        js2[2 * i + 1] = vm_keep(use, w * e.jy.s2);
        if (tilt) {
            jtx[2 * i] = vm_keep(use, w * e.jx.tx);
            jtx[2 * i + 1] = vm_keep(use, w * e.jy.tx);
            jty[2 * i] = vm_keep(use, w * e.jx.ty);
            jty[2 * i + 1] = vm_keep(use, w * e.jy.ty);
        }
    }
}

VM_KERNEL void dss_model_batch(const dss_model *m, const dss_table *t, const double *x_px,
                               const double *y_px, const double *sw, double *f,
                               double *const col[DSS_NP])
{
    int disc = m->disc_c_rad2 != 0.0;
    if (m->tilt)
        model_batch_loop(m, t, x_px, y_px, sw, f, col, disc, 1);
    else if (disc)
        model_batch_loop(m, t, x_px, y_px, sw, f, col, 1, 0);
    else
        model_batch_loop(m, t, x_px, y_px, sw, f, col, 0, 0);
}

VM_KERNEL int dss_field_tan_chunk(size_t k, const double *r_mm, double H_mm, double t_mm,
                                   double n, double disc_c, const double *start, double *tangent,
                                   double *slope, long *failed)
{
    /* A lane without a finite distance (a spot the campaign did not see is
     * NaN) fails at once, as it would after OPTICS_FIELD_MAX_ITER steps, and
     * iterates on 0 meanwhile: it does not hold its chunk for the whole
     * budget. */
    _Alignas(VM_ALIGN) double T[DSS_CHUNK], r[DSS_CHUNK], sl[DSS_CHUNK];
    _Alignas(VM_ALIGN) long active[DSS_CHUNK], bad[DSS_CHUNK];
    double A = H_mm - t_mm, T_max = tan(OPTICS_FIELD_THETA_MAX_RAD);
    size_t kp = vm_pad(k);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        bad[i] = (long)!(fabs(r_mm[i]) <= DBL_MAX);
        r[i] = vm_keep(!bad[i], r_mm[i]);
        T[i] = dss_lane_tan_start(r[i], H_mm, t_mm, n, T_max);
        sl[i] = 0.0;
        active[i] = !bad[i];
    }
    /* a loop of its own: a masked load from a NULL start would fault or
     * trap to microcode on some CPUs */
    if (start) {
        VM_SIMD for (size_t i = 0; i < kp; i++)
            T[i] = vm_select((start[i] >= 0.0) & (start[i] <= T_max), start[i], T[i]);
    }
    long left = 0;
    for (size_t i = 0; i < kp; i++)
        left += active[i];
    int it;
    for (it = 0; it < OPTICS_FIELD_MAX_ITER && left > 0; it++) {
        left = 0;
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            dss_lane_tan o = dss_lane_tan_step(r[i], A, t_mm, n, disc_c, T_max, T[i]);
            T[i] = vm_select(active[i] != 0, o.T, T[i]);
            sl[i] = vm_select(active[i] != 0, o.slope, sl[i]);
            active[i] = active[i] & (long)!o.done;
        }
        for (size_t i = 0; i < kp; i++)
            left += active[i];
    }
    for (size_t i = 0; i < kp; i++) {
        tangent[i] = bad[i] ? NAN : T[i];
        if (slope)
            slope[i] = sl[i];
        failed[i] = active[i] | bad[i];
    }
    return it;
}

/* One chunk's compensation lanes: the spot from the pinhole's foot (mm),
 * the field angle's tangent, F' there (dss_lane_tan) and whether it failed. */
typedef struct {
    _Alignas(VM_ALIGN) double dx[DSS_CHUNK];
    _Alignas(VM_ALIGN) double dy[DSS_CHUNK];
    _Alignas(VM_ALIGN) double r[DSS_CHUNK];
    _Alignas(VM_ALIGN) double T[DSS_CHUNK];
    _Alignas(VM_ALIGN) double slope[DSS_CHUNK];
    long failed[DSS_CHUNK];
} comp_lanes;

/* The untilting's refinements: each multiplies the error of the ray's
 * direction by about the tilted plane's rise over the pinhole height
 * (1e-2 or less), so four take the pinhole line's start to the bit. */
#define DSS_UNTILT_ITER 4

/* A tilted model's measured spots (px, on the tilted detector, in its
 * axes) carried back to z = 0 (px) along the sun's ray: the spot S = D^T
 * (x, y, 0) in the sensor frame lies on p0 + lambda u (dss_lane_tilt), so
 * p0 = S - u S_z / u_z; u from the pinhole's line P - S first, then from
 * p0's own inversion (the field angle's tangent T and azimuth: u = (dx / r
 * T, dy / r T, 1)). */
VM_KERNEL static void comp_untilt(const dss_model *m, size_t k, const double *x_px,
                                  const double *y_px, double *xo_px, double *yo_px)
{
    _Alignas(VM_ALIGN) double Sx[DSS_CHUNK], Sy[DSS_CHUNK], Sz[DSS_CHUNK], r[DSS_CHUNK];
    _Alignas(VM_ALIGN) double dx[DSS_CHUNK], dy[DSS_CHUNK], T[DSS_CHUNK];
    long failed[DSS_CHUNK];
    double H = m->p[DSS_P_H], t = m->p[DSS_P_T], n = m->p[DSS_P_N], pm = m->pixel_mm;
    double x0 = m->p[DSS_P_X0], y0 = m->p[DSS_P_Y0];
    const double(*D)[3] = (const double(*)[3])m->D;
    size_t kp = vm_pad(k);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        double sx = x_px[i] * pm, sy = y_px[i] * pm;
        Sx[i] = D[0][0] * sx + D[1][0] * sy;
        Sy[i] = D[0][1] * sx + D[1][1] * sy;
        Sz[i] = D[0][2] * sx + D[1][2] * sy;
        double l = Sz[i] / (H - Sz[i]); /* u = P - S, u_z = H - S_z */
        dx[i] = x0 - (Sx[i] - (x0 - Sx[i]) * l);
        dy[i] = y0 - (Sy[i] - (y0 - Sy[i]) * l);
        r[i] = hypot(dx[i], dy[i]);
    }
    for (int it = 0; it < DSS_UNTILT_ITER; it++) {
        dss_field_tan_chunk(k, r, H, t, n, m->disc_c_rad2, NULL, T, NULL, failed);
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            double rr = vm_select(r[i] > 0.0, r[i], 1.0);
            double ux = dx[i] / rr * T[i], uy = dy[i] / rr * T[i]; /* u_z = 1 */
            dx[i] = x0 - (Sx[i] - ux * Sz[i]);
            dy[i] = y0 - (Sy[i] - uy * Sz[i]);
            r[i] = hypot(dx[i], dy[i]);
        }
    }
    for (size_t i = 0; i < kp; i++) {
        xo_px[i] = (x0 - dx[i]) / pm;
        yo_px[i] = (y0 - dy[i]) / pm;
    }
}

/* The field angles of k <= DSS_CHUNK spots (padded lanes), the sun's disc
 * in the model's r = gain(theta) f(theta); from warm's solution moved by
 * (r - r_warm) / F' when warm is given (the same spot without its noise:
 * one or two steps instead of four or five). */
VM_KERNEL static void comp_solve(const dss_model *m, size_t k, const double *x_px,
                                 const double *y_px, const comp_lanes *warm, comp_lanes *L)
{
    _Alignas(VM_ALIGN) double start[DSS_CHUNK], xu[DSS_CHUNK], yu[DSS_CHUNK];
    double H = m->p[DSS_P_H], t = m->p[DSS_P_T], n = m->p[DSS_P_N];
    size_t kp = vm_pad(k);
    if (m->tilt) {
        comp_untilt(m, k, x_px, y_px, xu, yu);
        x_px = xu;
        y_px = yu;
    }
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        L->dx[i] = m->p[DSS_P_X0] - x_px[i] * m->pixel_mm;
        L->dy[i] = m->p[DSS_P_Y0] - y_px[i] * m->pixel_mm;
        L->r[i] = hypot(L->dx[i], L->dy[i]);
    }
    if (warm) {
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            double sl = vm_select(warm->slope[i] > 0.0, warm->slope[i], 1.0);
            start[i] = warm->T[i] + (L->r[i] - warm->r[i]) / sl;
        }
    }
    dss_field_tan_chunk(k, L->r, H, t, n, m->disc_c_rad2, warm ? start : NULL, L->T, L->slope,
                        L->failed);
}

/* The calibrated angles of kp spots at field angles of tangent T and
 * azimuths (dx, dy) / r: w = M^T u, then w's angles as mounted (atan2,
 * which takes u at any positive scale: u = (dx / r T, dy / r T, 1)) or the
 * table solved for w when aligned (u of unit length); the mount mode is
 * chosen outside the loop, so only its own calls are made.  ok[i] is 1.0
 * or 0.0. */
VM_KERNEL static void angles_chunk(const dss_model *m, size_t kp, const double *dx,
                                   const double *dy, const double *r, const double *T,
                                   double *a, double *b, double *ok)
{
    if (m->mount != DSS_MOUNT_ALIGNED) {
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            geo_v3 w = dss_lane_model_w(m, dx[i], dy[i], r[i], T[i], 1.0);
            dss_lane_angles o = dss_lane_angles_mounted(w);
            a[i] = o.alpha;
            b[i] = o.beta;
            ok[i] = vm_select(o.ok, 1.0, 0.0);
        }
        return;
    }
    double v_phi = atan2(m->v0[1], m->v0[2]);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        double c = 1.0 / sqrt(1.0 + T[i] * T[i]);
        geo_v3 w = dss_lane_model_w(m, dx[i], dy[i], r[i], T[i] * c, c);
        dss_lane_angles o = dss_lane_angles_aligned(m, w, v_phi);
        a[i] = o.alpha;
        b[i] = o.beta;
        ok[i] = vm_select(o.ok, 1.0, 0.0);
    }
}

/* The calibrated angles of solved lanes L; status[i] SUNMC_OK or SUNMC_EDOM. */
static void comp_finish(const dss_model *m, size_t k, const comp_lanes *L, double *alpha,
                        double *beta, int *status)
{
    _Alignas(VM_ALIGN) double a[DSS_CHUNK], b[DSS_CHUNK], ok[DSS_CHUNK];
    angles_chunk(m, vm_pad(k), L->dx, L->dy, L->r, L->T, a, b, ok);
    for (size_t i = 0; i < k; i++) {
        status[i] = L->failed[i] == 0 && ok[i] != 0.0 ? SUNMC_OK : SUNMC_EDOM;
        alpha[i] = a[i];
        beta[i] = b[i];
    }
}

/* Copies of spots [i0, i0 + k) into padded chunk arrays (pads repeat lane 0). */
static void load_chunk(const double *x_px, const double *y_px, size_t i0, size_t k, double *x,
                       double *y)
{
    memcpy(x, x_px + i0, k * sizeof *x);
    memcpy(y, y_px + i0, k * sizeof *y);
    for (size_t i = k; i < vm_pad(k); i++) {
        x[i] = x[0];
        y[i] = y[0];
    }
}

static int any_failed(const int *status, size_t k)
{
    int st = SUNMC_OK;
    for (size_t i = 0; i < k; i++)
        if (status[i] != SUNMC_OK)
            st = SUNMC_EDOM;
    return st;
}

int dss_model_compensate_batch(const dss_model *m, size_t n, const double *x_px,
                               const double *y_px, double *alpha, double *beta, int *status)
{
    _Alignas(VM_ALIGN) double x[DSS_CHUNK], y[DSS_CHUNK];
    comp_lanes L;
    int st = SUNMC_OK;
    for (size_t i0 = 0; i0 < n; i0 += DSS_CHUNK) {
        size_t k = n - i0 < DSS_CHUNK ? n - i0 : DSS_CHUNK;
        load_chunk(x_px, y_px, i0, k, x, y);
        comp_solve(m, k, x, y, NULL, &L);
        comp_finish(m, k, &L, alpha + i0, beta + i0, status + i0);
        if (any_failed(status + i0, k) != SUNMC_OK)
            st = SUNMC_EDOM;
    }
    return st;
}

int dss_model_compensate_pair_batch(const dss_model *m, size_t n, const double *x_px,
                                    const double *y_px, const double *x0_px,
                                    const double *y0_px, double *alpha, double *beta,
                                    int *status, double *alpha0, double *beta0, int *status0)
{
    _Alignas(VM_ALIGN) double x[DSS_CHUNK], y[DSS_CHUNK];
    comp_lanes L, L0;
    int st = SUNMC_OK;
    for (size_t i0 = 0; i0 < n; i0 += DSS_CHUNK) {
        size_t k = n - i0 < DSS_CHUNK ? n - i0 : DSS_CHUNK;
        load_chunk(x_px, y_px, i0, k, x, y);
        comp_solve(m, k, x, y, NULL, &L);
        comp_finish(m, k, &L, alpha + i0, beta + i0, status + i0);
        load_chunk(x0_px, y0_px, i0, k, x, y);
        comp_solve(m, k, x, y, &L, &L0);
        comp_finish(m, k, &L0, alpha0 + i0, beta0 + i0, status0 + i0);
        if (any_failed(status + i0, k) != SUNMC_OK || any_failed(status0 + i0, k) != SUNMC_OK)
            st = SUNMC_EDOM;
    }
    return st;
}

int dss_model_compensate(const dss_model *m, double x_px, double y_px, double *alpha,
                         double *beta)
{
    double a, b;
    int status;
    if (dss_model_compensate_batch(m, 1, &x_px, &y_px, &a, &b, &status) != SUNMC_OK)
        return SUNMC_EDOM;
    *alpha = a;
    *beta = b;
    return SUNMC_OK;
}
