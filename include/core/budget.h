/* budget.h - the error budget: what each source contributes to the mean
 * square error, with intervals, and how far each may go (inverse limits).
 *
 * Sources: every tolerance key of the config's family whose value is > 0
 * (ESS: dH_um, dd_um, ...) and every noise key the family declares
 * (family.h: family_noise; ESS noise.row_current_pct, noise.encoder_arcsec,
 * calibration.roll_sigma_arcsec; DSS noise.centroid_px,
 * noise.encoder_arcsec) whose value is > 0, treated alike.  The Monte Carlo
 * runs, all on the same seed and units (common random numbers):
 *   all:    the config as it is;
 *   floor:  every source at 0 (the nominal design, noise-free);
 *   alone:  per source, the floor with that source at its value;
 *   no tolerance: tolerances 0, noise on (design + noise, for reference).
 * The budget is read in one report row: the last measured angle (ESS
 * alpha, DSS total) and the widest band.
 *
 * One share definition, of mean squares (MS = mean over units of RMS^2;
 * independent additive sources add in MS), all over the same denominator:
 *   floor share       = MS_floor / MS_all
 *   share of source i = (MS_alone_i - MS_floor) / MS_all
 *   interaction       = 1 - floor - sum of the source shares
 * so floor + sources + interaction = 100 % exactly; the interaction is what
 * the sources do together beyond the sum of what each does alone (the
 * calibration fit couples them).  Before and after calibration alike.  Each
 * share is a ratio of means over the units that have a fit in every run
 * (paired_units), with the delta-method t interval of the paired per-unit
 * values (stats_ratio_t); `significant` when the interval excludes 0.
 * Sources are ranked on the after-calibration share.
 *
 * Inverse limit: the largest value of the source (others at theirs) for
 * which the yield (fraction of units whose after-calibration RMS meets
 * report.spec_arcsec) is still >= report.yield_target, found by expanding
 * the bracket by BUDGET_EXPAND and bisecting report.budget_steps times on
 * Monte Carlos of report.budget_units units.  Its interval comes from the
 * yield intervals (Wilson) of the values the search tried: lo = the largest
 * value whose yield interval lies wholly at or above the target, hi = the
 * smallest whose interval lies wholly below; NaN where no tried value is
 * that clear (more budget_units narrow it).
 */
#ifndef SUNMC_BUDGET_H
#define SUNMC_BUDGET_H

#include "config.h"
#include "family.h"
#include "stats.h"

#include <stddef.h>

#define BUDGET_MAX_SOURCES 32
/* Most bytes of validation readings the floor and alone runs keep for the
 * runs that share them (unit_store.h); above it they are read again. */
#define BUDGET_STORE_MAX_BYTES (1024.0 * 1024.0 * 1024.0)
#define BUDGET_EXPAND 4.0   /* bracket growth factor while the yield still holds */

enum budget_limit_status {
    BUDGET_LIMIT_OK = 0,    /* limit found within the key's range */
    BUDGET_LIMIT_AT_MAX,    /* the yield holds up to the key's maximum */
    BUDGET_LIMIT_UNMET      /* the yield fails even with this source at 0 */
};

enum budget_kind { BUDGET_TOLERANCE = 0, BUDGET_NOISE };

/* The Monte Carlo statistics of one configuration in the budget row. */
typedef struct {
    double before_mean, after_mean; /* mean RMS over units with a fit, family rms unit */
    double yield;
    stats_interval yield_ci;        /* Wilson, report.confidence */
    long fit_failures;
    /* units failing the spec's verdict (verdict.h) because a spec band's
     * points were not all read, or because its statistic was over the spec */
    long fail_coverage, fail_spec;
} budget_stats;

/* What ended an inverse limit's search: the yield lost to units over the
 * spec, to units that lost their field (coverage), to failed fits, or the
 * key's range. */
enum budget_limit_end { BUDGET_END_SPEC = 0, BUDGET_END_COVERAGE, BUDGET_END_FIT, BUDGET_END_RANGE };

/* The smallest share the ranking counts: half a printed 0.01 %. */
#define BUDGET_SHARE_RESOLUTION 5e-5

/* A share of MS_all with its interval; significant = interval excludes 0. */
typedef struct {
    double v;
    stats_interval ci;
    int significant;
} budget_share;

typedef struct {
    char name[CONFIG_STR_MAX];      /* tolerance "dH_um", noise "noise.row_current_pct" */
    int kind;                       /* enum budget_kind */
    const config_key *key;          /* its row in the key table */
    double tolerance;               /* today's value, unit of the key */
    budget_stats alone;             /* the floor plus this source */
    budget_share share_before, share_after;
    int rank;                       /* 1 = largest share after calibration (outside the
                                       noise), then before; those in the noise last */
    int in_noise;                   /* every share's interval holds 0: ranked last */
    double limit;                   /* inverse limit, unit of the key */
    stats_interval limit_ci;        /* from the yield intervals (see above) */
    int limit_status;               /* enum budget_limit_status */
    int limit_end;                  /* enum budget_limit_end: at the smallest failing value */
    double limit_end_at;            /* that value (NaN: none failed) */
    double yield_today;             /* yield at today's value (budget_units units) */
    stats_interval yield_today_ci;
    int limit_runs;                 /* Monte Carlos the search took */
    long limit_units;               /* unit runs it made (today's yield is the all-sources run's) */
    long limit_reused;              /* of those, finished from the all-sources run's readings */
} budget_source;

