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

VM_KERNEL void dss_model_batch(const dss_model *m, const dss_table *t, const double *x_px,
                               const double *y_px, const double *sw, double *f,
                               double *const col[DSS_NP])
{
    const double *restrict m0 = t->m[0], *restrict m1 = t->m[1], *restrict m2 = t->m[2];
    const double *restrict m3 = t->m[3], *restrict m4 = t->m[4], *restrict m5 = t->m[5];
    const double *restrict m6 = t->m[6], *restrict m7 = t->m[7], *restrict m8 = t->m[8];
    double *jx0 = col[DSS_P_X0], *jy0 = col[DSS_P_Y0], *jh = col[DSS_P_H], *jt = col[DSS_P_T];
    double *jc1 = col[DSS_P_C1], *jc2 = col[DSS_P_C2], *jc3 = col[DSS_P_C3], *jn = col[DSS_P_N];
    double *js1 = col[DSS_P_S1], *js2 = col[DSS_P_S2];
    VM_SIMD for (size_t i = 0; i < vm_pad(t->n); i++) {
        geo_table R = {m0[i], m1[i], m2[i], m3[i], m4[i], m5[i], m6[i], m7[i], m8[i]};
        dss_lane_model e = dss_lane_model_spot(m, R, 1);
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
    }
}

VM_KERNEL void dss_field_angle_chunk(size_t k, const double *r_mm, double H_mm, double t_mm,
                                     double n, double *theta, long *failed)
{
    /* A lane without a finite distance (a spot the campaign did not see is
     * NaN) fails at once, as it would after OPTICS_FIELD_MAX_ITER steps, and
     * iterates on 0 meanwhile: it neither holds its chunk for the whole
     * budget nor sends the vector sine and cosine to their slow path. */
    _Alignas(VM_ALIGN) double th[DSS_CHUNK], r[DSS_CHUNK];
    _Alignas(VM_ALIGN) long active[DSS_CHUNK], bad[DSS_CHUNK];
    size_t kp = vm_pad(k);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        bad[i] = (long)!(fabs(r_mm[i]) <= DBL_MAX);
        r[i] = vm_keep(!bad[i], r_mm[i]);
        th[i] = optics_lane_field_start(r[i], H_mm, t_mm, n);
        active[i] = !bad[i];
    }
    long left = 0;
    for (size_t i = 0; i < kp; i++)
        left += active[i];
    for (int it = 0; it < OPTICS_FIELD_MAX_ITER && left > 0; it++) {
        left = 0;
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            double step;
            double next = optics_lane_field_step(r[i], H_mm, t_mm, n, th[i], &step);
            th[i] = vm_select(active[i] != 0, next, th[i]);
            active[i] = active[i] & (long)!(fabs(step) < OPTICS_FIELD_TOL_RAD);
        }
        for (size_t i = 0; i < kp; i++)
            left += active[i];
    }
    for (size_t i = 0; i < kp; i++) {
        theta[i] = bad[i] ? NAN : th[i];
        failed[i] = active[i] | bad[i];
    }
}

#define DSS_DISC_PASSES 2

/* The calibrated angles of kp spots at field angles th and azimuths (dx,
 * dy) / r: w = M^T u, then w's angles as mounted or the table solved for
 * w when aligned (dss_lane.h); the mount mode is chosen outside the loop,
 * so only its own calls are made.  ok[i] is 1.0 or 0.0. */
