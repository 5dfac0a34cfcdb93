/* psd_fitchan.c - the physical model's first fit stage: the four channel
 * signals themselves, each reading's light projected out (psd_model.h,
 * psd_phys_fit_channels). */
#include "psd_model.h"
#include "status.h"
#include "vmath.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <string.h>

/* Forward-difference steps of the geometry columns (internal units). */
static const double fd_step[PSD_NP_GEOMETRY] = {1e-6, 1e-6, 1e-6, 1e-7, 1e-7, 1e-7};

/* ---- the fit: the four channels, each reading's light projected out ----
 *
 * Row r's dark-corrected channels v_k = m_k - dark_k are predicted as
 * P_r a_k with a_k = gain_k i_k (i_k the photocurrents of unit light, the
 * geometry's) and P_r the light that reached the sensor at that reading,
 * which the lab does not know (lamp drift, a beam that is not uniform over
 * the table's travel, the cosine): P_r = a.v / a.a, the least-squares
 * value for the other parameters (variable projection).  The residuals are
 * v - P_r a, four per row, divided by the fixed scale S0 sens (S0 the
 * start's mean dark-corrected sum) so that they are about radians like the
 * compensated angles.  Unlike the two ratios, the four channels see every
 * dark signal (the corner layouts' product i1 i2 / (i3 i4) is fixed by the
 * geometry) and give no minimum where gains run away and both ratios sit
 * at a corner. */

typedef struct {
    psd_rows *d;
    int nfree;
    int free[PSD_NP];
    double p[PSD_NP];                /* every parameter; the free ones from x */
    double scale;                    /* 1 / (S0 sens) */
    double *a;                       /* 4 n: unit-light currents of the base */
    double *P;                       /* n: each row's projected light (NaN: unused row) */
} fdf_ctx;

static double row_weight(const psd_rows *d, size_t r)
{
    double w = d->w ? d->w[r] : 1.0;
    return w > 0 ? sqrt(w) : 0.0;
}

/* Unit-light currents of row r under m; SUNMC_EDOM when it sees no sun. */
static int row_currents(const psd_phys *m, const double ut[3], double i[4])
{
    double u[3], spot[2];
    mat3_vec(m->s.M, ut, u);
    if (psd_sensor_spot(&m->s, u, spot) != SUNMC_OK)
        return SUNMC_EDOM;
    psd_sensor_currents(&m->s, spot, u[2], i);
    return i[0] + i[1] + i[2] + i[3] > 0.0 ? SUNMC_OK : SUNMC_EDOM;
}

/* Base residuals; a row the model cannot predict counts nothing. */
static void base_residuals(fdf_ctx *c, double *f, size_t ld)
{
    psd_rows *d = c->d;
    psd_phys_set(&d->work, d->design, c->p);
    const psd_phys *m = &d->work;
    for (size_t r = 0; r < d->n; r++) {
        double *i = c->a + 4 * r, sw = row_weight(d, r), aa = 0.0, av = 0.0, v[4];
        int ok = sw > 0 && row_currents(m, d->ut + 3 * r, i) == SUNMC_OK;
        for (int k = 0; k < PSD_CHANNELS; k++) {
            v[k] = d->m[k][r] - m->dark[k];
            aa += m->gain[k] * i[k] * m->gain[k] * i[k];
            av += m->gain[k] * i[k] * v[k];
        }
        c->P[r] = ok && aa > 0 ? av / aa : NAN;
        ok = isfinite(c->P[r]);
        for (int k = 0; k < PSD_CHANNELS; k++)
            f[4 * r + k] = ok ? sw * c->scale * (v[k] - c->P[r] * m->gain[k] * i[k]) : 0.0;
    }
    for (size_t i = 4 * d->n; i < ld; i++)
        f[i] = 0.0;
}

/* d residual / d (a) for a change da of the model vector at row r:
 * -(P da + a (da.v - 2 P a.da) / a.a), with v = P a + residual. */
static void projected_column(const double a[4], const double v[4], double P, const double da[4],
                             double k, double *col)
{
    double aa = 0.0, dav = 0.0, ada = 0.0;
    for (int q = 0; q < PSD_CHANNELS; q++) {
        aa += a[q] * a[q];
        dav += da[q] * v[q];
        ada += a[q] * da[q];
    }
    double dP = (dav - 2.0 * P * ada) / aa;
    for (int q = 0; q < PSD_CHANNELS; q++)
        col[q] = -k * (P * da[q] + a[q] * dP);
}

/* Row r's model vector a_k = gain_k i_k and signals v_k under c->p. */
static void row_vectors(const fdf_ctx *c, size_t r, double a[4], double v[4])
{
    const psd_phys *m = &c->d->work;
    for (int k = 0; k < PSD_CHANNELS; k++) {
        a[k] = m->gain[k] * c->a[4 * r + k];
        v[k] = c->d->m[k][r] - m->dark[k];
    }
}

