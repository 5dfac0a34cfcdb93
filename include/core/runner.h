/* runner.h - what a Monte Carlo run does with its units as they stream by
 * (montecarlo.h's blocks, in unit order): the statistics of the summary,
 * the rows of units.tsv, the time split of `run --profile`.  Nothing is
 * held per unit beyond what the statistics need (report.h). */
#ifndef SUNMC_RUNNER_H
#define SUNMC_RUNNER_H

#include "checkpoint.h"
#include "montecarlo.h"
#include "report.h"
#include "status.h"
#include "unitfile.h"
#include "unitsum.h"

#include <stdio.h>

/* run --until: stop after the first block at whose end the half-width of
 * stat's interval in the widest band (report.h) is at most `halfwidth`. */
typedef struct {
    int stat;              /* report_stat_find */
    double halfwidth;      /* target, in the statistic's unit (yield: a fraction) */
    int band;              /* report_widest_band */
    int met;               /* out: the target was met */
    double reached;        /* out: the half-width after the last block (NaN: none yet) */
} run_until;

typedef struct {
    const sunmc_config *c;
    const sensor_family *fam;
    report_acc *acc;
    FILE *units_tsv;                 /* rows written here when non-NULL */
    FILE *units_bin;                 /* records written here when non-NULL */
    unitfile_layout layout;
    double phase_s[UNIT_PHASES];     /* summed over the units (run --profile) */
    run_until *until;                /* NULL: run every unit */
    checkpoint *ckpt;                /* each block committed here when non-NULL */
    int distribute;                  /* split the blocks across MPI ranks (mc_plan) */
    int ckpt_status;                 /* the first checkpoint error (then no more) */
    unitsum_acc sum;                 /* checksums of the records written to units_bin */
    char ckpt_err[SUNMC_ERRLEN];
} run_sink;

/* units_tsv and units_bin may be NULL (no per-unit rows, records); their
 * headers are written here. */
int run_sink_init(run_sink *r, const sunmc_config *c, FILE *units_tsv,
                  FILE *units_bin, char *err, size_t errlen);
/* An mc_sink_fn; ctx is the run_sink. */
int run_sink_block(const unit_result *results, long n, void *ctx, int *stop, char *err,
                   size_t errlen);
void run_sink_free(run_sink *r);
/* The checksums of the records written so far into m (units_sum_units,
 * units_fnv1a64). */
void run_sink_sums(run_sink *r, run_manifest *m);

/* Stream units [first, end) of c through r in blocks of c->block_units. */
int run_stream(run_sink *r, long first, long end, int threads, mc_progress_fn progress,
               void *progress_ctx, long *done, char *err, size_t errlen);

/* Hand the records of units [first, end) in the units.bin file `path` to
 * r, in blocks of c->block_units, as if they were being run: SUNMC_EINPUT
 * naming the unit when the file holds another unit where one is expected,
 * fewer or more records than end - first, or another layout.  *done (may
 * be NULL) gets the units handed over (fewer when r's --until stopped). */
int run_replay(run_sink *r, const char *path, long first, long end, long *done, char *err,
               size_t errlen);

#endif
