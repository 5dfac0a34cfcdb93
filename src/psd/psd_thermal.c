/* psd_thermal.c - a four-channel unit at another temperature (see psd_thermal.h). */
#include "psd_thermal.h"

#include <math.h>

#define PER_PPM 1e-6

void psd_sensor_at_temp(const sunmc_config *c, const psd_sensor *s, double temp_c,
                        psd_sensor *out)
{
    *out = *s;
    double dT = temp_c - c->cal_temp_c;
    if (dT == 0.0)
        return;
    const psd_config *p = psd_cfg(c);
    out->h_mm = s->h_mm * (1.0 + c->spacer_cte_ppm_k * PER_PPM * dT);
    out->glass_t_mm = s->glass_t_mm * (1.0 + c->glass_cte_ppm_k * PER_PPM * dT);
    out->glass_n = s->glass_n + c->glass_dn_dt_ppm_k * PER_PPM * dT;
    double dark = p->dark_doubling_k > 0 ? pow(2.0, dT / p->dark_doubling_k) : 1.0;
    double gain = 1.0 + p->responsivity_tc_ppm_k * PER_PPM * dT;
    for (int k = 0; k < PSD_CHANNELS; k++) {
        out->dark[k] = s->dark[k] * dark;
        out->gain[k] = s->gain[k] * gain;
    }
}
