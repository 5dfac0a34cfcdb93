/* dss_sensor.h - one physical pinhole digital sun sensor (DSS) on the rotary
 * table: its sampled deviations, where its sun spot falls and the angles its
 * on-board formula (DSS paper eq. 9-10) reads.  This generates the data; the
 * calibration models (dss_model.h, dss_poly.h) only fit them.
 *
 * Frames (rotation conventions in rotation.h):
 *  - Sensor frame b: origin at the detector centre, which the on-board
 *    formula takes as principal point; X along the pixel rows, Y along the
 *    columns, Z the detector normal toward the mask.  Spot coordinates
 *    x_px, y_px are measured from the detector centre along X and Y.
 *  - The true pinhole is at (dx, dy, h + dh) (the design puts it at
 *    (0, 0, h)): dx, dy are the principal-point errors, dh the height error,
 *    all in pixels as in the DSS paper.  The cover glass has thickness
 *    t + dt and index n + dn.
 *  - The sensor is mounted on the table top rotated by zxy (c1 about X, c2
 *    about Y, c3 about Z): M = rot_zxy(c1, c2, c3) takes table-top vectors
 *    into frame b.  The sun simulator's direction in the table's base
 *    frame is v_sun, and at table angles b the sun in frame b is
 *        u = M R(b) v_sun                       (general lab geometry).
 *    campaign.mount = as_mounted (default): the unit sits as mounted and the
 *    simulator points where it points, v_sun = R(sun_b1, sun_b2) e_z (the
 *    direction a perfect simulator would have with the table at sun_b1,
 *    sun_b2; both deviations).  campaign.mount = aligned: the DSS paper's
 *    eq. 6 (S_b = C_bc C_ca C_ba^-1 S_b0): the lab first aligns the sun
 *    perpendicular to the detector at the table's zero, v_sun = M^T e_z, so
 *    the installation rotations vanish at the centre of the field and grow
 *    toward its edge (DSS paper Fig. 4); sun_b1, sun_b2 are not used.
 *  - Truth, the frame of every calibrated angle: as_mounted, the angles
 *    (alpha, beta) = (atan(w_x/w_z), atan(w_y/w_z)) of the true sun w =
 *    R(b) v_sun in the table-top frame, i.e. the mount's frame with the
 *    installation removed; with a perfect simulator (v_sun = e_z) these are
 *    the table's angles of eq. 3-4.  aligned: the table's angles (alpha0,
 *    beta0) of eq. 3-4, the paper's truth.
 *  - On-board formula: the exact inverse of the nominal geometry (dss_onboard
 *    below).  With design.onboard_refraction = corrected (the default) it
 *    undoes the nominal cover glass, so the error before calibration is
 *    what manufacturing and mounting do; with `ignored` it is the DSS
 *    paper's eq. 9-10, alpha_m = atan(-x / h), beta_m = atan(-y / h) (x, y in
 *    mm; the pinhole inverts the image), and the refraction error of the
 *    paper's Fig. 5 is part of the error before calibration.
 *
 * Sun disc: the spot is the pinhole's image of the sun's disc (apparent
 * diameter design.sun_disc_deg, linear limb darkening u), traced through
 * the glass.  Each point of the disc at angular offset (a radial, b
 * tangential) lands at f(theta0 + a + b^2 / (2 tan theta0)) along azimuth
 * phi0 + b / sin theta0, f(theta) = (H - t) tan theta + t tan theta_g the
 * radial spot distance; averaged over the disc (<a^2> = <b^2> = m2 / 2) the
 * centroid lies along the centre's spot, farther out by
 *     dr = (m2 / 4) (f'' + f' / tan theta - f / sin^2 theta)
 * to second order in the disc's radius R (next terms ~ R^4), with
 * m2 = <r^2> = R^2 (15 - 7u) / (10 (3 - u)) (R^2 / 2 for a uniform disc).
 * Without glass dr = (m2 / 2) h tan theta / cos^2 theta: an angle bias of
 * (m2 / 2) tan theta = (R^2 / 4) tan theta uniform, ~1.0 arcsec tan theta at
 * u = 0.6.  dss_lane_disc_gain gives 1 + dr / f; test_dss_disc checks it
 * against a numerical integration over the disc.
 *
 * Detector tilt (outside the calibration model, issue 38): the detector
 * plane is turned against the mask by D = rot_zxy(tilt_x, tilt_y, 0)
 * (detector_tilt_x about X, then detector_tilt_y about the new Y; D takes
 * frame-b vectors into the detector's frame, whose rows are the detector's
 * axes and normal in frame b) about the detector's centre.  The ray leaves
 * the cover glass as today (the glass is the package's window, parallel to
 * the mask, above the die: the tilt's rise, under 10 um, is taken in air)
 * and goes on along -u from p0, its point on z = 0, to the tilted plane;
 * the spot is that point in the detector's axes: with q = D p0, w = D u,
 *     x = q_x - w_x q_z / w_z,   y = q_y - w_y q_z / w_z.
 * Zero tilt is the untilted spot to the bit.  For a tilt a about X alone
 * and the sun in the Y-Z plane at field angle theta, y = y0 cos theta /
 * cos(theta + a).  The sun disc's gain is taken on the untilted plane (its
 * change with the tilt is of order R^2 a).  A pinhole with the glass
 * removed would be the calibration model again (pinhole offset, height and
 * rotation); the glass, parallel to the mask and not to the detector, is
 * what the model cannot follow.
 *
 * Centroid: the spot is the pinhole's shadow, a disc of the pinhole's
 * diameter; its centroid carries the optional S-curve bias (dss_centroid.h)
 * , the detector's fixed pattern (PRNU, DSNU) and the cover glass's ghost
 * (dss_pattern.h: a centroid window of 2.5 sigma, the ghost pulls only
 * while inside it), and Gaussian detector noise.  A spot whose disc leaves
 * the detector is not seen (SUNMC_EDOM).
 */
