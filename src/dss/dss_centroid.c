/* dss_centroid.c - S-curve centroid bias of a disc spot (see dss_centroid.h). */
#include "dss_centroid.h"
#include "dss_lane.h"
#include "dss_pattern.h"
#include "units.h"

#include <gsl/gsl_sf_bessel.h>
#include <math.h>

void dss_scurve_amplitudes(double spot_px, double amp_px[DSS_SCURVE_HARMONICS])
{
    for (int k = 1; k <= DSS_SCURVE_HARMONICS; k++) {
        double z = M_PI * spot_px * k;
        gsl_sf_result j1;
        /* J1 of a finite argument cannot fail; 0 if GSL reports otherwise. */
        double F = gsl_sf_bessel_J1_e(z, &j1) == 0 ? 2.0 * j1.val / z : 0.0;
        double sign = (k % 2) ? -1.0 : 1.0;
        amp_px[k - 1] = sign * F / (M_PI * k);
    }
}

VM_NOSAN double dss_scurve_bias(const double amp_px[DSS_SCURVE_HARMONICS], double x_px)
{
    return dss_lane_scurve(amp_px, x_px, 0.0).x;
}

/* The diffraction-limited S-curve (dss_centroid.h, Diffraction): the
 * spot's 1-D spectrum on DSS_SPOT_NQ + 1 Simpson nodes over [0, nu_c], the
 * pixel signals of a spot at DSS_SPOT_NPHASE phases in the window by the
 * cosine transform (a rotation recurrence along the window), the bias's
 * sine harmonics by the discrete transform. */
#define DSS_SPOT_NQ 128
#define DSS_SPOT_NPHASE 128

/* 2 J1(z) / z, 1 at 0 (the transform of a uniform disc's chord profile). */
static double jinc(double z)
{
    if (fabs(z) < 1e-8)
        return 1.0;
    gsl_sf_result j1;
    return gsl_sf_bessel_J1_e(z, &j1) == 0 ? 2.0 * j1.val / z : 0.0;
}

/* The incoherent MTF of a circular aperture at r = nu / nu_c. */
static double mtf_circ(double r)
{
    if (r >= 1.0)
        return 0.0;
    return (2.0 / M_PI) * (acos(r) - r * sqrt(1.0 - r * r));
}

double dss_spot_cutoff_px(const dss_design *d)
{
    if (d->wavelength_nm <= 0.0)
        return 0.0;
    double d_mm = d->pinhole_um * MM_PER_UM, lam_mm = d->wavelength_nm * MM_PER_NM;
    return d_mm / (lam_mm * d->h_mm) * (d->pixel_um * MM_PER_UM);
}

double dss_spot_sun_px(const dss_design *d)
{
    double t = d->glass_thickness_mm, n = d->glass_index;
    return (d->h_mm - t + t / n) * d->sun_disc_deg * RAD_PER_DEG / (d->pixel_um * MM_PER_UM);
}

double dss_spot_sigma_px(const dss_design *d)
{
    double D = d->pinhole_um / d->pixel_um, Ds = dss_spot_sun_px(d), sa = 0.0;
    if (d->wavelength_nm > 0.0) /* the Airy core's Gaussian: 0.42 lambda h / d */
        sa = DSS_AIRY_SIGMA * d->wavelength_nm * MM_PER_NM * d->h_mm /
             (d->pinhole_um * MM_PER_UM) / (d->pixel_um * MM_PER_UM);
    return sqrt(D * D / 16.0 + sa * sa + Ds * Ds / 16.0);
}

/* The whole spot's S-curve (dss_scurve_amplitudes' Poisson sum) with the
 * spectrum of diffraction and the sun's disc: 0 for k >= nu_c. */
static void scurve_whole(const dss_design *d, double nuc, double amp_px[DSS_SCURVE_HARMONICS])
{
    double D = d->pinhole_um / d->pixel_um, Ds = dss_spot_sun_px(d);
    for (int k = 1; k <= DSS_SCURVE_HARMONICS; k++) {
        double F = jinc(M_PI * D * k) * mtf_circ(k / nuc) * jinc(M_PI * Ds * k);
        amp_px[k - 1] = ((k % 2) ? -1.0 : 1.0) * F / (M_PI * k);
    }
}

void dss_scurve_design(const dss_design *d, double amp_px[DSS_SCURVE_HARMONICS])
{
    double nuc = dss_spot_cutoff_px(d);
    if (nuc <= 0.0) {
        dss_scurve_amplitudes(d->pinhole_um / d->pixel_um, amp_px);
        return;
    }
    if (d->centroid_window_px <= 0) {
        scurve_whole(d, nuc, amp_px);
        return;
    }
    int half_px = d->centroid_window_px;
    double D = d->pinhole_um / d->pixel_um, Ds = dss_spot_sun_px(d);
    double H[DSS_SPOT_NQ + 1], cphi[DSS_SPOT_NQ + 1], sphi[DSS_SPOT_NQ + 1], nu[DSS_SPOT_NQ + 1];
    double h = nuc / DSS_SPOT_NQ;
    for (int q = 0; q <= DSS_SPOT_NQ; q++) {
        nu[q] = q * h;
        double w = (q == 0 || q == DSS_SPOT_NQ) ? 1.0 : (q % 2 ? 4.0 : 2.0);
        double box = q == 0 ? 1.0 : sin(M_PI * nu[q]) / (M_PI * nu[q]);
        H[q] = w * h / 3.0 * jinc(M_PI * D * nu[q]) * mtf_circ(nu[q] / nuc) *
               jinc(M_PI * Ds * nu[q]) * box;
        cphi[q] = cos(2.0 * M_PI * nu[q]);
        sphi[q] = sin(2.0 * M_PI * nu[q]);
    }
    int n = 2 * half_px + 1;
    double bias[DSS_SPOT_NPHASE];
    for (int j = 0; j < DSS_SPOT_NPHASE; j++) {
        double x0 = (j + 0.5) / DSS_SPOT_NPHASE - 0.5, S = 0.0, S1 = 0.0;
        double s[2 * DSS_WINDOW_HALF_MAX + 1] = {0};
        for (int q = 0; q <= DSS_SPOT_NQ; q++) {
            /* cos(2 pi nu (k - half - x0)) for k = 0 .. n-1, by rotation */
            double a = 2.0 * M_PI * nu[q] * (-half_px - x0), c = cos(a), sn = sin(a);
            for (int k = 0; k < n; k++) {
                s[k] += H[q] * c;
                double c2 = c * cphi[q] - sn * sphi[q];
                sn = sn * cphi[q] + c * sphi[q];
                c = c2;
            }
        }
        for (int k = 0; k < n; k++) {
            S += s[k];
            S1 += (k - half_px) * s[k];
        }
        bias[j] = S1 / S - x0;
    }
    for (int k = 1; k <= DSS_SCURVE_HARMONICS; k++) {
        double a = 0.0;
        for (int j = 0; j < DSS_SPOT_NPHASE; j++)
            a += bias[j] * sin(2.0 * M_PI * k * ((j + 0.5) / DSS_SPOT_NPHASE - 0.5));
        amp_px[k - 1] = 2.0 * a / DSS_SPOT_NPHASE;
    }
}
