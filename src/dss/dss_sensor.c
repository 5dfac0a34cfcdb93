/* dss_sensor.c - one DSS unit: deviations, construction, spot and on-board
 * angles (see dss_sensor.h). */
#include "dss_sensor.h"
#include "dss_lane.h"
#include "dss_score.h"
#include "rotation.h"
#include "family.h"
#include "rng.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

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

void dss_sun_measured_arcsec(const sunmc_config *c, uint64_t seed, long unit,
                             const dss_deviations *d, double out[2])
{
    const dss_config *dc = dss_cfg(c);
    out[0] = out[1] = 0.0;
    if (dc->sun_mode != DSS_SUN_MEASURED || dc->design.mount != DSS_MOUNT_AS_MOUNTED)
        return;
    rng_stream r;
    rng_stream_init(&r, unit_stream_seed(c, seed, RNG_STREAM_SUN_B), (uint64_t)unit,
                    RNG_STREAM_SUN_B);
    out[0] = d->sun_b1_arcsec + dc->sun_sigma_arcsec * rng_normal(&r);
    out[1] = d->sun_b2_arcsec + dc->sun_sigma_arcsec * rng_normal(&r);
}

double dss_disc_coefficient(double sun_disc_deg, double limb_darkening)
{
    double R = 0.5 * sun_disc_deg * RAD_PER_DEG, u = limb_darkening;
    return R * R * (15.0 - 7.0 * u) / (40.0 * (3.0 - u));
}

/* The DSS paper's eq. 5-6 taken literally (design.principal_point =
 * paper_eq6): the pinhole sits where the on-board formula assumes it, the
 * sun at the table's zero arrives along S_b0 = (dx, dy, -h) in the sensor
 * frame (its spot at (dx, dy)), the table rotates that ray, and eq. 9-10
 * measure the spot from (dx, dy).  w = the sun whose spot at the built
 * pinhole and glass is (dx, dy) (the exact inverse, dss_onboard_angles);
 * the sun the spots see is v0 turned by the rotation taking e_z to w
 * (Rodrigues, k = e_z x w: u' = c u + k x u + k (k.u) / (1 + c), c = w_z),
 * so v_sun = M^T u' with u0 = M v0. */
static void dss_sensor_paper_eq6(dss_sensor *s, const dss_deviations *dev)
{
    dss_onboard o = {.h_mm = s->pinhole_mm[2], .pixel_um = s->pixel_mm * UM_PER_MM,
                     .pixel_mm = s->pixel_mm, .glass_t_mm = s->glass_t_mm,
                     .glass_n = s->glass_n};
    double a = 0.0, b = 0.0, w[3], u[3], k[3], v[3];
    (void)dss_onboard_angles(&o, dev->dx_px, dev->dy_px, &a, &b); /* small: always found */
    sun_vector_of(a, b, w);
    mat3_vec(s->M, s->v0, u);
    k[0] = -w[1];
    k[1] = w[0];
    k[2] = 0.0;
    double c = w[2], ku = k[0] * u[0] + k[1] * u[1];
    v[0] = c * u[0] + (k[1] * u[2] - k[2] * u[1]) + k[0] * ku / (1.0 + c);
    v[1] = c * u[1] + (k[2] * u[0] - k[0] * u[2]) + k[1] * ku / (1.0 + c);
    v[2] = c * u[2] + (k[0] * u[1] - k[1] * u[0]);
    mat3 Mt;
    mat3_transpose(s->M, Mt);
    mat3_vec(Mt, v, s->v_sun);
    s->pinhole_mm[0] = s->pinhole_mm[1] = 0.0;
    s->onboard.x0_px = dev->dx_px;
    s->onboard.y0_px = dev->dy_px;
}

double dss_spot_px(const dss_design *d)
{
    return d->pinhole_um / d->pixel_um;
}

void dss_sensor_init(dss_sensor *s, const dss_design *d, const dss_deviations *dev, int s_curve)
{
    dss_sensor_init_amp(s, d, dev, s_curve, NULL);
}

void dss_sensor_init_amp(dss_sensor *s, const dss_design *d, const dss_deviations *dev,
                         int s_curve, const double *amp_px)
{
    memset(s, 0, sizeof *s);
    dss_onboard_init(&s->onboard, d);
    s->pixel_mm = d->pixel_um * MM_PER_UM;
    s->half_side_mm = 0.5 * d->detector_px * s->pixel_mm;
    s->pixel_phase_px = (d->detector_px % 2 == 0) ? 0.5 : 0.0;
    s->pinhole_mm[0] = dev->dx_px * s->pixel_mm;
    s->pinhole_mm[1] = dev->dy_px * s->pixel_mm;
    /* a mask of thickness T: the tube's light is centred at its mid-plane */
    s->pinhole_mm[2] = d->h_mm + dev->dh_px * s->pixel_mm + 0.5 * d->mask_thickness_um * MM_PER_UM;
    s->tube_ratio = d->mask_thickness_um / d->pinhole_um;
    s->glass_t_mm = d->glass_thickness_mm + dev->glass_thickness_um * MM_PER_UM;
    s->glass_n = d->glass_index + dev->glass_index;
    rot_zxy(dev->c1_arcsec * RAD_PER_ARCSEC, dev->c2_arcsec * RAD_PER_ARCSEC,
            dev->c3_arcsec * RAD_PER_ARCSEC, s->M);
    rot_zxy(dev->detector_tilt_x_arcsec * RAD_PER_ARCSEC,
            dev->detector_tilt_y_arcsec * RAD_PER_ARCSEC, 0.0, s->D);
    s->mount = d->mount;
    dss_sun_direction(d->mount, s->M, dev->sun_b1_arcsec * RAD_PER_ARCSEC,
                      dev->sun_b2_arcsec * RAD_PER_ARCSEC, s->v0);
    memcpy(s->v_sun, s->v0, sizeof s->v_sun);
    if (d->principal_point == DSS_PP_PAPER_EQ6)
        dss_sensor_paper_eq6(s, dev);
    s->spot_px = dss_spot_px(d);
    s->disc_c_rad2 = dss_disc_coefficient(d->sun_disc_deg, d->limb_darkening);
    s->s_curve = s_curve;
    dss_pattern_init(&s->pattern, dss_spot_sigma_px(d), s->pixel_phase_px);
    if (d->centroid_window_px > 0)
        s->pattern.half_px = d->centroid_window_px;
    if (amp_px)
        memcpy(s->scurve_amp_px, amp_px, sizeof s->scurve_amp_px);
    else if (s_curve) /* else unused: memset left them 0 */
        dss_scurve_design(d, s->scurve_amp_px);
    s->pattern.prnu = dev->prnu_pct * FRACTION_PER_PCT;
    s->pattern.dsnu = dev->dsnu_pct * FRACTION_PER_PCT;
    s->pattern.ghost = dev->glass_ghost;
}

