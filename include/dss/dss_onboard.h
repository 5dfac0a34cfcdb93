/* dss_onboard.h - the DSS's on-board formula: the angles its software
 * computes from a spot with the nominal design (frames in dss_sensor.h).
 *
 * design.onboard_refraction = corrected (default): the exact inverse of the
 * nominal geometry, cover glass included, so that the error before
 * calibration is what manufacturing and mounting do; `ignored`: the DSS
 * paper's eq. 9-10, which leaves the glass's refraction (the paper's Fig. 5)
 * in the error before calibration.
 */
#ifndef SUNMC_DSS_ONBOARD_H
#define SUNMC_DSS_ONBOARD_H

#include "dss_config.h"

#include <stddef.h>

/* The on-board formula: the nominal design as the sensor's software knows
 * it.  A spot at (x, y) px lies r = pixel_mm hypot(x, y) from the nominal
 * pinhole foot (the detector centre); the field angle theta solves
 * r = (h - t) tan(theta) + t tan(theta_g), sin(theta_g) = sin(theta) / n
 * (optics_field_angle), and the sun is u = (-x/r sin theta, -y/r sin
 * theta, cos theta): alpha = atan(-x tan(theta) / r), likewise beta.  With
 * glass_t_mm = 0 this is eq. 9-10 exactly, alpha = atan(-x pixel_mm / h). */
typedef struct {
    double h_mm;        /* pinhole height over the detector, glass included */
    double pixel_um;    /* as configured (params.ini records it) */
    double pixel_mm;    /* pixel_um * MM_PER_UM */
    double glass_t_mm;  /* 0: the glass is ignored (design.onboard_refraction) */
    double glass_n;
    double x0_px, y0_px; /* the spot taken as the origin: 0 but for
                          * design.principal_point = paper_eq6 (eq. 9-10) */
} dss_onboard;

/* The on-board formula of design d (its onboard_refraction setting). */
void dss_onboard_init(dss_onboard *o, const dss_design *d);

/* The on-board angles (rad) of a spot (px from the detector centre).
 * SUNMC_EDOM (angles NaN) when no field angle below 86 deg puts a spot
 * there. */
int dss_onboard_angles(const dss_onboard *o, double x_px, double y_px, double *alpha,
                       double *beta);

/* The same for k <= DSS_CHUNK spots at once (dss_model.h; arrays of
 * vm_pad(k) values, pads any valid numbers: vmath.h): status[i] = SUNMC_OK
 * or SUNMC_EDOM (angles NaN). */
void dss_onboard_chunk(const dss_onboard *o, size_t k, const double *x_px, const double *y_px,
                       double *alpha, double *beta, int *status);

#endif
