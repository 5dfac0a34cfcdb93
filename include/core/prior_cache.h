/* prior_cache.h - a process's priors' pilots, each made once (prior.h).
 *
 * A pilot depends only on its inputs: the config with its noise and
 * pick-freeze cleared (a sunmc_config is plain bytes: config.h), the
 * campaign's table angles and the fit's layout.  Runs and threads with the
 * same inputs (the threads of a run, sensitivity's pick-freeze runs, a
 * budget's noise sources, a design's confirmation of a screened candidate)
 * share one pilot instead of each making it again: the same priors, the
 * same bits.  The key is those inputs' bytes, compared whole: two pilots
 * are one only when every byte is equal (a difference that does not matter
 * only costs a second pilot).  The store keeps the last PRIOR_CACHE_SIZE
 * pilots; it is safe to use from several threads at once.
 */
#ifndef SUNMC_PRIOR_CACHE_H
#define SUNMC_PRIOR_CACHE_H

#include "prior.h"

#include <stddef.h>

#define PRIOR_CACHE_SIZE 32

/* One part of a key: bytes bytes at p. */
typedef struct {
    const void *p;
    size_t bytes;
} prior_key_part;

/* 1 when the pilot of key (its n parts, in order) has been made in this
 * process: its priors into *p, its status (SUNMC_OK, or SUNMC_EINPUT with
 * its message into err) into *status; else 0, nothing written. */
int prior_cache_find(const prior_key_part *key, int n, calib_prior *p, int *status, char *err,
                     size_t errlen);

/* Keep the pilot of key: its priors p and status (SUNMC_OK or
 * SUNMC_EINPUT, whose message is err; any other status is not kept, and
 * neither is anything when memory is short). */
void prior_cache_keep(const prior_key_part *key, int n, const calib_prior *p, int status,
                      const char *err);

/* Adds a pilot's units to p (reset for its parameters): SUNMC_OK, or a
 * failure (out of memory) with its message. */
typedef int (*prior_pilot_fn)(void *ctx, calib_prior *p, char *err, size_t errlen);

/* The pilot of key into p (reset by the caller): the store's, or made by
 * add(ctx, ...) and kept.  add's status (SUNMC_OK when found). */
int prior_cache_pilot(const prior_key_part *key, int n, calib_prior *p, prior_pilot_fn add,
                      void *ctx, char *err, size_t errlen);

/* Forget every pilot (tests). */
void prior_cache_clear(void);

#endif
