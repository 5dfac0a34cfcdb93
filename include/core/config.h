/* config.h - the effective configuration of a sunmc run.
 *
 * The key tables (config_keys.c + each family's) drive everything: parsing an INI file,
 * `--set section.key=value`, range validation, `sunmc config` (the effective
 * config), configs/reference.ini (every key, commented) and the key list in
 * --help.  Each key has a section, a name carrying its unit (_mm, _um, _deg,
 * _arcsec, _pct, _px), a type, a default, an allowed range and a help text.
 *
 * Shared keys (core's table) apply to every family; each family adds its own
 * keys (its *_keys.c), reached through the registry (registry.h).  A key of
 * another family in a file is an error naming the file, the line and the key.
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
#define CONFIG_PICK_MAX 8      /* most streams one pick-freeze source swaps */
#define CONFIG_TEMPS_MAX 16    /* most operating temperatures (environment.operating_temp_c) */

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
    double lot;    /* share of the variance common to a lot (NAME_lot, 0..1) */
    double cost;   /* `allocate`: what today's value costs (NAME_cost) */
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

/* A family's own configuration (its design, tolerances, noise, grids):
 * opaque to core, read by the family through its accessor (ess_cfg(c),
 * dss_cfg(c)).  Plain bytes, so a sunmc_config copies with `=`; each family
 * asserts at compile time that its struct fits. */
#define FAMILY_CONFIG_MAX 4096
typedef union {
    max_align_t align;
    unsigned char bytes[FAMILY_CONFIG_MAX];
} family_config;

struct sensor_family;

/* report.yield_interval (the key's enum order). */
enum config_yield_interval {
    CONFIG_YIELD_WILSON = 0,
    CONFIG_YIELD_CLOPPER_PEARSON = 1,
    CONFIG_YIELD_CLOPPER_PEARSON_LOWER = 2
};

/* run.sampling (the key's enum order). */
enum config_sampling {
    CONFIG_SAMPLING_RANDOM = 0,
    CONFIG_SAMPLING_LHS = 1,
    CONFIG_SAMPLING_SOBOL = 2
};

/* calibration.priors (the key's enum order). */
enum config_priors { CONFIG_PRIORS_OFF = 0, CONFIG_PRIORS_TOLERANCES = 1 };
enum config_outliers { CONFIG_OUTLIERS_KEEP = 0, CONFIG_OUTLIERS_DROP = 1 };

