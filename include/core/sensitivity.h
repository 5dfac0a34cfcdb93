/* sensitivity.h - variance-based sensitivity (Sobol indices) of the per-unit
 * RMS before and after calibration to each random input of a unit.
 *
 * Inputs ("sources"): every tolerance of the family whose value is > 0 and
 * whose distribution is not fixed (a fixed deviation does not vary), and
 * every noise stream of the family (family.h: family_noise) with a scaling
 * key > 0 -- ESS campaign_noise (encoder + row currents of the calibration
 * readings, one stream), validation_noise (row currents of the validation
 * readings: the sensor's repeatability), roll_measurement; DSS
 * campaign_noise, validation_noise.
 *
 * Pick-freeze without an extra sampler: unit u of sample A is unit u of the
 * config under run.seed, of sample B unit u under seed_b = run.seed XOR
 * SENS_SEED_B_XOR; every input draws from its own Philox stream, so A_B^(i)
 * -- A with input i taken from B -- is unit u with input i's stream(s)
 * keyed by seed_b (config.h: pick).  N units cost (d + 2) N unit runs; the
 * result depends only on (seed, N), never on the thread count.
 *
 * Y = the unit's RMS in the budget's row (last measured angle, widest band),
 * before and after calibration.  Units whose fit fails in any of the d + 2
 * runs are left out (counted).  Estimators and bootstrap intervals:
 * stats_sobol (Saltelli 2010 first order, Jansen 1999 total), SENS_BOOTSTRAP
 * resamples with the fixed seed SENS_BOOT_SEED.
 */
#ifndef SUNMC_SENSITIVITY_H
#define SUNMC_SENSITIVITY_H

#include "config.h"
#include "family.h"
#include "stats.h"

#define SENS_MAX_SOURCES 48
/* Most bytes of validation readings kept for the runs that share A's
 * (unit_store.h); above it they are read again (the same bits). */
#define SENS_STORE_MAX_BYTES (1024.0 * 1024.0 * 1024.0)
#define SENS_SEED_B_XOR 0x5DEECE66DL /* sample B's seed: run.seed XOR this */
#define SENS_BOOTSTRAP 1000          /* bootstrap resamples of the indices */
#define SENS_BOOT_SEED 2010u         /* their fixed seed */

enum sens_kind { SENS_TOLERANCE = 0, SENS_NOISE };

typedef struct {
    char name[CONFIG_STR_MAX];      /* "dH_um", "campaign_noise" */
    int kind;                       /* enum sens_kind */
    char keys[2 * CONFIG_STR_MAX];  /* what scales it: "tolerance.dH_um", "noise.a, noise.b" */
    uint32_t stream;                /* its rng stream */
    stats_sobol_index before, after;
} sens_source;

typedef struct {
    int angle, band;                /* the report row (as the budget's) */
    long units;                     /* N, rows of A and of B */
    long paired_units;              /* rows with a fit in every run */
    long reused_units;              /* unit runs finished from stored readings */
    long seed, seed_b;
    int n;
    sens_source src[SENS_MAX_SOURCES];
    double var_before, var_after;   /* variance of Y over A and B (the indices' denominator) */
    double mean_before, mean_after; /* mean of Y over A and B */
} sens_result;

/* Called before each Monte Carlo: what ("A", "B", "dH_um from B"), i of n. */
typedef void (*sens_progress_fn)(const char *what, int i, int n, void *ctx);

/* Fill s->src with c's inputs and choose the row.  SUNMC_EINPUT when the
 * family declares no random inputs or none varies. */
int sens_sources(const sunmc_config *c, sens_result *s, char *err, size_t errlen);

/* How many random inputs of c vary (sens_sources' count; -1 out of
 * memory).  0: every unit of c is the same unit (every tolerance 0 or
 * fixed, every noise 0), which budget's floor run uses to run one. */
int sens_random_inputs(const sunmc_config *c);

/* Sobol indices of c's inputs over N = units units.  threads: 0 = OpenMP
 * default; progress (may be NULL) is called before each Monte Carlo ("Monte
 * Carlo runs", i of the d + 2). */
int sens_run(const sunmc_config *c, long units, int threads, sens_progress_fn progress,
             void *ctx, sens_result *s, char *err, size_t errlen);

/* --until: which intervals must be narrow enough (after calibration, or
 * before it: S1 or ST of every input). */
enum sens_until_stat { SENS_UNTIL_ST = 0, SENS_UNTIL_S1, SENS_UNTIL_ST_BEFORE,
                       SENS_UNTIL_S1_BEFORE, SENS_UNTIL_STATS };
extern const char *const sens_until_names[SENS_UNTIL_STATS]; /* "st", "s1", ... */

/* Stop when the widest interval of stat over the inputs has a half-width
 * (half its length, in index units) at most halfwidth. */
typedef struct {
    int stat;         /* enum sens_until_stat */
    double halfwidth; /* > 0 */
    long block;       /* units added between checks (run.block_units) */
    int met;          /* out: 1 when a check met it */
    double reached;   /* out: the widest half-width at the last check */
} sens_until;

/* sens_run in blocks of until->block units (from 0, at most units): after
 * each block the indices of the units so far are estimated, and the run
 * stops once until's statistic is narrow enough.  s holds the indices of
 * the units taken (s->units): the same bytes as sens_run of that many units.
 * progress is called before each block ("block", i of the most blocks). */
int sens_run_until(const sunmc_config *c, long units, sens_until *until, int threads,
                   sens_progress_fn progress, void *ctx, sens_result *s, char *err,
                   size_t errlen);

#endif
