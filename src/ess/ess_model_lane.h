/* ess_model_lane.h - the ESS calibration model's geometry at one point, as
 * inline functions of one vector lane, shared by the paper's model
 * (ess_model.c) and the extended one (ess_model_ext.c): the turntable
 * matrix element by element, the sun vector's s_y and s_z in the sensor
 * frame, T = s_y / s_z, and d raw / d (installation, sun) from d raw / d T.
 * Everything is passed and returned by value (a loop under "omp simd"
 * turns local arrays into per-lane memory, which stops GCC vectorising). */
#ifndef SUNMC_ESS_MODEL_LANE_H
#define SUNMC_ESS_MODEL_LANE_H

#include "ess_model.h"
#include "ess_series.h"
#include "status.h"
#include "vmath.h"

#include <string.h>

/* A turntable matrix, element by element. */
typedef struct {
    double m00, m01, m02, m10, m11, m12, m20, m21, m22;
} ess_table_mat;

/* Row r of a times (x, y, z). */
VM_INLINE double ess_lane_row3(const mat3 a, int r, double x, double y, double z)
{
    return a[r][0] * x + a[r][1] * y + a[r][2] * z;
}

/* The sun in the turntable frame (w) and in the sensor frame (s_y, s_z). */
typedef struct {
    double w0, w1, w2, sy, sz, T;
} ess_lane_geom;

VM_INLINE ess_lane_geom ess_lane_geometry(const ess_model *m, ess_table_mat M)
{
    /* Only s_y and s_z are needed: T = s_y / s_z. */
    const double *v = m->v;
    ess_lane_geom g;
    g.w0 = M.m00 * v[0] + M.m01 * v[1] + M.m02 * v[2];
    g.w1 = M.m10 * v[0] + M.m11 * v[1] + M.m12 * v[2];
    g.w2 = M.m20 * v[0] + M.m21 * v[1] + M.m22 * v[2];
    g.sy = ess_lane_row3(m->R, 1, g.w0, g.w1, g.w2);
    g.sz = ess_lane_row3(m->R, 2, g.w0, g.w1, g.w2);
    g.T = g.sy / g.sz;
    return g;
}

/* d raw / d (inst_y, inst_z, sun_y) from k = d raw / d T. */
typedef struct {
    double inst_y, inst_z, sun_y;
} ess_lane_mount;

VM_INLINE ess_lane_mount ess_lane_mount_partials(const ess_model *m, ess_table_mat M,
                                                 ess_lane_geom g, double k)
{
    const double *dv = m->dv;
    double g1 = k / g.sz, g2 = -k * g.sy / (g.sz * g.sz);
    ess_lane_mount e;
    e.inst_y = g1 * ess_lane_row3(m->dR_y, 1, g.w0, g.w1, g.w2) +
               g2 * ess_lane_row3(m->dR_y, 2, g.w0, g.w1, g.w2);
    e.inst_z = g1 * ess_lane_row3(m->dR_z, 1, g.w0, g.w1, g.w2) +
               g2 * ess_lane_row3(m->dR_z, 2, g.w0, g.w1, g.w2);
    double d0 = M.m00 * dv[0] + M.m01 * dv[1] + M.m02 * dv[2];
    double d1 = M.m10 * dv[0] + M.m11 * dv[1] + M.m12 * dv[2];
    double d2 = M.m20 * dv[0] + M.m21 * dv[1] + M.m22 * dv[2];
    e.sun_y = g1 * ess_lane_row3(m->R, 1, d0, d1, d2) + g2 * ess_lane_row3(m->R, 2, d0, d1, d2);
    return e;
}

/* Compensation of k <= ESS_COMP_CHUNK raws (both models): the lanes'
 * start (x = r = raw, padded lanes a copy of the first, every lane active)
 * and, once x holds alpha_d, eq. 13: tan(alpha) = (b - tan alpha_d) /
 * (c tan alpha_d - a) into alpha[i], status[i] = SUNMC_EDOM for a lane
 * still active or with eq. 13 undefined. */
VM_INLINE void ess_lane_comp_start(size_t k, const double *raw, double *x, double *r,
                                   long *active)
{
    size_t kp = vm_pad(k);
    memcpy(r, raw, k * sizeof *r);
    for (size_t i = k; i < kp; i++)
        r[i] = raw[0];
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        x[i] = r[i];
        active[i] = 1;
    }
}

