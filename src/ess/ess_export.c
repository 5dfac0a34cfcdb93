/* ess_export.c - the ESS's paper model (eq. 12, its fine-code term) as C
 * code for `sunmc export` (lab_export.h): ess_model_compensate's inversion
 * (Halley on the fine code, bisection where it does not settle, eq. 13)
 * with the unit's fitted constants. */
#include "ess_config.h"
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
/* ESS_EXPORT_HALLEY_STEPS: ess_export.h */
/* ESS_EXPORT_BISECTIONS: ess_export.h */
/* Newton steps on the extended model's fine code (quadratic from within
 * its few-arcsecond terms of the root: the last bit in 4 or 5). */
/* ESS_EXPORT_NEWTON_STEPS: ess_export.h */
/* The table's range of output_deg: an ESS encodes the incidence's tangent,
 * no output reaches +-90 deg (ess_lab.c's reading check). */
#define ESS_EXPORT_TABLE_DEG 89.0
/* Eq. 13's structural correction taken as alpha_d + atan(e) within these
 * (ess_model_lane.h: ESS_EQ13_E_MAX, ESS_EQ13_AD_MAX), else directly. */
/* ESS_EXPORT_E_MAX: ess_export.h */
/* ESS_EXPORT_AD_MAX: ess_export.h */
/* A spline's table form spans its field shrunk by this factor. */
#define ESS_EXPORT_EDGE_IN (1 - 1e-12)

static const char *const axis_names[] = {"output_deg", NULL};

static int supported(const void *model, char *err, size_t errlen)
{
    const ess_model *m = model;
    if (m->kind == ESS_MODEL_EXTENDED ? !m->invertible
                                      : !(m->omega * hypot(m->p[ESS_P_KS], m->p[ESS_P_KC]) < 1.0))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "the fine-code terms are not invertible: no export");
    return SUNMC_OK;
}

/* The spline models: their table form only (lab_export.model_form). */
static int model_form(const void *model, char *err, size_t errlen)
{
    const ess_model *m = model;
    static const char *const names[ESS_N_MODELS] = {"", "", "spline", "hybrid", "table"};
    if (ESS_MODEL_HAS_SPLINE(m->kind))
        return lab_export_table_only("ess", names[m->kind], "deg of output_deg", err, errlen);
    return SUNMC_OK;
}

/* +-ESS_EXPORT_TABLE_DEG; a spline's calibrated field (just inside: its
 * edge may round outside it). */
static void axes_range(const void *model, double *lo, double *hi)
{
    const ess_model *m = model;
    lo[0] = -ESS_EXPORT_TABLE_DEG;
    hi[0] = ESS_EXPORT_TABLE_DEG;
    if (ESS_MODEL_HAS_SPLINE(m->kind)) {
        double l = (m->kind == ESS_MODEL_TABLE ? m->table.lo[0] : m->spline.lo[0]) * DEG_PER_RAD;
        double h = (m->kind == ESS_MODEL_TABLE ? m->table.hi[0] : m->spline.hi[0]) * DEG_PER_RAD;
        lo[0] = 0.5 * (l + h) - 0.5 * (h - l) * ESS_EXPORT_EDGE_IN;
        hi[0] = 0.5 * (l + h) + 0.5 * (h - l) * ESS_EXPORT_EDGE_IN;
    }
}

/* The nominal model of c: the paper's a = 1, no fine-code term. */
static void nominal(const sunmc_config *c, void *model)
{
    ess_model_init_kind(model, ess_cfg(c)->cal_model, ess_cfg(c)->design.theta0_deg * RAD_PER_DEG,
                        0.0);
}

/* reading_check of ess_lab.c: no output at or beyond +-90 deg. */
static void emit_check(const void *model, FILE *f)
{
    (void)model;
    fputs("    if (!(SR_FABS(raw[0]) < SR(90)))\n        return SUNMC_CAL_OUTSIDE_RANGE;\n", f);
}

/* The paper's fine code: x - ks sin(w x) - kc cos(w x) = r by Halley. */
static void emit_paper_solve(const ess_model *m, FILE *f)
{
    const double *p = m->p;
    double k = hypot(p[ESS_P_KS], p[ESS_P_KC]);
    fprintf(f, "    const sunmc_real ks = SR(%.17g), kc = SR(%.17g), w = SR(%.17g);\n",
            p[ESS_P_KS], p[ESS_P_KC], m->omega);
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
}

/* The extended model's fine code F(x) and F'(x) (ess_model_ext.c, fine()):
 * arg(1 + rho e^{4ix}) / w1 with rho = w1 (ks + i kc + (ks4 + i kc4) c^4 +
 * (ks8 + i kc8) c^8), c = cos x, plus the 1x and 2x terms. */