#ifndef SUNMC_DSS_SENSOR_H
#define SUNMC_DSS_SENSOR_H

#include "dss_config.h"
#include "deviation.h"
#include "dss_centroid.h"
#include "dss_onboard.h"
#include "dss_pattern.h"
#include "rotation.h"

#include <stdint.h>

/* One unit's deviations, in the units of their names: one field per line
 * of DSS_DEVIATIONS (dss_deviations.h). */
typedef struct {
    double dh_px, dx_px, dy_px;
    double c1_arcsec, c2_arcsec, c3_arcsec;
    double glass_thickness_um; /* deviation from design.glass_thickness_mm */
    double glass_index;        /* deviation from design.glass_index */
    double sun_b1_arcsec, sun_b2_arcsec;
    /* the unit's thermal coefficients against the environment's (dss_thermal.h) */
    double spacer_cte_ppm_k, detector_cte_ppm_k, glass_cte_ppm_k, glass_dn_dt_ppm_k;
    /* the detector plane against the mask (truth only; see Detector tilt) */
    double detector_tilt_x_arcsec, detector_tilt_y_arcsec;
    /* the detector's fixed pattern and the glass's ghost (truth only; dss_pattern.h) */
    double prnu_pct, dsnu_pct, glass_ghost;
} dss_deviations;

/* calibration.sun = measured (campaign.mount = as_mounted): unit `unit`'s
 * measurement of its sun simulator's direction, out = (sun_b1, sun_b2)
 * arcsec: the deviations d->sun_b1_arcsec, d->sun_b2_arcsec plus normal
 * errors of calibration.sun_sigma_arcsec from stream RNG_STREAM_SUN_B, drawn
 * only here, so no other draw moves; (0, 0) when the direction is fitted. */
void dss_sun_measured_arcsec(const sunmc_config *c, uint64_t seed, long unit,
                             const dss_deviations *d, double out[2]);

/* DSS_DEVIATIONS as a table (dss_sensor.c). */
extern const deviation_spec dss_deviation_list[DSS_N_TOL];

/* Column names, in the order of dss_deviations_values(). */
extern const char *const dss_deviation_names[DSS_N_DEV];
void dss_deviations_values(const dss_deviations *d, double out[DSS_N_DEV]);

/* Draw unit `unit`'s deviations; each from its own stream (its stream id in
 * DSS_DEVIATIONS), so it depends only on (seed, unit, id). */
void dss_deviations_sample(const sunmc_config *c, uint64_t seed, long unit, dss_deviations *d);