/* Eq. 13 as alpha = alpha_d + atan(e), e = tan(alpha - alpha_d) =
 * (b + (a - 1) td - c td^2) / ((b + c) td - a - td^2), td = tan alpha_d
 * (eq. 13's tan alpha = (b - td) / (c td - a) put into the tangent's
 * subtraction formula), here with td = tn / q (numerator and denominator
 * times q^2: one division where td comes from an addition formula; q = 1
 * otherwise).  The calibration's structural correction e is small (about
 * 1e-3 for the shipped tolerances), so its arctangent is the series
 * (ess_lane_atan_small) instead of a libm call, to the last bit of alpha.
 * far = 1 for a lane outside that range (|e| > ESS_EQ13_E_MAX, or
 * |alpha_d| > ESS_EQ13_AD_MAX where alpha might leave atan's principal
 * range), which takes ess_lane_eq13_atan on its own. */
#define ESS_EQ13_E_MAX 1e-2
#define ESS_EQ13_AD_MAX 1.4
typedef struct {
    double alpha;
    long far;
} ess_lane_eq13;

VM_INLINE ess_lane_eq13 ess_lane_eq13_turn(const double *p, double ad, double tn, double q)
{
    double e = (p[ESS_P_B] * (q * q) + (p[ESS_P_A] - 1.0) * tn * q - p[ESS_P_C] * tn * tn) /
               ((p[ESS_P_B] + p[ESS_P_C]) * tn * q - p[ESS_P_A] * (q * q) - tn * tn);
    ess_lane_eq13 o;
    o.alpha = ad + ess_lane_atan_small(e);
    long in = fabs(e) <= ESS_EQ13_E_MAX ? 1 : 0;
    o.far = fabs(ad) <= ESS_EQ13_AD_MAX ? 1 - in : 1;
    return o;
}

/* Eq. 13 by libm's arctangent, for a lane ess_lane_eq13_turn leaves. */
VM_INLINE double ess_lane_eq13_atan(const double *p, double td)
{
    double den = p[ESS_P_C] * td - p[ESS_P_A];
    return atan((p[ESS_P_B] - td) / den);
}

/* Eq. 13 on kp lanes: td[i] = tan x[i] and alpha[i] (ess_lane_eq13_turn,
 * its far lanes by ess_lane_eq13_atan); a lane where eq. 13 is undefined
 * (c td = a) set active. */
VM_INLINE void ess_lane_eq13_lanes(const ess_model *m, size_t kp, const double *x, long *active,
                                   double *td, double *alpha)
{
    const double *p = m->p;
    _Alignas(VM_ALIGN) long far[ESS_COMP_CHUNK];
    long any_far = 0;
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        td[i] = tan(x[i]);
        ess_lane_eq13 q = ess_lane_eq13_turn(p, x[i], td[i], 1.0);
        alpha[i] = q.alpha;
        far[i] = q.far;
        any_far |= q.far;
        active[i] = p[ESS_P_C] * td[i] == p[ESS_P_A] ? 1 : active[i];
    }
    for (size_t i = 0; any_far && i < kp; i++)
        if (far[i])
            alpha[i] = ess_lane_eq13_atan(p, td[i]);
}

/* ess_lane_eq13_lanes of k lanes into alpha[i], status[i] = SUNMC_EDOM
 * for a lane still active or with eq. 13 undefined. */
VM_INLINE void ess_lane_comp_eq13(const ess_model *m, size_t k, double *x, long *active,
                                  double *alpha, int *status)
{
    _Alignas(VM_ALIGN) double td[ESS_COMP_CHUNK], out[ESS_COMP_CHUNK];
    ess_lane_eq13_lanes(m, vm_pad(k), x, active, td, out);
    for (size_t i = 0; i < k; i++) {
        status[i] = active[i] ? SUNMC_EDOM : SUNMC_OK;
        alpha[i] = out[i];
    }
}

/* The nine matrix arrays of t as restrict pointers, for the loops. */
#define ESS_TABLE_POINTERS(t)                                                                 \
    const double *restrict m0 = (t)->m[0], *restrict m1 = (t)->m[1], *restrict m2 = (t)->m[2], \
                           *restrict m3 = (t)->m[3], *restrict m4 = (t)->m[4],                 \
                           *restrict m5 = (t)->m[5], *restrict m6 = (t)->m[6],                 \
                           *restrict m7 = (t)->m[7], *restrict m8 = (t)->m[8]
#define ESS_TABLE_POINT(i) {m0[i], m1[i], m2[i], m3[i], m4[i], m5[i], m6[i], m7[i], m8[i]}

#endif
