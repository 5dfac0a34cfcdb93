/* psd_model.c - the physical calibration model: ratios, their inversion
 * and the fit (see psd_model.h). */
#include "psd_model.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <string.h>

const char *const psd_param_names[PSD_NP] = {
    "dx_um", "dy_um", "dh_um", "tilt_x_arcsec", "tilt_y_arcsec", "rot_z_arcsec",
    "gain2_rel", "gain3_rel", "gain4_rel", "dark1_raw", "dark2_raw", "dark3_raw", "dark4_raw"};
const double psd_param_scale[PSD_NP] = {
    1.0 / MM_PER_UM, 1.0 / MM_PER_UM, 1.0 / MM_PER_UM, ARCSEC_PER_RAD, ARCSEC_PER_RAD,
    ARCSEC_PER_RAD, 1, 1, 1, 1, 1, 1, 1};

/* Forward-difference steps of the fit's Jacobian (internal units). */
static const double fd_step[PSD_NP_GEOMETRY] = {1e-6, 1e-6, 1e-6, 1e-7, 1e-7, 1e-7};
/* Step of the inversion's numeric Jacobian (tan units). */
#define PSD_NEWTON_STEP 1e-7

void psd_phys_set(psd_phys *m, const psd_design *d, const double p[PSD_NP])
{
    psd_deviations dev;
    memset(&dev, 0, sizeof dev);
    dev.dx_um[0] = p[PSD_P_DX] / MM_PER_UM;
    dev.dy_um[0] = p[PSD_P_DY] / MM_PER_UM;
    dev.dh_um[0] = p[PSD_P_DH] / MM_PER_UM;
    dev.tilt_x_arcsec[0] = p[PSD_P_TX] * ARCSEC_PER_RAD;
    dev.tilt_y_arcsec[0] = p[PSD_P_TY] * ARCSEC_PER_RAD;
    dev.rot_z_arcsec[0] = p[PSD_P_RZ] * ARCSEC_PER_RAD;
    psd_sensor_build(d, &dev, &m->s);
    m->gain[0] = 1.0;
    for (int k = 1; k < PSD_CHANNELS; k++)
        m->gain[k] = p[PSD_P_G2 + k - 1];
    for (int k = 0; k < PSD_CHANNELS; k++)
        m->dark[k] = p[PSD_P_D1 + k];
    /* with the fitted height: a fit cannot shrink its residuals by letting
     * h, and with it the ratios' slope, go to 0 */
    m->sens = d->detector == PSD_QUADRANT ? m->s.h_mm * 4.0 / (M_PI * m->s.R_mm)
                                          : m->s.h_mm / m->s.half_mm;
}

int psd_phys_observed(const psd_phys *m, const double r[4], double *x, double *y)
{
    double s[PSD_CHANNELS];
    for (int k = 0; k < PSD_CHANNELS; k++)
        s[k] = (r[k] - m->dark[k]) / m->gain[k];
    psd_ratios(m->s.detector, m->s.lateral, s, x, y);
    return isfinite(*x) && isfinite(*y) ? SUNMC_OK : SUNMC_EDOM;
}

int psd_phys_predicted(const psd_phys *m, const double ut[3], double *x, double *y)
{
    double u[3], spot[2], i[4];
    mat3_vec(m->s.M, ut, u);
    if (psd_sensor_spot(&m->s, u, spot) != SUNMC_OK)
        return SUNMC_EDOM;
    psd_sensor_currents(&m->s, spot, u[2], i);
    psd_ratios(m->s.detector, m->s.lateral, i, x, y);
    return isfinite(*x) && isfinite(*y) ? SUNMC_OK : SUNMC_EDOM;
}

static int predict_tan(const psd_phys *m, double ta, double tb, double *x, double *y)
{
    double n = sqrt(1.0 + ta * ta + tb * tb), ut[3] = {ta / n, tb / n, 1.0 / n};
    return psd_phys_predicted(m, ut, x, y);
}

