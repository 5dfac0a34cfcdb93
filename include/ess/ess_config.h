/* ess_config.h - the ESS family's own configuration: its design, tolerances,
 * noise, campaign and validation grids and calibration settings.
 *
 * It lives in the opaque sunmc_config.fam; read it through ess_cfg(c).  The
 * keys that fill it, with their defaults, are in ess_keys.c (paper: Fan et
 * al., "Error Modeling and Calibration for Encoded Sun Sensors", Sensors 2013).
 */
#ifndef SUNMC_ESS_CONFIG_H
#define SUNMC_ESS_CONFIG_H

#include "config.h"
#include "deviation.h"
#include "ess_deviations.h"

typedef struct {
    double H_mm;                  /* nominal slit-to-code-dial distance */
    double theta0_deg;            /* fine-code period */
    double coarse_resolution_deg; /* coarse-code cell width */
    double_list coarse_rows_x_mm; /* x position of each coarse row */
    double_list fine_rows_x_mm;   /* x position of the 4 fine rows */
    double tilt_pivot_mm;         /* x about which the slit's tilt dphi turns */
    double slit_width_um;         /* entrance slit width */
    double dial_duty;             /* transparent fraction of a fine period */
    double sun_diameter_deg;      /* angular diameter of the sun */
    int harmonics;                /* 0 derived, 1 given */
    double a3_ratio;              /* given a3/a1 */
    double a5_ratio;              /* given a5/a1 */
    double fov_deg;               /* half field of view in alpha */
} ess_design;

/* One tolerance per line of ESS_DEVIATIONS. */
typedef struct {
    ESS_DEVIATIONS(DEVIATION_X_TOLERANCE)
} ess_tolerances;

typedef struct {
    double row_current_pct;  /* sigma of each fine-row current, % of a1 */
} ess_noise;

typedef struct {
    ess_design design;
    ess_tolerances tol;
    ess_noise noise;

    /* [campaign]: turntable alpha scans at each beta */
    double cal_alpha_min_deg, cal_alpha_max_deg, cal_alpha_step_deg;
    double_list cal_beta_deg;

    /* [calibration] */
    double roll_sigma_arcsec;     /* roll alignment measurement */
    double roll_measured_arcsec;  /* `calibrate`: known roll, default 0 */
    double alias_threshold;
    int cal_model;                /* enum ess_model_kind: paper | extended */
    int sun_y_mode;               /* enum ess_sun_y_mode: fitted | measured */
    double sun_y_sigma_arcsec;    /* sun-simulator tilt toward Y: measurement sigma */
    double sun_y_measured_arcsec; /* `calibrate`: its measured value, default 0 */

    /* [validation] */
    double val_alpha_min_deg, val_alpha_max_deg, val_alpha_step_deg, val_alpha_offset_deg;
    double_list val_beta_deg;
} ess_config;

/* calibration.sun_y (the key's enum order): the sun simulator's tilt toward
 * Y fitted with the rest, or fixed at a measurement like the roll. */
enum ess_sun_y_mode { ESS_SUN_Y_FITTED = 0, ESS_SUN_Y_MEASURED = 1 };

/* The ESS part of config c (const for a const c). */
#define ess_cfg(c)                                                                                \
    _Generic((c), const sunmc_config *: (const ess_config *)(const void *)(c)->fam.bytes,        \
             sunmc_config *: (ess_config *)(void *)(c)->fam.bytes)

/* The family's keys, its defaults of shared keys and its cross-key checks
 * (ess_keys.c), for its sensor_family struct. */
extern const config_key ess_keys[];         /* ends with a NULL section */
extern const config_default ess_defaults[]; /* ends with a NULL section */
int ess_config_validate(const sunmc_config *c, char *err, size_t errlen);

#endif
