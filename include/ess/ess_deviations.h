/* ess_deviations.h - THE list of ESS tolerances: one line each.
 *
 * X(name, unit, count, stream, columns, default, dist, max, help)
 *   name     tolerance.NAME and tolerance.NAME_dist in the config, and the
 *            field of ess_tolerances and of ess_deviations (ess_sensor.h)
 *   unit     of the key (help, reference)
 *   count    draws per unit: 1, or ESS_FINE_ROWS for a per-row error
 *            (its ess_deviations field is then an array)
 *   stream   draws come from RNG_STREAM_TOLERANCE + stream: fixed forever;
 *            a new tolerance takes the next unused id, wherever it is listed
 *   columns  its units.tsv column name(s), count of them
 *   default, dist, max, help: the key's default magnitude and distribution
 *            (fixed|uniform|normal|truncnormal), its maximum and help line
 *
 * Adding a tolerance: one line here, its field in ess_deviations, and its
 * physics (where the sensor or the unit uses the field).
 * Defaults: product type A of the ESS paper (Fan et al., Sensors 2013).
 */
#ifndef SUNMC_ESS_DEVIATIONS_H
#define SUNMC_ESS_DEVIATIONS_H

#include "deviation.h"

#define ESS_FINE_ROWS 4

/* The units.tsv columns of a per-fine-row deviation: "gain1_pct".."gain4_pct". */
#define ESS_PER_ROW(stem, suffix) stem "1" suffix, stem "2" suffix, stem "3" suffix, stem "4" suffix

#define ESS_DEVIATIONS(X)                                                                         \
    X(dH_um, "um", 1, 0, "dH_um", "2", "uniform", 1000,                                           \
      "slit-to-dial distance error dH (ESS paper sec. 3.1: +-2 um)")                              \
    X(dd_um, "um", 1, 1, "dd_um", "1", "uniform", 1000,                                           \
      "slit offset dd from the dial's centre line (ESS paper sec. 3.2: +-1 um)")                  \
    X(dphi_deg, "deg", 1, 2, "dphi_deg", "0.01", "uniform", 10,                                   \
      "slit tilt dphi against the dial's centre line (ESS paper sec. 3.2: +-0.01 deg)")           \
    X(slit_width_um, "um", 1, 3, "slit_width_um", "1", "uniform", 100,                            \
      "slit width error (changes the derived fine-code harmonics)")                               \
    X(harmonic_phase_deg, "deg", 1, 4, "harmonic_phase_deg", "180", "uniform", 180,               \
      "phase of the 3rd harmonic against the fundamental, from etched-edge asymmetry "            \
      "(ESS paper Tables 3-4 show t far from 0)")                                                 \
    X(gain_pct, "%", ESS_FINE_ROWS, 5, ESS_PER_ROW("gain", "_pct"), "1", "uniform", 50,           \
      "per-row photocell gain error (ESS paper sec. 3.4: within +-1%)")                           \
    X(etch_um, "um", ESS_FINE_ROWS, 6, ESS_PER_ROW("etch", "_um"), "0.2", "uniform", 50,          \
      "per-row etching position error of the fine-code pattern (ESS paper sec. 3.4)")             \
    X(install_x_arcsec, "arcsec", 1, 7, "install_x_arcsec", "60", "uniform", 36000,               \
      "ESS-to-turntable rotation about X (roll in the sensing plane; measured, not fitted)")      \
    X(install_y_arcsec, "arcsec", 1, 8, "install_y_arcsec", "300", "uniform", 36000,              \
      "ESS-to-turntable rotation about Y (ESS paper Table 3: up to 5')")                          \
    X(install_z_arcsec, "arcsec", 1, 9, "install_z_arcsec", "90", "uniform", 36000,               \
      "ESS-to-turntable rotation about Z (ESS paper Table 3: up to 1'8\")")                       \
    X(sun_x_arcsec, "arcsec", 1, 10, "sun_x_arcsec", "60", "uniform", 36000,                      \
      "sun-simulator direction tilt toward X (the V0 of ESS paper eq. 14)")                       \
    X(sun_y_arcsec, "arcsec", 1, 11, "sun_y_arcsec", "60", "uniform", 36000,                      \
      "sun-simulator direction tilt toward Y")                                                    \
    X(spacer_cte_ppm_k, "ppm/K", 1, 12, "spacer_cte_ppm_k", "0", "uniform", 50,                   \
      "the unit's spacer expansion against environment.spacer_cte_ppm_k (lot scatter; moves H "   \
      "only away from calibration_temp_c; 0: no stated source)")                                  \
    X(mask_cte_ppm_k, "ppm/K", 1, 13, "mask_cte_ppm_k", "0", "uniform", 50,                       \
      "the unit's dial expansion against environment.mask_cte_ppm_k (moves the code pitch only "  \
      "away from calibration_temp_c; 0: no stated source)")                                      \
    X(dial_tilt_deg, "deg", 1, 14, "dial_tilt_deg", "0.01", "uniform", 10,                        \
      "code dial's tilt about the code-row axis (Y, through x = 0): a row at x sits x "           \
      "tan(tilt) farther from the slit (ESS paper sec. 3.2's dphi as its Figs. 6-7 show it: "    \
      "+-0.01 deg; docs/ess.md)")

/* Entries, and units.tsv columns of the list (a derived column, the roll
 * measurement, follows them: ESS_N_DEV in ess_sensor.h). */
enum {
    ESS_N_TOL = 0 ESS_DEVIATIONS(DEVIATION_X_ONE),
    ESS_N_TOL_COLUMNS = 0 ESS_DEVIATIONS(DEVIATION_X_COUNT)
};

#endif
