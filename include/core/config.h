/* config.h - the effective configuration of a sunmc run.
 *
 * ONE table of keys (config_keys.c) drives everything: parsing an INI file,
 * `--set section.key=value`, range validation, `sunmc config` (the effective
 * config), configs/reference.ini (every key, commented) and the key list in
 * --help.  Each key has a section, a name carrying its unit (_mm, _um, _deg,
 * _arcsec, _pct, _px), a type, a default, an allowed range and a help text.
 *
 * Keys belong to one sensor family (ess, dss) or to both.  A key of the other
 * family in a file is an error naming the file, the line and the key.
 *
 * Angles are stored in the unit their key names (degrees, arcseconds); the
 * physics modules convert to radians at their entry.
 */
#ifndef SUNMC_CONFIG_H
#define SUNMC_CONFIG_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define CONFIG_LIST_MAX 32     /* most values in a list key */
#define CONFIG_BANDS_MAX 8     /* most report bands */
#define CONFIG_STR_MAX 64      /* longest string value */
#define CONFIG_ORIGIN_MAX 300  /* "file:line" or "--set" or "default" */

/* Sensor families. */
enum sensor_family_id { FAMILY_ESS = 1, FAMILY_DSS = 2 };
#define FAMILY_BOTH (FAMILY_ESS | FAMILY_DSS)

/* Distribution of a manufacturing or assembly tolerance.
 * fixed:       the deviation is `value` for every unit;
 * uniform:     uniform on [-value, +value];
 * normal:      normal with sigma = value;
 * truncnormal: normal with sigma = value, truncated at
 *              +-tolerance.truncation_sigmas * sigma. */
enum dist_kind { DIST_FIXED = 0, DIST_UNIFORM, DIST_NORMAL, DIST_TRUNCNORMAL };

typedef struct {
    double value;  /* in the unit of its key's name */
    int dist;      /* enum dist_kind */
} tolerance;

typedef struct {
    int n;
    double v[CONFIG_LIST_MAX];
} double_list;

/* Report bands on |angle|: band i holds lo[i] < |x| <= hi[i], or
 * 0 <= |x| <= hi[i] when lo[i] == 0.  Written "0:30, 30:60, 0:62". */
typedef struct {
    int n;
    double lo[CONFIG_BANDS_MAX];
    double hi[CONFIG_BANDS_MAX];
} band_list;

/* ESS design, tolerances and noise (paper: Fan et al., Sensors 2013). */
typedef struct {
    double H_mm;                  /* nominal slit-to-code-dial distance */
    double theta0_deg;            /* fine-code period */
    double coarse_resolution_deg; /* coarse-code cell width */
    double_list coarse_rows_x_mm; /* x position of each coarse row */
    double_list fine_rows_x_mm;   /* x position of the 4 fine rows */
    double slit_width_um;         /* entrance slit width */
    double dial_duty;             /* transparent fraction of a fine period */
    double sun_diameter_deg;      /* angular diameter of the sun */
    int harmonics;                /* 0 derived, 1 given */
    double a3_ratio;              /* given a3/a1 */
    double a5_ratio;              /* given a5/a1 */
    double fov_deg;               /* half field of view in alpha */
} ess_design;

typedef struct {
    tolerance dH_um, dd_um, dphi_deg, slit_width_um, harmonic_phase_deg;
    tolerance gain_pct, etch_um;
    tolerance install_x_arcsec, install_y_arcsec, install_z_arcsec;
    tolerance sun_x_arcsec, sun_y_arcsec;
} ess_tolerances;

typedef struct {
    double row_current_pct;  /* sigma of each fine-row current, % of a1 */
} ess_noise;

/* DSS design, tolerances and noise (paper: Wei et al.). */
typedef struct {
    double h_mm;             /* nominal pinhole-to-detector height */
    double pixel_um;         /* pixel pitch */
    int detector_px;         /* detector side in pixels (square) */
    double pinhole_um;       /* pinhole diameter */
    double glass_thickness_mm;
    double glass_index;
    double fov_deg;          /* half field of view, per axis */
} dss_design;

typedef struct {
    tolerance dh_px, dx_px, dy_px;
    tolerance c1_arcsec, c2_arcsec, c3_arcsec;
    tolerance glass_thickness_um, glass_index;
} dss_tolerances;

typedef struct {
    double centroid_px;      /* sigma of the spot centre, per axis */
    int s_curve;             /* 1: add the pixel-phase (S-curve) bias */
} dss_noise;