typedef struct {
    /* [sensor] */
    const struct sensor_family *family; /* from the registry (registry.h) */
    char product[CONFIG_STR_MAX];       /* label in reports */

    double truncation_sigmas;           /* [tolerance] truncnormal limit */
    double encoder_arcsec;              /* [noise] sigma of each table axis reading */
    int cal_repeats;                    /* [campaign] readings averaged per point */
    double dwell_s;                     /* [campaign] cost: time per reading */
    double point_settle_s;              /* [campaign] cost: settling after a step */
    double line_settle_s;               /* [campaign] cost: settling after a slow-axis move */
    double slew_deg_per_s;              /* [campaign] cost: table rate */
    /* [campaign] search_*: the candidate space of `sunmc design` (design.h) */
    double_list search_steps_deg;       /* fast-axis steps */
    int search_max_lines;               /* symmetric line sets of 1..this many lines */
    double search_beta_max_deg;         /* largest |line| */
    double search_beta_step_deg;        /* line-set extents: this step up to the max */
    double_list search_repeats;         /* readings per point */
    long search_screen_units;           /* units of the screen */
    long search_max_units;              /* most units a candidate is run on */
    int search_shortlist;               /* passing candidates settled before stopping */
    double search_max_extrapolation_deg; /* candidates validated further beyond their span: skipped */
    int max_iterations;                 /* [calibration] most fit iterations */
    double max_dropped_fraction;        /* [calibration] calibrate: gross-error rows refused above */
    double max_residual_ratio;          /* [calibration] calibrate: residual / noise refused above */
    int cal_priors;                     /* [calibration] enum config_priors: off | tolerances */
    int prior_units;                    /* [calibration] pilot units of the priors */
    int cal_outlier_campaigns;          /* [calibration] enum config_outliers: keep | drop */

    /* [environment]: temperatures and materials (docs/temperature.md) */
    double cal_temp_c;                  /* the lab's temperature: campaign and fit */
    double_list op_temps_c;             /* the validations' temperatures (orbit); thermal.h */
    double spacer_cte_ppm_k;            /* spacer: ESS slit-to-dial H, DSS pinhole height h */
    double mask_cte_ppm_k;              /* ESS dial (code pitch) */
    double detector_cte_ppm_k;          /* DSS pixel pitch */
    double glass_cte_ppm_k;             /* DSS cover-glass thickness */
    double glass_dn_dt_ppm_k;           /* DSS cover-glass index, dn/dT */

    /* [run] */
    long units;
    long seed;
    int threads;
    long block_units;                   /* run --until: units per block */
    long lot_size;                      /* units per lot (tolerance NAME_lot) */
    int sampling;                       /* enum config_sampling: the tolerance draws' design */
    long sampling_block;                /* units per randomised design block (sampling.h) */

    /* [report] */
    band_list bands_deg;
    double spec_arcsec;
    int spec_statistic;                 /* enum verdict_statistic (verdict.h) */
    char spec_bands[CONFIG_STR_MAX];    /* "all", or the bands the spec names ("0:25, 25:50") */
    double min_coverage;                /* share of a spec band's validation points a unit must read */
    double yield_target;                /* budget: yield the inverse limits must keep */
    long budget_units;                  /* budget: units per bisection step */
    int budget_steps;                   /* budget: bisection steps per source */
    double confidence;                  /* level of the confidence intervals */
    int yield_interval;                 /* enum config_yield_interval */
    double cost_exponent;               /* allocate: cost of a tolerance ~ 1 / value^k */
    long model_form_every;              /* every N-th unit gets the model-form pass (modelform.h) */
    char onboard[CONFIG_STR_MAX];       /* calibration.onboard: double|float|table:STEP (lab_onboard.h) */

    family_config fam;                  /* the family's own keys (its keys table) */

    /* Pick-freeze of `sunmc sensitivity`, not a key: the n random streams
     * listed (rng.h ids) draw from seed `seed` instead of run.seed; n = 0
     * in every other command (family.h: unit_stream_seed). */
    struct {
        long seed;
        int n;
        uint32_t stream[CONFIG_PICK_MAX];
    } pick;
    /* Not a key: 1 when the caller reads only the RMS before and after and
     * the yield (design, budget, sensitivity), so units skip the noise-free
     * validation pass and leave rms_after_sys NaN; 0 in every other
     * command. */
    int no_systematic;
} sunmc_config;

/* One row of a key table: core's shared keys (config_keys.c) or a family's
 * own keys (its *_keys.c, reached through the registry). */
enum key_type { KEY_DOUBLE, KEY_INT, KEY_LONG, KEY_ENUM, KEY_STRING, KEY_LIST, KEY_BANDS,
                KEY_FAMILY /* sensor.family: a name from the registry */ };

typedef struct {
    const char *section;
    const char *name;
    int type;                /* enum key_type */
    const char *unit;        /* for help and the reference file */
    const char *def;         /* default, as text (a family may override a shared key's) */
    double min, max;         /* allowed range (each element of a list) */
    const char *choices;     /* KEY_ENUM: "a|b|c", index = stored value */
    size_t offset;           /* shared key: into sunmc_config; a family's: into its config */
    const char *help;        /* one line; source of the default if any */
} config_key;

/* A family's default for a shared key ("sensor", "product", "DSS"). */
typedef struct {
    const char *section;
    const char *name;
    const char *value;
} config_default;

/* Core's shared keys, every family's. */
extern const config_key config_keys[];
extern const size_t config_key_count;

/* Sections in the order files, dumps and the reference list them; every
 * key's section is one of these. */
extern const char *const config_sections[];
extern const size_t config_section_count;

/* A tolerance is four keys of its family: its magnitude, its distribution,
 * the share of its variance common to the units of a lot (run.lot_size
 * units in unit order, deviation.h) and its cost (allocate.h); off is the offset of its `tolerance`
 * in the family's config. */
