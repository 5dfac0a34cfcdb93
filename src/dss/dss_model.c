/* dss_model.c - the physical DSS calibration model (see dss_model.h). */
#include "dss_model.h"
#include "dss_lane.h"
#include "rotation.h"
#include "dss_sensor.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

const char *const dss_param_names[DSS_NP] = {
    "fit_dx_px",     "fit_dy_px",     "fit_dh_px",       "fit_glass_thickness_um",
    "fit_c1_arcsec", "fit_c2_arcsec", "fit_c3_arcsec",   "fit_glass_index",
    "fit_sun_b1_arcsec", "fit_sun_b2_arcsec", "fit_detector_tilt_x_arcsec",
    "fit_detector_tilt_y_arcsec"};

double dss_param_scale(const dss_model *m, int k)
{
    switch (k) {
    case DSS_P_X0: case DSS_P_Y0: case DSS_P_H:
        return 1.0 / m->pixel_mm;
    case DSS_P_T:
        return UM_PER_MM;
    case DSS_P_N:
        return 1.0;
    default: /* c1-c3, s1, s2, tx, ty */
        return ARCSEC_PER_RAD;
    }
}

double dss_param_value(const dss_model *m, int k)
{
    return (m->p[k] - m->nominal[k]) * dss_param_scale(m, k);
}

void dss_param_set(dss_model *m, int k, double value)
{
    m->p[k] = m->nominal[k] + value / dss_param_scale(m, k);
}

void dss_model_init(dss_model *m, const dss_design *d)
{
    memset(m, 0, sizeof *m);
    m->p[DSS_P_H] = d->h_mm;
    m->p[DSS_P_T] = d->glass_thickness_mm;
    m->p[DSS_P_N] = d->glass_index;
    m->pixel_um = d->pixel_um;
    m->pixel_mm = d->pixel_um * MM_PER_UM;
    m->half_px = 0.5 * d->detector_px;
    m->mount = d->mount;
    m->tilt = d->fit_tilt != 0;
    m->disc_c_rad2 = dss_disc_coefficient(d->sun_disc_deg, d->limb_darkening);
    memcpy(m->nominal, m->p, sizeof m->nominal);
    dss_model_prepare(m);
}

void dss_model_prepare(dss_model *m)
{
    double c1 = m->p[DSS_P_C1], c2 = m->p[DSS_P_C2], c3 = m->p[DSS_P_C3];
    rot_zxy(c1, c2, c3, m->M);
    rot_zxy_deriv(c1, c2, c3, m->dM[0], m->dM[1], m->dM[2]);
    double s1 = m->p[DSS_P_S1], s2 = m->p[DSS_P_S2];
    dss_sun_direction(m->mount, m->M, s1, s2, m->v0);
    rot_zxy(m->p[DSS_P_TX], m->p[DSS_P_TY], 0.0, m->D);
    mat3 dz;
    rot_zxy_deriv(m->p[DSS_P_TX], m->p[DSS_P_TY], 0.0, m->dD[0], m->dD[1], dz);
    memset(m->dv0, 0, sizeof m->dv0);
    if (m->mount == DSS_MOUNT_ALIGNED) {
        /* v = M^T e_z, the third row of M */
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++)
                m->dv0[k][i] = m->dM[k][2][i];
    } else {
        /* v = R(s1, s2) e_z, the third column of rot_zxy(s1, s2, 0) */
        mat3 d1, d2, d3;
        rot_zxy_deriv(s1, s2, 0.0, d1, d2, d3);
        for (int i = 0; i < 3; i++) {
            m->dv0[3][i] = d1[i][2];
            m->dv0[4][i] = d2[i][2];
        }
    }
}

VM_NOSAN int dss_model_spot(const dss_model *m, double b1, double b2, double spot_px[2],
                            double J[2][DSS_NP])
{
    dss_lane_model e = dss_lane_model_spot(m, geo_table_of(b1, b2), J != NULL);
    if (!e.ok)
        return SUNMC_EDOM;
    spot_px[0] = e.x;
    spot_px[1] = e.y;
    if (J) {
        const dss_lane_par *g[2] = {&e.jx, &e.jy};
        for (int a = 0; a < 2; a++) {
            double v[DSS_NP] = {g[a]->x0, g[a]->y0, g[a]->H,  g[a]->t,  g[a]->c1, g[a]->c2,
                                g[a]->c3, g[a]->n,  g[a]->s1, g[a]->s2, g[a]->tx, g[a]->ty};
            for (int j = 0; j < DSS_NP; j++)
                J[a][j] = v[j];
        }
    }
    return SUNMC_OK;
}

/* dss_model_compensate: dss_model_batch.c, as the batches. */

void dss_model_truth(const dss_model *m, double b1, double b2, double *alpha, double *beta)
{
    dss_truth_angles(m->mount, m->v0, b1, b2, alpha, beta);
}
