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

/* Amplitudes amp_px[k-1] = (-1)^k F(k) / (pi k) of the S-curve for a disc
 * spot of diameter spot_px (pixels, > 0). */
void dss_scurve_amplitudes(double spot_px, double amp_px[DSS_SCURVE_HARMONICS]);

/* Bias (pixels) of the centroid of a spot centred at x_px, where x_px is
 * measured from a pixel centre (pixel centres at the integers). */
double dss_scurve_bias(const double amp_px[DSS_SCURVE_HARMONICS], double x_px);

#endif