static void emit_helpers(const void *model, FILE *f)
{
    const ess_model *m = model;
    const double *p = m->p;
    if (m->kind != ESS_MODEL_EXTENDED)
        return;
    fprintf(f,
            "static void sunmc_fine(sunmc_real ad, sunmc_real *F, sunmc_real *dF)\n{\n"
            "    const sunmc_real w = SR(%.17g), w1 = SR(0.25) * w;\n"
            "    const sunmc_real ks = SR(%.17g), kc = SR(%.17g), ks4 = SR(%.17g);\n"
            "    const sunmc_real kc4 = SR(%.17g), ks8 = SR(%.17g), kc8 = SR(%.17g);\n"
            "    const sunmc_real k1s = SR(%.17g), k1c = SR(%.17g), k2s = SR(%.17g);\n"
            "    const sunmc_real k2c = SR(%.17g), k2s2 = SR(%.17g), k2c2 = SR(%.17g);\n",
            m->omega, p[ESS_P_KS], p[ESS_P_KC], p[ESS_P_KS4], p[ESS_P_KC4], p[ESS_P_KS8],
            p[ESS_P_KC8], p[ESS_P_K1S], p[ESS_P_K1C], p[ESS_P_K2S], p[ESS_P_K2C], p[ESS_P_K2S2],
            p[ESS_P_K2C2]);
    fputs("    sunmc_real s1 = SR_SIN(w1 * ad), c1 = SR_COS(w1 * ad);\n"
          "    sunmc_real s2 = SR(2) * s1 * c1, c2 = c1 * c1 - s1 * s1;\n"
          "    sunmc_real s4 = SR(2) * s2 * c2, c4 = c2 * c2 - s2 * s2;\n"
          "    sunmc_real ca = SR_COS(ad), sa = SR_SIN(ad);\n"
          "    sunmc_real ca2 = ca * ca, ca4 = ca2 * ca2, ca8 = ca4 * ca4;\n"
          "    sunmc_real dca4 = SR(-4) * ca2 * ca * sa, dca8 = SR(2) * ca4 * dca4;\n"
          "    sunmc_real rr = w1 * (ks + ks4 * ca4 + ks8 * ca8);\n"
          "    sunmc_real ri = w1 * (kc + kc4 * ca4 + kc8 * ca8);\n"
          "    sunmc_real wr = rr * c4 - ri * s4, wi = rr * s4 + ri * c4;\n"
          "    sunmc_real Dr = SR(1) + wr, q = Dr * Dr + wi * wi;\n"
          "    sunmc_real Er = c4 * Dr + s4 * wi, Ei = s4 * Dr - c4 * wi;\n"
          "    sunmc_real drr = w1 * (ks4 * dca4 + ks8 * dca8);\n"
          "    sunmc_real dri = w1 * (kc4 * dca4 + kc8 * dca8);\n"
          "    sunmc_real Xr = drr - w * ri, Xi = dri + w * rr;\n"
          "    sunmc_real a2s = k2s + k2s2 * ca2, a2c = k2c + k2c2 * ca2;\n"
          "    sunmc_real L = k1s * s1 + k1c * c1 + a2s * s2 + a2c * c2;\n"
          "    sunmc_real dL = w1 * (k1s * c1 - k1c * s1) + SR(2) * w1 * (a2s * c2 - a2c * s2) -\n"
          "                    SR(2) * ca * sa * (k2s2 * s2 + k2c2 * c2);\n"
          "    *F = SR_ATAN2(wi, Dr) / w1 + L;\n"
          "    *dF = (Xr * Ei + Xi * Er) / (q * w1) + dL;\n}\n\n",
          f);
}

/* The extended model's fine code: x - F(x) = r by Newton (ess_model_ext.c). */
static void emit_extended_solve(const ess_model *m, FILE *f)
{
    fprintf(f,
            "    /* the fine code: x - F(x) = r, Newton, a fixed count */\n"
            "    for (it = 0; it < %d; it++) {\n"
            "        sunmc_real F, dF;\n        sunmc_fine(x, &F, &dF);\n"
            "        dx = (x - F - r) / (SR(1) - dF);\n        x -= dx;\n    }\n"
            "    if (!(SR_FABS(dx) <= SR_STEP_TOL * (SR(1) + SR_FABS(x)))) {\n"
            "        /* not settled: bisection of the increasing x - F(x), a fixed count */\n"
            "        sunmc_real lo = r - SR(%.17g), hi = r + SR(%.17g);\n"
            "        for (it = 0; it < %d; it++) {\n"
            "            sunmc_real mid = SR(0.5) * (lo + hi), F, dF;\n"
            "            sunmc_fine(mid, &F, &dF);\n"
            "            if (mid - F - r < SR(0))\n"
            "                lo = mid;\n            else\n                hi = mid;\n        }\n"
            "        x = SR(0.5) * (lo + hi);\n    }\n",
            ESS_EXPORT_NEWTON_STEPS, 2.0 / (0.25 * m->omega), 2.0 / (0.25 * m->omega),
            ESS_EXPORT_BISECTIONS);
}

static void emit_model(const void *model, FILE *f)
{
    const ess_model *m = model;
    const double *p = m->p;
    fprintf(f,
            "    const sunmc_real a = SR(%.17g), b = SR(%.17g), c = SR(%.17g);\n"
            "    sunmc_real r = raw[0] * SR(%.17g), x = r, dx = SR(0), td, e;\n    int it;\n",
            p[ESS_P_A], p[ESS_P_B], p[ESS_P_C], RAD_PER_DEG);
    if (m->kind == ESS_MODEL_EXTENDED)
        emit_extended_solve(m, f);
    else
        emit_paper_solve(m, f);
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
    .model_form = model_form,
    .axes_range = axes_range,
    .axes_are_raw = 1, /* the axes are the raw columns (lab_export_axes.c) */
    .emit_helpers = emit_helpers,
    .emit_check = emit_check,
    .emit_model = emit_model,
    .eval_float = ess_export_eval_float,
    .onboard_mc = 1,
    .nominal = nominal,
    .iterations = "Loops: the fine code's Halley iteration, 8 steps (the last bit in 3 or 4 "
                  "for w k < 0.5;\n *   the extended model's Newton, 12); a reading not settled "
                  "then, 64 bisections.\n *   The table form covers output_deg +-89.",
};
