/* lab.h - the lab commands (`simulate`, `calibrate`, `compensate`): the
 * hooks a family fills (family_lab, a struct of function pointers in the
 * manner of GSL's plug-in types, reached as sensor_family.lab) and the
 * pipeline they share, written once here:
 *
 *   lab_columns_read     a lab CSV's columns by name (weight optional)
 *   lab_params_header    params.ini's [calibration] section
 *   lab_cross_validate   hold each fold out, refit, score (the skeleton)
 *   lab_write_calibration  params.ini, residuals.tsv, bands.tsv,
 *                        crossval.tsv and the family's own files
 *   lab_compensate_csv   a raw CSV with the compensated columns added
 *
 * Units: a family's CSV columns keep the units of their names (deg, px);
 * the hooks convert.  Angles passed back to core are rad.
 */
#ifndef SUNMC_LAB_H
#define SUNMC_LAB_H

#include "calreport.h"
#include "config.h"
#include "params_io.h"

#include <stddef.h>
#include <stdio.h>

#define LAB_MAX_COLUMNS 8
/* The least reading noise (arcsec) a fit's residual is judged against. */
#define LAB_NOISE_FLOOR_ARCSEC 1.0
/* Files `simulate` writes, in this order: campaign.csv, truth.csv, validation.csv. */
#define LAB_SIM_FILES 3
/* Room for what a lab hook gives the command to print. */
#define LAB_NOTE_MAX 16384

extern const char *const lab_sim_files[LAB_SIM_FILES];

/* A lab data file's columns, in the order of the family's list: v[k][i] in
 * the units of column k's name; the last column of the list is "weight"
 * (optional: 1 when absent; never negative).  line[i] is row i's line in
 * the file. */
typedef struct {
    const char *path;
    size_t n;
    int n_cols;
    double *v[LAB_MAX_COLUMNS];
    int *line;
    /* Campaigns: the rows after each "# source: NAME" comment line (as the
     * importers write them) are one; source[i] is row i's (0 .. n_sources-1),
     * rows before the first such line, if any, campaign 0 named "(head)".
     * source NULL, n_sources 0: the file has no such line. */
    int *source;
    int n_sources;
    char **source_name;
} lab_columns;

/* The simulated unit a lab file describes, for its head comments. */
typedef struct {
    const char *config;      /* the config file as given */
    long unit;
    const char *out_dir;
} lab_unit_ref;

/* A measurement calibrate needs from the lab beside its data file: a
 * config key (section, name) whose default only stands in for it, why it
 * matters and how to give it. */
typedef struct lab_measured_key {
    const char *section, *name;
    const char *why;
    const char *action;
} lab_measured_key;

/* A calibration model a family's params.ini can hold: the name its
 * [calibration] model line gives, the sections its file has beside
 * [calibration] and [prior] (blank-separated), and a key (section, key)
 * every file of this model has and no other model's of the family (NULL:
 * none; at most one model of a family has none), by which a model line
 * naming another model than the file holds is caught.  extends: the name
 * of a model whose sections and signature every file of this one holds
 * too (e.g. a correction on top of a physical model), or NULL. */
typedef struct lab_params_model {
    const char *name;
    const char *sections;
    const char *sig_section, *sig_key;
    const char *extends;
} lab_params_model;

