/* unit_store.h - units' validation readings kept between runs of configs
 * that share them (family.h: unit_read, unit_finish).
 *
 * What a unit's sensor reads on the validation grid, with its validation
 * noise, depends on (seed, unit) and on the sensor, its tolerances, the
 * validation grid and the noise, not on the calibration campaign: `design`
 * runs the same units for every candidate campaign and reads them once.
 * A store holds the readings of `capacity` units; mc_run_store (montecarlo.h)
 * finishes a unit from its slot when the slot holds that unit's readings for
 * a config with the same readings (unit_readings_same), else reads it into
 * the slot first.  A reading is a function of (config, unit) alone, so the
 * results are the same bits with or without a store, in any thread count
 * and in any order of runs.
 */
#ifndef SUNMC_UNIT_STORE_H
#define SUNMC_UNIT_STORE_H

#include "config.h"

#include <stddef.h>

typedef struct unit_store unit_store;

/* 1 when configs a and b read every unit's validation the same: the same
 * family, which splits its units, the same pick-freeze and the same value
 * of every key but those its readings_ignore names. */
int unit_readings_same(const sunmc_config *a, const sunmc_config *b);

/* A store of capacity units' readings for configs like c (its family's
 * readings_bytes(c) each) into *out.  SUNMC_ENOMEM with a message when
 * out of memory; SUNMC_OK and *out NULL when c's family does not split its
 * units (runs then go without a store). */
int unit_store_alloc(const sunmc_config *c, long capacity, unit_store **out, char *err,
                     size_t errlen);
void unit_store_free(unit_store *s);

/* unit_store_alloc when the store takes at most max_bytes
 * (unit_store_bytes); otherwise SUNMC_OK and *out NULL: the runs then
 * read their readings again, the same bits at a store's memory saved. */
int unit_store_alloc_upto(const sunmc_config *c, long capacity, double max_bytes,
                          unit_store **out, char *err, size_t errlen);

/* Bytes unit_store_alloc takes for capacity units of c (0: no store). */
double unit_store_bytes(const sunmc_config *c, long capacity);

/* ---- For mc_run_store (montecarlo.c) ---- */

/* Before a run of units [first, end) of config c (one thread): 1 when the
 * store serves it (the family splits, c's readings fit a slot, the range
 * fits the store); a config whose readings differ from the store's empties
 * it first. */
int unit_store_bind(unit_store *s, const sunmc_config *c, long first, long end);

/* 1 when the store serves a run of units [first, end) of c as it is
 * (without emptying it). */
int unit_store_serves(const unit_store *s, const sunmc_config *c, long first, long end);

/* Unit u's slot (units of one bound run have distinct slots); *held = 1
 * when it already holds u's readings. */
void *unit_store_slot(unit_store *s, long u, int *held);

/* Record that u's readings are now in its slot. */
void unit_store_fill(unit_store *s, long u);

/* Units read into the store since it was made (0 for NULL). */
long unit_store_reads(const unit_store *s);

#endif
