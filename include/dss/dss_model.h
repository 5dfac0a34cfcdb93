/* dss_model.h - the physical DSS calibration model: the spot a unit with
 * parameters p shows at recorded table angles (b1, b2), its analytic
 * Jacobian, and its inverse (a spot into calibrated angles).
 *
 * It is the geometry of dss_sensor.h with the as-built quantities as
 * parameters (lengths in mm, angles in rad):
 *     u    = M R(b) v_sun,            M = rot_zxy(c1, c2, c3)
 *     v_sun = M^T e_z (campaign.mount = aligned) or R(s1, s2) e_z (as_mounted)
 *     spot = (x0, y0) - (ux, uy) q(u; H, t, n)          (optics.h)
 * and is fitted in pixels.  What the campaign cannot separate (found from
 * the Jacobian's conditioning, see dss_calib.h) is held fixed by the fit;
 * the model itself carries every parameter.
 *
 * With calibration.fit_detector_tilt = on the spot is then carried along
 * the sun's ray to the detector plane tilted by D = rot_zxy(tx, ty, 0) and
 * read in its axes, as the truth does (dss_sensor.h, Detector tilt).
 *
 * Compensation inverts it exactly (a tilted model first carries the
 * measured spot back to z = 0 along the sun's ray, the ray refined from
 * the spot's own inversion, DSS_UNTILT_ITER times): the spot's distance from (x0, y0) gives
 * the field angle (Newton on the glass formula), its direction the azimuth;
 * that u is taken back through M into the table-top frame, w = M^T u.
 * as_mounted: the output is w's angles (atan(w_x/w_z), atan(w_y/w_z)), the
 * sun in the mount's frame.  aligned: the table is solved for the b with
 * R(b) v_sun = w and the output is that b's truth angles (eq. 3-4), the
 * angles the table would have set (dss_sensor.h, Truth).
 */
#ifndef SUNMC_DSS_MODEL_H
#define SUNMC_DSS_MODEL_H

#include "dss_config.h"
#include "rotation.h"

#include <stddef.h>

enum dss_param {
    DSS_P_X0 = 0, /* pinhole foot x (mm): dx */
    DSS_P_Y0,     /* pinhole foot y (mm): dy */
    DSS_P_H,      /* pinhole height (mm): h + dh */
    DSS_P_T,      /* cover-glass thickness (mm) */
    DSS_P_C1,     /* installation rotation about X (rad) */
    DSS_P_C2,     /* about Y (rad) */
    DSS_P_C3,     /* about Z (rad) */
    DSS_P_N,      /* cover-glass index */
    DSS_P_S1,     /* sun simulator: table angle b1 it equals (rad), as_mounted */
    DSS_P_S2,     /* and b2 (rad) */
    DSS_P_TX,     /* detector tilt about X (rad): calibration.fit_detector_tilt = on only */
    DSS_P_TY,     /* about the new Y (rad) */
    DSS_NP
};
/* Rotation parameters whose d v_sun / d p the model caches: c1-c3, s1, s2. */
#define DSS_N_ROT 5

/* The parameters as every output names them (units.tsv, the calibrate
 * report, params.ini), in enum order: each the fitted deviation from the
 * nominal design in its name's unit, as the matching tolerance is:
 * fit_dx_px, fit_dy_px, fit_dh_px (height, glass included),
 * fit_glass_thickness_um, fit_c1_arcsec .. fit_c3_arcsec (the mount),
 * fit_glass_index, fit_sun_b1_arcsec, fit_sun_b2_arcsec (the sun
 * simulator), fit_detector_tilt_x_arcsec, fit_detector_tilt_y_arcsec (the
 * detector plane against the mask; only with calibration.fit_detector_tilt
 * = on: off, the model has no tilt, holds them at 0 and no output names
 * them). */
extern const char *const dss_param_names[DSS_NP];

typedef struct {
    double p[DSS_NP];
    double pixel_um;       /* detector pitch as configured (params.ini records it) */
    double pixel_mm;       /* the same in mm: pixel_um * MM_PER_UM, the model's spots are in px */
    double half_px;        /* half the detector side: no reading beyond it (0: unknown) */
    int mount;             /* enum dss_mount */
    double disc_c_rad2;    /* the sun's disc (dss_disc_coefficient; 0: a point sun) */
    double nominal[DSS_NP]; /* the design's values (dss_model_init) */
    int tilt;              /* 1: the detector tilt extension (design.fit_tilt) */
    /* filled by dss_model_prepare */
    mat3 M, dM[3];         /* M and dM/dc1, dM/dc2, dM/dc3 */
    double v0[3];          /* v_sun */
    double dv0[DSS_N_ROT][3]; /* d v_sun / d (c1, c2, c3, s1, s2) */
    mat3 D, dD[2];         /* tilt: rot_zxy(tx, ty, 0) and its derivatives (dss_sensor.h) */
} dss_model;