typedef struct family_lab {
    /* ---- simulate: one unit's campaign as a lab records it, its truth and
     * the readings `run` validates it on. ---- */
    /* Simulate unit ref->unit of c into a new record *sim. */
    int (*sim_run)(const sunmc_config *c, long unit, void **sim, char *err, size_t errlen);
    /* Write the record as lab_sim_files (f[k] is file k). */
    int (*sim_write)(const void *sim, const sunmc_config *c, const lab_unit_ref *ref,
                     FILE *const f[LAB_SIM_FILES]);
    /* What `simulate` prints once the files are written (lines, ending in '\n'). */
    void (*sim_summary)(const void *sim, const sunmc_config *c, const lab_unit_ref *ref,
                        char *buf, size_t len);
    void (*sim_free)(void *sim);

    /* ---- calibrate: fit the family's model to a lab's data. ---- */
    /* Data columns (NULL-terminated, "weight" last) and the shape of a row,
     * for --help and messages. */
    const char *const *cal_columns;
    /* calibrate --help: the columns' conventions, lines each starting with
     * seven spaces and ending in '\n' (or NULL). */
    const char *cal_help;
    /* Fewest data rows c's model can be fitted to, and why (for the message). */
    size_t (*cal_min_rows)(const sunmc_config *c, char *why, size_t len);
    /* Fit d (which must outlive *cal) and fill rep; *cal is the fitted
     * calibration, freed with cal_free.  Non-OK (message in err) for data
     * the model cannot be fitted to; a fit that fails is not an error
     * (rep->fit_ok = 0). */
    int (*cal_run)(const sunmc_config *c, const lab_columns *d, void **cal, calreport *rep,
                   char *err, size_t errlen);
    /* Sanity of the data before the fit (lab_check_data): the first
     * cal_n_inputs columns are table angles (deg), the next ones up to
     * "weight" the sensor's outputs. */
    int cal_n_inputs;
    /* Units the output columns are often written in by mistake, for the
     * diagnosis of data inconsistent with the design: factor[u] turns a
     * value in unit what[u] ("micrometres (5.5 per pixel)") into the
     * column's own unit.  Returns the count (at most max); NULL: none. */
    int (*cal_output_units)(const sunmc_config *c, double *factor, const char **what, int max);
    /* Fewest distinct values each table angle must take (cal_n_inputs). */
    const int *cal_min_distinct;
    /* The configured campaign range of table angle k (deg). */
    void (*cal_campaign_range)(const sunmc_config *c, int k, double *lo_deg, double *hi_deg);
    /* ---- What a unit within the config's tolerances can read
     * (lab_predict.c derives it from the family's deviation list, so a new
     * tolerance reaches it with no code here); cal_unit_build NULL: no
     * consistency check.  A built unit takes cal_unit_bytes (at most
     * LAB_UNIT_MAX_BYTES). ---- */
    size_t cal_unit_bytes;
    /* Build a unit of c whose deviations are dev_values, in the order of
     * the family's deviation list (deviations_values), into unit. */
    void (*cal_unit_build)(const sunmc_config *c, const double *dev_values, void *unit);
    /* The unit's noiseless outputs at table angles in_deg: out[j] per output
     * column, in its unit.  Non-OK where it sees no sun. */
    int (*cal_unit_read)(const sunmc_config *c, const void *unit, const double *in_deg,
                         double *out);
    /* What the deviation list leaves out of a reading's spread (noise,
     * code ripple, margins), per output column in its unit. */
    const double *cal_predict_margin;
    /* The residual standard deviation the config's reading noise gives
     * (arcsec): a fit far above it did not find the sensor in the data. */
    double (*cal_noise_arcsec)(const sunmc_config *c);
    /* Config keys calibrate takes as measurements of the real unit, each
     * warned about when left at its default (NULL-key terminated, or NULL). */
    const struct lab_measured_key *cal_measured;
    /* params.ini: the title comment, and the family's sections. */
    const char *params_title;
    int (*params_fill)(const void *cal, const sunmc_config *c, const calreport *rep,
                       params_file *p);
    /* residuals.tsv: every data row with its residual and angle errors. */
    int (*write_residuals)(const void *cal, FILE *f);
    /* Row i's error of the fitted calibration along the two table angles'
     * directions (rad): what lab_drift compares between a file's
     * campaigns.  Non-OK for a row the fit did not use or cannot read;
     * NULL: no campaign report. */
    int (*cal_row_error)(const void *cal, size_t i, double err_rad[2]);
    /* The family's further files (NULL-terminated, or NULL) and their writer. */
    const char *const *extra_files;
    int (*write_extra)(const void *cal, const sunmc_config *c, int k, FILE *f);
    /* 1: calibrate also writes models.tsv, the model comparison cal_run
     * left in rep->models (calreport_write_models), after extra_files. */
    int cal_models_tsv;
    void (*cal_free)(void *cal);

    /* ---- compensate: apply params.ini to raw readings. ---- */
    const char *const *raw_columns;   /* read, NULL-terminated */
    const char *const *comp_columns;  /* added, NULL-terminated; deg */
    /* Optional inputs (NULL-terminated, or NULL): read when the file has
     * every one of them, and then opt_comp_columns (deg) are added too
     * (e.g. the table angles and the truth they give).  compensate gets
     * them after raw_columns (NaN when absent) and fills theirs after
     * comp_columns. */
    const char *const *opt_columns;
    const char *const *opt_comp_columns;
    /* compensate --help: what comp_columns (and opt_comp_columns) hold,
     * lines as cal_help's (or NULL). */
    const char *comp_help;
    /* Said after the count of readings that could not be compensated, or NULL. */
    const char *comp_fail_note;

    /* 1 when the fit itself counts the rows at one point once (their mean,
     * the scatter reported as repeatability): calibrate then leaves exact
     * repeats to it, unless --duplicates is given. */
    int cal_counts_repeats_once;
    /* The models its params.ini can hold (NULL-name terminated; lab_params.h
     * checks the model line, the sections and the header against them). */
    const lab_params_model *params_models;
    /* The calibration a params.ini describes, into model (model_size bytes):
     * every key of the model's sections known or refused at its line. */
    size_t model_size;
    int (*params_load)(const params_file *p, void *model, char *err, size_t errlen);
    /* Can the calibrated sensor produce reading raw (as compensate gets
     * it)?  LAB_READING_OK, or why not (enum lab_reading); NULL: every
     * reading can.  compensate is called only for readings that can. */
    int (*reading_check)(const void *model, const double *raw);
    /* raw[k]: column k of raw_columns in its unit; comp_rad[k]: compensated
     * angle k in rad.  Non-OK when the model has no inverse there. */
    int (*compensate)(const void *model, const double *raw, double *comp_rad);

    /* ---- export: the model as C code (lab_export.h); NULL: none. ---- */
    const struct lab_export *export;
} family_lab;

