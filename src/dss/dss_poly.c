/* dss_poly.c - 2-D polynomial correction of the DSS angles (see dss_poly.h). */
#include "dss_poly.h"
#include "status.h"

#include <math.h>
#include <string.h>

int dss_poly_n_terms(int order) { return (order + 1) * (order + 2) / 2; }

void dss_poly_basis(int order, double u, double v, double *t)
{
    int k = 0;
    for (int d = 0; d <= order; d++)
        for (int j = 0; j <= d; j++) /* u^(d-j) v^j */
            t[k++] = pow(u, d - j) * pow(v, j);
}

void dss_poly_init(dss_poly *p, int order, const dss_onboard *o, double fov_rad)
{
    memset(p, 0, sizeof *p);
    p->order = order;
    p->n_terms = dss_poly_n_terms(order);
    p->scale_rad = fov_rad;
    p->onboard = *o;
}

void dss_poly_apply(const dss_poly *p, double alpha_m, double beta_m, double *alpha,
                    double *beta)
{
    double t[DSS_POLY_MAX_TERMS];
    dss_poly_basis(p->order, alpha_m / p->scale_rad, beta_m / p->scale_rad, t);
    double a = alpha_m, b = beta_m;
    for (int k = 0; k < p->n_terms; k++) {
        a += p->ca[k] * t[k];
        b += p->cb[k] * t[k];
    }
    *alpha = a;
    *beta = b;
}

int dss_poly_compensate(const dss_poly *p, double x_px, double y_px, double *alpha,
                        double *beta)
{
    double am, bm;
    int st = dss_onboard_angles(&p->onboard, x_px, y_px, &am, &bm);
    if (st != SUNMC_OK)
        return st;
    dss_poly_apply(p, am, bm, alpha, beta);
    return SUNMC_OK;
}