uint32_t dss_pattern_key(const sunmc_config *c, uint64_t seed, long unit)
{
    rng_stream r;
    /* seeded as prnu_pct's stream, so a pick-freeze of it freezes the
     * pattern too (the DSNU pattern shares the key: one detector) */
    rng_stream_init(&r, unit_stream_seed(c, seed, RNG_STREAM_TOLERANCE + DSS_PRNU_STREAM),
                    (uint64_t)unit, RNG_STREAM_PATTERN);
    /* 32 bits of a uniform in [0, 1) */
    return (uint32_t)(rng_uniform(&r) * DSS_PATTERN_KEYS);
}

int dss_sensor_extras_on(const dss_sensor *s)
{
    return s->pattern.prnu != 0.0 || s->pattern.dsnu != 0.0 || s->pattern.ghost != 0.0;
}

void dss_sensor_extras(const dss_sensor *s, const double u[3], double *x_px, double *y_px)
{
    const dss_pattern *p = &s->pattern;
    double ex = 0.0, ey = 0.0, gx = 0.0, gy = 0.0;
    dss_pattern_error(p, *x_px, *y_px, &ex, &ey);
    if (p->ghost != 0.0 && u[2] > 0.0) {
        double n = s->glass_n, s2 = u[0] * u[0] + u[1] * u[1];
        double a = p->ghost * dss_ghost_intensity(u[2], n);
        double k = -2.0 * s->glass_t_mm / (sqrt(n * n - s2) * s->pixel_mm);
        dss_ghost_pull(p, a, *x_px, *y_px, k * u[0], k * u[1], &gx, &gy);
    }
    *x_px += ex + gx;
    *y_px += ey + gy;
}

void dss_sun_direction(int mount, const mat3 M, double sun_b1, double sun_b2, double v[3])
{
    if (mount == DSS_MOUNT_ALIGNED) {
        for (int i = 0; i < 3; i++)
            v[i] = M[2][i]; /* M^T e_z: the third row of M */
        return;
    }
    mat3 S;
    table_rotation(sun_b1, sun_b2, S);
    for (int i = 0; i < 3; i++)
        v[i] = S[i][2]; /* R(s) e_z: the third column */
}

void dss_truth_angles(int mount, const double v_sun[3], double b1, double b2, double *alpha,
                      double *beta)
{
    /* a chunk of one, padded (the kernel reads vm_pad(1) lanes) */
    _Alignas(VM_ALIGN) double p[DSS_CHUNK], q[DSS_CHUNK], a[DSS_CHUNK], b[DSS_CHUNK];
    for (size_t i = 0; i < vm_pad(1); i++) {
        p[i] = b1;
        q[i] = b2;
    }
    dss_truth_batch(mount, v_sun, 1, p, q, a, b);
    *alpha = a[0];
    *beta = b[0];
}

void dss_sensor_truth(const dss_sensor *s, double b1, double b2, double *alpha, double *beta)
{
    dss_truth_angles(s->mount, s->v0, b1, b2, alpha, beta);
}

VM_NOSAN void dss_sensor_sun(const dss_sensor *s, double b1, double b2, double u[3])
{
    geo_v3 v = dss_lane_sun(s, b1, b2);
    u[0] = v.x;
    u[1] = v.y;
    u[2] = v.z;
}

VM_NOSAN int dss_sensor_spot(const dss_sensor *s, const double u[3], const double noise_px[2],
                             double *x_px, double *y_px)
{
    dss_lane_spot sp = dss_lane_sensor_spot(s, geo_v3_of(u));
    if (!sp.ok)
        return SUNMC_EDOM;
    if (dss_sensor_extras_on(s))
        dss_sensor_extras(s, u, &sp.x, &sp.y);
    *x_px = noise_px ? sp.x + noise_px[0] : sp.x;
    *y_px = noise_px ? sp.y + noise_px[1] : sp.y;
    return SUNMC_OK;
}

/* dss_sensor_read: dss_readings.c, as the batches. */

int dss_sensor_angles(const dss_sensor *s, double x_px, double y_px, double *alpha,
                      double *beta)
{
    return dss_onboard_angles(&s->onboard, x_px, y_px, alpha, beta);
}