/* truth.csv's head for a family that writes its simulated unit's
 * deviations as comments (lab_sim.c): "# sunmc VERSION simulate: truth of
 * unit U of CONFIG, seed S", then "# NAME = VALUE" for each of the n_dev
 * deviations, values (%.17g) in the units of their names. */
void lab_sim_truth_head(FILE *f, const sunmc_config *c, const lab_unit_ref *ref,
                        const char *const *dev_names, const double *dev_values, int n_dev);

/* Read columns names (NULL-terminated, "weight" last) of the CSV at path,
 * every value checked, then at least min_rows rows (why: the reason, for
 * the message).  Messages "FILE:LINE: ...".  d is freed with
 * lab_columns_free, also after an error. */
int lab_columns_read(const char *path, const char *const *names, size_t min_rows,
                     const char *why, lab_columns *d, char *err, size_t errlen);
void lab_columns_free(lab_columns *d);
/* The campaigns of d (read from d->path; d->line filled): source,
 * n_sources, source_name.  Called by lab_columns_read. */
int lab_columns_sources(lab_columns *d, char *err, size_t errlen);
/* The campaigns of d against the fitted cal (lab_drift.h) into rep->drift,
 * and a warning when one drifted; nothing without lab->cal_row_error or
 * with fewer than two campaigns. */
void lab_drift_report(const family_lab *lab, const void *cal, const lab_columns *d,
                      calreport *rep);

