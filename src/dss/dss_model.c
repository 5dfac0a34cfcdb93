/* dss_model.c - the physical DSS calibration model (see dss_model.h). */
#include "dss_model.h"
#include "dss_optics.h"
#include "dss_rotation.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

const char *const dss_param_names[DSS_NP] = {"x0_mm", "y0_mm", "H_mm", "t_mm",
                                              "c1_rad", "c2_rad", "c3_rad", "n"};

void dss_model_init(dss_model *m, const dss_design *d)
{
    memset(m, 0, sizeof *m);
    m->p[DSS_P_H] = d->h_mm;
    m->p[DSS_P_T] = d->glass_thickness_mm;
    m->p[DSS_P_N] = d->glass_index;
    m->pixel_mm = d->pixel_um * MM_PER_UM;
    dss_model_prepare(m);
}

void dss_model_prepare(dss_model *m)
{
    double c1 = m->p[DSS_P_C1], c2 = m->p[DSS_P_C2], c3 = m->p[DSS_P_C3];
    dss_zxy(c1, c2, c3, m->M);
    dss_zxy_deriv(c1, c2, c3, m->dM[0], m->dM[1], m->dM[2]);
    for (int i = 0; i < 3; i++) {
        m->v0[i] = m->M[2][i];
        for (int k = 0; k < 3; k++)
            m->dv0[k][i] = m->dM[k][2][i];
    }
}

int dss_model_spot(const dss_model *m, double b1, double b2, double spot_px[2],
                   double J[2][DSS_NP])
{
    mat3 R;
    dss_table_rotation(b1, b2, R);
    double w[3], u[3];
    mat3_vec(R, m->v0, w);
    mat3_vec(m->M, w, u);
    double H = m->p[DSS_P_H], t = m->p[DSS_P_T], n = m->p[DSS_P_N];
    if (!(u[2] > 0.0) || !(n * n > u[0] * u[0] + u[1] * u[1]))
        return SUNMC_EDOM;
    double g[DSS_OPTICS_NGRAD];
    double q = dss_optics_q(u, H, t, n, J ? g : NULL);
    double inv_pix = 1.0 / m->pixel_mm;
    spot_px[0] = (m->p[DSS_P_X0] - u[0] * q) * inv_pix;
    spot_px[1] = (m->p[DSS_P_Y0] - u[1] * q) * inv_pix;
    if (!J)
        return SUNMC_OK;

    for (int a = 0; a < 2; a++) {
        double ua = u[a];
        J[a][DSS_P_X0] = a == 0 ? inv_pix : 0.0;
        J[a][DSS_P_Y0] = a == 1 ? inv_pix : 0.0;
        J[a][DSS_P_H] = -ua * g[3] * inv_pix;
        J[a][DSS_P_T] = -ua * g[4] * inv_pix;
        J[a][DSS_P_N] = -ua * g[5] * inv_pix;
        /* d spot_a / d u_j = -(delta_aj q + u_a dq/du_j) */
        double dsdu[3];
        for (int j = 0; j < 3; j++)
            dsdu[j] = -((a == j ? q : 0.0) + ua * g[j]) * inv_pix;
        for (int k = 0; k < 3; k++) {
            /* du/dc_k = dM_k R v0 + M R dv0_k */
            double t1[3], t2[3], t3[3];
            mat3_vec(m->dM[k], w, t1);
            mat3_vec(R, m->dv0[k], t2);
            mat3_vec(m->M, t2, t3);
            double d = 0.0;
            for (int j = 0; j < 3; j++)
                d += dsdu[j] * (t1[j] + t3[j]);
            J[a][DSS_P_C1 + k] = d;
        }
    }
    return SUNMC_OK;
}

int dss_model_compensate(const dss_model *m, double x_px, double y_px, double *alpha,
                         double *beta)
{
    double dx = m->p[DSS_P_X0] - x_px * m->pixel_mm;
    double dy = m->p[DSS_P_Y0] - y_px * m->pixel_mm;
    double r = hypot(dx, dy), theta;
    int st = dss_optics_field_angle(r, m->p[DSS_P_H], m->p[DSS_P_T], m->p[DSS_P_N], &theta);
    if (st != SUNMC_OK)
        return st;
    double u[3] = {0.0, 0.0, 1.0};
    if (r > 0.0) {
        double s = sin(theta);
        u[0] = dx / r * s;
        u[1] = dy / r * s;
        u[2] = cos(theta);
    }
    mat3 Mt;
    mat3_transpose(m->M, Mt);
    double w[3], b1, b2;
    mat3_vec(Mt, u, w);
    if ((st = dss_table_solve(m->v0, w, &b1, &b2)) != SUNMC_OK)
        return st;
    dss_table_truth(b1, b2, alpha, beta);
    return SUNMC_OK;
}