/* The parts of the mean square after calibration (budget_result.part_after). */
enum { BUDGET_PART_NOISE = 0, BUDGET_PART_ESTIMATION, BUDGET_PART_MODEL_FORM, BUDGET_PARTS };

typedef struct {
    int angle, band;                /* the report row of the budget */
    long units;                     /* units per run */
    long paired_units;              /* units with a fit in every run: the shares' sample */
    int n;
    budget_source src[BUDGET_MAX_SOURCES];
    budget_stats all, floor, no_tolerance;
    budget_share floor_before, floor_after;
    budget_share interaction_before, interaction_after;
    /* The all-sources mean square after calibration by kind (modelform.h):
     * the validation reading's noise, the calibration's estimation error,
     * model form; over part_units units run again with the systematic and
     * model-form passes (lab condition, the budget's row). */
    budget_share part_after[BUDGET_PARTS];
    long part_units;
    /* calibration.onboard other than double (onboard_name "ONBOARD_TABLE",
     * "ONBOARD_FLOAT"; "" for double): the on-board arithmetic's part of
     * that mean square, MS(on board) - MS(double) of the same units, the
     * three parts above then from the double run. */
    char onboard_name[24];
    budget_share part_onboard;
    int order[BUDGET_MAX_SOURCES];  /* src indices, rank order */
    budget_stats today;             /* units [0, today_units) of the all-sources run */
    long today_units;               /* report.budget_units, or 0 when more than units */
    long unit_runs;                 /* unit runs of the all/floor/alone/no-tolerance runs */
    long reused_units;              /* of those and the searches', finished from stored
                                     * validation readings (unit_store.h) */
    /* During budget_run: the all-sources run's readings of units
     * [0, today_units), for the searches of the sources they do not read;
     * NULL outside it */
    struct unit_store *today_store;
} budget_result;

/* Unit runs the whole budget made: its runs and the inverse limits' searches. */
long budget_unit_runs(const budget_result *b);

/* Of those, the unit runs finished from stored validation readings of
 * another run (unit_store.h) instead of reading their own. */
long budget_reused_units(const budget_result *b);

/* Called before each Monte Carlo: what (e.g. "dH_um alone"), i of n. */
typedef void (*budget_progress_fn)(const char *what, int i, int n, void *ctx);

/* The budget's report row: the last measured angle, the widest band. */
void budget_row(const sunmc_config *c, int *angle, int *band);

/* Fill b->src with c's sources (tolerance keys of its family with value >
 * 0, then its noise keys with value > 0) and choose the budget row.
 * SUNMC_EINPUT when there is none. */
int budget_sources(const sunmc_config *c, budget_result *b, char *err, size_t errlen);

/* The statistics of config c over units [0, units) in row (angle, band);
 * sq_before, sq_after (may be NULL) get each unit's RMS^2, NaN for a unit
 * without a fit or a value. */
int budget_monte_carlo(const sunmc_config *c, long units, int threads, int angle, int band,
                       budget_stats *out, double *sq_before, double *sq_after, char *err,
                       size_t errlen);

/* The unit runs a Monte Carlo of `units` units of c makes: 1 when no
 * random input of c varies (sens_random_inputs: every unit is the same
 * unit, run once and copied), else units. */
long budget_units_run(const sunmc_config *c, long units);

/* budget_monte_carlo of c over its report.budget_units units in b's row,
 * those units' validation readings taken from the all-sources run's
 * (b->today_store) when c reads them the same (unit_readings_same: c differs
 * from it in keys the readings ignore); *reused: the unit runs finished
 * from them. */
int budget_monte_carlo_today(const sunmc_config *c, const budget_result *b, budget_stats *out,
                             int threads, long *reused, char *err, size_t errlen);

/* Set source `key`'s value in cfg (unit of the key). */
void budget_set_tolerance(sunmc_config *cfg, const config_key *key, double value);

/* The whole budget of c: sources, all/floor/alone/no-tolerance runs with
 * `units` units each, shares with intervals and ranks, and (when
 * with_limits) the inverse limits.  threads: 0 = OpenMP default.  progress
 * may be NULL. */
int budget_run(const sunmc_config *c, long units, int threads, int with_limits,
               budget_progress_fn progress, void *ctx, budget_result *b, char *err,
               size_t errlen);

/* The inverse limit of source s (budget_limit.c). */
int budget_inverse_limit(const sunmc_config *c, const budget_result *b, budget_source *s,
                         int threads, char *err, size_t errlen);

#endif
