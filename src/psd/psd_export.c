/* psd_export.c - the four-channel sensor's models as C code for `sunmc
 * export` (lab_export.h): the physical model's forward ratios
 * (psd_sensor.c, psd_overlap.c) and their Newton inversion
 * (psd_phys_invert), or the polynomial (psd_poly_eval), with the unit's
 * fitted constants. */
#include "lab_export.h"
#include "psd_export.h"
#include "psd_lab.h"
#include "psd_model.h"
#include "status.h"

#include <math.h>

static const char *const axis_names[] = {"ratio_x", "ratio_y", NULL};

/* Corner signs of channels 1-4 (psd_sensor.c). */
static const double corner_sx[PSD_CHANNELS] = {-1, 1, 1, -1};
static const double corner_sy[PSD_CHANNELS] = {-1, 1, -1, 1};

/* The test vectors' and table nodes' light: the channels' signals sum to
 * this (in channel 1's unit; an inverting unit's to this fraction of its
 * smallest dark); the ratios do not depend on it. */
#define PSD_EXPORT_LIGHT 0.5
/* The polynomial's table ends this fraction inside its reading check's
 * range, so that its edge nodes pass the check whatever the rounding of
 * their channels' ratios. */
#define PSD_EXPORT_EDGE_IN (1 - 1e-12)

static int supported(const void *model, char *err, size_t errlen)
{
    const psd_model_file *m = model;
    if (m->cal.model == PSD_MODEL_HYBRID)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "the psd_hybrid model cannot be exported: its correction reads the "
                          "physical model's angles, which depend on the fitted darks and not on "
                          "the raw ratios a table takes; calibrate with calibration.model = "
                          "physical, or spline or table (then export --form table:STEP)");
    return SUNMC_OK;
}

/* The spline and table: their table form only (lab_export.model_form). */
static int model_form(const void *model, char *err, size_t errlen)
{
    const psd_model_file *m = model;
    if (PSD_MODEL_HAS_SPLINE(m->cal.model))
        return lab_export_table_only("psd", psd_model_names[m->cal.model],
                                     "the raw ratios ratio_x, ratio_y", err, errlen);
    return SUNMC_OK;
}

/* The float path (psd_export_float.c) has the physical and polynomial
 * models. */
static int float_supported(const void *model, char *err, size_t errlen)
{
    const psd_model_file *m = model;
    if (m->cal.model == PSD_MODEL_PHYSICAL || m->cal.model == PSD_MODEL_POLYNOMIAL)
        return SUNMC_OK;
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "the PSD's %s model has no float path in sunmc (physical and "
                      "polynomial have; use double or table:STEP)",
                      psd_model_names[m->cal.model]);
}

static int is_duo(const psd_model_file *m)
{
    return m->cfg.design.detector == PSD_LATERAL && m->cfg.design.lateral == PSD_DUO;
}

/* The ratios' range: the physical model's normalised position (the
 * pincushion's stretch included), the polynomial's calibrated field and
 * its margin (reading_check). */
static void axes_range(const void *model, double *lo, double *hi)
{
    const psd_model_file *m = model;
    if (PSD_MODEL_HAS_SPLINE(m->cal.model)) { /* the calibrated field, just inside */
        for (int k = 0; k < 2; k++) {
            double l = m->cal.model == PSD_MODEL_TABLE ? m->cal.table.lo[k] : m->cal.spline.lo[k];
            double h = m->cal.model == PSD_MODEL_TABLE ? m->cal.table.hi[k] : m->cal.spline.hi[k];
            lo[k] = 0.5 * (l + h) - 0.5 * (h - l) * PSD_EXPORT_EDGE_IN;
            hi[k] = 0.5 * (l + h) + 0.5 * (h - l) * PSD_EXPORT_EDGE_IN;
        }
        return;
    }
    double r = m->cal.model == PSD_MODEL_POLYNOMIAL
                   ? m->cal.poly.scale * (1 + PSD_POLY_RANGE_MARGIN) * PSD_EXPORT_EDGE_IN
                   : 1.0 + fabs(m->cfg.design.pincushion);
    lo[0] = lo[1] = -r;
    hi[0] = hi[1] = r;
}

/* Channels whose ratios (psd_ratios) are q, at PSD_EXPORT_LIGHT of the
 * full sun, through the physical model's darks and gains (the polynomial's
 * raw ratios: none). */
