/* ess_export_float.c - the exported ESS model (ess_export.c) built with
 * -DSUNMC_FLOAT, in process (lab_export.eval_float, lab_onboard.h): the
 * generated statements written here again with the same macros, so each
 * operation is the float one the flight computer makes.  A change of
 * ess_export.c's statements is a change here (tests/cli/test_onboard.c
 * compares the two bit for bit). */
#include "ess_export.h"
#include "ess_model.h"
#include "lab.h"
#include "units.h"

#include <math.h>

/* The generated code's macros under -DSUNMC_FLOAT (lab_export.c). */
#define SR(x) ((float)(x))
#define SR_SIN sinf
#define SR_COS cosf
#define SR_ATAN atanf
#define SR_ATAN2 atan2f
#define SR_FABS fabsf
#define SR_STEP_TOL 1e-4

/* emit_helpers' sunmc_fine: the extended model's fine code. */
static void fine(const ess_model *m, float ad, float *F, float *dF)
{
    const double *p = m->p;
    const float w = SR(m->omega), w1 = SR(0.25) * w;
    const float ks = SR(p[ESS_P_KS]), kc = SR(p[ESS_P_KC]), ks4 = SR(p[ESS_P_KS4]);
    const float kc4 = SR(p[ESS_P_KC4]), ks8 = SR(p[ESS_P_KS8]), kc8 = SR(p[ESS_P_KC8]);
    const float k1s = SR(p[ESS_P_K1S]), k1c = SR(p[ESS_P_K1C]), k2s = SR(p[ESS_P_K2S]);
    const float k2c = SR(p[ESS_P_K2C]), k2s2 = SR(p[ESS_P_K2S2]), k2c2 = SR(p[ESS_P_K2C2]);
    float s1 = SR_SIN(w1 * ad), c1 = SR_COS(w1 * ad);
    float s2 = SR(2) * s1 * c1, c2 = c1 * c1 - s1 * s1;
    float s4 = SR(2) * s2 * c2, c4 = c2 * c2 - s2 * s2;
    float ca = SR_COS(ad), sa = SR_SIN(ad);
    float ca2 = ca * ca, ca4 = ca2 * ca2, ca8 = ca4 * ca4;
    float dca4 = SR(-4) * ca2 * ca * sa, dca8 = SR(2) * ca4 * dca4;
    float rr = w1 * (ks + ks4 * ca4 + ks8 * ca8);
    float ri = w1 * (kc + kc4 * ca4 + kc8 * ca8);
    float wr = rr * c4 - ri * s4, wi = rr * s4 + ri * c4;
    float Dr = SR(1) + wr, q = Dr * Dr + wi * wi;
    float Er = c4 * Dr + s4 * wi, Ei = s4 * Dr - c4 * wi;
    float drr = w1 * (ks4 * dca4 + ks8 * dca8);
    float dri = w1 * (kc4 * dca4 + kc8 * dca8);
    float Xr = drr - w * ri, Xi = dri + w * rr;
    float a2s = k2s + k2s2 * ca2, a2c = k2c + k2c2 * ca2;
    float L = k1s * s1 + k1c * c1 + a2s * s2 + a2c * c2;
    float dL = w1 * (k1s * c1 - k1c * s1) + SR(2) * w1 * (a2s * c2 - a2c * s2) -
               SR(2) * ca * sa * (k2s2 * s2 + k2c2 * c2);
    *F = SR_ATAN2(wi, Dr) / w1 + L;
    *dF = (Xr * Ei + Xi * Er) / (q * w1) + dL;
}

/* emit_extended_solve: x - F(x) = r. */
static float extended_solve(const ess_model *m, float r)
{
    float x = r, dx = SR(0);
    int it;
    for (it = 0; it < ESS_EXPORT_NEWTON_STEPS; it++) {
        float F, dF;
        fine(m, x, &F, &dF);
        dx = (x - F - r) / (SR(1) - dF);
        x -= dx;
    }
    if (!(SR_FABS(dx) <= SR_STEP_TOL * (SR(1) + SR_FABS(x)))) {
        double half = 2.0 / (0.25 * m->omega);
        float lo = r - SR(half), hi = r + SR(half);
        for (it = 0; it < ESS_EXPORT_BISECTIONS; it++) {
            float mid = SR(0.5) * (lo + hi), F, dF;
            fine(m, mid, &F, &dF);
            if (mid - F - r < SR(0))
                lo = mid;
            else
                hi = mid;
        }
        x = SR(0.5) * (lo + hi);
    }
    return x;
}

/* emit_paper_solve: x - ks sin(w x) - kc cos(w x) = r by Halley. */
static float paper_solve(const ess_model *m, float r)
{
    const double *p = m->p;
    double k = hypot(p[ESS_P_KS], p[ESS_P_KC]);
    const float ks = SR(p[ESS_P_KS]), kc = SR(p[ESS_P_KC]), w = SR(m->omega);
    float x = r, dx = SR(0);
    int it;
    for (it = 0; it < ESS_EXPORT_HALLEY_STEPS; it++) {
        float sn = SR_SIN(w * x), cs = SR_COS(w * x);
        float g = x - ks * sn - kc * cs - r;
        float g1 = SR(1) - w * (ks * cs - kc * sn);
        float g2 = w * w * (ks * sn + kc * cs);
        dx = SR(2) * g * g1 / (SR(2) * g1 * g1 - g * g2);
        x -= dx;
    }
    if (!(SR_FABS(dx) <= SR_STEP_TOL * (SR(1) + SR_FABS(x)))) {
        float lo = r - SR(2 * k), hi = r + SR(2 * k);
        for (it = 0; it < ESS_EXPORT_BISECTIONS; it++) {
            float mid = SR(0.5) * (lo + hi);
            if (mid - ks * SR_SIN(w * mid) - kc * SR_COS(w * mid) - r < SR(0))
                lo = mid;
            else
                hi = mid;
        }
        x = SR(0.5) * (lo + hi);
    }
    return x;
}

/* sunmc_check and sunmc_model (emit_model) in float: the angle in rad
 * (lab_onboard.c makes sunmc_NAME_cal's last step). */
int ess_export_eval_float(const void *model, const float *raw, float *ang_rad)
{
    const ess_model *m = model;
    const double *p = m->p;
    if (!(SR_FABS(raw[0]) < SR(90)))
        return LAB_OUTSIDE_RANGE;
    const float a = SR(p[ESS_P_A]), b = SR(p[ESS_P_B]), c = SR(p[ESS_P_C]);
    float r = raw[0] * SR(RAD_PER_DEG), x, td, e, ang;
    x = m->kind == ESS_MODEL_EXTENDED ? extended_solve(m, r) : paper_solve(m, r);
    td = SR_SIN(x) / SR_COS(x);
    if (c * td == a)
        return LAB_NO_INVERSE;
    e = (b + (a - SR(1)) * td - c * td * td) / ((b + c) * td - a - td * td);
    if (SR_FABS(e) <= SR(ESS_EXPORT_E_MAX) && SR_FABS(x) <= SR(ESS_EXPORT_AD_MAX))
        ang = x + SR_ATAN(e);
    else
        ang = SR_ATAN((b - td) / (c * td - a));
    if (!(SR_FABS(ang) < SR(90.0 * RAD_PER_DEG)))
        return LAB_NO_INVERSE;
    ang_rad[0] = ang;
    return LAB_READING_OK;
}
