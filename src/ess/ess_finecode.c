/* ess_finecode.c - fine-code row currents and their four-quadrant
 * demodulation (ESS paper sec. 3.3, eq. 2-8, Fig. 8).
 *
 * Row m (m = 0..3 for F1..F4) is the same pattern shifted by m quarter
 * periods.  With x = 2 pi psi / theta0 its current is
 *     I_m = illum g_m [ DC - sum_n c_n cos(n (x - m pi/2) + phi_n) ] + noise_m,
 * (for n = 1 this is eq. 1: F1 = DC - cos x, F2 = DC - sin x, ...).
 * The chopper sums the rows in quadrature; the phase of the fundamental of
 * the chopped sequence is the DFT bin 1 of (I_0..I_3):
 *     x_hat = atan2(I_3 - I_1, I_2 - I_0).
 * Only harmonics n = 3, 7, ... (as e^{+inx}) and n = 1, 5, ... (as
 * e^{-inx}) reach bin 1, so a third harmonic alone gives
 *     x_hat - x = -atan(r sin 4x / (1 + r cos 4x)),  r = c3/c1:
 * the ESS paper's eq. 7 (whose eq. 8 carries this same minus sign).
 *
 * Derived harmonics: a dial of duty D has c_n proportional to sin(n pi D)/n;
 * the slit (angular width w cos^2(psi)/H) multiplies by sinc(n w'/theta0) and
 * the sun's disc (diameter S, a semicircle profile) by 2 J1(z)/z with
 * z = pi n S/theta0.
 */
#include "ess_lane.h"

#include <gsl/gsl_sf_bessel.h>
#include <math.h>

/* The per-reading formulas (harmonics at a dial angle, a row's current, the
 * demodulation) are inline in ess_lane.h, shared with the vectorised batch;
 * here are the unit's constants and the scalar entry points. */

static double disc_transfer(double z) /* 2 J1(z)/z, the projected uniform disc */
{
    if (fabs(z) < 1e-8)
        return 1.0;
    return 2.0 * gsl_sf_bessel_J1(z) / z;
}

void ess_finecode_init(ess_sensor *s)
{
    static const int harmonic_order[ESS_HARMONICS] = {1, 3, 5};
    for (int i = 0; i < ESS_HARMONICS; i++) {
        int n = harmonic_order[i];
        s->dial_sun[i] = sin(n * M_PI * s->duty) / n *
                         disc_transfer(M_PI * n * s->sun_diameter_rad / s->theta0_rad);
    }
    /* the fundamental's transfer at normal incidence: the dial and sun
     * factor times the slit's sinc there */
    s->norm1 = 1.0;
    int given = s->harmonics_given;
    s->harmonics_given = 0;
    s->norm1 = ess_lane_harmonics(s, 0.0).c1;
    s->harmonics_given = given;
    /* Square wave of duty D: DC = D, a1 = (2/pi) sin(pi D) x transfer. */
    s->dc_ratio = M_PI * s->duty / (2.0 * s->norm1);
}

VM_NOSAN void ess_finecode_harmonics(const ess_sensor *s, double psi_rad,
                                     double c[ESS_HARMONICS])
{
    ess_lane_harm h = ess_lane_harmonics(s, psi_rad);
    c[0] = h.c1;
    c[1] = h.c3;
    c[2] = h.c5;
}

VM_NOSAN void ess_finecode_currents(const ess_sensor *s, const double psi_rad[ESS_FINE_ROWS],
                                    double illum, const double noise[ESS_FINE_ROWS],
                                    double current[ESS_FINE_ROWS])
{
    /* The slit's share of the harmonics changes with cos^2(psi): over the
     * few micrometres between rows that is below 1e-9, so one evaluation at
     * the first row serves the four. */
    ess_lane_harm h = ess_lane_harmonics(s, psi_rad[0]);
    for (int m = 0; m < ESS_FINE_ROWS; m++)
        current[m] = ess_lane_current(s, m, h, psi_rad[m], illum, noise ? noise[m] : 0.0);
}

VM_NOSAN double ess_finecode_demodulate(const double current[ESS_FINE_ROWS])
{
    return ess_lane_demodulate(current[0], current[1], current[2], current[3]);
}