static void raw_at(const void *model, const double *q, double *raw)
{
    const psd_model_file *m = model;
    double s[PSD_CHANNELS];
    if (is_duo(m)) {
        s[0] = 0.5 * (1 - q[0]);
        s[1] = 0.5 * (1 + q[0]);
        s[2] = 0.5 * (1 - q[1]);
        s[3] = 0.5 * (1 + q[1]);
    } else {
        for (int k = 0; k < PSD_CHANNELS; k++)
            s[k] = 0.25 * (1 + corner_sx[k] * q[0]) * (1 + corner_sy[k] * q[1]);
    }
    int phys = m->cal.model == PSD_MODEL_PHYSICAL;
    double lit = m->cfg.design.polarity == PSD_INVERTED ? -1.0 : 1.0, amp = PSD_EXPORT_LIGHT;
    /* an inverting amplifier's lit channel reads below its dark, down to 0 */
    for (int k = 0; phys && lit < 0 && k < PSD_CHANNELS; k++)
        if (m->cal.phys.dark[k] > 0 && PSD_EXPORT_LIGHT * m->cal.phys.dark[k] /
                                               fabs(m->cal.phys.gain[k]) < amp)
            amp = PSD_EXPORT_LIGHT * m->cal.phys.dark[k] / fabs(m->cal.phys.gain[k]);
    for (int k = 0; k < PSD_CHANNELS; k++)
        raw[k] = phys ? m->cal.phys.dark[k] + lit * m->cal.phys.gain[k] * amp * s[k]
                      : amp * s[k];
}

/* C: the ratios x, y of sig[4] (psd_ratios). */
static void put_ratios(const psd_model_file *m, FILE *f, const char *sig, const char *x,
                       const char *y)
{
    if (is_duo(m))
        fprintf(f, "    %s = (%s[1] - %s[0]) / (%s[0] + %s[1]);\n"
                   "    %s = (%s[3] - %s[2]) / (%s[2] + %s[3]);\n",
                x, sig, sig, sig, sig, y, sig, sig, sig, sig);
    else
        fprintf(f, "    {\n        sunmc_real sum = %s[0] + %s[1] + %s[2] + %s[3];\n"
                   "        %s = (%s[1] + %s[2] - %s[0] - %s[3]) / sum;\n"
                   "        %s = (%s[1] + %s[3] - %s[0] - %s[2]) / sum;\n    }\n",
                sig, sig, sig, sig, x, sig, sig, sig, sig, y, sig, sig, sig, sig);
}

/* C: s[k], the reading's signals as the model takes them. */
static void put_signals(const psd_model_file *m, FILE *f)
{
    fputs("    sunmc_real s[4];\n", f);
    for (int k = 0; k < PSD_CHANNELS; k++) {
        if (m->cal.model == PSD_MODEL_PHYSICAL)
            fprintf(f, "    s[%d] = (raw[%d] - SR(%.17g)) / SR(%.17g);\n", k, k,
                    m->cal.phys.dark[k], m->cal.phys.gain[k]);
        else
            fprintf(f, "    s[%d] = raw[%d];\n", k, k);
    }
}

/* The nominal model of c: the design's physical calibration (a
 * polynomial's over ratios up to 1, the most its table spans: the size
 * checked with the config bounds every unit's). */
static void nominal(const sunmc_config *c, void *model)
{
    psd_model_file *m = model;
    m->cfg = *psd_cfg(c);
    psd_cal_nominal(&m->cal, &m->cfg.design);
    m->cal.model = m->cfg.cal_model;
    m->cal.poly.scale = 1.0;
}

/* emit_axes in process: put_signals, then put_ratios, in their order of
 * operations. */
static int axes_at(const void *model, const double *raw, double *q)
{
    const psd_model_file *m = model;
    double s[PSD_CHANNELS];
    for (int k = 0; k < PSD_CHANNELS; k++)
        s[k] = m->cal.model == PSD_MODEL_PHYSICAL ? (raw[k] - m->cal.phys.dark[k]) /
                                                       m->cal.phys.gain[k]
                                                 : raw[k];
    if (is_duo(m)) {
        q[0] = (s[1] - s[0]) / (s[0] + s[1]);
        q[1] = (s[3] - s[2]) / (s[2] + s[3]);
    } else {
        double sum = s[0] + s[1] + s[2] + s[3];
        q[0] = (s[1] + s[2] - s[0] - s[3]) / sum;
        q[1] = (s[1] + s[3] - s[0] - s[2]) / sum;
    }
    return isfinite(q[0]) && isfinite(q[1]) ? SUNMC_OK : SUNMC_EDOM;
}