int psd_phys_invert(const psd_phys *m, double x, double y, double ut[3])
{
    if (!isfinite(x) || !isfinite(y))
        return SUNMC_EDOM;
    /* linear start: the spot where the ratios put it, seen through the aperture */
    double ta = -x / m->sens, tb = -y / m->sens;
    /* Newton's method; the Jacobian (forward differences, two predictions)
     * is kept once a step has shrunk ten times against the one before: the
     * root is where the predicted ratios equal (x, y) whatever Jacobian
     * leads there, and near it one prediction per step suffices. */
    double j11 = 0, j12 = 0, j21 = 0, j22 = 0, det = 0, last = INFINITY, before = INFINITY;
    for (int it = 0; it < PSD_NEWTON_MAX_ITER; it++) {
        double fx, fy, ax, ay, bx, by;
        if (predict_tan(m, ta, tb, &fx, &fy) != SUNMC_OK)
            return SUNMC_EDOM;
        if (!(last < 0.1 * before)) {
            if (predict_tan(m, ta + PSD_NEWTON_STEP, tb, &ax, &ay) != SUNMC_OK ||
                predict_tan(m, ta, tb + PSD_NEWTON_STEP, &bx, &by) != SUNMC_OK)
                return SUNMC_EDOM;
            j11 = (ax - fx) / PSD_NEWTON_STEP, j21 = (ay - fy) / PSD_NEWTON_STEP;
            j12 = (bx - fx) / PSD_NEWTON_STEP, j22 = (by - fy) / PSD_NEWTON_STEP;
            det = j11 * j22 - j12 * j21;
            if (!(fabs(det) > 1e-12 * m->sens * m->sens))
                return SUNMC_EDOM; /* saturated: the ratios no longer move */
        }
        double ex = x - fx, ey = y - fy;
        double da = (j22 * ex - j12 * ey) / det, db = (-j21 * ex + j11 * ey) / det;
        ta += da;
        tb += db;
        before = last;
        last = fabs(da) + fabs(db);
        if (last < PSD_NEWTON_TOL) {
            double n = sqrt(1.0 + ta * ta + tb * tb);
            ut[0] = ta / n;
            ut[1] = tb / n;
            ut[2] = 1.0 / n;
            return SUNMC_OK;
        }
    }
    return SUNMC_EDOM;
}

/* ---- start values ---- */

void psd_phys_start(psd_rows *d, double p[PSD_NP])
{
    memset(p, 0, PSD_NP * sizeof *p);
    psd_phys_set(&d->work, d->design, p);
    double sw[PSD_CHANNELS] = {0}, sx[PSD_CHANNELS] = {0}, sy[PSD_CHANNELS] = {0};
    double sxx[PSD_CHANNELS] = {0}, sxy[PSD_CHANNELS] = {0};
    for (size_t r = 0; r < d->n; r++) {
        double w = d->w ? d->w[r] : 1.0, u[3], spot[2], i[4];
        mat3_vec(d->work.s.M, d->ut + 3 * r, u);
        if (!(w > 0) || psd_sensor_spot(&d->work.s, u, spot) != SUNMC_OK)
            continue;
        psd_sensor_currents(&d->work.s, spot, u[2], i);
        for (int k = 0; k < PSD_CHANNELS; k++) {
            sw[k] += w;
            sx[k] += w * i[k];
            sy[k] += w * d->m[k][r];
            sxx[k] += w * i[k] * i[k];
            sxy[k] += w * i[k] * d->m[k][r];
        }
    }
    double g[PSD_CHANNELS], off[PSD_CHANNELS];
    for (int k = 0; k < PSD_CHANNELS; k++) {
        double den = sw[k] * sxx[k] - sx[k] * sx[k];
        g[k] = den != 0.0 ? (sw[k] * sxy[k] - sx[k] * sy[k]) / den : 0.0;
        off[k] = sw[k] > 0 ? (sy[k] - g[k] * sx[k]) / sw[k] : 0.0;
    }
    int ok = g[0] != 0.0 && isfinite(g[0]);
    d->sig1 = ok ? g[0] : 0.0;
    for (int k = 0; k < PSD_CHANNELS; k++) {
        if (k > 0)
            p[PSD_P_G2 + k - 1] = ok ? g[k] / g[0] : 1.0;
        p[PSD_P_D1 + k] = off[k];
    }
}

/* ---- the fit ---- */

/* Corner signs of the ratios' numerators (psd_sensor.h). */
static const double ratio_cx[PSD_CHANNELS] = {-1, 1, 1, -1};
static const double ratio_cy[PSD_CHANNELS] = {-1, 1, -1, 1};

