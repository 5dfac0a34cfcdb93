/* psd_export_float.c - the exported PSD models (psd_export.c) built with
 * -DSUNMC_FLOAT, in process (lab_export.eval_float, lab_onboard.h): the
 * generated statements written here again with the same macros, each
 * operation the float one the flight computer makes, in the generated
 * order.  A change of psd_export.c's statements is a change here
 * (tests/cli/test_onboard.c compares the two bit for bit). */
#include "lab.h"
#include "psd_export.h"
#include "psd_lab.h"
#include "psd_model.h"
#include "units.h"

#include <math.h>

/* The generated code's macros under -DSUNMC_FLOAT (lab_export.c,
 * psd_export.c's emit_helpers). */
#define SR(x) ((float)(x))
#define SR_SQRT sqrtf
#define SR_ATAN2 atan2f
#define SR_ATAN atanf
#define SR_ASIN asinf
#define SR_FABS fabsf
#define PSD_FD_STEP SR(3e-4)
#define PSD_TOL SR(1e-5)

/* Corner signs of channels 1-4 (psd_export.c, psd_sensor.c). */
static const double corner_sx[PSD_CHANNELS] = {-1, 1, 1, -1};
static const double corner_sy[PSD_CHANNELS] = {-1, 1, -1, 1};

/* put_ratios: the ratios x, y of sig[4]. */
static void ratios(int duo, const float *sig, float *x, float *y)
{
    if (duo) {
        *x = (sig[1] - sig[0]) / (sig[0] + sig[1]);
        *y = (sig[3] - sig[2]) / (sig[2] + sig[3]);
    } else {
        float sum = sig[0] + sig[1] + sig[2] + sig[3];
        *x = (sig[1] + sig[2] - sig[0] - sig[3]) / sum;
        *y = (sig[1] + sig[3] - sig[0] - sig[2]) / sum;
    }
}

/* disc_rect_code: psd_overlap.c's area and moments of a disc in a
 * rectangle. */
static float h0(float R, float x)
{
    float t = x / R, w = R * R - x * x, h;
    t = t > SR(1) ? SR(1) : t < SR(-1) ? SR(-1) : t;
    h = SR_SQRT(w > SR(0) ? w : SR(0));
    return SR(0.5) * (x * h + R * R * SR_ASIN(t));
}

static float h1(float R, float x)
{
    float w = R * R - x * x, h = SR_SQRT(w > SR(0) ? w : SR(0));
    return -h * h * h / SR(3);
}

static void piece(float R, float a, float b, float x1, float x2, int full, float s[3])
{
    float k;
    if (x1 < a)
        x1 = a;
    if (!(x2 > x1))
        return;
    if (full) {
        s[0] += SR(2) * (h0(R, x2) - h0(R, x1));
        s[1] += SR(2) * (h1(R, x2) - h1(R, x1));
        return;
    }
    s[0] += h0(R, x2) - h0(R, x1) - b * (x2 - x1);
    s[1] += h1(R, x2) - h1(R, x1) - SR(0.5) * b * (x2 * x2 - x1 * x1);
    k = R * R - b * b;
    s[2] += SR(0.5) * (k * (x2 - x1) - (x2 * x2 * x2 - x1 * x1 * x1) / SR(3));
}

static void corner(float R, float a, float b, float s[3])
{
    float xb;
    s[0] = s[1] = s[2] = SR(0);
    if (b >= R || a >= R)
        return;
    if (b <= -R) {
        piece(R, a, b, -R, R, 1, s);
        return;
    }
    xb = SR_SQRT(R * R - b * b);
    piece(R, a, b, -xb, xb, 0, s);
    if (b < SR(0)) {
        piece(R, a, b, -R, -xb, 1, s);
        piece(R, a, b, xb, R, 1, s);
    }
}

static void disc_rect(float R, float x1, float x2, float y1, float y2, float *area, float *mx,
                      float *my)
{
    float s11[3], s21[3], s12[3], s22[3];
    corner(R, x1, y1, s11);
    corner(R, x2, y1, s21);
    corner(R, x1, y2, s12);
    corner(R, x2, y2, s22);
    *area = s11[0] - s21[0] - s12[0] + s22[0];
    *mx = s11[1] - s21[1] - s12[1] + s22[1];
    *my = s11[2] - s21[2] - s12[2] + s22[2];
}

/* put_currents, quadrant: each channel's overlap with the spot. */
static void currents_quadrant(const psd_sensor *s, float sx, float sy, float uz, float i[4])
{
    const float R = SR(s->R_mm), L2 = SR(s->half_mm);
    const float g = SR(s->gap_half_mm), disc = SR(M_PI) * R * R;
    for (int k = 0; k < PSD_CHANNELS; k++) {
        float x1 = corner_sx[k] > 0 ? g : -L2, x2 = corner_sx[k] > 0 ? L2 : -g;
        float y1 = corner_sy[k] > 0 ? g : -L2, y2 = corner_sy[k] > 0 ? L2 : -g;
        float a, mx, my;
        disc_rect(R, x1 - sx, x2 - sx, y1 - sy, y2 - sy, &a, &mx, &my);
        i[k] = uz * a / disc;
    }
}