static void emit_axes(const void *model, FILE *f)
{
    const psd_model_file *m = model;
    fputs("    {\n", f);
    put_signals(m, f);
    put_ratios(m, f, "s", "q[0]", "q[1]");
    fputs("    }\n    if (!isfinite(q[0]) || !isfinite(q[1]))\n"
          "        return SUNMC_CAL_NO_INVERSE;\n",
          f);
}

/* reading_check of psd_lab.c. */
static void emit_check(const void *model, FILE *f)
{
    const psd_model_file *m = model;
    int phys = m->cal.model == PSD_MODEL_PHYSICAL;
    double lit = m->cfg.design.polarity == PSD_INVERTED ? -1.0 : 1.0;
    fputs("    sunmc_real sum = SR(0), x, y;\n    int k, any = 0;\n    (void)x;\n    (void)y;\n"
          "    for (k = 0; k < 4; k++)\n        if (!(raw[k] >= SR(0)))\n"
          "            return SUNMC_CAL_OUTSIDE_RANGE;\n",
          f);
    for (int k = 0; k < PSD_CHANNELS; k++) {
        if (phys)
            fprintf(f, "    {\n        sunmc_real s = SR(%.17g) * (raw[%d] - SR(%.17g)) / "
                       "SR(%.17g);\n",
                    lit, k, m->cal.phys.dark[k], m->cal.phys.gain[k]);
        else
            fprintf(f, "    {\n        sunmc_real s = raw[%d];\n", k);
        fputs("        any |= s > SR(0);\n        sum += s;\n    }\n", f);
    }
    fputs("    if (!any)\n        return SUNMC_CAL_NO_SIGNAL;\n"
          "    if (!(sum > SR(0)))\n        return SUNMC_CAL_NEGATIVE_SUM;\n",
          f);
    if (m->cal.model == PSD_MODEL_POLYNOMIAL) {
        put_ratios(m, f, "raw", "x", "y");
        fprintf(f, "    if (isfinite(x) && isfinite(y) &&\n"
                   "        (SR_FABS(x) > SR(%.17g) || SR_FABS(y) > SR(%.17g)))\n"
                   "        return SUNMC_CAL_OUTSIDE_RANGE;\n",
                m->cal.poly.scale * (1 + PSD_POLY_RANGE_MARGIN),
                m->cal.poly.scale * (1 + PSD_POLY_RANGE_MARGIN));
    }
}

/* psd_overlap.c's area and moments of a disc in a rectangle. */
static const char disc_rect_code[] =
    "static sunmc_real sunmc_h0(sunmc_real R, sunmc_real x)\n{\n"
    "    sunmc_real t = x / R, w = R * R - x * x, h;\n"
    "    t = t > SR(1) ? SR(1) : t < SR(-1) ? SR(-1) : t;\n"
    "    h = SR_SQRT(w > SR(0) ? w : SR(0));\n"
    "    return SR(0.5) * (x * h + R * R * SR_ASIN(t));\n}\n\n"
    "static sunmc_real sunmc_h1(sunmc_real R, sunmc_real x)\n{\n"
    "    sunmc_real w = R * R - x * x, h = SR_SQRT(w > SR(0) ? w : SR(0));\n"
    "    return -h * h * h / SR(3);\n}\n\n"
    "static void sunmc_piece(sunmc_real R, sunmc_real a, sunmc_real b, sunmc_real x1,\n"
    "                        sunmc_real x2, int full, sunmc_real s[3])\n{\n"
    "    sunmc_real k;\n    if (x1 < a)\n        x1 = a;\n    if (!(x2 > x1))\n        return;\n"
    "    if (full) {\n"
    "        s[0] += SR(2) * (sunmc_h0(R, x2) - sunmc_h0(R, x1));\n"
    "        s[1] += SR(2) * (sunmc_h1(R, x2) - sunmc_h1(R, x1));\n        return;\n    }\n"
    "    s[0] += sunmc_h0(R, x2) - sunmc_h0(R, x1) - b * (x2 - x1);\n"
    "    s[1] += sunmc_h1(R, x2) - sunmc_h1(R, x1) - SR(0.5) * b * (x2 * x2 - x1 * x1);\n"
    "    k = R * R - b * b;\n"
    "    s[2] += SR(0.5) * (k * (x2 - x1) - (x2 * x2 * x2 - x1 * x1 * x1) / SR(3));\n}\n\n"
    "static void sunmc_corner(sunmc_real R, sunmc_real a, sunmc_real b, sunmc_real s[3])\n{\n"
    "    sunmc_real xb;\n    s[0] = s[1] = s[2] = SR(0);\n"
    "    if (b >= R || a >= R)\n        return;\n"
    "    if (b <= -R) {\n        sunmc_piece(R, a, b, -R, R, 1, s);\n        return;\n    }\n"
    "    xb = SR_SQRT(R * R - b * b);\n    sunmc_piece(R, a, b, -xb, xb, 0, s);\n"
    "    if (b < SR(0)) {\n        sunmc_piece(R, a, b, -R, -xb, 1, s);\n"
    "        sunmc_piece(R, a, b, xb, R, 1, s);\n    }\n}\n\n"
    "static void sunmc_disc_rect(sunmc_real R, sunmc_real x1, sunmc_real x2, sunmc_real y1,\n"
    "                            sunmc_real y2, sunmc_real *area, sunmc_real *mx,\n"
    "                            sunmc_real *my)\n{\n"
    "    sunmc_real s11[3], s21[3], s12[3], s22[3];\n"
    "    sunmc_corner(R, x1, y1, s11);\n    sunmc_corner(R, x2, y1, s21);\n"
    "    sunmc_corner(R, x1, y2, s12);\n    sunmc_corner(R, x2, y2, s22);\n"
    "    *area = s11[0] - s21[0] - s12[0] + s22[0];\n"
    "    *mx = s11[1] - s21[1] - s12[1] + s22[1];\n"
    "    *my = s11[2] - s21[2] - s12[2] + s22[2];\n}\n\n";

