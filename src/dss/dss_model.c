/* dss_model.c - the physical DSS calibration model (see dss_model.h). */
#include "dss_model.h"
#include "dss_lane.h"
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

VM_NOSAN int dss_model_spot(const dss_model *m, double b1, double b2, double spot_px[2],
                            double J[2][DSS_NP])
{
    dss_lane_model e = dss_lane_model_spot(m, dss_lane_table_of(b1, b2), J != NULL);
    if (!e.ok)
        return SUNMC_EDOM;
    spot_px[0] = e.x;
    spot_px[1] = e.y;
    if (J) {
        const dss_lane_par *g[2] = {&e.jx, &e.jy};
        for (int a = 0; a < 2; a++) {
            double v[DSS_NP] = {g[a]->x0, g[a]->y0, g[a]->H,  g[a]->t,
                                g[a]->c1, g[a]->c2, g[a]->c3, g[a]->n};
            for (int j = 0; j < DSS_NP; j++)
                J[a][j] = v[j];
        }
    }
    return SUNMC_OK;
}

/* dss_model_compensate: dss_model_batch.c, as the batches. */
