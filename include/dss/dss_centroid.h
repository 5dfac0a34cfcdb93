/* dss_centroid.h - the measured spot centre: the pixel-phase (S-curve) bias
 * of a centre-of-mass centroid of a finite spot, and detector noise.
 *
 * S-curve.  A spot of 1-D profile f, integrated over unit pixels whose
 * centres sit at the integers, has the centre-of-mass centroid c(x0) of a
 * spot centred at x0 (pixels).  By Poisson summation (the pixel box's
 * transform sinc(k) vanishes at every integer k != 0, leaving its
 * derivative (-1)^k / k):
 *     c(x0) - x0 = sum_{k>=1} (-1)^k F(k) sin(2 pi k x0) / (pi k),
 * F(k) = f^(k) / f^(0) the normalised transform of the profile.  The spot is
 * the pinhole's shadow, a uniform disc of diameter D pixels, whose 1-D
 * profile (chord length) has F(k) = 2 J1(pi D k) / (pi D k).  F(k) falls
 * only as k^-1.5 (the disc's sharp edge), so DSS_SCURVE_HARMONICS terms are
 * kept (summed by recurrence): the first amplitude of a D = 10.9 px spot
 * is 2.2e-3 px and the truncation error below 2e-6 px (1.3e-5 px for
 * D = 2.5; a test checks the sum against the brute-force centroid of the
 * pixel-integrated disc).  The centroid window
 * is assumed wide enough to hold the whole spot.
 */
#ifndef SUNMC_DSS_CENTROID_H
#define SUNMC_DSS_CENTROID_H

#define DSS_SCURVE_HARMONICS 64
/* The Gaussian that best fits the Airy pattern's core: sigma = 0.42 lambda N
 * (N = h / d; Zhang, Zerubia & Olivo-Marin, Appl. Opt. 46, 1819 (2007)). */
#define DSS_AIRY_SIGMA 0.42

#include "dss_config.h"

/* Amplitudes amp_px[k-1] = (-1)^k F(k) / (pi k) of the S-curve for a disc
 * spot of diameter spot_px (pixels, > 0). */
void dss_scurve_amplitudes(double spot_px, double amp_px[DSS_SCURVE_HARMONICS]);

/* Bias (pixels) of the centroid of a spot centred at x_px, where x_px is
 * measured from a pixel centre (pixel centres at the integers). */
double dss_scurve_bias(const double amp_px[DSS_SCURVE_HARMONICS], double x_px);

/* Diffraction (issue 38).  With design.wavelength_nm > 0 the spot is the
 * pinhole's shadow (a disc of D = pinhole / pixel) blurred by diffraction
 * and by the sun's disc: its 1-D spectrum is
 *     F(nu) = jinc(pi D nu) MTF(nu / nu_c) jinc(pi Ds nu),
 * jinc(z) = 2 J1(z) / z, MTF the incoherent transfer function of the
 * circular pinhole, nu_c = d / (lambda h) its cut-off (0.17 cycles per
 * pixel for configs/dss.ini at 650 nm), Ds the sun's disc on the detector
 * in pixels ((h - t + t / n) times its angle).  The pixel (fill factor 1)
 * multiplies it by sinc(nu).  F vanishes above nu_c < 1: the spot is
 * band-limited below the pixel frequency, and a whole-spot centroid has no
 * S-curve at all (the harmonics k >= 1 of the Poisson sum are 0, whatever
 * the fill factor: the pixel's transform multiplies F, which is already 0).
 * What a real algorithm adds is its window's: a fixed window of 2 m + 1
 * pixels (design.centroid_window_px = m) without a threshold cuts the
 * spot's tails (the diffraction line-spread function falls only as x^-2),
 * by an amount that depends on the sub-pixel phase and jumps where the
 * window moves on by a pixel.  dss_scurve_design computes that centroid
 * numerically (the pixel signals by Simpson's rule over the spectrum, 128
 * phases) and returns its sine harmonics. */

/* nu_c in cycles per pixel (0 for wavelength_nm = 0). */
double dss_spot_cutoff_px(const dss_design *d);
/* The sun's disc on the detector, diameter in pixels, at normal incidence. */
double dss_spot_sun_px(const dss_design *d);
/* The spot's rms radius per axis (px): the disc's D / 4, the Airy core's
 * DSS_AIRY_SIGMA lambda h / d and the sun disc's Ds / 4 in quadrature. */
double dss_spot_sigma_px(const dss_design *d);
/* The S-curve amplitudes of design d's spot: wavelength_nm = 0, the
 * geometric disc's (dss_scurve_amplitudes); centroid_window_px = 0, the
 * whole spot's, the Poisson sum with the spectrum above (0 when nu_c <= 1,
 * as for configs/dss.ini); else the window's, numerically. */
void dss_scurve_design(const dss_design *d, double amp_px[DSS_SCURVE_HARMONICS]);

#endif
