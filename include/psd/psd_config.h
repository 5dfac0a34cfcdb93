/* psd_config.h - the four-channel analog sun sensor ("psd" family): an
 * aperture at height h over a four-electrode detector, a lateral-effect
 * position-sensitive detector (duo- or tetra-lateral) or a quadrant
 * photodiode.  Its configuration, read through psd_cfg(c).
 *
 * THE list of PSD tolerances is PSD_DEVIATIONS below, one line each:
 * X(name, unit, count, stream, columns, default, dist, max, help) as in
 * deviation.h.  Adding a tolerance: its line here, its physics in
 * psd_sensor.c (psd_sensor_build reads the psd_deviations field).
 * Defaults: typical CubeSat fine sun sensors built on a Hamamatsu S5990 /
 * S5991 tetra-lateral PSD or a quadrant photodiode (docs/psd.md, Sources).
 */
#ifndef SUNMC_PSD_CONFIG_H
#define SUNMC_PSD_CONFIG_H

#include "config.h"
#include "deviation.h"

#define PSD_CHANNELS 4
/* The units.tsv columns of a per-channel deviation: "gain1_pct".."gain4_pct". */
#define PSD_PER_CHANNEL(stem, suffix) stem "1" suffix, stem "2" suffix, stem "3" suffix, stem "4" suffix

#define PSD_DEVIATIONS(X)                                                                         \
    X(dh_um, "um", 1, 0, "dh_um", "20", "uniform", 5000,                                          \
      "aperture height error (machining and spacer stack: +-20 um)")                              \
    X(dx_um, "um", 1, 1, "dx_um", "20", "uniform", 5000,                                          \
      "aperture offset from the detector centre along X (placement: +-20 um)")                    \
    X(dy_um, "um", 1, 2, "dy_um", "20", "uniform", 5000,                                          \
      "aperture offset from the detector centre along Y")                                         \
    X(aperture_um, "um", 1, 3, "aperture_um", "10", "uniform", 2000,                              \
      "aperture diameter error")                                                                  \
    X(tilt_x_arcsec, "arcsec", 1, 4, "tilt_x_arcsec", "60", "uniform", 36000,                     \
      "detector/mount rotation about X (zxy order, rotation.h; the DSS's c1)")                    \
    X(tilt_y_arcsec, "arcsec", 1, 5, "tilt_y_arcsec", "60", "uniform", 36000,                     \
      "detector/mount rotation about Y (the DSS's c2)")                                           \
    X(rot_z_arcsec, "arcsec", 1, 6, "rot_z_arcsec", "300", "uniform", 36000,                      \
      "detector rotation about its normal Z (die placement, the DSS's c3)")                       \
    X(gain_pct, "%", PSD_CHANNELS, 7, PSD_PER_CHANNEL("gain", "_pct"), "2", "uniform", 50,        \
      "per-channel responsivity x amplifier gain error")                                          \
    X(dark_pct, "%", PSD_CHANNELS, 8, PSD_PER_CHANNEL("dark", "_pct"), "0.5", "uniform", 50,      \
      "per-channel dark signal (dark current, amplifier offset), % of the ADC's full scale")      \
    X(background_pct, "%", 1, 9, "background_pct", "0", "uniform", 50,                           \
      "uniform background light on the whole active area (albedo, lab stray light), % of the "   \
      "sun's signal at normal incidence")                                                         \
    X(glass_thickness_um, "um", 1, 10, "glass_thickness_um", "10", "uniform", 1000,               \
      "cover-glass thickness error (where design.glass_thickness_mm > 0)")                        \
    X(glass_index, "", 1, 11, "glass_index", "0.005", "uniform", 0.5,                             \
      "cover-glass refractive index error")


