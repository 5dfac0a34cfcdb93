/* dss_export.c - the DSS's physical model as C code for `sunmc export`
 * (lab_export.h): the inversion of dss_model_compensate (dss_model_batch.c,
 * dss_lane.h) written out with the unit's fitted constants. */
#include "dss_calib.h"
#include "dss_config.h"
#include "dss_poly.h"
#include "dss_export.h"
#include "lab_export.h"
#include "optics_lane.h"
#include "status.h"
#include "units.h"

#include <math.h>

/* Newton steps on the field angle's tangent, fixed: from the paraxial
 * start the physical model's tangent converges to the last bit of a double
 * in at most 6 steps over a 2048 px detector at 3 mm (tests/cli/test_export.c
 * checks the result against compensate); the extra steps stay at the root. */
/* DSS_EXPORT_NEWTON_STEPS: dss_export.h */
/* A spline's table form spans its field shrunk by this factor about its
 * middle: a node on the field's very edge may round outside it. */
#define DSS_EXPORT_EDGE_IN (1 - 1e-12)

static const char *const axis_names[] = {"x_px", "y_px", NULL};

static int supported(const void *model, char *err, size_t errlen)
{
    const dss_calibration *cal = model;
    /* the generated physical model has no untilting step (dss_model_batch.c) */
    if (DSS_MODEL_HAS_PHYSICS(cal->kind) && cal->phys.tilt)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "the detector tilt (calibration.fit_detector_tilt = on) is not in the "
                          "exported model: no export");
    if (DSS_MODEL_HAS_PHYSICS(cal->kind) && !(cal->phys.half_px > 0))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "design.detector_px is missing: the export needs the detector's side");
    if (cal->kind == DSS_MODEL_POLYNOMIAL && !(cal->poly.scale_rad > 0))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "the polynomial's field (its scale) is missing: no export");
    return SUNMC_OK;
}

/* The spline models: their table form only (lab_export.model_form). */
static int model_form(const void *model, char *err, size_t errlen)
{
    const dss_calibration *cal = model;
    if (DSS_MODEL_HAS_SPLINE(cal->kind))
        return lab_export_table_only("dss", dss_model_names[cal->kind], "px of the spot's x_px, y_px",
                                     err, errlen);
    return SUNMC_OK;
}

/* The detector (physical model); the polynomial's params have no detector
 * side: the spots of its field, scale_rad on each axis. */
static void axes_range(const void *model, double *lo, double *hi)
{
    const dss_calibration *cal = model;
    if (DSS_MODEL_HAS_SPLINE(cal->kind)) {
        /* the calibrated field, just inside (its edge is refused by a hair) */
        const double *l = cal->kind == DSS_MODEL_TABLE ? cal->table.lo : cal->spline.lo;
        const double *h = cal->kind == DSS_MODEL_TABLE ? cal->table.hi : cal->spline.hi;
        for (int k = 0; k < 2; k++) {
            lo[k] = 0.5 * (l[k] + h[k]) - 0.5 * (h[k] - l[k]) * DSS_EXPORT_EDGE_IN;
            hi[k] = 0.5 * (l[k] + h[k]) + 0.5 * (h[k] - l[k]) * DSS_EXPORT_EDGE_IN;
        }
        return;
    }
    const dss_onboard *o = &cal->poly.onboard;
    double half = DSS_MODEL_HAS_PHYSICS(cal->kind)
                      ? cal->phys.half_px
                      : o->h_mm * tan(cal->poly.scale_rad) / o->pixel_mm;
    lo[0] = lo[1] = -half;
    hi[0] = hi[1] = half;
}

/* The nominal calibration of c: the design's physical model, the
 * polynomial's zero correction over the field (its table's range). */
static void nominal(const sunmc_config *c, void *model)
{
    const dss_config *dc = dss_cfg(c);
    dss_calibration *cal = model;
    dss_onboard ob;
    cal->kind = dc->cal_model;
    dss_model_init(&cal->phys, &dc->design);
    dss_onboard_init(&ob, &dc->design);
    dss_poly_init(&cal->poly, dc->poly_order, &ob, dc->design.fov_deg * RAD_PER_DEG);
}

/* reading_check of dss_lab.c: a spot beyond the detector (the polynomial:
 * every spot). */
