/* dss_sensor.c - one DSS unit: deviations, construction, spot and on-board
 * angles (see dss_sensor.h). */
#include "dss_sensor.h"
#include "dss_optics.h"
#include "dss_rotation.h"
#include "rng.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

/* The plane-parallel glass may sit anywhere under the pinhole (dss_optics.h);
 * it is traced lying on the detector. */
#define DSS_GLASS_GAP_MM 0.0

_Static_assert(sizeof(dss_deviations) == DSS_N_DEV * sizeof(double),
               "dss_deviations: one double per column of DSS_DEVIATIONS");

DSS_DEVIATIONS(DEVIATION_X_COLUMNS)

const deviation_spec dss_deviation_list[DSS_N_TOL] = {
#define DSS_X_SPEC(name, unit, count, stream, ...)                                                \
    DEVIATION_SPEC(dss_config, dss_deviations, name, count, stream),
    DSS_DEVIATIONS(DSS_X_SPEC)
#undef DSS_X_SPEC
};

const char *const dss_deviation_names[DSS_N_DEV] = {
    DSS_DEVIATIONS(DEVIATION_X_NAMES)
};

void dss_deviations_values(const dss_deviations *d, double out[DSS_N_DEV])
{
    deviations_values(dss_deviation_list, DSS_N_TOL, d, out, DSS_N_DEV);
}

void dss_deviations_sample(const sunmc_config *c, uint64_t seed, long unit, dss_deviations *d)
{
    deviations_sample(dss_deviation_list, DSS_N_TOL, c, seed, unit, d);
}

void dss_sensor_init(dss_sensor *s, const dss_design *d, const dss_deviations *dev, int s_curve)
{
    memset(s, 0, sizeof *s);
    dss_onboard_init(&s->onboard, d);
    s->pixel_mm = d->pixel_um * MM_PER_UM;
    s->half_side_mm = 0.5 * d->detector_px * s->pixel_mm;
    s->pixel_phase_px = (d->detector_px % 2 == 0) ? 0.5 : 0.0;
    s->pinhole_mm[0] = dev->dx_px * s->pixel_mm;
    s->pinhole_mm[1] = dev->dy_px * s->pixel_mm;
    s->pinhole_mm[2] = d->h_mm + dev->dh_px * s->pixel_mm;
    s->glass_t_mm = d->glass_thickness_mm + dev->glass_thickness_um * MM_PER_UM;
    s->glass_n = d->glass_index + dev->glass_index;
    dss_zxy(dev->c1_arcsec * RAD_PER_ARCSEC, dev->c2_arcsec * RAD_PER_ARCSEC,
            dev->c3_arcsec * RAD_PER_ARCSEC, s->M);
    for (int i = 0; i < 3; i++)
        s->v0[i] = s->M[2][i]; /* M^T e_z: the third row of M */
    s->spot_px = d->pinhole_um / d->pixel_um;
    s->s_curve = s_curve;
    dss_scurve_amplitudes(s->spot_px, s->scurve_amp_px);
}

void dss_sensor_sun(const dss_sensor *s, double b1, double b2, double u[3])
{
    mat3 R;
    double w[3];
    dss_table_rotation(b1, b2, R);
    mat3_vec(R, s->v0, w);
    mat3_vec(s->M, w, u);
}

int dss_sensor_spot(const dss_sensor *s, const double u[3], const double noise_px[2],
                    double *x_px, double *y_px)
{
    double spot[2];
    int st = dss_optics_trace(u, s->pinhole_mm, DSS_GLASS_GAP_MM, s->glass_t_mm, s->glass_n, spot);
    if (st != SUNMC_OK)
        return st;
    double lim = s->half_side_mm - 0.5 * s->spot_px * s->pixel_mm;
    if (fabs(spot[0]) > lim || fabs(spot[1]) > lim)
        return SUNMC_EDOM;
    double x = spot[0] / s->pixel_mm, y = spot[1] / s->pixel_mm;
    if (s->s_curve) {
        x += dss_scurve_bias(s->scurve_amp_px, x - s->pixel_phase_px);
        y += dss_scurve_bias(s->scurve_amp_px, y - s->pixel_phase_px);
    }
    if (noise_px) {
        x += noise_px[0];
        y += noise_px[1];
    }
    *x_px = x;
    *y_px = y;
    return SUNMC_OK;
}

int dss_sensor_read(const dss_sensor *s, double b1, double b2, const double noise_px[2],
                    double *x_px, double *y_px)
{
    double u[3];
    dss_sensor_sun(s, b1, b2, u);
    return dss_sensor_spot(s, u, noise_px, x_px, y_px);
}

int dss_sensor_angles(const dss_sensor *s, double x_px, double y_px, double *alpha,
                      double *beta)
{
    return dss_onboard_angles(&s->onboard, x_px, y_px, alpha, beta);
}
