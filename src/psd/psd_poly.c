/* psd_poly.c - the field's polynomial calibration (see psd_model.h). */
#include "psd_model.h"
#include "status.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <math.h>
#include <string.h>

int psd_poly_init(psd_poly *q, int order, int form)
{
    memset(q, 0, sizeof *q);
    q->order = order;
    q->form = form;
    for (int deg = 0; deg <= order; deg++)
        for (int ey = 0; ey <= deg; ey++) {
            int ex = deg - ey;
            if (form == PSD_POLY_FSS20 && ex == 2 && ey == 2)
                continue; /* FSScalibration's 20 terms leave x^2 y^2 out */
            q->ex[q->nt] = ex;
            q->ey[q->nt] = ey;
            q->nt++;
        }
    return q->nt;
}

int psd_poly_ratios(const psd_design *d, const double r[4], double *x, double *y)
{
    psd_ratios(d->detector, d->lateral, r, x, y);
    return isfinite(*x) && isfinite(*y) ? SUNMC_OK : SUNMC_EDOM;
}

static void terms(const psd_poly *q, double x, double y, double *t)
{
    double px[PSD_POLY_MAX_ORDER + 1], py[PSD_POLY_MAX_ORDER + 1];
    x /= q->scale;
    y /= q->scale;
    px[0] = py[0] = 1.0;
    for (int k = 1; k <= q->order; k++) {
        px[k] = px[k - 1] * x;
        py[k] = py[k - 1] * y;
    }
    for (int k = 0; k < q->nt; k++)
        t[k] = px[q->ex[k]] * py[q->ey[k]];
}

int psd_poly_fit(psd_poly *q, const psd_rows *d, double *work)
{
    int nt = q->nt;
    double *A = work, *b = work + nt * nt, *c = b + nt, t[PSD_POLY_MAX_TERMS];
    memset(A, 0, (size_t)(nt * nt + 2 * nt) * sizeof *A);
    q->scale = 0.0;
    for (size_t r = 0; r < d->n; r++) {
        double x, y, rd[4] = {d->m[0][r], d->m[1][r], d->m[2][r], d->m[3][r]};
        if ((!d->w || d->w[r] > 0) && psd_poly_ratios(d->design, rd, &x, &y) == SUNMC_OK)
            q->scale = fmax(q->scale, fmax(fabs(x), fabs(y)));
    }
    if (!(q->scale > 0.0))
        return SUNMC_EFIT;
    for (size_t r = 0; r < d->n; r++) {
        double w = d->w ? d->w[r] : 1.0, x, y;
        double rd[4] = {d->m[0][r], d->m[1][r], d->m[2][r], d->m[3][r]};
        const double *u = d->ut + 3 * r;
        if (!(w > 0) || psd_poly_ratios(d->design, rd, &x, &y) != SUNMC_OK)
            continue;
        terms(q, x, y, t);
        for (int i = 0; i < nt; i++) {
            for (int j = 0; j <= i; j++)
                A[i * nt + j] += w * t[i] * t[j];
            b[i] += w * t[i] * u[0] / u[2];
            c[i] += w * t[i] * u[1] / u[2];
        }
    }
    for (int i = 0; i < nt; i++)
        for (int j = i + 1; j < nt; j++)
            A[i * nt + j] = A[j * nt + i];
    gsl_matrix_view Av = gsl_matrix_view_array(A, (size_t)nt, (size_t)nt);
    gsl_vector_view bv = gsl_vector_view_array(b, (size_t)nt), cv = gsl_vector_view_array(c, (size_t)nt);
    if (gsl_linalg_cholesky_decomp1(&Av.matrix) != GSL_SUCCESS)
        return SUNMC_EFIT;
    if (gsl_linalg_cholesky_svx(&Av.matrix, &bv.vector) != GSL_SUCCESS ||
        gsl_linalg_cholesky_svx(&Av.matrix, &cv.vector) != GSL_SUCCESS)
        return SUNMC_EFIT;
    for (int k = 0; k < nt; k++) {
        q->ca[k] = b[k];
        q->cb[k] = c[k];
        if (!isfinite(b[k]) || !isfinite(c[k]))
            return SUNMC_EFIT;
    }
    return SUNMC_OK;
}

int psd_poly_eval(const psd_poly *q, const psd_design *d, const double r[4], double *alpha,
                  double *beta)
{
    double x, y, t[PSD_POLY_MAX_TERMS], ta = 0.0, tb = 0.0;
    if (psd_poly_ratios(d, r, &x, &y) != SUNMC_OK)
        return SUNMC_EDOM;
    terms(q, x, y, t);
    for (int k = 0; k < q->nt; k++) {
        ta += q->ca[k] * t[k];
        tb += q->cb[k] * t[k];
    }
    *alpha = atan(ta);
    *beta = atan(tb);
    return SUNMC_OK;
}
