/* budget.h - the tolerance budget (the optician's "worst offenders").
 *
 * The error sources are the tolerance keys of the config's family whose
 * value is > 0 (ESS: dH_um, dd_um, dphi_deg, ...).  For each source the
 * Monte Carlo runs (same seed, so differences are not noise)
 *   alone:   that source at its tolerance, every other tolerance 0;
 *   removed: that source 0, every other at its tolerance;
 * plus "all" (every source on) and "none" (every tolerance 0: what the
 * design and the noise leave).  The budget is read in one report row: the
 * last measured angle (ESS alpha, DSS total) and the widest band.
 *
 * Shares are of mean squares (MS = mean over units of RMS^2, which add for
 * independent sources):
 *   share_removed = (MS_all - MS_removed) / MS_all: the part of the total
 *                   that goes away without the source; ranked on the
 *                   after-calibration value;
 *   share_alone   = (MS_alone - MS_none) / (MS_all - MS_none): the part of
 *                   the tolerance-caused error the source makes on its own.
 *
 * Inverse limit: the largest tolerance of the source (others at theirs) for
 * which the yield (fraction of units whose after-calibration RMS meets
 * report.spec_arcsec) is still >= report.yield_target, found by expanding
 * the bracket by BUDGET_EXPAND and bisecting report.budget_steps times on
 * Monte Carlos of report.budget_units units.
 */
#ifndef SUNMC_BUDGET_H
#define SUNMC_BUDGET_H

#include "config.h"
#include "family.h"

#include <stddef.h>

#define BUDGET_MAX_SOURCES 32
#define BUDGET_EXPAND 4.0   /* bracket growth factor while the yield still holds */

enum budget_limit_status {
    BUDGET_LIMIT_OK = 0,    /* limit found within the key's range */
    BUDGET_LIMIT_AT_MAX,    /* the yield holds up to the key's maximum */
    BUDGET_LIMIT_UNMET      /* the yield fails even with this source at 0 */
};

/* The Monte Carlo statistics of one configuration in the budget row. */
typedef struct {
    double before_mean, after_mean; /* mean RMS, family rms unit */
    double before_ms, after_ms;     /* mean of RMS^2 */
    double yield;
    long fit_failures;
} budget_stats;

typedef struct {
    char name[CONFIG_STR_MAX];      /* tolerance key name, e.g. "dH_um" */
    const config_key *key;          /* its row in the key table */
    double tolerance;               /* today's value, unit of the key */
    budget_stats alone, removed;
    double share_alone_before, share_alone_after;
    double share_removed_before, share_removed_after;
    int rank;                       /* 1 = explains most after calibration */
    double limit;                   /* inverse limit, unit of the key */
    int limit_status;               /* enum budget_limit_status */
    double yield_today;             /* yield at today's tolerance (budget_units units) */
    int limit_runs;                 /* Monte Carlos the search took */
} budget_source;

typedef struct {
    int angle, band;                /* the report row of the budget */
    long units;                     /* units per alone/removed run */
    int n;
    budget_source src[BUDGET_MAX_SOURCES];
    budget_stats all, none;
    int order[BUDGET_MAX_SOURCES];  /* src indices, rank order */
} budget_result;

/* Called before each Monte Carlo: what (e.g. "dH_um removed"), i of n. */
typedef void (*budget_progress_fn)(const char *what, int i, int n, void *ctx);

/* Fill b->src with c's sources (tolerance keys of its family with value >
 * 0) and choose the budget row.  SUNMC_EINPUT when there is none. */
int budget_sources(const sunmc_config *c, budget_result *b, char *err, size_t errlen);

/* The statistics of config c over units [0, units) in row (angle, band). */
int budget_monte_carlo(const sunmc_config *c, long units, int threads, int angle, int band,
                       budget_stats *out, char *err, size_t errlen);

/* Set source `key`'s value in cfg (unit of the key). */
void budget_set_tolerance(sunmc_config *cfg, const config_key *key, double value);

/* The whole budget of c: sources, alone/removed/all/none with `units`
 * units each, shares and ranks, and (when with_limits) the inverse limits.
 * threads: 0 = OpenMP default.  progress may be NULL. */
int budget_run(const sunmc_config *c, long units, int threads, int with_limits,
               budget_progress_fn progress, void *ctx, budget_result *b, char *err,
               size_t errlen);

#endif
