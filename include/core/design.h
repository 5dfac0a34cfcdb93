/* design.h - `sunmc design`: the cheapest calibration campaign whose yield
 * meets the target, for any family (its design_step_key and
 * design_lines_key, family.h).
 *
 * Candidates: every step of campaign.search_steps_deg x every symmetric
 * line set (1 line at 0; n = 2..search_max_lines lines evenly spaced over
 * +-B, B = search_beta_step_deg, 2 x that, ... up to search_beta_max_deg;
 * none when the family has no line key) x every count of
 * campaign.search_repeats, plus the input config's own campaign; a
 * candidate whose validation angles lie more than
 * campaign.search_max_extrapolation_deg beyond its span is not tried.
 * Every candidate runs the same units with the same seed (common random
 * numbers: the tolerance draws of unit u are the same in every candidate,
 * so their differences are the campaign's, not the draws').
 *
 * Yield: of the widest band, last measured angle (as `budget`), with
 * Wilson's interval at report.confidence.  Stages:
 *  1. screen: search_screen_units units each; a candidate whose campaign
 *     aliased (any unit) is marked and never chosen; one whose upper bound
 *     is below report.yield_target is dropped;
 *  2. settle: the survivors, cheapest first, run on in blocks of
 *     run.block_units units until the lower bound reaches the target
 *     (pass), the upper bound falls below it (fail) or search_max_units
 *     (undecided); it stops once search_shortlist candidates passed.
 * The bound is looked at after every block, so its coverage is somewhat
 * below the nominal level; re-run the chosen campaign with another seed to
 * confirm it (the printed command does).
 * Rank: turntable hours (campaign.h), then the yield.
 */
#ifndef SUNMC_DESIGN_H
#define SUNMC_DESIGN_H

#include "config.h"
#include "stats.h"

#include <stddef.h>

#define DESIGN_TEXT 160

enum design_verdict {
    DESIGN_PASS = 0,     /* lower bound >= target */
    DESIGN_FAIL,         /* upper bound < target after settling */
    DESIGN_SCREENED_OUT, /* upper bound < target on the screen */
    DESIGN_ALIASED,      /* the campaign aliased the family's term: never chosen */
    DESIGN_UNDECIDED,    /* search_max_units reached with the target inside the interval */
    DESIGN_NOT_SETTLED,  /* survived the screen; the short list filled before its turn */
    DESIGN_VERDICTS
};

extern const char *const design_verdict_names[DESIGN_VERDICTS];

typedef struct {
    char step[DESIGN_TEXT];     /* value of the step key, as text */
    char lines[DESIGN_TEXT];    /* value of the line key ("" when none) */
    int repeats;
    int is_input;               /* the input config's own campaign */
    sunmc_config cfg;           /* the candidate's config */
    long points;
    double hours, extrapolation_deg;
    long units, alias_units, fit_failures;
    double yield, after_mean;   /* after_mean: mean RMS after, family rms unit */
    stats_interval yield_ci, after_ci;
    int verdict;                /* enum design_verdict */
    int pareto;                 /* on the front of yield against hours */
} design_candidate;

typedef struct {
    int n;
    design_candidate *cand;     /* n, in space order (input first) */
    int *order;                 /* n indices: hours, then yield descending */
    int best;                   /* index of the chosen candidate, -1 when none passed */
    long units_run;             /* units over all candidates */
    /* of which finished from validation readings already read for another
     * candidate (unit_store.h; 0 when the family does not split its units
     * or reuse is off) */
    long units_reused;
    int no_reuse;               /* set before design_run: read every unit afresh */
    int n_extrapolating;        /* candidates not tried: they extrapolate too far */
    int angle, band;            /* the yield's report row */
} design_result;

/* Called before each Monte Carlo block: stage ("screen"/"settle"), i of n. */
typedef void (*design_progress_fn)(const char *stage, int i, int n, void *ctx);

/* Build the candidate space of c (see above).  SUNMC_EINPUT when the family
 * has no design keys or a candidate does not validate (message names it),
 * SUNMC_ENOMEM. */
int design_space(const sunmc_config *c, design_result *d, char *err, size_t errlen);

/* Screen and settle d's candidates; threads 0 = OpenMP's default. */
int design_run(design_result *d, int threads, design_progress_fn progress, void *ctx, char *err,
               size_t errlen);

void design_free(design_result *d);

#endif
