/* dss_thermal.c - a DSS unit at another temperature (see dss_thermal.h). */
#include "dss_thermal.h"
#include "dss_config.h"
#include "units.h"

#define PER_PPM 1e-6

void dss_deviations_at_temp(const sunmc_config *c, const dss_deviations *d, double temp_c,
                            dss_deviations *out)
{
    *out = *d;
    double dT = temp_c - c->cal_temp_c;
    if (dT == 0.0)
        return;
    const dss_design *g = &dss_cfg(c)->design;
    double p_mm = g->pixel_um * MM_PER_UM;
    double pitch = 1.0 + (c->detector_cte_ppm_k + d->detector_cte_ppm_k) * PER_PPM * dT;
    double h_mm = (g->h_mm + d->dh_px * p_mm) *
                  (1.0 + (c->spacer_cte_ppm_k + d->spacer_cte_ppm_k) * PER_PPM * dT);
    double t_mm = (g->glass_thickness_mm + d->glass_thickness_um * MM_PER_UM) *
                  (1.0 + (c->glass_cte_ppm_k + d->glass_cte_ppm_k) * PER_PPM * dT);
    out->dh_px = (h_mm / pitch - g->h_mm) / p_mm;
    out->glass_thickness_um = (t_mm / pitch - g->glass_thickness_mm) * UM_PER_MM;
    double dn_dt = (c->glass_dn_dt_ppm_k + d->glass_dn_dt_ppm_k) * PER_PPM;
    out->glass_index = d->glass_index + dn_dt * dT;
    out->dx_px = d->dx_px / pitch;
    out->dy_px = d->dy_px / pitch;
}
