/* montecarlo.h - run units [first, end) of a config in parallel.
 *
 * OpenMP over units, dynamic schedule, one family workspace per thread.
 * Since a unit's draws depend only on (seed, u) and aggregation is in unit
 * order, the results do not depend on the thread count.
 *
 * mc_run fills an array of every unit's results (small runs: budget
 * points, tests).  mc_stream runs the units in blocks of block_units and
 * hands each block, complete and in unit order, to a sink before the next
 * one starts: the block buffer is the reorder buffer, so memory does not
 * grow with the number of units, and a sink may stop the run after any
 * block (run --until) -- the units handed over are then exactly those of a
 * fixed run of that many units.
 */
#ifndef SUNMC_MONTECARLO_H
#define SUNMC_MONTECARLO_H

#include "config.h"
#include "family.h"

/* Called from one thread now and then (done units, total); may be NULL. */
typedef void (*mc_progress_fn)(long done, long total, void *ctx);

/* threads: 0 = OpenMP's default.  Returns SUNMC_OK, or the first error of a
 * family workspace allocation or unit run (message in err). */
int mc_run(const sunmc_config *c, long first, long end, int threads,
           unit_result *results, mc_progress_fn progress, void *ctx, char *err, size_t errlen);

/* mc_run with a store of validation readings (unit_store.h; NULL: none):
 * a unit whose readings the store holds for a config like c is not read
 * again, and those it reads are kept.  The results are the same bits as
 * mc_run's. */
struct unit_store;
int mc_run_store(const sunmc_config *c, struct unit_store *store, long first, long end,
                 int threads, unit_result *results, mc_progress_fn progress, void *ctx,
                 char *err, size_t errlen);

/* Receives config i's results[n] of mc_run_each, in unit order, from the
 * thread that ran them: calls for distinct i may run at once.  A status
 * other than SUNMC_OK ends the run (message in err). */
typedef int (*mc_each_fn)(int i, const unit_result *results, long n, void *ctx, char *err,
                          size_t errlen);

/* Units [first, end) of each of n configs c[i]: the configs shared among
 * the threads (dynamic, in the order given), each one's units run in order
 * by one thread with a workspace of its own, then handed to each(i, ...).
 * With a store (NULL: none), the units' validation readings are read into
 * it first (c[0]'s, the units shared among the threads) and every config
 * the store serves (unit_store_serves) is finished from them.  Results are
 * the same bits as mc_run's of each config, in any thread count; a run of
 * many configs on few units has one barrier, not one a config.  progress
 * (may be NULL) counts configs done. */
int mc_run_each(const sunmc_config *const *c, int n, struct unit_store *store, long first,
                long end, int threads, mc_each_fn each, void *ctx, mc_progress_fn progress,
                void *progress_ctx, char *err, size_t errlen);

/* Receives results[n], the next block in unit order; sets *stop = 1 to end
 * the run after this block.  A status other than SUNMC_OK ends the run with
 * that status (message in err). */
typedef int (*mc_sink_fn)(const unit_result *results, long n, void *ctx, int *stop, char *err,
                          size_t errlen);

typedef struct {
    long first, end;      /* units [first, end) */
    long block_units;     /* units per block, > 0; block k is [first + k B, first + (k+1) B) */
    int threads;          /* 0 = OpenMP's default */
    mc_sink_fn sink;
    void *sink_ctx;
    mc_progress_fn progress; /* may be NULL; done counts from first */
    void *progress_ctx;
    /* Split the blocks across the MPI ranks (ranks.h): every rank calls
     * mc_stream with the same plan; block k is run by rank k mod R and
     * rank 0 receives every block in unit order and alone calls the sink
     * (the others' sink is never called); its stop ends every rank.  The
     * sink thus sees exactly what a single process would. */
    int distribute;
} mc_plan;

/* Run the plan's blocks in order.  *done (may be NULL) gets the number of
 * units handed to the sink (0 on ranks other than 0). */
int mc_stream(const sunmc_config *c, const mc_plan *p, long *done,
              char *err, size_t errlen);

#endif