/* C: the currents i[4] of the spot (sx, sy) at uz (psd_sensor_currents). */
static void put_currents(const psd_model_file *m, FILE *f)
{
    const psd_sensor *s = &m->cal.phys.s;
    fprintf(f, "    const sunmc_real R = SR(%.17g), L2 = SR(%.17g);\n", s->R_mm, s->half_mm);
    if (s->detector == PSD_QUADRANT) {
        fprintf(f, "    const sunmc_real g = SR(%.17g), disc = SR(%.17g) * R * R;\n",
                s->gap_half_mm, M_PI);
        for (int k = 0; k < PSD_CHANNELS; k++) {
            const char *x1 = corner_sx[k] > 0 ? "g" : "-L2", *x2 = corner_sx[k] > 0 ? "L2" : "-g";
            const char *y1 = corner_sy[k] > 0 ? "g" : "-L2", *y2 = corner_sy[k] > 0 ? "L2" : "-g";
            fprintf(f, "    {\n        sunmc_real a, mx, my;\n"
                       "        sunmc_disc_rect(R, %s - sx, %s - sx, %s - sy, %s - sy, &a, &mx, "
                       "&my);\n        i[%d] = uz * a / disc;\n    }\n",
                    x1, x2, y1, y2, k);
        }
        return;
    }
    fprintf(f, "    sunmc_real X, Y, P;\n"
               "    if (SR_FABS(sx) + R <= L2 && SR_FABS(sy) + R <= L2) {\n"
               "        X = sx / L2;\n        Y = sy / L2;\n        P = uz;\n    } else {\n"
               "        sunmc_real a, mx, my;\n"
               "        sunmc_disc_rect(R, -L2 - sx, L2 - sx, -L2 - sy, L2 - sy, &a, &mx, &my);\n"
               "        if (!(a > SR(0))) {\n            X = Y = P = SR(0);\n        } else {\n"
               "            X = (sx + mx / a) / L2;\n            Y = (sy + my / a) / L2;\n"
               "            P = uz * (a / (SR(%.17g) * R * R));\n        }\n    }\n",
            M_PI);
    if (s->lateral == PSD_DUO) {
        fputs("    i[0] = SR(0.5) * P * (SR(1) - X);\n    i[1] = SR(0.5) * P * (SR(1) + X);\n"
              "    i[2] = SR(0.5) * P * (SR(1) - Y);\n    i[3] = SR(0.5) * P * (SR(1) + Y);\n",
              f);
        return;
    }
    fprintf(f, "    {\n        sunmc_real k = SR(%.17g);\n"
               "        sunmc_real Xp = X * (SR(1) + k * Y * Y), Yp = Y * (SR(1) + k * X * X);\n",
            s->pincushion);
    for (int k = 0; k < PSD_CHANNELS; k++)
        fprintf(f, "        i[%d] = SR(0.25) * P * (SR(1) + SR(%g) * Xp) * (SR(1) + SR(%g) * Yp);\n",
                k, corner_sx[k], corner_sy[k]);
    fputs("    }\n", f);
}