/* The nominal unit of design d (prepared; d->mount is the model's). */
void dss_model_init(dss_model *m, const dss_design *d);

/* Named value of parameter k (see dss_param_names): (p - nominal) times
 * dss_param_scale; and the scale (named unit per internal unit). */
double dss_param_value(const dss_model *m, int k);
double dss_param_scale(const dss_model *m, int k);

/* Set parameter k from its named value (not prepared). */
void dss_param_set(dss_model *m, int k, double value);

/* Recompute the cached rotations after changing m->p. */
void dss_model_prepare(dss_model *m);

/* Predicted spot (px from the detector centre) at table angles (b1, b2) rad;
 * if J != NULL, J[0][j] and J[1][j] receive d x_px / d p_j and d y_px / d p_j.
 * SUNMC_EDOM when the sun is behind the sensor or totally reflected. */
int dss_model_spot(const dss_model *m, double b1, double b2, double spot_px[2],
                   double J[2][DSS_NP]);

/* The truth angles (rad) the model assigns to table angles (b1, b2) rad:
 * dss_truth_angles with its v_sun. */
void dss_model_truth(const dss_model *m, double b1, double b2, double *alpha, double *beta);

/* Calibrated angles (rad) of a measured spot (px).  SUNMC_EDOM when the spot
 * cannot come from a sun in front of the sensor. */
int dss_model_compensate(const dss_model *m, double x_px, double y_px, double *alpha,
                         double *beta);

/* Readings per vectorised chunk of the batch forms. */
#define DSS_CHUNK 64

/* Rotary-table rotations R(b1, b2) of n points, structure of arrays for the
 * fit: m[3 r + c][i] = R_i[r][c], each array vm_pad(n) values (vmath.h). */
typedef struct {
    size_t n;
    double *m[9];
} dss_table;

/* Fill t from b1_rad, b2_rad (vm_pad(t->n) values each). */
void dss_table_fill(dss_table *t, const double *b1_rad, const double *b2_rad);

/* The fit's residuals and Jacobian at every point of t at once
 * (vectorised), rows 2i (x) and 2i + 1 (y): f = sw (model - measured) px,
 * col[j][row] = sw d model / d p_j, all 0 where sw[i] = 0 or the model has
 * no spot.  Arrays of vm_pad(t->n) points (f and each col of twice that);
 * col[j] may point to a scratch column for a parameter not fitted. */
void dss_model_batch(const dss_model *m, const dss_table *t, const double *x_px,
                     const double *y_px, const double *sw, double *f, double *const col[DSS_NP]);

/* dss_model_compensate for n spots at once (vectorised; each gives the bits
 * it gives alone): alpha[i], beta[i], status[i] = SUNMC_OK or SUNMC_EDOM.
 * Returns SUNMC_EDOM if any failed. */
int dss_model_compensate_batch(const dss_model *m, size_t n, const double *x_px,
                               const double *y_px, double *alpha, double *beta, int *status);

/* The same for the noisy spots (x, y) and the same spots without their
 * noise (x0, y0): each noise-free spot's inversion starts from its noisy
 * twin's solution (dss_field_sine_chunk's start), so its angles may differ
 * from dss_model_compensate's in the last bits (the root is the same). */
int dss_model_compensate_pair_batch(const dss_model *m, size_t n, const double *x_px,
                                    const double *y_px, const double *x0_px,
                                    const double *y0_px, double *alpha, double *beta,
                                    int *status, double *alpha0, double *beta0, int *status0);

/* The tangent of the field angle of k <= DSS_CHUNK spots at radial
 * distances r_mm from the pinhole's foot: the root of gain(theta)
 * f(theta) = r with f the glass formula (optics.h) and gain the sun disc's
 * (dss_sensor.h; disc_c = dss_disc_coefficient, 0: none), by Newton in the
 * tangent (dss_lane_tan_step: a square root and two divisions a step),
 * each lane stopping once its error bound is below DSS_TAN_TOL of its
 * tangent.  start (may be NULL: the paraxial angle) gives each lane's first
 * tangent, a value outside [0, tan OPTICS_FIELD_THETA_MAX_RAD] taking the
 * paraxial one.  tangent[i] (NaN where r is not finite), slope[i] = F' at
 * the last step (slope may be NULL), failed[i] = 1 where it did not
 * converge within OPTICS_FIELD_MAX_ITER steps.  Arrays of vm_pad(k) values
 * (vmath.h), r_mm's pads any valid numbers.  Returns the steps the chunk
 * took (its slowest lane's). */
int dss_field_tan_chunk(size_t k, const double *r_mm, double H_mm, double t_mm, double n,
                         double disc_c, const double *start, double *tangent, double *slope,
                         long *failed);

#endif