#define CONFIG_DIST_CHOICES "fixed|uniform|normal|truncnormal"
#define CONFIG_TOLERANCE_KEYS(off, name, unit, defv, defdist, maxv, help)                         \
    {"tolerance", name, KEY_DOUBLE, unit, defv, 0, maxv, NULL,                                   \
     (off) + offsetof(tolerance, value), help},                                                   \
    {"tolerance", name "_dist", KEY_ENUM, "", defdist, 0, 0, CONFIG_DIST_CHOICES,               \
     (off) + offsetof(tolerance, dist),                                                           \
     "distribution of " name ": fixed (the value), uniform (+-value), normal "                   \
     "(sigma = value), truncnormal (sigma = value, cut at truncation_sigmas)"},                  \
    {"tolerance", name "_lot", KEY_DOUBLE, "", "0", 0, 1, NULL, (off) + offsetof(tolerance, lot), \
     "share of " name "'s variance common to the units of one lot (run.lot_size units): the "  \
     "correlation of two units of a lot; its distribution is unchanged (Gaussian copula); "      \
     "0 = every unit drawn alone"},                                                              \
    {"tolerance", name "_cost", KEY_DOUBLE, "", "1", 0, 1e9, NULL,                              \
     (off) + offsetof(tolerance, cost),                                                           \
     "`allocate`: what " name " at today's value costs (any unit, the same for every "         \
     "tolerance); a value v costs NAME_cost * (today / v)^report.cost_exponent; 0 = free"}

/* Check a grid lo..hi in steps of step against the field of view +-fov
 * (deg); what names it in the message ("campaign.alpha"). */
int config_check_grid(double lo, double hi, double step, double fov, const char *what, char *err,
                      size_t errlen);

/* A physical quantity q = design + scale * d, d any draw of a tolerance,
 * that must stay above floor (strict: q > floor, else q >= floor): one
 * row of a family's table of impossible sensors.  Offsets are into the
 * family's config (sunmc_config.fam); the tolerance's draws are
 * tolerance_range's. */
#define CONFIG_PHYSICAL_NONE ((size_t)-1)
typedef struct {
    const char *quantity;  /* "the slit-to-dial height H + dH" */
    const char *unit;      /* of the quantity: "mm", or "" */
    const char *design_key; /* "design.H_mm", or a text naming a fixed value */
    size_t design_offset;  /* its double, or CONFIG_PHYSICAL_NONE: design_fixed */
    double design_fixed;
    const char *tol_key;   /* "tolerance.dH_um" */
    size_t tol_offset;     /* its `tolerance` */
    double scale;          /* tolerance unit -> quantity unit ... */
    size_t scale_offset;   /* ... times the double here (CONFIG_PHYSICAL_NONE: 1) */
    double floor;
    int strict;
} config_physical;

/* Check each row of list (ended by a NULL quantity) against c; the first
 * that fails gives SUNMC_EINPUT with a message naming both keys, the
 * quantity and the extreme value the draws reach. */
int config_check_physical(const sunmc_config *c, const config_physical *list, char *err,
                          size_t errlen);

/* Where each key's value came from, for `sunmc config` and messages. */
typedef struct {
    char origin[CONFIG_ORIGIN_MAX];
} config_origin;

/* A configuration being built: values, the keys of its family in the order
 * `sunmc config` lists them, and each key's origin. */
typedef struct {
    sunmc_config cfg;
    const config_key **keys;  /* n_keys: shared and family keys, dump order */
    config_origin *origins;   /* n_keys entries, parallel to keys */
    size_t n_keys;
} config_state;

/* Build the effective config from an INI file (path may be NULL: defaults
 * only) and a list of "section.key=value" overrides.  The family is taken
 * from sensor.family (overrides first, then the file, else the registry's
 * first family); defaults of that family are applied, then the file, then the overrides, then
 * config_validate.  On error returns SUNMC_EINPUT (an unreadable file
 * included) with "FILE:LINE: message" (or "FILE: message") in err. */
int config_build(config_state *st, const char *path, const char *const *sets, int n_sets,
                 char *err, size_t errlen);
void config_state_free(config_state *st);

/* config_build without its final config_check, for a command that changes
 * values before the cross-key checks (curve --only); config_check must
 * follow. */
int config_build_unchecked(config_state *st, const char *path, const char *const *sets,
                           int n_sets, char *err, size_t errlen);

/* config_validate, its message led by the origins of the keys it names
 * ("--set tolerance.dH_um, a.ini:11: ..."; path, or "config", when it names
 * none that was set). */
int config_check(config_state *st, const char *path, char *err, size_t errlen);

/* Set one key from text.  `where` names the origin for messages
 * ("file.ini:12", "--set").  Checks type, range and family. */
int config_set_value(config_state *st, const char *section, const char *name,
                     const char *value, const char *where, char *err, size_t errlen);

