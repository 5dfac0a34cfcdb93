/* ess_thermal.c - an ESS unit at another temperature (see ess_thermal.h). */
#include "ess_thermal.h"
#include "ess_config.h"
#include "units.h"

#define PER_PPM 1e-6

void ess_deviations_at_temp(const sunmc_config *c, const ess_deviations *d, double temp_c,
                            ess_deviations *out)
{
    *out = *d;
    double dT = temp_c - c->cal_temp_c;
    if (dT == 0.0)
        return;
    double H_mm = ess_cfg(c)->design.H_mm;
    double Hr_mm = H_mm + d->dH_um * MM_PER_UM;
    double grow = 1.0 + (c->spacer_cte_ppm_k + d->spacer_cte_ppm_k) * PER_PPM * dT;
    double pitch = 1.0 + (c->mask_cte_ppm_k + d->mask_cte_ppm_k) * PER_PPM * dT;
    out->dH_um = (Hr_mm * grow / pitch - H_mm) * UM_PER_MM;
}
