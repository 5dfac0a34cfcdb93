/* allocate.h - tolerance allocation: the cheapest joint set of tolerances
 * whose yield (after-calibration RMS within report.spec_arcsec, in the
 * budget's row: budget.h) meets report.yield_target, with its lower
 * confidence bound confirmed by a Monte Carlo on an independent seed.
 *
 * Sources: the family's tolerances above 0 and not fixed (budget.h's
 * tolerance sources); noise keys stay as they are.  Cost: a tolerance at
 * value v costs tolerance.NAME_cost * (today / v)^k, k =
 * report.cost_exponent; the total is their sum (today's: the sum of the
 * NAME_cost).
 *
 * Surrogate (per unit, common random numbers, `units` units on run.seed):
 * runs with every source at 0 (base, noise on), all at today's values, and
 * each source alone on the base at today's value and at ALLOCATE_PROBE
 * times it.  Unit u's RMS^2 at tolerances t is taken as
 *   base_u + sum_i d_iu x_i + I_u (sum_i s_i x_i / sum_i s_i),
 * x_i = (t_i / today_i)^p_i, d_iu its increment alone, s_i the mean of
 * d_iu, I_u the rest at today's values (the interaction, scaled with the
 * additive part), p_i from the mean increments at the two values (2 for a
 * square law, clipped to [1, 6]).  The surrogate yield is the share of
 * units whose RMS^2 is within spec^2.
 *
 * Search: the cost-optimal shape of the mean-square budget (Lagrange:
 * x_i = (k w_i / (p_i lambda s_i))^(1 / (k / p_i + 1)), within
 * [today / ALLOCATE_RANGE, min(today * ALLOCATE_PROBE, key max)]: the
 * surrogate interpolates, never extrapolates, above today), lambda
 * by bisection for the loosest set whose surrogate yield reaches the
 * yield needed for the lower bound at `units` units to clear the target;
 * then a greedy loosening of each source while the surrogate holds.
 * Refined by Monte Carlo on seed run.seed + 1 (a shortfall raises the
 * surrogate's requirement, at most ALLOCATE_REFINE times) and confirmed on
 * seed run.seed + 2, independent of both.
 */
#ifndef SUNMC_ALLOCATE_H
#define SUNMC_ALLOCATE_H

#include "budget.h"
#include "config.h"

#define ALLOCATE_PROBE 4.0   /* second value of each source, times today's: the loosest */
#define ALLOCATE_RANGE 16.0  /* the tightest: today / 16 */
#define ALLOCATE_REFINE 3    /* Monte Carlo refinements at most */

enum allocate_status {
    ALLOCATE_CONFIRMED = 0, /* the confirmation's lower bound meets the target */
    ALLOCATE_UNCONFIRMED,   /* a set was found, its confirmation falls short */
    ALLOCATE_NONE           /* not even every source at today / ALLOCATE_RANGE meets it */
};

typedef struct {
    char name[CONFIG_STR_MAX];
    const config_key *key;
    double today, allocated;      /* unit of the key */
    double lo, hi;                /* the search range */
    double weight;                /* tolerance.NAME_cost */
    double power;                 /* p_i */
    double ms_share;              /* s_i, mean RMS^2 increment alone at today's value */
    double cost_today, cost_allocated;
} allocate_source;

typedef struct {
    int n;
    allocate_source src[BUDGET_MAX_SOURCES];
    int angle, band;
    long units;
    double cost_today, cost_allocated;
    double yield_needed;          /* surrogate yield asked for at the end */
    double surrogate_yield;       /* of the answer */
    double yield_today;           /* Monte Carlo, run.seed */
    stats_interval yield_today_ci;
    double yield_refine;          /* last refinement, run.seed + 1 */
    double yield;                 /* confirmation, run.seed + 2 */
    stats_interval yield_ci;
    long confirm_seed;
    int refinements;
    int status;                   /* enum allocate_status */
} allocate_result;

/* Called before each Monte Carlo: what, i of n (n may grow). */
typedef void (*allocate_progress_fn)(const char *what, int i, int n, void *ctx);

/* Allocate c's tolerances on `units` units per run (at least 10).
 * SUNMC_EINPUT when c has no tolerance to allocate or `units` units
 * cannot show the target at report.confidence even if every unit passed. */
int allocate_run(const sunmc_config *c, long units, int threads, allocate_progress_fn progress,
                 void *ctx, allocate_result *a, char *err, size_t errlen);

/* 1 when a yield interval's lower bound meets c's report.yield_target (the
 * promise is the bound, not the estimate); NaN bounds never do. */
int allocate_meets(const sunmc_config *c, stats_interval yield_ci);

/* Set the allocated values in cfg. */
void allocate_apply(const allocate_result *a, sunmc_config *cfg);

#endif
