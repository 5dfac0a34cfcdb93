/* ess_export.c - the ESS's paper model (eq. 12, its fine-code term) as C
 * code for `sunmc export` (lab_export.h): ess_model_compensate's inversion
 * (Halley on the fine code, bisection where it does not settle, eq. 13)
 * with the unit's fitted constants. */
#include "ess_export.h"
#include "ess_model.h"
#include "lab_export.h"
#include "status.h"
#include "units.h"

#include <math.h>

/* Halley steps on the fine code, fixed: from alpha_d = raw (within 2 k of
 * the root, k ~ 0.04 deg) its cubic convergence reaches the last bit in 3
 * or 4 steps for w k < 0.5; a reading not settled after them is bisected
 * (ESS_EXPORT_BISECTIONS halvings of [raw - 2k, raw + 2k]: below a double's
 * resolution). */
#define ESS_EXPORT_HALLEY_STEPS 8
#define ESS_EXPORT_BISECTIONS 64
/* The table's range of output_deg: an ESS encodes the incidence's tangent,
 * no output reaches +-90 deg (ess_lab.c's reading check). */
#define ESS_EXPORT_TABLE_DEG 89.0
/* Eq. 13's structural correction taken as alpha_d + atan(e) within these
 * (ess_model_lane.h: ESS_EQ13_E_MAX, ESS_EQ13_AD_MAX), else directly. */
#define ESS_EXPORT_E_MAX 1e-2
#define ESS_EXPORT_AD_MAX 1.4

static const char *const axis_names[] = {"output_deg", NULL};

static int supported(const void *model, char *err, size_t errlen)
{
    const ess_model *m = model;
    if (m->kind != ESS_MODEL_PAPER)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "the ESS extended model is not exported yet (ess_eq12_finecode is)");
    if (!(m->omega * hypot(m->p[ESS_P_KS], m->p[ESS_P_KC]) < 1.0))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "the fine-code term is not invertible (w k >= 1): no export");
    return SUNMC_OK;
}

static void axes_range(const void *model, double *lo, double *hi)
{
    (void)model;
    lo[0] = -ESS_EXPORT_TABLE_DEG;
    hi[0] = ESS_EXPORT_TABLE_DEG;
}

static void raw_at(const void *model, const double *q, double *raw)
{
    (void)model;
    raw[0] = q[0];
}

static void emit_axes(const void *model, FILE *f)
{
    (void)model;
    fputs("    q[0] = raw[0];\n", f);
}

/* reading_check of ess_lab.c: no output at or beyond +-90 deg. */
static void emit_check(const void *model, FILE *f)
{
    (void)model;
    fputs("    if (!(SR_FABS(raw[0]) < SR(90)))\n        return SUNMC_CAL_OUTSIDE_RANGE;\n", f);
}

static void emit_model(const void *model, FILE *f)
{
    const ess_model *m = model;
    const double *p = m->p;
    double k = hypot(p[ESS_P_KS], p[ESS_P_KC]);
    fprintf(f,
            "    const sunmc_real ks = SR(%.17g), kc = SR(%.17g), w = SR(%.17g);\n"
            "    const sunmc_real a = SR(%.17g), b = SR(%.17g), c = SR(%.17g);\n"
            "    sunmc_real r = raw[0] * SR(%.17g), x = r, dx = SR(0), td, e;\n    int it;\n",
            p[ESS_P_KS], p[ESS_P_KC], m->omega, p[ESS_P_A], p[ESS_P_B], p[ESS_P_C], RAD_PER_DEG);
    fprintf(f,
            "    /* the fine code: x - ks sin(w x) - kc cos(w x) = r, Halley, a fixed count */\n"
            "    for (it = 0; it < %d; it++) {\n"
            "        sunmc_real sn = SR_SIN(w * x), cs = SR_COS(w * x);\n"
            "        sunmc_real g = x - ks * sn - kc * cs - r;\n"
            "        sunmc_real g1 = SR(1) - w * (ks * cs - kc * sn);\n"
            "        sunmc_real g2 = w * w * (ks * sn + kc * cs);\n"
            "        dx = SR(2) * g * g1 / (SR(2) * g1 * g1 - g * g2);\n"
            "        x -= dx;\n    }\n",
            ESS_EXPORT_HALLEY_STEPS);
    fprintf(f,
            "    if (!(SR_FABS(dx) <= SR_STEP_TOL * (SR(1) + SR_FABS(x)))) {\n"
            "        /* not settled: bisection of the increasing g, a fixed count */\n"
            "        sunmc_real lo = r - SR(%.17g), hi = r + SR(%.17g);\n"
            "        for (it = 0; it < %d; it++) {\n"
            "            sunmc_real mid = SR(0.5) * (lo + hi);\n"
            "            if (mid - ks * SR_SIN(w * mid) - kc * SR_COS(w * mid) - r < SR(0))\n"
            "                lo = mid;\n            else\n                hi = mid;\n        }\n"
            "        x = SR(0.5) * (lo + hi);\n    }\n",
            2 * k, 2 * k, ESS_EXPORT_BISECTIONS);
    fprintf(f,
            "    /* eq. 13: tan alpha = (b - td) / (c td - a), td = tan alpha_d */\n"
            "    td = SR_SIN(x) / SR_COS(x);\n"
            "    if (c * td == a)\n        return SUNMC_CAL_NO_INVERSE;\n"
            "    e = (b + (a - SR(1)) * td - c * td * td) / ((b + c) * td - a - td * td);\n"
            "    if (SR_FABS(e) <= SR(%g) && SR_FABS(x) <= SR(%g))\n"
            "        ang[0] = x + SR_ATAN(e);\n"
            "    else\n        ang[0] = SR_ATAN((b - td) / (c * td - a));\n"
            "    if (!(SR_FABS(ang[0]) < SR(%.17g)))\n        return SUNMC_CAL_NO_INVERSE;\n",
            ESS_EXPORT_E_MAX, ESS_EXPORT_AD_MAX, 90.0 * RAD_PER_DEG);
}

const lab_export ess_export = {
    .n_axes = 1,
    .axis_names = axis_names,
    .supported = supported,
    .axes_range = axes_range,
    .raw_at = raw_at,
    .emit_axes = emit_axes,
    .emit_check = emit_check,
    .emit_model = emit_model,
    .iterations = "Loops: the fine code's Halley iteration, 8 steps (the last bit in 3 or 4 "
                  "for w k < 0.5);\n *   a reading not settled then, 64 bisections. The table "
                  "form covers output_deg +-89.",
};