enum psd_detector { PSD_LATERAL = 0, PSD_QUADRANT = 1 };
enum psd_lateral { PSD_DUO = 0, PSD_TETRA = 1 };
enum psd_polarity { PSD_POSITIVE = 0, PSD_INVERTED = 1 };
/* The lab's two-axis table: how (alpha, beta) put the sun in the table top
 * (rotation.h's passive rotations): projected: tan(alpha) = u_x/u_z and
 * tan(beta) = u_y/u_z; alpha_outer: u = rot_x(sb beta) rot_y(-sa alpha) e_z;
 * beta_outer: u = rot_y(-sa alpha) rot_x(sb beta) e_z (sa, sb the signs). */
enum psd_table { PSD_TABLE_PROJECTED = 0, PSD_TABLE_ALPHA_OUTER = 1, PSD_TABLE_BETA_OUTER = 2 };
enum psd_model { PSD_MODEL_PHYSICAL = 0, PSD_MODEL_POLYNOMIAL = 1, PSD_MODEL_SPLINE = 2,
                 PSD_MODEL_HYBRID = 3, PSD_MODEL_TABLE = 4 };
#define PSD_N_MODELS 5
/* Does model m fit core's spline (alone, under a table, or as a correction)? */
#define PSD_MODEL_HAS_SPLINE(m) \
    ((m) == PSD_MODEL_SPLINE || (m) == PSD_MODEL_HYBRID || (m) == PSD_MODEL_TABLE)
/* Does model m fit the physical model (alone, or under a correction)? */
#define PSD_MODEL_HAS_PHYSICS(m) ((m) == PSD_MODEL_PHYSICAL || (m) == PSD_MODEL_HYBRID)
enum psd_poly_form { PSD_POLY_FULL = 0, PSD_POLY_FSS20 = 1 };

typedef struct {
    PSD_DEVIATIONS(DEVIATION_X_TOLERANCE)
} psd_tolerances;

/* One unit's deviations, in the units of their names. */
#define PSD_X_FIELD(name, unit, count, ...) double name[count];
typedef struct {
    PSD_DEVIATIONS(PSD_X_FIELD)
} psd_deviations;
#undef PSD_X_FIELD

enum {
    PSD_N_TOL = 0 PSD_DEVIATIONS(DEVIATION_X_ONE),
    PSD_N_DEV = 0 PSD_DEVIATIONS(DEVIATION_X_COUNT)
};

typedef struct {
    int detector, lateral, polarity;
    double h_mm, active_mm, aperture_um, gap_um, pincushion;
    double glass_thickness_mm, glass_index;
    double fov_deg;
    double signal_fs;       /* sun signal at normal incidence, fraction of the ADC's full scale */
    double dark_fs;         /* nominal dark signal of each channel, fraction of full scale */
} psd_design;

typedef struct {
    psd_design design;
    psd_tolerances tol;
    double noise_fs_pct;    /* channel noise sigma, % of full scale */
    double lamp_pct;        /* the lab's light, sigma of its change per reading, % */
    double table_line_arcsec; /* the table's setting error per scan line, sigma per axis */
    double common_pct;      /* noise shared by the channels, sigma, % of full scale */
    double_list common_signs; /* its sign (weight) on each channel: 4 values */
    int adc_bits;
    int table_order;
    int table_alpha_sign, table_beta_sign; /* 0: +1, 1: -1 */
    double cal_alpha_max_deg, cal_alpha_step_deg;
    double_list cal_beta_deg;
    double val_alpha_max_deg, val_alpha_step_deg, val_alpha_offset_deg;
    double_list val_beta_deg;
    int cal_model, poly_order, poly_form, fit_tilt;
    /* [environment] (psd_thermal.h) */
    double dark_doubling_k;       /* the dark signals double every this many K; 0: no drift */
    double responsivity_tc_ppm_k; /* the channels' gains per kelvin */
} psd_config;

static inline const psd_config *psd_cfg(const sunmc_config *c)
{
    return (const psd_config *)(const void *)c->fam.bytes;
}

extern const config_key psd_keys[];
extern const config_default psd_defaults[];
int psd_validate(const sunmc_config *c, char *err, size_t errlen);

#endif