/* put_currents, lateral: the spot's (clipped) centroid and power, then the
 * duo's or the tetra's (pincushioned) channels. */
static void currents_lateral(const psd_sensor *s, float sx, float sy, float uz, float i[4])
{
    const float R = SR(s->R_mm), L2 = SR(s->half_mm);
    float X, Y, P;
    if (SR_FABS(sx) + R <= L2 && SR_FABS(sy) + R <= L2) {
        X = sx / L2;
        Y = sy / L2;
        P = uz;
    } else {
        float a, mx, my;
        disc_rect(R, -L2 - sx, L2 - sx, -L2 - sy, L2 - sy, &a, &mx, &my);
        if (!(a > SR(0))) {
            X = Y = P = SR(0);
        } else {
            X = (sx + mx / a) / L2;
            Y = (sy + my / a) / L2;
            P = uz * (a / (SR(M_PI) * R * R));
        }
    }
    if (s->lateral == PSD_DUO) {
        i[0] = SR(0.5) * P * (SR(1) - X);
        i[1] = SR(0.5) * P * (SR(1) + X);
        i[2] = SR(0.5) * P * (SR(1) - Y);
        i[3] = SR(0.5) * P * (SR(1) + Y);
        return;
    }
    float kp = SR(s->pincushion);
    float Xp = X * (SR(1) + kp * Y * Y), Yp = Y * (SR(1) + kp * X * X);
    for (int k = 0; k < PSD_CHANNELS; k++)
        i[k] = SR(0.25) * P * (SR(1) + SR(corner_sx[k]) * Xp) * (SR(1) + SR(corner_sy[k]) * Yp);
}

/* put_predict's sunmc_predict: the physical model's ratios at table-top
 * tangents (ta, tb); 1 where it has none. */
static int predict(const psd_model_file *m, float ta, float tb, float *x, float *y)
{
    const psd_sensor *s = &m->cal.phys.s;
    float nn = SR_SQRT(SR(1) + ta * ta + tb * tb);
    float t0 = ta / nn, t1 = tb / nn, t2 = SR(1) / nn, i[4];
    float u[3];
    for (int r = 0; r < 3; r++)
        u[r] = SR(s->M[r][0]) * t0 + SR(s->M[r][1]) * t1 + SR(s->M[r][2]) * t2;
    float ux = u[0], uy = u[1], uz = u[2];
    float s2 = ux * ux + uy * uy, q, sx, sy;
    if (s->glass_t_mm > 0) {
        const float gn2 = SR(s->glass_n * s->glass_n);
        if (!(uz > SR(0)) || !(gn2 > s2))
            return 1;
        q = SR(s->h_mm - s->glass_t_mm) / uz + SR(s->glass_t_mm) / SR_SQRT(gn2 - s2);
    } else {
        if (!(uz > SR(0)))
            return 1;
        q = SR(s->h_mm) / uz;
    }
    sx = SR(s->x0_mm) - ux * q;
    sy = SR(s->y0_mm) - uy * q;
    if (s->detector == PSD_QUADRANT)
        currents_quadrant(s, sx, sy, uz, i);
    else
        currents_lateral(s, sx, sy, uz, i);
    ratios(s->detector == PSD_LATERAL && s->lateral == PSD_DUO, i, x, y);
    return isfinite(*x) && isfinite(*y) ? 0 : 1;
}

static int is_duo(const psd_model_file *m)
{
    return m->cfg.design.detector == PSD_LATERAL && m->cfg.design.lateral == PSD_DUO;
}

/* emit_physical: put_signals, the ratios, Newton in (tan alpha, tan beta)
 * from the ratios' linear start, the Jacobian by forward differences kept
 * once a step has shrunk ten times; at most PSD_NEWTON_MAX_ITER steps. */