/* Lab data a calibration must not be run on (exit 2, "FILE:LINE: ..."),
 * before the fit: table angles that look like radians (all within +-2 pi,
 * spanning as radians what the configured campaign spans in degrees), too
 * few distinct values of a table angle, and outputs the design cannot
 * read at their table angles in more than LAB_MAX_INCONSISTENT of the rows
 * (with the likely cause: an output's sign flipped, two table angles or two
 * outputs swapped).  Also scales the weights so that the largest is 1: only
 * their ratios matter. */
#define LAB_MAX_INCONSISTENT 0.1
/* Exact duplicate rows (every column equal, weight > 0): a reading logged
 * twice.  LAB_DUP_AVERAGE counts each once (the later copies' weight is
 * set to 0), LAB_DUP_REFUSE refuses the file (FILE:LINE naming both
 * lines), LAB_DUP_KEEP leaves them.  note gets "LINE = FIRST_LINE, ..." of
 * the first LAB_DUP_SHOWN; returns their count (>= 0), or minus a status. */
enum { LAB_DUP_AVERAGE, LAB_DUP_REFUSE, LAB_DUP_KEEP };
#define LAB_DUP_SHOWN 5
int lab_duplicates(lab_columns *d, int mode, char *note, size_t notelen, char *err,
                   size_t errlen);

int lab_check_data(const family_lab *lab, const sunmc_config *c, lab_columns *d, char *err,
                   size_t errlen);

/* What a unit within c's tolerances reads at table angles in_deg: out[j],
 * the nominal unit's output j, and allowed[j], how far any unit may read
 * from it: the family's margin plus, for each entry of its deviation list,
 * the larger output change of the unit with that entry alone at the +- ends
 * of its tolerance (every value of the entry at once).  A linear envelope:
 * exact for one tolerance, a sum of the worst cases for several.  The
 * units are built once (lab_predict_alloc); NULL with err when the family
 * has no lab prediction or memory is short. */
#define LAB_UNIT_MAX_BYTES 16384
typedef struct lab_predictor lab_predictor;
lab_predictor *lab_predict_alloc(const family_lab *lab, const sunmc_config *c, char *err,
                                 size_t errlen);
int lab_predict(const lab_predictor *p, const double *in_deg, double *out, double *allowed);
void lab_predict_free(lab_predictor *p);

/* Refuse a fit that converged on data it did not explain (rep->fit_ok = 0,
 * rep->refused says why): more than calibration.max_dropped_fraction of the
 * rows dropped as gross errors, a rank-deficient Jacobian (condition number
 * above LAB_MAX_CONDITION, or none), a residual above
 * calibration.max_residual_ratio times the reading noise. */
#define LAB_MAX_CONDITION 1e12
void lab_check_fit(const family_lab *lab, const sunmc_config *c, const lab_columns *d,
                   calreport *rep);

/* A warning in rep naming the config's campaign grid points (family_grid,
 * FAMILY_GRID_CAMPAIGN) that have no row (of any weight) in d, when d follows
 * that grid (at least 90 % of its rows on it): rows lost from a lab file
 * otherwise go unnoticed.  Nothing when the lab ran another grid. */
void lab_check_grid(const family_lab *lab, const sunmc_config *c, const lab_columns *d,
                    calreport *rep);

/* A warning in rep for each of lab's measured keys whose value in st is
 * the default (no config file or --set gave it). */
void lab_check_measured(const family_lab *lab, const config_state *st, calreport *rep);

/* params.ini's [calibration] section: version, sensor, model, data file
 * and its FNV-1a 64, rows, config, residual sigma, cross-validation RMS. */
int lab_params_header(params_file *p, const char *data, const char *config, size_t rows,
                      const calreport *rep, char *err, size_t errlen);

