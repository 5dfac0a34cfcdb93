/* dss_export_float.c - the exported DSS models (dss_export.c) built with
 * -DSUNMC_FLOAT, in process (lab_export.eval_float, lab_onboard.h): the
 * generated statements written here again with the same macros, each
 * operation the float one the flight computer makes.  A change of
 * dss_export.c's statements is a change here (tests/cli/test_onboard.c
 * compares the two bit for bit). */
#include "dss_calib.h"
#include "dss_export.h"
#include "lab.h"
#include "optics_lane.h"
#include "units.h"

#include <math.h>

/* The generated code's macros under -DSUNMC_FLOAT (lab_export.c). */
#define SR(x) ((float)(x))
#define SR_SQRT sqrtf
#define SR_SIN sinf
#define SR_COS cosf
#define SR_ATAN atanf
#define SR_ATAN2 atan2f
#define SR_ASIN asinf
#define SR_FABS fabsf
#define SR_STEP_TOL 1e-4

/* emit_tangent: the field angle's tangent *T of a spot at r (mm) under a
 * pinhole at H over glass t, n and the sun's disc C; non-OK where the
 * export returns NO_INVERSE. */
static int tangent(float r, double H, double t_mm, double n, double disc, float *T_out)
{
    const float A = SR(H - t_mm), t = SR(t_mm), n2 = SR(n * n);
    const float C = SR(disc), T_max = SR(tan(OPTICS_FIELD_THETA_MAX_RAD));
    float T = r / SR(H - t_mm + t_mm / n), step = SR(0);
    int it;
    if (T > T_max)
        T = T_max;
    for (it = 0; it < DSS_EXPORT_NEWTON_STEPS; it++) {
        float m2 = n2 - SR(1), T2 = T * T, a = SR(1) - SR(2) * n2;
        float ig = SR(1) / SR_SQRT(n2 + m2 * T2), ig2 = ig * ig;
        float ig3 = ig2 * ig, ig5 = ig3 * ig2, ig7 = ig5 * ig2;
        float P = SR(2) * A + t * (a * ig3 + SR(3) * n2 * ig5);
        float Pt = SR(-3) * t * m2 * (a * ig5 + SR(5) * n2 * ig7);
        float E = T * (SR(1) + T2), E1 = SR(1) + SR(3) * T2;
        float F = T * (A + t * ig) + C * E * P - r;
        float F1 = A + t * n2 * ig3 + C * (E1 * P + E * T * Pt);
        step = F / F1;
        T -= step;
        if (T < SR(0))
            T = SR(0);
        if (T > T_max)
            T = T_max;
    }
    if (!(SR_FABS(step) <= SR_STEP_TOL * (SR(1) + T)) || !(T < T_max))
        return LAB_NO_INVERSE;
    *T_out = T;
    return LAB_READING_OK;
}

/* emit_polynomial. */
static int polynomial(const dss_poly *q, const float *raw, float *ang)
{
    const dss_onboard *o = &q->onboard;
    float x = (raw[0] - SR(o->x0_px)) * SR(o->pixel_mm);
    float y = (raw[1] - SR(o->y0_px)) * SR(o->pixel_mm);
    float r = SR_SQRT(x * x + y * y), kr, am, bm, u, v, a, b;
    float pu[DSS_POLY_MAX_ORDER + 1], pv[DSS_POLY_MAX_ORDER + 1];
    if (o->glass_t_mm > 0) {
        float T = 0;
        int st = tangent(r, o->h_mm, o->glass_t_mm, o->glass_n, 0.0, &T);
        if (st != LAB_READING_OK)
            return st;
        kr = r > SR(0) ? T / r : SR(1) / SR(o->h_mm);
    } else {
        kr = SR(1) / SR(o->h_mm);
    }
    am = SR_ATAN(-x * kr);
    bm = SR_ATAN(-y * kr);
    u = am / SR(q->scale_rad);
    v = bm / SR(q->scale_rad);
    pu[0] = pv[0] = SR(1);
    for (int k = 1; k <= q->order; k++) {
        pu[k] = pu[k - 1] * u;
        pv[k] = pv[k - 1] * v;
    }
    a = am;
    b = bm;
    int k = 0;
    for (int d = 0; d <= q->order; d++)
        for (int j = 0; j <= d; j++, k++) {
            a += SR(q->ca[k]) * (pu[d - j] * pv[j]);
            b += SR(q->cb[k]) * (pu[d - j] * pv[j]);
        }
    ang[0] = a;
    ang[1] = b;
    return LAB_READING_OK;
}

/* emit_model's physical part, after the tangent: the sun's direction in
 * the frame the angles are read in. */
static int physical_angles(const dss_model *m, float dx, float dy, float r, float T, float *ang)
{
    int aligned = m->mount == DSS_MOUNT_ALIGNED;
    float c = aligned ? SR(1) / SR_SQRT(SR(1) + T * T) : SR(1), s = aligned ? T * c : T;
    float ux = r > SR(0) ? dx / r * s : SR(0);
    float uy = r > SR(0) ? dy / r * s : SR(0);
    float uz = r > SR(0) ? c : SR(1);
    float w[3];
    for (int i = 0; i < 3; i++)
        w[i] = SR(m->M[0][i]) * ux + SR(m->M[1][i]) * uy + SR(m->M[2][i]) * uz;
    if (!aligned) {
        if (!(w[2] > SR(0)))
            return LAB_NO_INVERSE;
        ang[0] = SR_ATAN2(w[0], w[2]);
        ang[1] = SR_ATAN2(w[1], w[2]);
        return LAB_READING_OK;
    }
    float rho = SR_SQRT(w[0] * w[0] + w[2] * w[2]), b1, b2;
    if (!(rho > SR(fabs(m->v0[0]))))
        return LAB_NO_INVERSE;
    b2 = SR_ASIN(SR(m->v0[0]) / rho) - SR_ATAN2(w[0], w[2]);
    b1 = SR_ATAN2(w[1], SR_SIN(-b2) * w[0] + SR_COS(-b2) * w[2]) - SR(atan2(m->v0[1], m->v0[2]));
    ang[0] = -b2;
    ang[1] = SR_ATAN(SR_SIN(b1) / SR_COS(b1) / SR_COS(b2));
    return LAB_READING_OK;
}

/* sunmc_check and sunmc_model in float: the angles in rad
 * (lab_onboard.c makes sunmc_NAME_cal's last step). */
int dss_export_eval_float(const void *model, const float *raw, float *ang)
{
    const dss_calibration *cal = model;
    int st;
    if (cal->kind == DSS_MODEL_POLYNOMIAL) {
        st = polynomial(&cal->poly, raw, ang);
    } else {
        const dss_model *m = &cal->phys;
        if (!(SR_FABS(raw[0]) <= SR(m->half_px) && SR_FABS(raw[1]) <= SR(m->half_px)))
            return LAB_OUTSIDE_DETECTOR;
        float dx = SR(m->p[DSS_P_X0]) - raw[0] * SR(m->pixel_mm);
        float dy = SR(m->p[DSS_P_Y0]) - raw[1] * SR(m->pixel_mm);
        float r = SR_SQRT(dx * dx + dy * dy), T = 0;
        st = tangent(r, m->p[DSS_P_H], m->p[DSS_P_T], m->p[DSS_P_N], m->disc_c_rad2, &T);
        if (st == LAB_READING_OK)
            st = physical_angles(m, dx, dy, r, T, ang);
    }
    return st;
}
