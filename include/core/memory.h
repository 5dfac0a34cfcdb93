/* memory.h - how much memory a run needs, checked before any work.
 *
 * A streamed run (montecarlo.h's blocks) holds a block of unit_results, the
 * RMS after of every unit per angle and band (for the p95) and one family
 * workspace per thread (the campaign's readings and the fit's Jacobian); an
 * in-memory run (mc_run: budget) a unit_result per unit.  Both are known from the config before a unit runs, so a run
 * that cannot fit is refused at once with the memory it would need, instead
 * of failing with "out of memory" after the allocation (or being killed by
 * the system part way through).
 */
#ifndef SUNMC_MEMORY_H
#define SUNMC_MEMORY_H

#include "config.h"

#include <stddef.h>

/* Most memory one thread's workspace may take: campaign and validation
 * grids past it are a config error (finer than any turntable needs). */
#define MEMORY_WORKSPACE_MAX_BYTES (1024.0 * 1024.0 * 1024.0)

/* "1.2 GB", "340 MB", "12 kB" (powers of 1000). */
void memory_text(double bytes, char *buf, size_t len);

/* Memory this process may use (bytes): the machine's physical memory, or
 * less under an address-space or data-size limit (ulimit -v, -d); 0 when
 * unknown. */
double memory_available_bytes(void);

/* Bytes a run of `units` units on `threads` threads of config c needs,
 * streamed in blocks (in_memory = 0) or held whole (1). */
double memory_run_bytes(const sunmc_config *c, long units, int threads, int in_memory);

/* SUNMC_EINPUT when a thread's workspace for c exceeds
 * MEMORY_WORKSPACE_MAX_BYTES (message naming the campaign keys). */
int memory_check_workspace(const sunmc_config *c, char *err, size_t errlen);

/* SUNMC_EINPUT when a run of units [first, end) on `threads` threads needs
 * more than limit_bytes (0: memory_available_bytes), with a message
 * giving what it needs and how to split it. */
int memory_check_run(const sunmc_config *c, long first, long end, int threads, int in_memory,
                     double limit_bytes, char *err, size_t errlen);

#endif
