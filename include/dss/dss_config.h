/* dss_config.h - the DSS family's own configuration: its design, tolerances,
 * noise, campaign and validation grids and calibration model.
 *
 * It lives in the opaque sunmc_config.fam; read it through dss_cfg(c).  The
 * keys that fill it, with their defaults, are in dss_keys.c (paper: Wei et
 * al., "System modeling based measurement error analysis of digital sun
 * sensors").
 */
#ifndef SUNMC_DSS_CONFIG_H
#define SUNMC_DSS_CONFIG_H

#include "config.h"
#include "deviation.h"
#include "dss_deviations.h"

typedef struct {
    double h_mm;             /* nominal pinhole-to-detector height */
    double pixel_um;         /* pixel pitch */
    int detector_px;         /* detector side in pixels (square) */
    double pinhole_um;       /* pinhole diameter */
    double wavelength_nm;    /* the sunlight's effective wavelength (0: no diffraction) */
    double mask_thickness_um; /* the mask's thickness: the pinhole is a tube */
    int centroid_window_px;  /* the centroid window's half-width m (0: the whole spot) */
    double glass_thickness_mm;
    double glass_index;
    double fov_deg;          /* half field of view, per axis */
    double sun_disc_deg;     /* the sun's apparent diameter (0: a point sun) */
    double limb_darkening;   /* linear limb-darkening coefficient u: I(mu) = 1 - u (1 - mu) */
    int onboard_refraction;  /* enum dss_onboard_refraction (dss_onboard.h) */
    int mount;               /* enum dss_mount: campaign.mount, the lab's procedure, carried
                              * with the design so every model of the unit knows it */
    int principal_point;     /* enum dss_principal_point: how dx, dy enter the sensor */
    int fit_tilt;            /* calibration.fit_detector_tilt: 1 extends the physical model by
                              * the detector's tilt (dss_model.h), carried with the design as
                              * mount is */
} dss_design;

/* The values of campaign.mount (dss_sensor.h): aligned = the DSS paper's
 * eq. 6, the lab aligns the sun to the detector normal at the table's zero
 * (sun simulator at M^T e_z); as_mounted = the unit sits on the table as
 * mounted and the sun simulator points where it points. */
enum dss_mount { DSS_MOUNT_ALIGNED = 0, DSS_MOUNT_AS_MOUNTED = 1 };

/* The values of calibration.sun: the sun simulator's direction (sun_b1,
 * sun_b2; campaign.mount = as_mounted) fitted with the rest, or fixed at a
 * measurement. */
enum dss_sun_mode { DSS_SUN_FITTED = 0, DSS_SUN_MEASURED = 1 };

/* The values of design.principal_point: physical = the pinhole sits at
 * (dx, dy) from where the on-board formula assumes it; paper_eq6 = the DSS
 * paper's eq. 5-6 taken literally: the pinhole is where assumed, the sun at
 * the table's zero arrives along S_b0 = (dx, dy, -h) and is rotated with
 * the table, and the on-board formula (eq. 9-10) subtracts (dx, dy). */
enum dss_principal_point { DSS_PP_PHYSICAL = 0, DSS_PP_PAPER_EQ6 = 1 };

/* The values of design.onboard_refraction. */
enum dss_onboard_refraction { DSS_ONBOARD_CORRECTED = 0, DSS_ONBOARD_IGNORED = 1 };

/* One tolerance per line of DSS_DEVIATIONS. */
typedef struct {
    DSS_DEVIATIONS(DEVIATION_X_TOLERANCE)
} dss_tolerances;

typedef struct {
    double centroid_px;      /* sigma of the spot centre, per axis */
    int s_curve;             /* 1: add the pixel-phase (S-curve) bias */
} dss_noise;

typedef struct {
    dss_design design;
    dss_tolerances tol;
    dss_noise noise;

    /* [campaign]: rotary-table b1 x b2 grid */
    double cal_b_min_deg, cal_b_max_deg, cal_b_step_deg;

    /* [calibration] */
    int cal_model;           /* 0 physical, 1 polynomial */
    int poly_order;
    int fit_glass_index;     /* physical model: 1 fits the glass index too */
    int sun_mode;            /* enum dss_sun_mode: calibration.sun */
    double sun_sigma_arcsec; /* sun simulator's direction: measurement sigma, per angle */
    double sun_b1_measured_arcsec, sun_b2_measured_arcsec; /* `calibrate`: its measured value */

    /* [validation] */
    double val_b_min_deg, val_b_max_deg, val_b_step_deg, val_b_offset_deg;
} dss_config;

/* The DSS part of config c (const for a const c). */
#define dss_cfg(c)                                                                                \
    _Generic((c), const sunmc_config *: (const dss_config *)(const void *)(c)->fam.bytes,        \
             sunmc_config *: (dss_config *)(void *)(c)->fam.bytes)

/* The family's keys, its defaults of shared keys and its cross-key checks
 * (dss_keys.c), for its sensor_family struct. */
extern const config_key dss_keys[];         /* ends with a NULL section */
extern const config_default dss_defaults[]; /* ends with a NULL section */
extern const char *const dss_sections_after_shared[];
int dss_config_validate(const sunmc_config *c, char *err, size_t errlen);

#endif