/* The physical model's ratios at table-top tangents (ta, tb)
 * (psd_phys_predicted); 1 where it has none. */
static void put_predict(const psd_model_file *m, FILE *f)
{
    const psd_sensor *s = &m->cal.phys.s;
    fputs("static int sunmc_predict(sunmc_real ta, sunmc_real tb, sunmc_real *x, sunmc_real *y)\n"
          "{\n    sunmc_real nn = SR_SQRT(SR(1) + ta * ta + tb * tb);\n"
          "    sunmc_real t0 = ta / nn, t1 = tb / nn, t2 = SR(1) / nn, i[4];\n",
          f);
    const char *u[3] = {"ux", "uy", "uz"};
    for (int r = 0; r < 3; r++)
        fprintf(f, "    sunmc_real %s = SR(%.17g) * t0 + SR(%.17g) * t1 + SR(%.17g) * t2;\n",
                u[r], s->M[r][0], s->M[r][1], s->M[r][2]);
    fputs("    sunmc_real s2 = ux * ux + uy * uy, q, sx, sy;\n", f);
    if (s->glass_t_mm > 0) {
        fprintf(f, "    const sunmc_real gn2 = SR(%.17g);\n"
                   "    if (!(uz > SR(0)) || !(gn2 > s2))\n        return 1;\n"
                   "    q = SR(%.17g) / uz + SR(%.17g) / SR_SQRT(gn2 - s2);\n",
                s->glass_n * s->glass_n, s->h_mm - s->glass_t_mm, s->glass_t_mm);
    } else {
        fprintf(f, "    (void)s2;\n    if (!(uz > SR(0)))\n        return 1;\n"
                   "    q = SR(%.17g) / uz;\n",
                s->h_mm);
    }
    fprintf(f, "    sx = SR(%.17g) - ux * q;\n    sy = SR(%.17g) - uy * q;\n", s->x0_mm, s->y0_mm);
    put_currents(m, f);
    put_ratios(m, f, "i", "*x", "*y");
    fputs("    return isfinite(*x) && isfinite(*y) ? 0 : 1;\n}\n\n", f);
}

static void emit_helpers(const void *model, FILE *f)
{
    const psd_model_file *m = model;
    if (m->cal.model != PSD_MODEL_PHYSICAL)
        return;
    fprintf(f, "/* The Newton inversion's numeric Jacobian step (tan) and its last step's\n"
               " * bound (|d tan alpha| + |d tan beta|). */\n"
               "#if defined(SUNMC_FLOAT)\n#define PSD_FD_STEP SR(3e-4)\n#define PSD_TOL SR(1e-5)\n"
               "#else\n#define PSD_FD_STEP SR(%.17g)\n#define PSD_TOL SR(%.17g)\n#endif\n"
               "#define PSD_NEWTON_STEPS %d\n\n",
            1e-7, PSD_NEWTON_TOL, PSD_NEWTON_MAX_ITER);
    fputs(disc_rect_code, f);
    put_predict(m, f);
}

/* psd_phys_invert: Newton in (tan alpha, tan beta) from the ratios' linear
 * start, the Jacobian by forward differences, kept once a step has shrunk
 * ten times against the one before; at most PSD_NEWTON_STEPS steps. */
