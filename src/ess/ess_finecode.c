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
#include "ess_sensor.h"

#include <gsl/gsl_sf_bessel.h>
#include <math.h>

static const int harmonic_order[ESS_HARMONICS] = {1, 3, 5};

static double sinc_pi(double z) /* sin(pi z) / (pi z) */
{
    if (fabs(z) < 1e-8)
        return 1.0;
    return sin(M_PI * z) / (M_PI * z);
}

static double disc_transfer(double z) /* 2 J1(z)/z, the projected uniform disc */
{
    if (fabs(z) < 1e-8)
        return 1.0;
    return 2.0 * gsl_sf_bessel_J1(z) / z;
}

/* Unnormalised amplitude of harmonic index i at dial angle psi: the dial
 * and sun factors do not depend on psi (precomputed), the slit's does. */
static double harmonic_raw(const ess_sensor *s, int i, double psi_rad)
{
    double cos_psi = cos(psi_rad);
    double slit_ang = s->slit_width_mm * cos_psi * cos_psi / s->H_mm;
    return s->dial_sun[i] * sinc_pi(harmonic_order[i] * slit_ang / s->theta0_rad);
}

void ess_finecode_init(ess_sensor *s)
{
    for (int i = 0; i < ESS_HARMONICS; i++) {
        int n = harmonic_order[i];
        s->dial_sun[i] = sin(n * M_PI * s->duty) / n *
                         disc_transfer(M_PI * n * s->sun_diameter_rad / s->theta0_rad);
    }
    s->norm1 = harmonic_raw(s, 0, 0.0);
    /* Square wave of duty D: DC = D, a1 = (2/pi) sin(pi D) x transfer. */
    s->dc_ratio = M_PI * s->duty / (2.0 * s->norm1);
}

void ess_finecode_harmonics(const ess_sensor *s, double psi_rad, double c[ESS_HARMONICS])
{
    for (int i = 0; i < ESS_HARMONICS; i++) {
        if (s->harmonics_given)
            c[i] = s->given_ratio[i];
        else
            c[i] = harmonic_raw(s, i, psi_rad) / s->norm1;
    }
}

void ess_finecode_currents(const ess_sensor *s, const double psi_rad[ESS_FINE_ROWS], double illum,
                           const double noise[ESS_FINE_ROWS], double current[ESS_FINE_ROWS])
{
    /* The slit's share of the harmonics changes with cos^2(psi): over the
     * few micrometres between rows that is below 1e-9, so one evaluation at
     * the first row serves the four. */
    double c[ESS_HARMONICS];
    ess_finecode_harmonics(s, psi_rad[0], c);
    for (int m = 0; m < ESS_FINE_ROWS; m++) {
        double x = 2.0 * M_PI * psi_rad[m] / s->theta0_rad;
        double sum = 0.0;
        for (int i = 0; i < ESS_HARMONICS; i++) {
            int n = harmonic_order[i];
            double phase = (n == 3) ? s->harmonic_phase_rad : 0.0;
            if (c[i] != 0.0)
                sum += c[i] * cos(n * (x - m * M_PI / 2.0) + phase);
        }
        current[m] = illum * s->gain[m] * (s->dc_ratio - sum) + (noise ? noise[m] : 0.0);
    }
}

double ess_finecode_demodulate(const double current[ESS_FINE_ROWS])
{
    double ph = atan2(current[3] - current[1], current[2] - current[0]);
    return ph < 0 ? ph + 2.0 * M_PI : ph;
}
