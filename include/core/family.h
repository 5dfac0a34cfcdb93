/* family.h - what the Monte Carlo engine needs from a sensor family.
 *
 * A family (ess, dss) samples one unit's deviations, simulates its
 * calibration campaign with its physical model, fits its calibration model
 * and validates it on a grid it was not calibrated on, filling a unit_result.
 * The engine (montecarlo.h) runs units in parallel; the report (report.h)
 * aggregates in unit order.
 */
#ifndef SUNMC_FAMILY_H
#define SUNMC_FAMILY_H

#include "config.h"
#include "bands.h"
#include "deviation.h"
#include "rng.h"

#include <stddef.h>
#include <stdint.h>

#define UNIT_MAX_DEV 32
#define UNIT_MAX_PAR 48
#define UNIT_MAX_ANGLES 3
#define UNIT_MAX_TEMPS CONFIG_TEMPS_MAX /* operating temperatures (thermal.h) */

/* Fit status of a unit, as written in units.tsv. */
enum unit_fit_status { UNIT_FIT_OK = 0, UNIT_FIT_FAILED = 1 };

/* Which grid family_grid.points lists. */
enum family_grid_which { FAMILY_GRID_CAMPAIGN = 0, FAMILY_GRID_VALIDATION = 1 };

/* Phases of a unit's run, timed for `run --profile` (never written to files). */
enum unit_phase { UNIT_PHASE_CAMPAIGN = 0, UNIT_PHASE_FIT, UNIT_PHASE_VALIDATION, UNIT_PHASES };

