/* psd_sensor.c - the four-channel sensor's physics (see psd_sensor.h). */
#include "psd_sensor.h"
#include "optics.h"
#include "status.h"
#include "units.h"

#include <math.h>

/* Corner signs of channels 1-4 (tetra-lateral electrodes and quadrants). */
static const double corner_sx[PSD_CHANNELS] = {-1, 1, 1, -1};
static const double corner_sy[PSD_CHANNELS] = {-1, 1, -1, 1};

static void sensor_common(const psd_design *d, psd_sensor *s, double dh_mm, double aperture_mm)
{
    s->detector = d->detector;
    s->lateral = d->lateral;
    s->h_mm = d->h_mm + dh_mm;
    s->R_mm = 0.5 * aperture_mm + s->h_mm * tan(PSD_SUN_HALF_ANGLE_DEG * RAD_PER_DEG);
    s->half_mm = 0.5 * d->active_mm;
    s->gap_half_mm = 0.5 * d->gap_um * MM_PER_UM;
    s->pincushion = d->lateral == PSD_TETRA ? d->pincushion : 0.0;
}

void psd_sensor_nominal(const psd_design *d, psd_sensor *s)
{
    sensor_common(d, s, 0.0, d->aperture_um * MM_PER_UM);
    s->x0_mm = s->y0_mm = 0.0;
    s->glass_t_mm = d->glass_thickness_mm;
    s->glass_n = d->glass_index;
    rot_zxy(0.0, 0.0, 0.0, s->M);
    double sign = d->polarity == PSD_INVERTED ? -1.0 : 1.0;
    for (int k = 0; k < PSD_CHANNELS; k++) {
        s->gain[k] = sign * d->signal_fs;
        s->dark[k] = d->dark_fs;
    }
    s->background = 0.0;
}

void psd_sensor_build(const psd_design *d, const psd_deviations *dev, psd_sensor *s)
{
    psd_sensor_nominal(d, s);
    sensor_common(d, s, dev->dh_um[0] * MM_PER_UM,
                  (d->aperture_um + dev->aperture_um[0]) * MM_PER_UM);
    s->x0_mm = dev->dx_um[0] * MM_PER_UM;
    s->y0_mm = dev->dy_um[0] * MM_PER_UM;
    s->glass_t_mm = d->glass_thickness_mm > 0.0
                        ? d->glass_thickness_mm + dev->glass_thickness_um[0] * MM_PER_UM
                        : 0.0;
    s->glass_n = d->glass_index + (d->glass_thickness_mm > 0.0 ? dev->glass_index[0] : 0.0);
    rot_zxy(dev->tilt_x_arcsec[0] * RAD_PER_ARCSEC, dev->tilt_y_arcsec[0] * RAD_PER_ARCSEC,
            dev->rot_z_arcsec[0] * RAD_PER_ARCSEC, s->M);
    for (int k = 0; k < PSD_CHANNELS; k++) {
        s->gain[k] *= 1.0 + dev->gain_pct[k] * FRACTION_PER_PCT;
        s->dark[k] += dev->dark_pct[k] * FRACTION_PER_PCT;
    }
    s->background = dev->background_pct[0] * FRACTION_PER_PCT;
}

int psd_sensor_spot(const psd_sensor *s, const double u[3], double spot[2])
{
    double s2 = u[0] * u[0] + u[1] * u[1];
    if (!(u[2] > 0.0) || (s->glass_t_mm > 0.0 && !(s->glass_n * s->glass_n > s2)))
        return SUNMC_EDOM;
    double q = s->glass_t_mm > 0.0 ? optics_q(u, s->h_mm, s->glass_t_mm, s->glass_n, NULL)
                                   : s->h_mm / u[2];
    spot[0] = s->x0_mm - u[0] * q;
    spot[1] = s->y0_mm - u[1] * q;
    return SUNMC_OK;
}

/* Lateral PSD: the centroid of the light on the active area (X, Y in
 * units of L/2) and the lit fraction of the spot. */
static double lateral_centroid(const psd_sensor *s, const double spot[2], double *X, double *Y)
{
    double R = s->R_mm, L2 = s->half_mm;
    if (fabs(spot[0]) + R <= L2 && fabs(spot[1]) + R <= L2) {
        *X = spot[0] / L2;
        *Y = spot[1] / L2;
        return 1.0;
    }
    double a, mx, my;
    psd_disc_rect(R, -L2 - spot[0], L2 - spot[0], -L2 - spot[1], L2 - spot[1], &a, &mx, &my);
    if (!(a > 0.0)) {
        *X = *Y = 0.0;
        return 0.0;
    }
    *X = (spot[0] + mx / a) / L2;
    *Y = (spot[1] + my / a) / L2;
    return a / (M_PI * R * R);
}