static int physical(const psd_model_file *m, const float *raw, float *ang)
{
    const float sens = SR(m->cal.phys.sens), det_min = SR(1e-12 * m->cal.phys.sens *
                                                           m->cal.phys.sens);
    float s[PSD_CHANNELS], x, y, ta, tb, nn;
    float j11 = SR(0), j12 = SR(0), j21 = SR(0), j22 = SR(0), det = SR(1);
    float last = SR(1e30), before = SR(1e30);
    int done = 0;
    for (int k = 0; k < PSD_CHANNELS; k++)
        s[k] = (raw[k] - SR(m->cal.phys.dark[k])) / SR(m->cal.phys.gain[k]);
    ratios(is_duo(m), s, &x, &y);
    if (!isfinite(x) || !isfinite(y))
        return LAB_NO_INVERSE;
    ta = -x / sens;
    tb = -y / sens;
    for (int it = 0; it < PSD_NEWTON_MAX_ITER && !done; it++) {
        float fx, fy, ax, ay, bx, by, ex, ey, da, db;
        if (predict(m, ta, tb, &fx, &fy))
            return LAB_NO_INVERSE;
        if (!(last < SR(0.1) * before)) {
            if (predict(m, ta + PSD_FD_STEP, tb, &ax, &ay) ||
                predict(m, ta, tb + PSD_FD_STEP, &bx, &by))
                return LAB_NO_INVERSE;
            j11 = (ax - fx) / PSD_FD_STEP;
            j21 = (ay - fy) / PSD_FD_STEP;
            j12 = (bx - fx) / PSD_FD_STEP;
            j22 = (by - fy) / PSD_FD_STEP;
            det = j11 * j22 - j12 * j21;
            if (!(SR_FABS(det) > det_min))
                return LAB_NO_INVERSE; /* saturated */
        }
        ex = x - fx;
        ey = y - fy;
        da = (j22 * ex - j12 * ey) / det;
        db = (-j21 * ex + j11 * ey) / det;
        ta += da;
        tb += db;
        before = last;
        last = SR_FABS(da) + SR_FABS(db);
        done = last < PSD_TOL;
    }
    if (!done)
        return LAB_NO_INVERSE;
    nn = SR_SQRT(SR(1) + ta * ta + tb * tb);
    ang[0] = SR_ATAN2(ta / nn, SR(1) / nn);
    ang[1] = SR_ATAN2(tb / nn, SR(1) / nn);
    return LAB_READING_OK;
}

/* emit_polynomial: the raw ratios' terms (x / scale)^ex (y / scale)^ey. */
static int polynomial(const psd_model_file *m, const float *raw, float *ang)
{
    const psd_poly *q = &m->cal.poly;
    float x, y, px[PSD_POLY_MAX_ORDER + 1], py[PSD_POLY_MAX_ORDER + 1], ta = SR(0), tb = SR(0);
    ratios(is_duo(m), raw, &x, &y);
    if (!isfinite(x) || !isfinite(y))
        return LAB_NO_INVERSE;
    px[0] = py[0] = SR(1);
    for (int k = 1; k <= q->order; k++) {
        px[k] = px[k - 1] * (x / SR(q->scale));
        py[k] = py[k - 1] * (y / SR(q->scale));
    }
    for (int k = 0; k < q->nt; k++) {
        ta += SR(q->ca[k]) * (px[q->ex[k]] * py[q->ey[k]]);
        tb += SR(q->cb[k]) * (px[q->ex[k]] * py[q->ey[k]]);
    }
    ang[0] = SR_ATAN(ta);
    ang[1] = SR_ATAN(tb);
    return LAB_READING_OK;
}

/* emit_check: reading_check of psd_lab.c. */
static int check(const psd_model_file *m, const float *raw)
{
    int phys = m->cal.model == PSD_MODEL_PHYSICAL, any = 0;
    double lit = m->cfg.design.polarity == PSD_INVERTED ? -1.0 : 1.0;
    float sum = SR(0), x, y;
    for (int k = 0; k < PSD_CHANNELS; k++)
        if (!(raw[k] >= SR(0)))
            return LAB_OUTSIDE_RANGE;
    for (int k = 0; k < PSD_CHANNELS; k++) {
        float s = phys ? SR(lit) * (raw[k] - SR(m->cal.phys.dark[k])) / SR(m->cal.phys.gain[k])
                       : raw[k];
        any |= s > SR(0);
        sum += s;
    }
    if (!any)
        return LAB_NO_SIGNAL;
    if (!(sum > SR(0)))
        return LAB_NEGATIVE_SUM;
    if (phys)
        return LAB_READING_OK;
    double lim = m->cal.poly.scale * (1 + PSD_POLY_RANGE_MARGIN);
    ratios(is_duo(m), raw, &x, &y);
    if (isfinite(x) && isfinite(y) && (SR_FABS(x) > SR(lim) || SR_FABS(y) > SR(lim)))
        return LAB_OUTSIDE_RANGE;
    return LAB_READING_OK;
}

/* sunmc_check and sunmc_model in float, the angles in rad (lab_onboard.c
 * makes sunmc_NAME_cal's last step): the physical and polynomial models
 * (the only ones psd_export.c emits a model for;
 * psd_export_float_supported refuses the others first). */
int psd_export_eval_float(const void *model, const float *raw, float *ang)
{
    const psd_model_file *m = model;
    int st = check(m, raw);
    if (st != LAB_READING_OK)
        return st;
    return m->cal.model == PSD_MODEL_POLYNOMIAL ? polynomial(m, raw, ang)
           : m->cal.model == PSD_MODEL_PHYSICAL ? physical(m, raw, ang)
                                                : LAB_NO_INVERSE;
}