/* The folds of a cross-validation and the family's refit. */
typedef struct {
    int n_folds;                     /* <= CALREPORT_MAX_FOLDS */
    size_t min_fit_rows;             /* a refit needs more rows than this */
    int (*fold_of)(const void *ctx, size_t i);                    /* row i's fold */
    void (*label)(const void *ctx, int k, char *buf, size_t len); /* fold k's name */
    /* Refit on the rows whose weight (the array given to
     * lab_cross_validate, set for the fold) is > 0 and score the refit:
     * sums of squared angle errors (rad^2) and their counts over the rows it
     * used (index 0) and over the rows with held[i] > 0 (index 1), and the
     * condition number of the refit's Jacobian at its solution (*cond; NaN
     * when the model has none).  Returns 1 when the refit converged. */
    int (*refit)(void *ctx, const double *held, double sum2[2], long n[2], double *cond);
    /* Folds left out of the pooled estimate (1 each): repeat campaigns the
     * family judged unlike the others (fold_outliers.h; the PSD on its best
     * model's folds, calreport_models), or NULL: none.  Folds over
     * different angles are never judged so: an edge line's larger error is
     * the field's, not a bad campaign's. */
    const unsigned char *outlier;
} lab_folds;

/* Hold out each fold in turn (weight[i] = 0 for its rows, restored after),
 * refit and score it into rep's folds and pooled RMS.  rep->cv_note says
 * why when it cannot be done. */
void lab_cross_validate(calreport *rep, double *weight, size_t n, const lab_folds *f, void *ctx);

/* Write a calibration's files into out_dir, all or nothing: params.ini
 * (header and the family's sections), residuals.tsv, bands.tsv,
 * crossval.tsv, lab->extra_files and, with lab->cal_models_tsv,
 * models.tsv (rep->models). */
int lab_write_calibration(const family_lab *lab, const void *cal, const sunmc_config *c,
                          const calreport *rep, const char *data, const char *config,
                          size_t rows, const char *out_dir, char *err, size_t errlen);

/* Why a reading gets no compensated angle (family_lab.reading_check; the
 * last, when compensate itself fails or gives no finite angle). */
enum lab_reading {
    LAB_READING_OK = 0,
    LAB_NO_SIGNAL,        /* channels at or below the dark level, no spot */
    LAB_NEGATIVE_SUM,     /* the dark-corrected channels sum below 0 */
    LAB_OUTSIDE_DETECTOR, /* a spot beyond the detector */
    LAB_OUTSIDE_RANGE,    /* beyond the output's range (an ADC below 0) */
    LAB_NO_INVERSE,       /* the model has no inverse there */
    LAB_OUTSIDE_FIELD,    /* beyond the field the calibration saw (an extrapolation) */
    LAB_N_READING
};

/* Each cause as compensate's count says it ("no signal (...)"). */
extern const char *const lab_reading_text[LAB_N_READING];

/* Counts of a compensation run. */
typedef struct {
    long failed;                     /* readings that could not be compensated */
    long by_cause[LAB_N_READING];    /* of them, by cause (index 0 unused) */
    int first_failed_line;
    int acc_nomem; /* the accuracy summary ran out of memory */
} lab_comp_stats;

/* "3 rows not compensated: 2 no signal (...), 1 outside the detector"
 * (causes in enum order, those with a count only) into buf. */
void lab_comp_summary(const lab_comp_stats *s, char *buf, size_t len);

/* Read raw_path (lab->raw_columns) and write it to out as CSV with
 * lab->comp_columns added (deg, "-" where a reading cannot be
 * compensated, counted in s by cause).  With acc (lab_accuracy_init'ed, or
 * NULL), each compensated_X is scored against truth_X of the same row, an
 * input column or one the family adds (acc->found says whether there were
 * any; a row without a compensated angle counts as missing).  Refused
 * (nothing written): bad input, a file with no data rows, a truth column
 * with a value that is no number, no truth columns when acc->required. */
struct lab_accuracy_s;
int lab_compensate_csv(const family_lab *lab, const void *model, const char *raw_path,
                       FILE *out, lab_comp_stats *s, struct lab_accuracy_s *acc, char *err,
                       size_t errlen);

#endif