/* d x / d s_k and d y / d s_k of the ratios at signals s (psd_ratios). */
static void ratio_grad(const psd_phys *m, const double s[4], double x, double y, double gx[4],
                       double gy[4])
{
    if (m->s.detector == PSD_LATERAL && m->s.lateral == PSD_DUO) {
        double sx = s[0] + s[1], sy = s[2] + s[3];
        gx[0] = (-1.0 - x) / sx;
        gx[1] = (1.0 - x) / sx;
        gx[2] = gx[3] = 0.0;
        gy[0] = gy[1] = 0.0;
        gy[2] = (-1.0 - y) / sy;
        gy[3] = (1.0 - y) / sy;
        return;
    }
    double S = s[0] + s[1] + s[2] + s[3];
    for (int k = 0; k < PSD_CHANNELS; k++) {
        gx[k] = (ratio_cx[k] - x) / S;
        gy[k] = (ratio_cy[k] - y) / S;
    }
}

/* Scratch of the fdf: the parameters it fits, and per row the base
 * ratios (observed, predicted) and the stepped predictions. */
typedef struct {
    psd_rows *d;
    int nfree;
    int free[PSD_NP];
    double p[PSD_NP];                /* every parameter; the free ones from x */
    int tie_dark4;                   /* corner layouts: dark4 follows the others */
    double dark_xy;                  /* dark1 + dark2 - dark3 - dark4, held */
    double *xo, *yo, *xp, *yp, *xp2, *yp2;
} fdf_ctx;

static double row_weight(const psd_rows *d, size_t r)
{
    double w = d->w ? d->w[r] : 1.0;
    return w > 0 ? sqrt(w) : 0.0;
}

/* Base residuals; a row the model cannot read or predict counts nothing. */
static void base_residuals(fdf_ctx *c, double *f, size_t ld)
{
    psd_rows *d = c->d;
    psd_phys_set(&d->work, d->design, c->p);
    for (size_t r = 0; r < d->n; r++) {
        double rd[4] = {d->m[0][r], d->m[1][r], d->m[2][r], d->m[3][r]};
        if (psd_phys_observed(&d->work, rd, &c->xo[r], &c->yo[r]) != SUNMC_OK)
            c->xo[r] = c->yo[r] = NAN;
        if (psd_phys_predicted(&d->work, d->ut + 3 * r, &c->xp[r], &c->yp[r]) != SUNMC_OK)
            c->xp[r] = c->yp[r] = NAN;
        double sw = row_weight(d, r);
        int ok = isfinite(c->xo[r]) && isfinite(c->xp[r]) && sw > 0;
        f[2 * r] = ok ? sw * (c->xo[r] - c->xp[r]) / d->work.sens : 0.0;
        f[2 * r + 1] = ok ? sw * (c->yo[r] - c->yp[r]) / d->work.sens : 0.0;
    }
    for (size_t i = 2 * d->n; i < ld; i++)
        f[i] = 0.0;
}

/* Column of a geometry parameter: forward difference of the residuals (the
 * height moves the prediction and the scale 1 / sens alike). */
static void geometry_column(fdf_ctx *c, int j, const double *f, double *col)
{
    psd_rows *d = c->d;
    double keep = c->p[j], h = fd_step[j];
    c->p[j] = keep + h;
    psd_phys_set(&d->work, d->design, c->p);
    for (size_t r = 0; r < d->n; r++) {
        double x2, y2;
        int ok = isfinite(c->xo[r]) && isfinite(c->xp[r]);
        if (!ok || row_weight(d, r) == 0.0 ||
            psd_phys_predicted(&d->work, d->ut + 3 * r, &x2, &y2) != SUNMC_OK) {
            col[2 * r] = col[2 * r + 1] = 0.0;
            continue;
        }
        /* the residual's own difference: the height moves the scale too */
        double k = row_weight(d, r) / d->work.sens;
        col[2 * r] = (k * (c->xo[r] - x2) - f[2 * r]) / h;
        col[2 * r + 1] = (k * (c->yo[r] - y2) - f[2 * r + 1]) / h;
    }
    c->p[j] = keep;
}

