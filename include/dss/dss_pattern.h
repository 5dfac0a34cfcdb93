/* dss_pattern.h - what the calibration model cannot follow in the spot's
 * centroid (issue 38): the detector's fixed pattern (PRNU, DSNU) and the
 * cover glass's ghost.
 *
 * Centroid window.  The spot's centroid is taken over a square window of
 * 2 m + 1 pixels, m = ceil(DSS_WINDOW_SIGMAS sigma), centred on the pixel
 * nearest the spot's centre; sigma is the spot's rms radius per axis
 * (dss_spot_sigma_px: the pinhole's shadow, a disc of D pixels, D / 4, with
 * the Airy core and the sun's disc in quadrature).
 * Inside the window the spot is weighted as a Gaussian of that sigma
 * sampled at the pixel centres, w_ij = g(x_i - x) g(y_j - y).
 *
 * Fixed pattern.  Pixel (i, j) (indices of its centre, pixel_phase_px + i,
 * from the detector's centre) has the gain 1 + p_ij and the dark offset
 * d_ij (a fraction of the spot's peak pixel), p = prnu z1, d = dsnu z2 with
 * z1, z2 uniform of unit variance from a 32-bit hash of (key, i, j): the
 * unit's pattern, drawn once per unit (key from the unit's stream
 * RNG_STREAM_PATTERN, deterministic in (seed, unit)) and the same every
 * time the spot lands on those pixels, so repeats do not average it out.
 * The centroid error is
 *     e_x = sum (x_i - x) v_ij / sum v_ij - sum (x_i - x) w_ij / sum w_ij,
 *     v_ij = w_ij (1 + p_ij) + d_ij,
 * the second term (the window's own truncation) taken out: the S-curve
 * (dss_centroid.h) is that of the whole spot.  Its rms over spot positions
 * is, to first order, sqrt(prnu^2 sum x^2 w^2 + dsnu^2 sum x^2) / sum w.
 *
 * Ghost.  The cover glass (a window with air on both sides) reflects a
 * ray twice inside: a second spot of relative intensity
 *     A = ghost (rs^4 + rp^4) / 2
 * (rs, rp the Fresnel amplitude coefficients at the glass's surface for
 * the field angle theta; (rs^2 + rp^2) / 2 = ((n-1)/(n+1))^2 at normal
 * incidence, A = 0.18 % for n = 1.52), displaced outward along the spot's
 * radial direction by 2 t tan(theta_r), theta_r the refraction angle:
 *     (dx, dy) = -(u_x, u_y) 2 t / sqrt(n^2 - sin^2 theta) / pixel.
 * Its pull on the windowed centroid: with Gaussian spots of sigma, the
 * window [lo, hi] = pixel edges of the window,
 *     e_x = (Sx My + A Sx' My') / (Mx My + A Mx' My') - Sx / Mx,
 * M the spot's mass in the window, S its first moment about x (primed: the
 * ghost's), by the normal distribution's closed forms.  A ghost beyond the
 * window pulls nothing: the pull is largest where the ghost sits on the
 * window's edge, near the boresight.
 */
#ifndef SUNMC_DSS_PATTERN_H
#define SUNMC_DSS_PATTERN_H

#include <stdint.h>

#define DSS_WINDOW_SIGMAS 2.5
/* The largest window half-width the fixed pattern sums over (a spot of
 * sigma up to DSS_WINDOW_HALF_MAX / DSS_WINDOW_SIGMAS px); wider spots are
 * summed over this window. */
#define DSS_WINDOW_HALF_MAX 64
/* Pattern keys: 2^32 (a uniform in (0, 1) times this, truncated). */
#define DSS_PATTERN_KEYS 4294967296.0

typedef struct {
    uint32_t key;      /* the unit's pattern */
    double prnu, dsnu; /* rms gain and dark offset (fractions) */
    double ghost;      /* the ghost's factor on the Fresnel double reflection */
    double sigma_px;   /* the spot's rms radius per axis */
    int half_px;       /* window half-width m */
    double phase_px;   /* pixel centres at phase_px + integer */
} dss_pattern;

/* The window's half-width m = ceil(DSS_WINDOW_SIGMAS sigma_px), in
 * [1, DSS_WINDOW_HALF_MAX]. */
int dss_window_half_px(double sigma_px);

/* The window and spot of a spot of rms radius sigma_px per axis
 * (dss_spot_sigma_px), pixel centres at phase_px + integer; no pattern, no
 * ghost. */
void dss_pattern_init(dss_pattern *p, double sigma_px, double phase_px);

/* The 32-bit hash of pixel (i, j) of pattern key; its two halves give z1,
 * z2 of the pixel (dss_pattern_pixel). */
uint32_t dss_pattern_hash(uint32_t key, int32_t i, int32_t j);

/* Pixel (i, j)'s gain error p and dark offset d (fractions). */
void dss_pattern_pixel(const dss_pattern *p, int32_t i, int32_t j, double *gain, double *dark);

/* The fixed pattern's centroid error (px) of a spot centred at (x_px,
 * y_px) from the detector's centre. */
void dss_pattern_error(const dss_pattern *p, double x_px, double y_px, double *ex, double *ey);

/* The ghost's relative intensity A at field angle theta (cos_th = cos
 * theta) for glass index n, factor ghost excluded. */
double dss_ghost_intensity(double cos_th, double n);

/* The ghost's pull (px) on the centroid of a spot at (x_px, y_px) whose
 * ghost lies (dx_px, dy_px) away with relative intensity a. */
void dss_ghost_pull(const dss_pattern *p, double a, double x_px, double y_px, double dx_px,
                    double dy_px, double *ex, double *ey);

#endif