static void emit_check(const void *model, FILE *f)
{
    const dss_calibration *cal = model;
    if (cal->kind != DSS_MODEL_PHYSICAL) {
        fputs("    (void)raw;\n", f);
        return;
    }
    fprintf(f, "    if (!(SR_FABS(raw[0]) <= SR(%.17g) && SR_FABS(raw[1]) <= SR(%.17g)))\n"
               "        return SUNMC_CAL_OUTSIDE_DETECTOR;\n",
            cal->phys.half_px, cal->phys.half_px);
}

/* The field angle's tangent T of a spot at r (mm) under a pinhole at H
 * over glass t, n and the sun's disc C: dss_lane_tan_step's Newton step,
 * a fixed count, then the root's check. */
static void emit_tangent(FILE *f, double H, double t, double n, double C)
{
    fprintf(f, "    const sunmc_real A = SR(%.17g), t = SR(%.17g), n2 = SR(%.17g);\n"
               "    const sunmc_real C = SR(%.17g), T_max = SR(%.17g);\n",
            H - t, t, n * n, C, tan(OPTICS_FIELD_THETA_MAX_RAD));
    fprintf(f, "    sunmc_real T = r / SR(%.17g), step = SR(0);\n    int it;\n",
            H - t + t / n);
    fprintf(f,
            "    if (T > T_max)\n        T = T_max;\n"
            "    for (it = 0; it < %d; it++) { /* Newton, a fixed count */\n"
            "        sunmc_real m2 = n2 - SR(1), T2 = T * T, a = SR(1) - SR(2) * n2;\n"
            "        sunmc_real ig = SR(1) / SR_SQRT(n2 + m2 * T2), ig2 = ig * ig;\n"
            "        sunmc_real ig3 = ig2 * ig, ig5 = ig3 * ig2, ig7 = ig5 * ig2;\n"
            "        sunmc_real P = SR(2) * A + t * (a * ig3 + SR(3) * n2 * ig5);\n"
            "        sunmc_real Pt = SR(-3) * t * m2 * (a * ig5 + SR(5) * n2 * ig7);\n"
            "        sunmc_real E = T * (SR(1) + T2), E1 = SR(1) + SR(3) * T2;\n"
            "        sunmc_real F = T * (A + t * ig) + C * E * P - r;\n"
            "        sunmc_real F1 = A + t * n2 * ig3 + C * (E1 * P + E * T * Pt);\n"
            "        step = F / F1;\n        T -= step;\n"
            "        if (T < SR(0))\n            T = SR(0);\n"
            "        if (T > T_max)\n            T = T_max;\n    }\n"
            "    if (!(SR_FABS(step) <= SR_STEP_TOL * (SR(1) + T)) || !(T < T_max))\n"
            "        return SUNMC_CAL_NO_INVERSE;\n",
            DSS_EXPORT_NEWTON_STEPS);
}

/* The polynomial (dss_poly_compensate): the on-board formula's angles
 * (dss_onboard_chunk: eq. 9-10, the glass's field angle by the same
 * Newton when it corrects for it), then the correction's monomials. */
static void emit_polynomial(const dss_poly *q, FILE *f)
{
    const dss_onboard *o = &q->onboard;
    fprintf(f, "    sunmc_real x = (raw[0] - SR(%.17g)) * SR(%.17g);\n"
               "    sunmc_real y = (raw[1] - SR(%.17g)) * SR(%.17g);\n"
               "    sunmc_real r = SR_SQRT(x * x + y * y), kr, am, bm, u, v, a, b;\n"
               "    sunmc_real pu[%d], pv[%d];\n    int k;\n",
            o->x0_px, o->pixel_mm, o->y0_px, o->pixel_mm, q->order + 1, q->order + 1);
    if (o->glass_t_mm > 0) {
        fputs("    {\n", f);
        emit_tangent(f, o->h_mm, o->glass_t_mm, o->glass_n, 0.0);
        fprintf(f, "    kr = r > SR(0) ? T / r : SR(1) / SR(%.17g);\n    }\n", o->h_mm);
    } else {
        fprintf(f, "    kr = SR(1) / SR(%.17g);\n", o->h_mm);
    }
    fprintf(f, "    am = SR_ATAN(-x * kr);\n    bm = SR_ATAN(-y * kr);\n"
               "    u = am / SR(%.17g);\n    v = bm / SR(%.17g);\n"
               "    pu[0] = pv[0] = SR(1);\n"
               "    for (k = 1; k <= %d; k++) {\n"
               "        pu[k] = pu[k - 1] * u;\n        pv[k] = pv[k - 1] * v;\n    }\n"
               "    a = am;\n    b = bm;\n",
            q->scale_rad, q->scale_rad, q->order);
    int k = 0;
    for (int d = 0; d <= q->order; d++)
        for (int j = 0; j <= d; j++, k++)
            fprintf(f, "    a += SR(%.17g) * (pu[%d] * pv[%d]);\n"
                       "    b += SR(%.17g) * (pu[%d] * pv[%d]);\n",
                    q->ca[k], d - j, j, q->cb[k], d - j, j);
    fputs("    ang[0] = a;\n    ang[1] = b;\n", f);
}

