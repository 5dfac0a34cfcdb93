/* dss_deviations.h - THE list of DSS tolerances: one line each.
 *
 * X(name, unit, count, stream, columns, default, dist, max, help): as in
 * ess_deviations.h (name: tolerance.NAME, NAME_dist and the field of
 * dss_tolerances and dss_deviations; stream: RNG_STREAM_TOLERANCE + stream,
 * fixed forever).  Adding a tolerance: one line here, its field in
 * dss_deviations (dss_sensor.h), and its physics.
 * Defaults: the DSS paper (Wei et al.), Figs. 2-4; c1-c3 are the mount's
 * rotation on the table top, sun_b1, sun_b2 the sun simulator's direction
 * (dss_sensor.h).  detector_tilt_x, _y are outside the calibration model
 * (issue 38): the die's wedge on its attach; 0 by default until a source
 * states it (an assumed 20 um over the 2048 x 5.5 um die would be 366").
 * prnu_pct, dsnu_pct (the detector's fixed pattern, each unit its own, its
 * rms amplitude uniform below the datasheet's bound) and glass_ghost
 * ('fixed': the physics of uncoated glass) are outside it too
 * (dss_pattern.h).
 */
#ifndef SUNMC_DSS_DEVIATIONS_H
#define SUNMC_DSS_DEVIATIONS_H

#include "deviation.h"

#define DSS_DEVIATIONS(X)                                                                         \
    X(dh_px, "px", 1, 0, "dh_px", "0.2", "uniform", 1000,                                         \
      "pinhole height error dh (DSS paper Fig. 2: 0.2 pixel)")                                    \
    X(dx_px, "px", 1, 1, "dx_px", "0.1", "uniform", 1000,                                         \
      "principal point error dx (DSS paper Fig. 3: 0.1 pixel)")                                   \
    X(dy_px, "px", 1, 2, "dy_px", "0.1", "uniform", 1000,                                         \
      "principal point error dy (DSS paper Fig. 3: 0.1 pixel)")                                   \
    X(c1_arcsec, "arcsec", 1, 3, "c1_arcsec", "10", "uniform", 36000,                             \
      "installation rotation c1 about X (DSS paper sec. 3: c1, c2 about X, Y, c3 about the "      \
      "principal axis, composed in zxy order; Fig. 4: 10\")")                                     \
    X(c2_arcsec, "arcsec", 1, 4, "c2_arcsec", "10", "uniform", 36000,                             \
      "installation rotation c2 about Y (DSS paper Fig. 4: 10\")")                                \
    X(c3_arcsec, "arcsec", 1, 5, "c3_arcsec", "10", "uniform", 36000,                             \
      "installation rotation c3 about Z, the principal axis (DSS paper Fig. 4: 10\")")            \
    X(glass_thickness_um, "um", 1, 6, "glass_thickness_um", "10", "uniform", 1000,                \
      "cover-glass thickness error")                                                              \
    X(glass_index, "", 1, 7, "glass_index", "0.005", "uniform", 0.5,                              \
      "cover-glass refractive index error")                                                       \
    X(sun_b1_arcsec, "arcsec", 1, 8, "sun_b1_arcsec", "10", "uniform", 36000,                     \
      "sun-simulator axis in the table base frame: it points where a perfect one would with the " \
      "table at (sun_b1, sun_b2); campaign.mount = as_mounted only")                              \
    X(sun_b2_arcsec, "arcsec", 1, 9, "sun_b2_arcsec", "10", "uniform", 36000,                     \
      "sun-simulator axis, the table angle about Y it equals (see sun_b1_arcsec)")                \
    X(spacer_cte_ppm_k, "ppm/K", 1, 10, "spacer_cte_ppm_k", "0", "uniform", 50,                   \
      "the unit's spacer expansion against environment.spacer_cte_ppm_k (lot scatter; moves h "   \
      "only away from calibration_temp_c; 0: no stated source)")                                  \
    X(detector_cte_ppm_k, "ppm/K", 1, 11, "detector_cte_ppm_k", "0", "uniform", 50,               \
      "the unit's detector expansion against environment.detector_cte_ppm_k (pixel pitch)")       \
    X(glass_cte_ppm_k, "ppm/K", 1, 12, "glass_cte_ppm_k", "0", "uniform", 50,                     \
      "the unit's cover-glass expansion against environment.glass_cte_ppm_k (its thickness)")     \
    X(glass_dn_dt_ppm_k, "ppm/K", 1, 13, "glass_dn_dt_ppm_k", "0", "uniform", 50,                 \
      "the unit's cover-glass dn/dT against environment.glass_dn_dt_ppm_k (melt scatter)")       \
    X(detector_tilt_x_arcsec, "arcsec", 1, 14, "detector_tilt_x_arcsec", "0", "uniform", 36000,   \
      "detector plane tilted against the mask about its X axis, not in the calibration model; "   \
      "0 until a source is found (a 20 um die-attach wedge over an 11.3 mm die would be "         \
      "atan(0.020 / 11.26) = 366\")")                                                              \
    X(detector_tilt_y_arcsec, "arcsec", 1, 15, "detector_tilt_y_arcsec", "0", "uniform", 36000,   \
      "detector plane tilted against the mask about its Y axis (see detector_tilt_x_arcsec)")    \
    X(prnu_pct, "%", 1, 16, "prnu_pct", "1", "uniform", 100,                                       \
      "pixel response non-uniformity, rms gain of the unit's fixed pattern (not in the "          \
      "calibration model; CMV4000 datasheet, the 2048 x 5.5 um detector: PRNU < 1 % rms, so "    \
      "units spread below it; the sign flips the pattern)")                                       \
    X(dsnu_pct, "%", 1, 17, "dsnu_pct", "0.1", "uniform", 100,                                     \
      "dark signal non-uniformity, rms dark offset of the fixed pattern in % of the spot's peak " \
      "pixel (CMV4000 datasheet: fixed pattern noise < 1 LSB rms of 10 bits, 0.1 % of full "    \
      "scale)")                                                                                   \
    X(glass_ghost, "", 1, 18, "glass_ghost", "1", "fixed", 100,                                    \
      "the cover glass's ghost (its double internal reflection) as a multiple of the Fresnel "   \
      "reflectance of uncoated glass (1: 0.18 % of the spot at n = 1.52; an AR coating is < 1)")

enum {
    DSS_N_TOL = 0 DSS_DEVIATIONS(DEVIATION_X_ONE),
    DSS_N_DEV = 0 DSS_DEVIATIONS(DEVIATION_X_COUNT)
};

#endif