typedef struct {
    /* [sensor] */
    int family;                         /* enum sensor_family_id */
    char product[CONFIG_STR_MAX];       /* label in reports */

    ess_design ess;
    ess_tolerances ess_tol;
    ess_noise ess_noise;

    dss_design dss;
    dss_tolerances dss_tol;
    dss_noise dss_noise;

    double truncation_sigmas;           /* [tolerance] truncnormal limit */
    double encoder_arcsec;              /* [noise] sigma of each table axis reading */

    /* [campaign]: ESS alpha/beta grid, DSS b1/b2 grid */
    double cal_alpha_min_deg, cal_alpha_max_deg, cal_alpha_step_deg;
    double_list cal_beta_deg;
    double cal_b_min_deg, cal_b_max_deg, cal_b_step_deg;
    int cal_repeats;

    /* [calibration] */
    int cal_model;                      /* DSS: 0 physical, 1 polynomial */
    int poly_order;
    int fit_glass_index;                /* DSS physical model: 1 fits the glass index too */
    double roll_sigma_arcsec;           /* ESS roll alignment measurement */
    double roll_measured_arcsec;        /* `calibrate`: known roll, default 0 */
    double alias_threshold;
    int max_iterations;

    /* [validation] */
    double val_alpha_min_deg, val_alpha_max_deg, val_alpha_step_deg, val_alpha_offset_deg;
    double_list val_beta_deg;
    double val_b_min_deg, val_b_max_deg, val_b_step_deg, val_b_offset_deg;

    /* [run] */
    long units;
    long seed;
    int threads;

    /* [report] */
    band_list bands_deg;
    double spec_arcsec;
    double yield_target;                /* budget: yield the inverse limits must keep */
    long budget_units;                  /* budget: units per bisection step */
    int budget_steps;                   /* budget: bisection steps per source */
} sunmc_config;

/* One row of the key table. */
enum key_type { KEY_DOUBLE, KEY_INT, KEY_LONG, KEY_ENUM, KEY_STRING, KEY_LIST, KEY_BANDS };

typedef struct {
    const char *section;
    const char *name;
    int type;                /* enum key_type */
    int families;            /* FAMILY_ESS, FAMILY_DSS or FAMILY_BOTH */
    const char *unit;        /* for help and the reference file */
    const char *def;         /* default, as text (ESS, or both) */
    const char *def_dss;     /* DSS default when it differs, else NULL */
    double min, max;         /* allowed range (each element of a list) */
    const char *choices;     /* KEY_ENUM: "a|b|c", index = stored value */
    size_t offset;           /* into sunmc_config */
    const char *help;        /* one line; source of the default if any */
} config_key;

extern const config_key config_keys[];
extern const size_t config_key_count;

/* Where each key's value came from, for `sunmc config` and messages. */
typedef struct {
    char origin[CONFIG_ORIGIN_MAX];
} config_origin;

/* A configuration being built: values plus per-key origins. */
typedef struct {
    sunmc_config cfg;
    config_origin *origins;  /* config_key_count entries */
} config_state;

/* Build the effective config from an INI file (path may be NULL: defaults
 * only) and a list of "section.key=value" overrides.  The family is taken
 * from sensor.family (overrides first, then the file, else ess); defaults of
 * that family are applied, then the file, then the overrides, then
 * config_validate.  On error returns SUNMC_EINPUT (or SUNMC_EIO for an
 * unreadable file) with "FILE:LINE: message" in err. */
int config_build(config_state *st, const char *path, const char *const *sets, int n_sets,
                 char *err, size_t errlen);
void config_state_free(config_state *st);

/* Set one key from text.  `where` names the origin for messages
 * ("file.ini:12", "--set").  Checks type, range and family. */
int config_set_value(config_state *st, const char *section, const char *name,
                     const char *value, const char *where, char *err, size_t errlen);

/* Cross-key checks (list lengths, ranges consistent with the field of view). */
int config_validate(const sunmc_config *c, char *err, size_t errlen);

/* Find a key; NULL when unknown. */
const config_key *config_find(const char *section, const char *name);

/* Format a key's current value as it would be written in a file. */
void config_format_value(const config_key *k, const sunmc_config *c, char *buf, size_t len);

/* Write the effective config of c's family (every key, defaults filled in),
 * with the origin of each value as a comment when origins != NULL. */
int config_write(FILE *f, const config_state *st);

/* Write the commented reference config: every key of every family with its
 * unit, range, default and help. */
int config_write_reference(FILE *f);

/* Read a numeric key's value by "section.key" (sweeps); SUNMC_EINPUT if not
 * a number key. */
int config_get_number(const sunmc_config *c, const char *dotted, double *out,
                      char *err, size_t errlen);

#endif