static void emit_model(const void *model, FILE *f)
{
    const dss_calibration *cal = model;
    if (cal->kind == DSS_MODEL_POLYNOMIAL) {
        emit_polynomial(&cal->poly, f);
        return;
    }
    const dss_model *m = &cal->phys;
    fprintf(f, "    /* the spot from the pinhole's foot (mm) */\n"
               "    sunmc_real dx = SR(%.17g) - raw[0] * SR(%.17g);\n"
               "    sunmc_real dy = SR(%.17g) - raw[1] * SR(%.17g);\n"
               "    sunmc_real r = SR_SQRT(dx * dx + dy * dy);\n",
            m->p[DSS_P_X0], m->pixel_mm, m->p[DSS_P_Y0], m->pixel_mm);
    emit_tangent(f, m->p[DSS_P_H], m->p[DSS_P_T], m->p[DSS_P_N], m->disc_c_rad2);
    int aligned = m->mount == DSS_MOUNT_ALIGNED;
    fputs("    {\n        /* u: the sun in the detector's frame; w = M^T u */\n", f);
    if (aligned)
        fputs("        sunmc_real c = SR(1) / SR_SQRT(SR(1) + T * T), s = T * c;\n", f);
    else
        fputs("        sunmc_real c = SR(1), s = T;\n", f);
    fputs("        sunmc_real ux = r > SR(0) ? dx / r * s : SR(0);\n"
          "        sunmc_real uy = r > SR(0) ? dy / r * s : SR(0);\n"
          "        sunmc_real uz = r > SR(0) ? c : SR(1);\n",
          f);
    const char *w[3] = {"wx", "wy", "wz"};
    for (int i = 0; i < 3; i++)
        fprintf(f, "        sunmc_real %s = SR(%.17g) * ux + SR(%.17g) * uy + SR(%.17g) * uz;\n",
                w[i], m->M[0][i], m->M[1][i], m->M[2][i]);
    if (!aligned) {
        fputs("        if (!(wz > SR(0)))\n            return SUNMC_CAL_NO_INVERSE;\n"
              "        ang[0] = SR_ATAN2(wx, wz);\n        ang[1] = SR_ATAN2(wy, wz);\n    }\n",
              f);
        return;
    }
    /* dss_lane_angles_aligned: the table solved for R(b) v0 = w */
    fprintf(f,
            "        sunmc_real rho = SR_SQRT(wx * wx + wz * wz), b1, b2;\n"
            "        if (!(rho > SR(%.17g)))\n            return SUNMC_CAL_NO_INVERSE;\n"
            "        b2 = SR_ASIN(SR(%.17g) / rho) - SR_ATAN2(wx, wz);\n"
            "        b1 = SR_ATAN2(wy, SR_SIN(-b2) * wx + SR_COS(-b2) * wz) - SR(%.17g);\n"
            "        ang[0] = -b2;\n        ang[1] = SR_ATAN(SR_SIN(b1) / SR_COS(b1) / "
            "SR_COS(b2));\n    }\n",
            fabs(m->v0[0]), m->v0[0], atan2(m->v0[1], m->v0[2]));
}

const lab_export dss_export = {
    .n_axes = 2,
    .axis_names = axis_names,
    .supported = supported,
    .model_form = model_form,
    .axes_range = axes_range,
    .axes_are_raw = 1, /* the axes are the raw columns (lab_export_axes.c) */
    .emit_check = emit_check,
    .emit_model = emit_model,
    .eval_float = dss_export_eval_float,
    .onboard_mc = 1,
    .nominal = nominal,
    .iterations = "Loops: the field angle's Newton iteration, 10 steps (the tangent converges "
                  "in at\n *   most 6 from its paraxial start); the polynomial's powers (order "
                  "steps).",
};