/* Column of a geometry parameter: forward difference of the currents. */
static void geometry_column(fdf_ctx *c, int j, double *col)
{
    psd_rows *d = c->d;
    double keep = c->p[j], h = fd_step[j];
    c->p[j] = keep + h;
    psd_phys_set(&d->work, d->design, c->p);
    for (size_t r = 0; r < d->n; r++) {
        double i2[4], a[4], v[4], da[4];
        if (!isfinite(c->P[r]) || row_currents(&d->work, d->ut + 3 * r, i2) != SUNMC_OK) {
            col[4 * r] = col[4 * r + 1] = col[4 * r + 2] = col[4 * r + 3] = 0.0;
            continue;
        }
        row_vectors(c, r, a, v);
        for (int k = 0; k < PSD_CHANNELS; k++)
            da[k] = d->work.gain[k] * (i2[k] - c->a[4 * r + k]) / h;
        projected_column(a, v, c->P[r], da, row_weight(d, r) * c->scale, col + 4 * r);
    }
    c->p[j] = keep;
    psd_phys_set(&d->work, d->design, c->p);
}

/* Columns of the gains and darks: analytic. */
static void channel_columns(fdf_ctx *c, double *J, size_t ld, const int *col_of)
{
    psd_rows *d = c->d;
    for (size_t r = 0; r < d->n; r++) {
        double a[4], v[4], aa = 0.0, k = row_weight(d, r) * c->scale;
        int ok = isfinite(c->P[r]);
        row_vectors(c, r, a, v);
        for (int q = 0; q < PSD_CHANNELS; q++)
            aa += a[q] * a[q];
        for (int ch = 0; ch < PSD_CHANNELS; ch++) {
            int jg = ch > 0 ? col_of[PSD_P_G2 + ch - 1] : -1, jd = col_of[PSD_P_D1 + ch];
            if (jg >= 0) { /* d a / d gain_ch = i_ch e_ch */
                double da[4] = {0, 0, 0, 0};
                da[ch] = c->a[4 * r + ch];
                if (ok)
                    projected_column(a, v, c->P[r], da, k, J + (size_t)jg * ld + 4 * r);
                else
                    memset(J + (size_t)jg * ld + 4 * r, 0, 4 * sizeof *J);
            }
            if (jd >= 0) /* d v / d dark_ch = -e_ch; P moves by -a_ch / a.a */
                for (int q = 0; q < PSD_CHANNELS; q++)
                    J[(size_t)jd * ld + 4 * r + q] =
                        ok ? k * ((q == ch ? -1.0 : 0.0) + a[q] * a[ch] / aa) : 0.0;
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
    base_residuals(c, f, ld);
    for (int q = 0; q < c->nfree; q++) {
        double *col = J + (size_t)q * ld;
        for (size_t i = 4 * c->d->n; i < ld; i++)
            col[i] = 0.0;
        if (c->free[q] < PSD_NP_GEOMETRY)
            geometry_column(c, c->free[q], col);
    }
    channel_columns(c, J, ld, col_of);
    for (int q = 0; q < c->nfree; q++) {
        double s = c->d->xscale[c->free[q]], *col = J + (size_t)q * ld;
        for (size_t i = 0; i < 4 * c->d->n; i++)
            col[i] *= s;
    }
    return GSL_SUCCESS;
}

/* The mean |dark-corrected sum| of the rows under p (the residuals' scale). */
static double signal_scale(const psd_rows *d, const double p[PSD_NP])
{
    double s = 0.0;
    size_t n = 0;
    for (size_t r = 0; r < d->n; r++) {
        double sum = 0.0;
        for (int k = 0; k < PSD_CHANNELS; k++)
            sum += d->m[k][r] - p[PSD_P_D1 + k];
        if (row_weight(d, r) > 0 && isfinite(sum)) {
            s += fabs(sum);
            n++;
        }
    }
    return n && s > 0 ? s / (double)n : 1.0;
}

int psd_phys_fit_channels(fit_workspace *fw, psd_rows *d, int fit_tilt, double p[PSD_NP],
                          fit_result *res)
{
    fdf_ctx c = {.d = d};
    for (int j = 0; j < PSD_NP; j++)
        if (fit_tilt || (j != PSD_P_TX && j != PSD_P_TY))
            c.free[c.nfree++] = j;
    if (fw->p != (size_t)c.nfree || fw->n < PSD_RESIDUALS_PER_ROW * d->n)
        return SUNMC_EFIT;
    memcpy(c.p, p, sizeof c.p);
    c.a = d->scratch;
    c.P = d->scratch + 4 * d->n;
    psd_phys_set(&d->work, d->design, p);
    c.scale = 1.0 / (signal_scale(d, p) * d->work.sens);
    /* variables of one size, as psd_phys_fit's */
    double sig = fabs(d->sig1) > 0 && isfinite(d->sig1) ? fabs(d->sig1) : 1.0, x[PSD_NP];
    for (int j = 0; j < PSD_NP; j++)
        d->xscale[j] = j < PSD_P_TX ? 1e-2 : j < PSD_P_G2 ? 1e-3 : j < PSD_P_D1 ? 1e-2 : 1e-2 * sig;
    for (int q = 0; q < c.nfree; q++)
        x[q] = p[c.free[q]] / d->xscale[c.free[q]];
    int st = fit_solve(fw, fdf, &c, x, PSD_FIT_MAX_ITER, res);
    for (int q = 0; q < c.nfree; q++)
        p[c.free[q]] = x[q] * d->xscale[c.free[q]];
    return st;
}

