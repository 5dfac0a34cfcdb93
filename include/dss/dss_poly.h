/* dss_poly.h - the conventional DSS calibration the DSS paper names: a 2-D
 * polynomial of the angle errors.
 *
 * From the on-board angles (alpha_m, beta_m) of dss_onboard.h (rad), with
 * u = alpha_m / s, v = beta_m / s (s = the design's half field of view, so
 * |u|, |v| <= 1 keep the normal equations conditioned):
 *     alpha = alpha_m + sum_k ca[k] T_k(u, v)
 *     beta  = beta_m  + sum_k cb[k] T_k(u, v)
 * T_k runs over the monomials u^i v^j with i + j <= order, by total degree
 * then falling power of u: 1, u, v, u^2, uv, v^2, u^3, ...  Coefficients in
 * rad.  The fit (dss_calib.h) is linear least squares on the same fit.h
 * engine as the physical model.
 */
#ifndef SUNMC_DSS_POLY_H
#define SUNMC_DSS_POLY_H

#include "dss_onboard.h"

#define DSS_POLY_MAX_ORDER 7
#define DSS_POLY_MAX_TERMS ((DSS_POLY_MAX_ORDER + 1) * (DSS_POLY_MAX_ORDER + 2) / 2)

typedef struct {
    int order;
    int n_terms;
    double scale_rad;          /* s above */
    dss_onboard onboard;       /* the on-board formula it corrects */
    double ca[DSS_POLY_MAX_TERMS];
    double cb[DSS_POLY_MAX_TERMS];
} dss_poly;

/* Number of monomials of total degree <= order. */
int dss_poly_n_terms(int order);

/* The monomials T_k(u, v), k < dss_poly_n_terms(order), into t. */
void dss_poly_basis(int order, double u, double v, double *t);

/* Zero polynomial of order `order` (1..DSS_POLY_MAX_ORDER) on top of the
 * on-board formula o, normalised by the half field fov_rad. */
void dss_poly_init(dss_poly *p, int order, const dss_onboard *o, double fov_rad);

/* Corrected angles (rad) from on-board angles (rad). */
void dss_poly_apply(const dss_poly *p, double alpha_m, double beta_m, double *alpha,
                    double *beta);

/* Calibrated angles (rad) of a spot (px): the on-board formula, then
 * dss_poly_apply.  SUNMC_EDOM where the on-board formula has no angle. */
int dss_poly_compensate(const dss_poly *p, double x_px, double y_px, double *alpha,
                         double *beta);

#endif