/* One built sensor: lengths in mm, angles in radians. */
typedef struct {
    /* design, as the on-board formula knows it */
    dss_onboard onboard;
    double pixel_mm;
    double half_side_mm;       /* half the detector's side */
    double pixel_phase_px;     /* pixel centres sit at x_px = pixel_phase_px + integer */
    /* as built */
    double pinhole_mm[3];      /* (dx, dy, h + dh) */
    double glass_t_mm;
    double glass_n;
    int mount;                 /* enum dss_mount */
    mat3 M;                    /* table top -> sensor frame */
    mat3 D;                    /* sensor frame -> the tilted detector's frame:
                                * rot_zxy(tilt_x, tilt_y, 0) (Detector tilt) */
    double v0[3];              /* sun in the table base frame: M^T e_z (aligned) or
                                * R(sun_b1, sun_b2) e_z (as_mounted): the truth */
    double v_sun[3];           /* the sun the spots see: v0, but for
                                * design.principal_point = paper_eq6 the ray
                                * S_b0 = (dx, dy, -h) at the table's zero */
    double spot_px;            /* spot diameter */
    double tube_ratio;         /* mask thickness / pinhole diameter: no light passes
                                * where tan(theta) >= 1 / tube_ratio */
    double disc_c_rad2;        /* the sun's disc: dss_disc_coefficient (0: a point sun) */
    int s_curve;               /* 1: apply the S-curve bias */
    double scurve_amp_px[DSS_SCURVE_HARMONICS];
    dss_pattern pattern;       /* fixed pattern and ghost (dss_pattern.h); its key is
                                * 0 until dss_sensor_pattern_key */
} dss_sensor;

/* Unit `unit`'s fixed-pattern key for seed: a draw of stream
 * RNG_STREAM_PATTERN (deterministic in (seed, unit), no other draw moves),
 * seeded as prnu_pct's stream (DSS_PRNU_STREAM). */
#define DSS_PRNU_STREAM 16
uint32_t dss_pattern_key(const sunmc_config *c, uint64_t seed, long unit);

/* Whether the spot of s carries a fixed pattern or a ghost. */
int dss_sensor_extras_on(const dss_sensor *s);

/* Add the fixed pattern's and the ghost's centroid errors (dss_pattern.h)
 * to the noiseless spot (x_px, y_px) of sun direction u. */
void dss_sensor_extras(const dss_sensor *s, const double u[3], double *x_px, double *y_px);

/* The sun disc's coefficient m2 / 4 (rad^2) of design.sun_disc_deg and
 * design.limb_darkening u (see Sun disc above): R^2 (15 - 7u) / (40 (3 - u)). */
#define DSS_DISC_C_MAX_RAD2 1e-4 /* above design.sun_disc_deg = 2's coefficient (7.6e-5) */
double dss_disc_coefficient(double sun_disc_deg, double limb_darkening);

/* Build the sensor from design d, deviations dev and s_curve (0 or 1). */
void dss_sensor_init(dss_sensor *s, const dss_design *d, const dss_deviations *dev, int s_curve);

/* The same with the S-curve amplitudes given (dss_scurve_amplitudes of
 * dss_spot_px(d), which depend on the design only: a run makes them once);
 * amp_px NULL makes them. */
void dss_sensor_init_amp(dss_sensor *s, const dss_design *d, const dss_deviations *dev,
                         int s_curve, const double *amp_px);

/* The spot's diameter (px) of design d: pinhole over pixel. */
double dss_spot_px(const dss_design *d);

/* The sun simulator's direction (unit) in the table base frame for mount
 * mode `mount` and mount rotation M: M^T e_z (aligned) or R(sun_b1,
 * sun_b2) e_z (as_mounted; angles in rad). */
void dss_sun_direction(int mount, const mat3 M, double sun_b1, double sun_b2, double v[3]);

/* The truth angles (rad) of a table at (b1, b2) rad under mount mode
 * `mount` with sun simulator v_sun (see Truth above). */
void dss_truth_angles(int mount, const double v_sun[3], double b1, double b2, double *alpha,
                      double *beta);

/* dss_truth_angles of sensor s. */
void dss_sensor_truth(const dss_sensor *s, double b1, double b2, double *alpha, double *beta);

/* Sun direction u[3] (unit, toward the sun) in frame b at true table angles
 * (b1, b2) rad. */
void dss_sensor_sun(const dss_sensor *s, double b1, double b2, double u[3]);

/* Measured spot centre (px from the detector centre) for sun direction u:
 * ray trace, S-curve bias (if on), plus noise_px[2] (NULL: none).
 * SUNMC_EDOM when the spot is not (wholly) on the detector. */
int dss_sensor_spot(const dss_sensor *s, const double u[3], const double noise_px[2],
                    double *x_px, double *y_px);

/* Table at true angles (b1, b2) rad: the measured spot (as above). */
int dss_sensor_read(const dss_sensor *s, double b1, double b2, const double noise_px[2],
                    double *x_px, double *y_px);

/* dss_onboard_angles with the sensor's nominal design. */
int dss_sensor_angles(const dss_sensor *s, double x_px, double y_px, double *alpha,
                       double *beta);

#endif