/* Columns of the gains and darks: analytic, through the observed ratios. */
static void channel_columns(fdf_ctx *c, double *J, size_t ld, const int *col_of)
{
    psd_rows *d = c->d;
    psd_phys_set(&d->work, d->design, c->p);
    const psd_phys *m = &d->work;
    for (size_t r = 0; r < d->n; r++) {
        double sw = row_weight(d, r), s[4], gx[4], gy[4];
        int ok = isfinite(c->xo[r]) && isfinite(c->xp[r]) && sw > 0;
        for (int k = 0; k < PSD_CHANNELS; k++)
            s[k] = (d->m[k][r] - m->dark[k]) / m->gain[k];
        ratio_grad(m, s, c->xo[r], c->yo[r], gx, gy);
        /* d s_k / d dark_k = -1 / g_k;  d s_k / d g_k = -s_k / g_k */
        double kk = ok ? sw / m->sens : 0.0, dd[2][PSD_CHANNELS];
        for (int k = 0; k < PSD_CHANNELS; k++) {
            dd[0][k] = kk * gx[k] * (-1.0 / m->gain[k]);
            dd[1][k] = kk * gy[k] * (-1.0 / m->gain[k]);
            int jg = k > 0 ? col_of[PSD_P_G2 + k - 1] : -1;
            if (jg >= 0) {
                J[(size_t)jg * ld + 2 * r] = kk * gx[k] * (-s[k] / m->gain[k]);
                J[(size_t)jg * ld + 2 * r + 1] = kk * gy[k] * (-s[k] / m->gain[k]);
            }
        }
        if (c->tie_dark4) /* dark4 = dark1 + dark2 - dark3 - const */
            for (int a = 0; a < 2; a++) {
                dd[a][0] += dd[a][3];
                dd[a][1] += dd[a][3];
                dd[a][2] -= dd[a][3];
            }
        for (int k = 0; k < PSD_CHANNELS; k++) {
            int jd = col_of[PSD_P_D1 + k];
            if (jd >= 0) {
                J[(size_t)jd * ld + 2 * r] = dd[0][k];
                J[(size_t)jd * ld + 2 * r + 1] = dd[1][k];
            }
        }
    }
}

static int fdf(const double *x, void *params, double *f, double *J, size_t ld)
{
    fdf_ctx *c = params;
    int col_of[PSD_NP];
    for (int j = 0; j < PSD_NP; j++)
        col_of[j] = -1;
    for (int q = 0; q < c->nfree; q++) {
        c->p[c->free[q]] = x[q] * c->d->xscale[c->free[q]];
        col_of[c->free[q]] = q;
    }
    if (c->tie_dark4)
        c->p[PSD_P_D4] = c->p[PSD_P_D1] + c->p[PSD_P_D2] - c->p[PSD_P_D3] - c->dark_xy;
    base_residuals(c, f, ld);
    for (int q = 0; q < c->nfree; q++) {
        double *col = J + (size_t)q * ld;
        for (size_t i = 2 * c->d->n; i < ld; i++)
            col[i] = 0.0;
        if (c->free[q] < PSD_NP_GEOMETRY)
            geometry_column(c, c->free[q], f, col);
    }
    channel_columns(c, J, ld, col_of);
    for (int q = 0; q < c->nfree; q++) {
        double s = c->d->xscale[c->free[q]], *col = J + (size_t)q * ld;
        for (size_t i = 0; i < 2 * c->d->n; i++)
            col[i] *= s;
    }
    psd_phys_set(&c->d->work, c->d->design, c->p);
    return GSL_SUCCESS;
}

/* Corner layouts (tetra-lateral, quadrant): the ratios do not see the
 * darks' combination dark1 + dark2 - dark3 - dark4 (it adds as much to
 * each numerator's two sides and nothing to the sum), so dark4 follows the
 * other three.  Electrode pairs (duo-lateral): the y ratio does not see a
 * common scale of channels 3 and 4, so gain3 stays at its start. */
static int corner_layout(const psd_design *d)
{
    return !(d->detector == PSD_LATERAL && d->lateral == PSD_DUO);
}

int psd_phys_free(const psd_design *d, int fit_tilt, int *free)
{
    int n = 0;
    for (int j = 0; j < PSD_NP; j++) {
        if (!fit_tilt && (j == PSD_P_TX || j == PSD_P_TY))
            continue;
        if ((corner_layout(d) && j == PSD_P_D4) || (!corner_layout(d) && j == PSD_P_G3))
            continue;
        free[n++] = j;
    }
    return n;
}