typedef struct {
    long unit;
    double phase_s[UNIT_PHASES];    /* wall seconds per phase (sampling counts as campaign) */
    double dev[UNIT_MAX_DEV];       /* sampled deviations (family's dev columns) */
    double par[UNIT_MAX_PAR];       /* fitted parameters (family's par columns) */
    /* RMS errors in the family's rms unit, per measured angle and band; NaN
     * when the band holds no validation point. */
    double rms_before[UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    double rms_after[UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    /* The systematic part of rms_after: the same validation points read
     * without reading noise (same unit, same fitted calibration). */
    double rms_after_sys[UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    /* The model-form part (modelform.h): the same unit calibrated on its
     * campaign without noise and read without noise; NaN for a unit
     * without the pass, a failed fit or an empty band. */
    double rms_after_mf[UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    /* The same unit (same calibration, made at environment.calibration_temp_c)
     * validated at operating temperature t (thermal.h; only when
     * thermal_n_temps(c) > 0, t < thermal_n_temps(c)): RMS before and after. */
    double rms_before_t[UNIT_MAX_TEMPS][UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    double rms_after_t[UNIT_MAX_TEMPS][UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    /* What the spec judges (verdict.h): report.spec_statistic of the error
     * after calibration per angle and band (the RMS, or the p99.7 or max of
     * |error| over the band's points read), rms unit, NaN when none was
     * read; the band's validation points, and those read and scored after
     * calibration; the same at each operating temperature. */
    double stat_after[UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    double stat_after_t[UNIT_MAX_TEMPS][UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    int points[CONFIG_BANDS_MAX];
    int read_after[UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    int read_after_t[UNIT_MAX_TEMPS][UNIT_MAX_ANGLES][CONFIG_BANDS_MAX];
    double fit_rms;                 /* fit residual RMS, rms unit */
    int fit_status;                 /* enum unit_fit_status */
    int fit_gsl_status;             /* GSL's status code of the fit */
    int fit_iterations;
    int alias_weak;                 /* calibration directions regularised for aliasing */
    int gross_cal;                  /* campaign points dropped as gross errors */
    int gross_val;                  /* validation points with a gross error */
} unit_result;

struct family_lab; /* lab.h */

/* A random input of a unit besides its tolerances: one of its random
 * streams (rng.h) and the config keys whose values scale its draws.  The
 * budget sets those keys to 0 like tolerances; `sunmc sensitivity` swaps the
 * stream between its two samples (pick-freeze). */
typedef struct {
    const char *name;               /* "campaign_noise" */
    uint32_t stream;                /* rng.h stream id */
    const char *const *keys;        /* "section.key" names, NULL-terminated */
    /* NULL, or whether the stream is drawn at all under config c (a
     * measurement only some modes make): when 0 it is no input, whatever
     * its keys say */
    int (*active)(const sunmc_config *c);
    /* 1 when only the calibration campaign draws from the stream (never
     * the validation readings): configs whose pick-freeze differs only in
     * such streams share their readings (unit_store.h).  0, the safe
     * default: the readings may draw from it. */
    int campaign_only;
} family_noise;

/* The turntable grids, for a campaign's cost and span (campaign.h), and
 * the campaign keys `sunmc design` searches (design.h). */
typedef struct family_grid {
    /* Table positions (deg) of the campaign (which = FAMILY_GRID_CAMPAIGN)
     * or of the validation (FAMILY_GRID_VALIDATION), in the order the table
     * visits them: axis 0 the fast axis, axis 1 the slow one.  Returns the
     * count; writes at most max (none when the arrays are NULL). */
    long (*points)(const sunmc_config *c, int which, double *axis0_deg, double *axis1_deg,
                   long max);
    const char *const *axis_names; /* {"alpha", "beta"}: for messages */
    /* "section.key" of the fast axis' step (a number key), and of the slow
     * axis' positions (a list key, one scan each) or NULL when the step
     * sets both axes; design_step_key NULL: `design` does not apply. */
    const char *design_step_key;
    const char *design_lines_key;
} family_grid;

/* Error curves and maps (`sunmc curve`).  A curve is one unit's error at
 * every point of a 2-D grid: axis 0 is the fast axis (ESS: table alpha;
 * DSS: sun angle alpha), axis 1 the series / slow axis (ESS: table beta;
 * DSS: sun angle beta).  The grid is the config's validation grid. */
typedef struct family_curve {
    /* Column names of the two axes, with units: {"alpha_deg", "beta_deg"}. */
    const char *const *axis_names;

    /* Grid values (deg) of axis `axis` (0 or 1) into values[max]; returns
     * the number of values (may exceed max: then only max are written). */
    long (*axis)(const sunmc_config *c, int axis, double *values_deg, long max);

    /* Workspace holding one built unit, its campaign and its fitted model. */
    void *(*alloc)(const sunmc_config *c, char *err, size_t errlen);
    void (*free)(void *cv);

    /* Build unit `unit` of c: its deviations drawn exactly as unit_run draws
     * them, each multiplied by dev_sign (+1, or -1 for the mirror unit: a
     * fixed tolerance of -V), simulate its calibration campaign (with c's
     * noise) and fit.  *fit_ok = 0 when the fit failed (after-errors are
     * then NaN).  Non-zero only for a failure of the machinery. */
    int (*prepare)(const sunmc_config *c, long unit, double dev_sign, void *cv, int *fit_ok);

    /* One noiseless reading of the prepared unit at table angles (deg)
     * axis0_deg, axis1_deg: for each measured angle a (n_angles of them)
     * before[a] = raw - truth and after[a] = compensated - truth, in the
     * family's rms_unit.  SUNMC_EDOM when the sun is not seen there or the
     * reading is a gross error (wrong code period). */
    int (*eval)(const sunmc_config *c, const void *cv, double axis0_deg, double axis1_deg,
                double before[UNIT_MAX_ANGLES], double after[UNIT_MAX_ANGLES]);
} family_curve;

typedef struct sensor_family {
    const char *name;               /* "ess", "dss": the value of sensor.family */
    const char *description;        /* for sensor.family's help: "encoded sun sensor" */
    const char *rms_unit;           /* unit of every RMS: "deg" or "arcsec" */
    double arcsec_per_rms_unit;     /* to compare with report.spec_arcsec */
    int rms_decimals;               /* shown in tables (report_decimals); 0: by rms_unit */

    /* ---- Configuration.  The family's own keys (offsets into its config,
     * which lives in sunmc_config.fam and is read through the family's
     * accessor), its defaults of shared keys (e.g. sensor.product), and its
     * cross-key checks, run after the shared ones. ---- */
    const config_key *keys;         /* ends with a row whose section is NULL */
    const config_default *defaults; /* ends with a row whose section is NULL */
    /* Sections whose family keys `sunmc config` lists after the shared ones
     * (else before them); NULL-terminated, or NULL for none. */
    const char *const *sections_after_shared;
    /* Shared keys this family does not take, "section.name", NULL-terminated
     * (NULL: it takes every one): they are unknown in its configs, left
     * out of its dumps, and the reference does not list it for them. */
    const char *const *shared_keys_unused;
    int (*validate)(const sunmc_config *c, char *err, size_t errlen);

    /* What a unit's campaign may fail to resolve, for the alias counts of
     * the reports ("the fine-code term"); NULL when it cannot alias. */
    const char *alias_term;

    /* The calibration model of config c, in words, for reports. */
    void (*model_label)(const sunmc_config *c, char *buf, size_t len);

    /* Measured angles reported (ESS: alpha; DSS: alpha, beta, total). */
    int (*n_angles)(const sunmc_config *c);
    const char *const *angle_names;
    /* What report.bands_deg bands, for table headers: "|alpha|" (ESS: the
     * incidence), "field angle" (DSS: the angle from the boresight).  NULL:
     * "|angle|". */
    const char *band_name;

    /* The random inputs: the deviation list (each tolerance's stream) and
     * the noise streams (NULL-name terminated).  NULL when the family does
     * not declare them (budget and sensitivity then see tolerances only /
     * refuse). */
    const deviation_spec *deviations;
    int n_deviations;
    /* 1 when unit_run validates at environment.operating_temp_c (filling
     * rms_before_t / rms_after_t); 0: a config whose operating temperatures
     * are other than the lab's is refused for this family. */
    int thermal;
    const family_noise *noise;

    /* Column names of unit_result.dev and .par for this config. */
    int (*dev_columns)(const sunmc_config *c, const char **names, int max);
    int (*par_columns)(const sunmc_config *c, const char **names, int max);

    /* Per-thread workspace, reused for every unit the thread runs. */
    void *(*workspace_alloc)(const sunmc_config *c, char *err, size_t errlen);
    void (*workspace_free)(void *ws);
    /* About how many bytes workspace_alloc takes for config c (the memory
     * check before a run, and its message); NULL: unknown. */
    double (*workspace_bytes)(const sunmc_config *c);

    /* Run unit `unit` end to end.  A failed fit is recorded in r and is not
     * an error; only a failure of the machinery returns non-zero. */
    int (*unit_run)(const sunmc_config *c, long unit, void *ws, unit_result *r);

    /* ---- A unit in two halves, for runs of several configs that share
     * its validation readings (unit_store.h); all NULL when the family
     * does not split.  unit_read fills rd (readings_bytes(c) bytes) with
     * what the unit's sensor reads on the validation grid, with its
     * validation noise, at every temperature it is validated at: a
     * function of (seed, unit) and of the keys not named in
     * readings_ignore alone.  unit_finish makes the rest of the unit
     * (campaign, fit, compensation, scores) from rd; unit_read then
     * unit_finish equals unit_run bit for bit. ---- */
    size_t (*readings_bytes)(const sunmc_config *c);
    int (*unit_read)(const sunmc_config *c, long unit, void *ws, void *rd);
    int (*unit_finish)(const sunmc_config *c, long unit, void *ws, const void *rd,
                       unit_result *r);
    /* "section" or "section.key" names of the keys the readings do not
     * depend on (NULL-terminated): configs that differ in these alone
     * share their readings. */
    const char *const *readings_ignore;

    /* ---- Sub-tables, NULL when the family has none: its turntable grids
     * and the campaign keys `design` searches (family_grid), its error
     * curves for `curve` (family_curve), its lab commands (family_lab,
     * lab.h). ---- */
    const struct family_grid *grid;
    const struct family_curve *curve;

    /* The lab commands' hooks (`simulate`, `calibrate`, `compensate`,
     * lab.h); NULL when the family has none. */
    const struct family_lab *lab;
} sensor_family;

/* Fill r's RMS before/after of measured angle `angle` from the unit's
 * accumulators (times scale, the rms unit per radian); after is NaN in every
 * band when the unit's fit failed. */
void unit_result_set_rms(unit_result *r, int angle, const band_acc *before, const band_acc *after,
                         const band_list *bands, double scale);

/* Fill what the verdict judges of angle `angle` (stat_after, read_after,
 * points; call after unit_result_set_rms): the RMS when the spec's
 * statistic is rms, else the tail's order statistic, over the points of
 * after; points[b] the band's validation points (read or not). */
void unit_result_set_stat(unit_result *r, const sunmc_config *c, int angle, const band_acc *after,
                          const band_tail *tail, const long *points, double scale);

/* Unit `unit` of a family that splits its units (unit_read, unit_finish)
 * into r: its validation readings read into rd first unless held (rd holds
 * them already), then the rest of the unit; the reading's time goes to r's
 * validation phase.  A family's unit_run and mc_run_store both run a unit
 * this way. */
int unit_read_finish(const sunmc_config *c, long unit, void *ws, void *rd, int held,
                     unit_result *r);

/* A layout of a unit's readings (readings_bytes, unit_read) for a
 * validation grid of n points: per validation read (thermal_n_reads) one
 * block of n_arrays arrays of n doubles, then n ints (a flag per point,
 * e.g. seen or a status) padded to whole doubles so that every block
 * starts aligned.  unit_rd_bytes: the readings' bytes for config c;
 * unit_rd_block: block k of rd, its array j at + j n; unit_rd_flags: the
 * flags of that block. */
size_t unit_rd_bytes(const sunmc_config *c, size_t n, int n_arrays);
double *unit_rd_block(const void *rd, size_t n, int n_arrays, int k);
int *unit_rd_flags(double *block, size_t n, int n_arrays);

/* Fill r's noise-free after RMS (rms_after_sys) of measured angle `angle`;
 * NaN in every band when the unit's fit failed or after_sys is NULL (the
 * pass skipped: c->no_systematic).  Sets the angle's rms_after_mf NaN
 * (the model-form pass, run by the engine, fills it: modelform.h). */
void unit_result_set_sys(unit_result *r, int angle, const band_acc *after_sys,
                         const band_list *bands, double scale);

/* Seed of random stream `stream` of c's units: c->pick.seed when c->pick
 * lists the stream (the pick-freeze of `sunmc sensitivity`), else `seed`
 * (the run's, c->seed). */
uint64_t unit_stream_seed(const sunmc_config *c, uint64_t seed, uint32_t stream);

/* rng_stream_init of stream `stream` of unit `unit` of c (run.seed, or the
 * pick-freeze seed as above). */
void unit_stream_init(rng_stream *r, const sunmc_config *c, long unit, uint32_t stream);

/* The phase timer, off by default (phase_s stays 0, so a unit's result is
 * the same bytes in every run); `run --profile` turns it on before the
 * Monte Carlo starts. */
void unit_profile_enable(int on);
/* Monotonic clock (s) when the timer is on, else 0. */
double unit_clock(void);
/* Add the time since *t to phase `phase` of r; *t becomes now. */
void unit_phase_end(unit_result *r, int phase, double *t);

#endif