VM_KERNEL static void angles_chunk(const dss_model *m, size_t kp, const double *dx,
                                   const double *dy, const double *r, const double *th,
                                   double *a, double *b, double *ok)
{
    if (m->mount != DSS_MOUNT_ALIGNED) {
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            geo_v3 w = dss_lane_model_w(m, dx[i], dy[i], r[i], sin(th[i]), cos(th[i]));
            dss_lane_angles o = dss_lane_angles_mounted(w);
            a[i] = o.alpha;
            b[i] = o.beta;
            ok[i] = vm_select(o.ok, 1.0, 0.0);
        }
        return;
    }
    double v_phi = atan2(m->v0[1], m->v0[2]);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        geo_v3 w = dss_lane_model_w(m, dx[i], dy[i], r[i], sin(th[i]), cos(th[i]));
        dss_lane_angles o = dss_lane_angles_aligned(m, w, v_phi);
        a[i] = o.alpha;
        b[i] = o.beta;
        ok[i] = vm_select(o.ok, 1.0, 0.0);
    }
}

/* Compensation of k <= DSS_CHUNK spots at once (padded lanes): every lane
 * iterates until its own Newton step is below OPTICS_FIELD_TOL_RAD, exactly
 * as one spot alone would; then the table solve.  status[i]: SUNMC_OK or
 * SUNMC_EDOM. */
VM_KERNEL static void compensate_chunk(const dss_model *m, size_t k, const double *x_px,
                                       const double *y_px, double *alpha, double *beta,
                                       int *status)
{
    _Alignas(VM_ALIGN) double dx[DSS_CHUNK], dy[DSS_CHUNK], r[DSS_CHUNK] = {0}, th[DSS_CHUNK];
    _Alignas(VM_ALIGN) double a[DSS_CHUNK], b[DSS_CHUNK], ok[DSS_CHUNK];
    long active[DSS_CHUNK];
    double H = m->p[DSS_P_H], t = m->p[DSS_P_T], n = m->p[DSS_P_N];
    size_t kp = vm_pad(k);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        dx[i] = m->p[DSS_P_X0] - x_px[i] * m->pixel_mm;
        dy[i] = m->p[DSS_P_Y0] - y_px[i] * m->pixel_mm;
        r[i] = hypot(dx[i], dy[i]);
    }
    dss_field_angle_chunk(k, r, H, t, n, th, active);
    /* the sun's disc: r = gain(theta) f(theta); solved again on r / gain of
     * the last theta: the gain's slope (~1e-4 / rad) times the first
     * theta's error (the bias, ~5e-6 rad) leaves ~3e-10 rad, the second
     * pass ~1e-14 */
    for (int pass = 0; pass < DSS_DISC_PASSES && m->disc_c_rad2 != 0.0; pass++) {
        _Alignas(VM_ALIGN) double rf[DSS_CHUNK];
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            double s = sin(th[i]), c = cos(th[i]);
            rf[i] = r[i] / dss_lane_disc_gain(m->disc_c_rad2, s * s, c, H, t, n);
        }
        dss_field_angle_chunk(k, rf, H, t, n, th, active);
    }
    angles_chunk(m, kp, dx, dy, r, th, a, b, ok);
    for (size_t i = 0; i < k; i++) {
        status[i] = active[i] == 0 && ok[i] != 0.0 ? SUNMC_OK : SUNMC_EDOM;
        alpha[i] = a[i];
        beta[i] = b[i];
    }
}

int dss_model_compensate_batch(const dss_model *m, size_t n, const double *x_px,
                               const double *y_px, double *alpha, double *beta, int *status)
{
    _Alignas(VM_ALIGN) double x[DSS_CHUNK], y[DSS_CHUNK];
    int st = SUNMC_OK;
    for (size_t i0 = 0; i0 < n; i0 += DSS_CHUNK) {
        size_t k = n - i0 < DSS_CHUNK ? n - i0 : DSS_CHUNK;
        memcpy(x, x_px + i0, k * sizeof *x);
        memcpy(y, y_px + i0, k * sizeof *y);
        for (size_t i = k; i < vm_pad(k); i++) {
            x[i] = x[0];
            y[i] = y[0];
        }
        compensate_chunk(m, k, x, y, alpha + i0, beta + i0, status + i0);
        for (size_t i = 0; i < k; i++)
            if (status[i0 + i] != SUNMC_OK)
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