int psd_phys_fit(fit_workspace *fw, psd_rows *d, int fit_tilt, double p[PSD_NP],
                 fit_result *res)
{
    fdf_ctx c = {.d = d, .tie_dark4 = corner_layout(d->design)};
    c.nfree = psd_phys_free(d->design, fit_tilt, c.free);
    if (fw->p != (size_t)c.nfree)
        return SUNMC_EFIT;
    int warm = 0;
    if (d->fw_channels) {
        double q[PSD_NP];
        fit_result r1;
        memcpy(q, p, sizeof q);
        int ok = psd_phys_fit_channels(d->fw_channels, d, fit_tilt, q, &r1) == SUNMC_OK;
        for (int j = 0; j < PSD_NP; j++)
            ok &= isfinite(q[j]);
        if (ok)
            memcpy(p, q, sizeof q);
        warm = ok;
    }
    /* from the first stage's answer the ratios' minimum is close: start
     * with the damping at its floor (fit.h, mu0) */
    fw->mu0 = warm ? PSD_FIT_MU0_WARM : PSD_FIT_MU0_COLD;
    memcpy(c.p, p, sizeof c.p);
    c.dark_xy = p[PSD_P_D1] + p[PSD_P_D2] - p[PSD_P_D3] - p[PSD_P_D4];
    double *buf = d->scratch, x[PSD_NP];
    c.xo = buf;
    c.yo = buf + d->n;
    c.xp = buf + 2 * d->n;
    c.yp = buf + 3 * d->n;
    c.xp2 = buf + 4 * d->n;
    c.yp2 = buf + 5 * d->n;
    /* variables of one size: 10 um, 1e-3 rad, 1 % of gain, 1 % of the
     * first channel's signal (its start value's straight-line slope) */
    double sig = fabs(d->sig1) > 0 && isfinite(d->sig1) ? fabs(d->sig1) : 1.0;
    for (int j = 0; j < PSD_NP; j++)
        d->xscale[j] = j < PSD_P_TX ? 1e-2 : j < PSD_P_G2 ? 1e-3 : j < PSD_P_D1 ? 1e-2 : 1e-2 * sig;
    for (int q = 0; q < c.nfree; q++)
        x[q] = p[c.free[q]] / d->xscale[c.free[q]];
    int st = fit_solve(fw, fdf, &c, x, PSD_FIT_MAX_ITER, res);
    for (int q = 0; q < c.nfree; q++)
        p[c.free[q]] = x[q] * d->xscale[c.free[q]];
    if (c.tie_dark4)
        p[PSD_P_D4] = p[PSD_P_D1] + p[PSD_P_D2] - p[PSD_P_D3] - c.dark_xy;
    return st;
}

/* ---- a fitted calibration ---- */

void psd_cal_nominal(psd_cal *k, const psd_design *d)
{
    memset(k, 0, sizeof *k);
    k->model = PSD_MODEL_PHYSICAL;
    k->design = d;
    for (int c = 1; c < PSD_CHANNELS; c++)
        k->p[PSD_P_G2 + c - 1] = 1.0;
    for (int c = 0; c < PSD_CHANNELS; c++)
        k->p[PSD_P_D1 + c] = d->dark_fs;
    psd_phys_set(&k->phys, d, k->p);
}

int psd_cal_angles(const psd_cal *k, const double r[4], double *alpha, double *beta)
{
    if (k->model == PSD_MODEL_POLYNOMIAL)
        return psd_poly_eval(&k->poly, k->design, r, alpha, beta);
    if (PSD_MODEL_HAS_SPLINE(k->model)) {
        double in[2], t[2];
        if (psd_spline_inputs(k, r, in) != SUNMC_OK || psd_spline_eval(k, in, t) != SUNMC_OK)
            return SUNMC_EDOM;
        int hyb = k->model == PSD_MODEL_HYBRID;
        *alpha = atan(t[0] + (hyb ? in[0] : 0.0));
        *beta = atan(t[1] + (hyb ? in[1] : 0.0));
        return SUNMC_OK;
    }
    double x, y, ut[3];
    if (psd_phys_observed(&k->phys, r, &x, &y) != SUNMC_OK ||
        psd_phys_invert(&k->phys, x, y, ut) != SUNMC_OK)
        return SUNMC_EDOM;
    sun_angles_of(ut, alpha, beta);
    return SUNMC_OK;
}