/* Cross-key checks: the shared keys, then the family's validate hook. */
int config_validate(const sunmc_config *c, char *err, size_t errlen);

/* Find a key of any family (or a shared one); NULL when unknown. */
const config_key *config_find(const char *section, const char *name);

/* Find a key of family fam (or a shared one); NULL when fam has none. */
const config_key *config_find_in(const struct sensor_family *fam, const char *section,
                                 const char *name);

/* 1 when k is one of core's shared keys. */
int config_key_is_shared(const config_key *k);

/* 1 when shared key k is one that family fam does not take
 * (sensor_family.shared_keys_unused); 0 for fam NULL or a family's key. */
int config_family_omits(const struct sensor_family *fam, const config_key *k);

/* 1 when k is a shared key or one of fam's own. */
int config_key_applies(const config_key *k, const struct sensor_family *fam);

/* 1 when k is a tolerance magnitude of fam (a "tolerance" number key of
 * fam's with a KEY_dist sibling). */
int config_is_tolerance(const config_key *k, const struct sensor_family *fam);

/* Where key k's value lives in c (k must apply to c's family). */
void *config_value_ptr(const config_key *k, sunmc_config *c);
const void *config_value_cptr(const config_key *k, const sunmc_config *c);

/* Origin of key k's value in st ("file:LINE", "--set ...", "default"); NULL
 * when k is not a key of st's family. */
const char *config_origin_of(const config_state *st, const config_key *k);

/* Format a key's current value as it would be written in a file. */
void config_format_value(const config_key *k, const sunmc_config *c, char *buf, size_t len);

/* ---- The key tables as lists (config.c, config_value.c, config_write.c) ---- */

#define CONFIG_KEYS_MAX 512    /* most keys of all families together */
#define CONFIG_FAMILIES_MAX 16 /* most registered families */

/* The keys of family fam (every registered family's when fam is NULL), in
 * the order dumps list them: section by section (config_sections), each
 * family's keys of the section, then the shared ones (or the other way round
 * in a family's sections_after_shared).  owners[i] is key i's family (NULL: a shared key).
 * Returns the count (at most max are written). */
size_t config_list_keys(const struct sensor_family *fam, const config_key **keys,
                        const struct sensor_family **owners, size_t max);

/* Default of key k for family fam (a family may give its own default of a
 * shared key); fam NULL: the registry's first family. */
const char *config_key_default(const config_key *k, const struct sensor_family *fam);

/* k's one-line help (sensor.family's names every registered family). */
void config_key_help(const config_key *k, char *buf, size_t len);

/* "one of a|b", "0.5 to 50 mm", ...: what k allows, for messages. */
void config_range_text(const config_key *k, char *buf, size_t len);

/* Parse text `value` for key k into dst (where its value lives); "where"
 * names the origin in messages.  Checks type and range. */
int config_parse_value(const config_key *k, void *dst, const char *value, const char *where,
                       char *err, size_t errlen);

/* " (did you mean SECTION.KEY?)" naming the key of any family nearest to
 * section.name (case-blind, at most two edits), or "" when none is near. */
void config_suggest(const struct sensor_family *fam, const char *section, const char *name,
                    char *buf, size_t len);
/* " (did you mean [SECTION]?)" for a mistyped section name, or "". */
void config_suggest_section(const char *section, char *buf, size_t len);

/* Registered family names as "a|b". */
void config_family_choices(char *buf, size_t len);

/* Write the effective config of c's family (every key, defaults filled in),
 * with the origin of each value as a comment when origins != NULL. */
int config_write(FILE *f, const config_state *st);

/* FNV-1a 64 of the effective config as config.ini writes it
 * ("section.key=value" lines, origins left out) without the keys that do
 * not change a unit's result or the summary: run.units (the unit range is
 * recorded apart), run.threads and run.block_units.  Shards of one run
 * and a run and its resume have the same hash. */
unsigned long long config_hash(const config_state *st);

/* Write the commented reference config: every key of every registered
 * family with its unit, range, default and help. */
int config_write_reference(FILE *f);

/* The key "section.key" of family fam (or a shared one); NULL when there
 * is none or dotted is not section.key. */
const config_key *config_find_dotted(const struct sensor_family *fam, const char *dotted);

/* Read a numeric key's value by "section.key" (sweeps); SUNMC_EINPUT if not
 * a number key. */
int config_get_number(const sunmc_config *c, const char *dotted, double *out,
                      char *err, size_t errlen);

#endif
