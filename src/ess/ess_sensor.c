/* ess_sensor.c - one ESS unit: its sampled deviations, its construction and
 * its raw output for a sun direction (the pieces are in ess_slit.c,
 * ess_finecode.c and ess_coarse.c). */
#include "ess_sensor.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

/* Sun closer to grazing than this is not seen by the sensor. */
#define ESS_MIN_COS_INCIDENCE 0.0175 /* cos(89 deg) */

_Static_assert(sizeof(ess_deviations) == ESS_N_DEV * sizeof(double),
               "ess_deviations: one double per column of ESS_DEVIATIONS, then the roll");

ESS_DEVIATIONS(DEVIATION_X_COLUMNS)

const deviation_spec ess_deviation_list[ESS_N_TOL] = {
#define ESS_X_SPEC(name, unit, count, stream, ...)                                                \
    DEVIATION_SPEC(ess_config, ess_deviations, name, count, stream),
    ESS_DEVIATIONS(ESS_X_SPEC)
#undef ESS_X_SPEC
};

const char *const ess_deviation_names[ESS_N_DEV] = {
    ESS_DEVIATIONS(DEVIATION_X_NAMES)
    "roll_measured_arcsec"};

void ess_deviations_values(const ess_deviations *d, double out[ESS_N_DEV])
{
    int k = deviations_values(ess_deviation_list, ESS_N_TOL, d, out, ESS_N_DEV);
    out[k] = d->roll_measured_arcsec;
}

void ess_deviations_sample(const sunmc_config *c, uint64_t seed, long unit, ess_deviations *d)
{
    memset(d, 0, sizeof *d);
    deviations_sample(ess_deviation_list, ESS_N_TOL, c, seed, unit, d);
    rng_stream r;
    rng_stream_init(&r, seed, (uint64_t)unit, RNG_STREAM_ALIGNMENT);
    d->roll_measured_arcsec =
        d->install_x_arcsec + ess_cfg(c)->roll_sigma_arcsec * rng_normal(&r);
}

void ess_sensor_init(ess_sensor *s, const ess_design *d, const ess_deviations *dev)
{
    memset(s, 0, sizeof *s);
    s->H_mm = d->H_mm;
    s->Hr_mm = d->H_mm + dev->dH_um * MM_PER_UM;
    s->dd_mm = dev->dd_um * MM_PER_UM;
    s->tan_dphi = tan(dev->dphi_deg * RAD_PER_DEG);
    s->theta0_rad = d->theta0_deg * RAD_PER_DEG;
    s->coarse_res_rad = d->coarse_resolution_deg * RAD_PER_DEG;
    s->n_coarse = d->coarse_rows_x_mm.n;
    for (int j = 0; j < s->n_coarse; j++)
        s->coarse_x_mm[j] = d->coarse_rows_x_mm.v[j];
    for (int m = 0; m < ESS_FINE_ROWS; m++) {
        s->fine_x_mm[m] = d->fine_rows_x_mm.v[m];
        s->gain[m] = 1.0 + dev->gain_pct[m] * FRACTION_PER_PCT;
        s->etch_mm[m] = dev->etch_um[m] * MM_PER_UM;
    }
    s->harmonics_given = d->harmonics == 1;
    s->given_ratio[0] = 1.0;
    s->given_ratio[1] = d->a3_ratio;
    s->given_ratio[2] = d->a5_ratio;
    s->slit_width_mm = (d->slit_width_um + dev->slit_width_um) * MM_PER_UM;
    if (s->slit_width_mm < 0)
        s->slit_width_mm = 0;
    s->duty = d->dial_duty;
    s->sun_diameter_rad = d->sun_diameter_deg * RAD_PER_DEG;
    s->harmonic_phase_rad = dev->harmonic_phase_deg * RAD_PER_DEG;
    ess_finecode_init(s);
}

int ess_sensor_output(const ess_sensor *s, const double sv[3], const double row_noise[ESS_FINE_ROWS],
                      double *out_rad)
{
    if (!(sv[2] > ESS_MIN_COS_INCIDENCE))
        return SUNMC_EDOM;
    double u = sv[0] / sv[2], v = sv[1] / sv[2];

    double psi_fine[ESS_FINE_ROWS], current[ESS_FINE_ROWS];
    for (int m = 0; m < ESS_FINE_ROWS; m++) {
        double eta = ess_slit_eta_mm(s, s->fine_x_mm[m], u, v) - s->etch_mm[m];
        psi_fine[m] = atan(eta / s->H_mm);
    }
    ess_finecode_currents(s, psi_fine, sv[2], row_noise, current);
    double phase = ess_finecode_demodulate(current);

    double psi_coarse[ESS_MAX_COARSE_ROWS];
    for (int j = 0; j < s->n_coarse; j++)
        psi_coarse[j] = atan(ess_slit_eta_mm(s, s->coarse_x_mm[j], u, v) / s->H_mm);
    double coarse = ess_coarse_read(s, psi_coarse);

    *out_rad = ess_combine(coarse, phase, s->theta0_rad);
    return SUNMC_OK;
}