void psd_sensor_currents(const psd_sensor *s, const double spot[2], double uz, double i[4])
{
    if (s->detector == PSD_QUADRANT) {
        double R = s->R_mm, L2 = s->half_mm, g = s->gap_half_mm, disc = M_PI * R * R;
        for (int k = 0; k < PSD_CHANNELS; k++) {
            double x1 = corner_sx[k] > 0 ? g : -L2, x2 = corner_sx[k] > 0 ? L2 : -g;
            double y1 = corner_sy[k] > 0 ? g : -L2, y2 = corner_sy[k] > 0 ? L2 : -g;
            double a, mx, my;
            psd_disc_rect(R, x1 - spot[0], x2 - spot[0], y1 - spot[1], y2 - spot[1], &a, &mx,
                          &my);
            i[k] = uz * a / disc;
        }
        return;
    }
    double X, Y, P = uz * lateral_centroid(s, spot, &X, &Y);
    if (s->lateral == PSD_DUO) {
        i[0] = 0.5 * P * (1.0 - X);
        i[1] = 0.5 * P * (1.0 + X);
        i[2] = 0.5 * P * (1.0 - Y);
        i[3] = 0.5 * P * (1.0 + Y);
        return;
    }
    double Xp = X * (1.0 + s->pincushion * Y * Y), Yp = Y * (1.0 + s->pincushion * X * X);
    for (int k = 0; k < PSD_CHANNELS; k++)
        i[k] = 0.25 * P * (1.0 + corner_sx[k] * Xp) * (1.0 + corner_sy[k] * Yp);
}

void psd_ratios(int detector, int lateral, const double sig[4], double *x, double *y)
{
    if (detector == PSD_LATERAL && lateral == PSD_DUO) {
        *x = (sig[1] - sig[0]) / (sig[0] + sig[1]);
        *y = (sig[3] - sig[2]) / (sig[2] + sig[3]);
        return;
    }
    double sum = sig[0] + sig[1] + sig[2] + sig[3];
    *x = (sig[1] + sig[2] - sig[0] - sig[3]) / sum;
    *y = (sig[1] + sig[3] - sig[0] - sig[2]) / sum;
}

int psd_sensor_read(const psd_sensor *s, const double u[3], double m[4])
{
    return psd_sensor_read_lit(s, u, 1.0, m);
}

int psd_sensor_read_lit(const psd_sensor *s, const double u[3], double light, double m[4])
{
    double spot[2], i[4];
    int st = psd_sensor_spot(s, u, spot);
    if (st != SUNMC_OK)
        return st;
    psd_sensor_currents(s, spot, u[2], i);
    double share = s->detector == PSD_LATERAL && s->lateral == PSD_DUO ? 0.5 : 0.25;
    if (!(i[0] + i[1] + i[2] + i[3] > 0.0) && !(s->background > 0.0))
        return SUNMC_EDOM;
    for (int k = 0; k < PSD_CHANNELS; k++)
        m[k] = s->dark[k] + s->gain[k] * (light * i[k] + share * s->background);
    return SUNMC_OK;
}

double psd_adc(double m, int bits)
{
    double top = ldexp(1.0, bits) - 1.0;
    double code = nearbyint(m * top);
    code = code < 0.0 ? 0.0 : code > top ? top : code;
    return code / top;
}

void psd_table_sun(const psd_config *pc, double alpha, double beta, double u[3])
{
    double a = pc->table_alpha_sign ? -alpha : alpha, b = pc->table_beta_sign ? -beta : beta;
    if (pc->table_order == PSD_TABLE_PROJECTED) {
        sun_vector_of(a, b, u);
        return;
    }
    mat3 ra, rb, r;
    rot_y(-a, ra);
    rot_x(b, rb);
    if (pc->table_order == PSD_TABLE_ALPHA_OUTER)
        mat3_mul(rb, ra, r);
    else
        mat3_mul(ra, rb, r);
    const double ez[3] = {0.0, 0.0, 1.0};
    mat3_vec(r, ez, u);
}