static void emit_physical(const psd_model_file *m, FILE *f)
{
    double sens = m->cal.phys.sens;
    put_signals(m, f);
    fprintf(f,
            "    sunmc_real x, y, ta, tb, nn;\n"
            "    sunmc_real j11 = SR(0), j12 = SR(0), j21 = SR(0), j22 = SR(0), det = SR(1);\n"
            "    sunmc_real last = SR(1e30), before = SR(1e30);\n    int it, done = 0;\n");
    put_ratios(m, f, "s", "x", "y");
    fprintf(f,
            "    if (!isfinite(x) || !isfinite(y))\n        return SUNMC_CAL_NO_INVERSE;\n"
            "    ta = -x / SR(%.17g);\n    tb = -y / SR(%.17g);\n"
            "    for (it = 0; it < PSD_NEWTON_STEPS && !done; it++) {\n"
            "        sunmc_real fx, fy, ax, ay, bx, by, ex, ey, da, db;\n"
            "        if (sunmc_predict(ta, tb, &fx, &fy))\n"
            "            return SUNMC_CAL_NO_INVERSE;\n"
            "        if (!(last < SR(0.1) * before)) {\n"
            "            if (sunmc_predict(ta + PSD_FD_STEP, tb, &ax, &ay) ||\n"
            "                sunmc_predict(ta, tb + PSD_FD_STEP, &bx, &by))\n"
            "                return SUNMC_CAL_NO_INVERSE;\n"
            "            j11 = (ax - fx) / PSD_FD_STEP;\n            j21 = (ay - fy) / PSD_FD_STEP;\n"
            "            j12 = (bx - fx) / PSD_FD_STEP;\n            j22 = (by - fy) / PSD_FD_STEP;\n"
            "            det = j11 * j22 - j12 * j21;\n"
            "            if (!(SR_FABS(det) > SR(%.17g)))\n"
            "                return SUNMC_CAL_NO_INVERSE; /* saturated */\n        }\n"
            "        ex = x - fx;\n        ey = y - fy;\n"
            "        da = (j22 * ex - j12 * ey) / det;\n        db = (-j21 * ex + j11 * ey) / det;\n"
            "        ta += da;\n        tb += db;\n        before = last;\n"
            "        last = SR_FABS(da) + SR_FABS(db);\n        done = last < PSD_TOL;\n    }\n"
            "    if (!done)\n        return SUNMC_CAL_NO_INVERSE;\n"
            "    nn = SR_SQRT(SR(1) + ta * ta + tb * tb);\n"
            "    ang[0] = SR_ATAN2(ta / nn, SR(1) / nn);\n    ang[1] = SR_ATAN2(tb / nn, SR(1) / nn);\n",
            sens, sens, 1e-12 * sens * sens);
}

/* psd_poly_eval: the raw ratios' terms (x / scale)^ex (y / scale)^ey. */
static void emit_polynomial(const psd_model_file *m, FILE *f)
{
    const psd_poly *q = &m->cal.poly;
    fprintf(f, "    sunmc_real x, y, px[%d], py[%d], ta = SR(0), tb = SR(0);\n    int k;\n",
            q->order + 1, q->order + 1);
    put_ratios(m, f, "raw", "x", "y");
    fprintf(f, "    if (!isfinite(x) || !isfinite(y))\n        return SUNMC_CAL_NO_INVERSE;\n"
               "    px[0] = py[0] = SR(1);\n"
               "    for (k = 1; k <= %d; k++) {\n"
               "        px[k] = px[k - 1] * (x / SR(%.17g));\n"
               "        py[k] = py[k - 1] * (y / SR(%.17g));\n    }\n",
            q->order, q->scale, q->scale);
    for (int k = 0; k < q->nt; k++)
        fprintf(f, "    ta += SR(%.17g) * (px[%d] * py[%d]);\n    tb += SR(%.17g) * (px[%d] * "
                   "py[%d]);\n",
                q->ca[k], q->ex[k], q->ey[k], q->cb[k], q->ex[k], q->ey[k]);
    fputs("    ang[0] = SR_ATAN(ta);\n    ang[1] = SR_ATAN(tb);\n", f);
}

static void emit_model(const void *model, FILE *f)
{
    const psd_model_file *m = model;
    if (m->cal.model == PSD_MODEL_POLYNOMIAL)
        emit_polynomial(m, f);
    else
        emit_physical(m, f);
}

const lab_export psd_export = {
    .n_axes = 2,
    .axis_names = axis_names,
    .supported = supported,
    .model_form = model_form,
    .axes_range = axes_range,
    .raw_at = raw_at,
    .emit_helpers = emit_helpers,
    .emit_axes = emit_axes,
    .emit_check = emit_check,
    .emit_model = emit_model,
    .axes_at = axes_at,
    .eval_float = psd_export_eval_float,
    .float_supported = float_supported,
    .onboard_mc = 1,
    .nominal = nominal,
    .iterations = "Loops: physical model: Newton in (tan alpha, tan beta), at most 40 steps, "
                  "stopping\n *   when a step is below 1e-13 (double; 1e-5 float); the "
                  "polynomial: none but its\n *   powers (order steps).",
};
