/* merge.h - checking that shard directories (`run --units FIRST:END` or
 * `--shard K/N` with --out) are parts of one run that tile a unit range:
 * the same sunmc version, family, config and seed, no gap, no overlap, no
 * directory twice.  `sunmc merge` then replays their units.bin in unit
 * order through the run's statistics (runner.h). */
#ifndef SUNMC_MERGE_H
#define SUNMC_MERGE_H

#include "unitfile.h"

typedef struct {
    const char *dir;
    run_manifest m;
} merge_shard;

/* Read DIR/manifest.ini of dirs[n] into shards[n], sorted by first unit,
 * and check them.  SUNMC_EINPUT with a message naming the directories and
 * the units: "units 100:200 are missing between A and B", "units 50:100
 * are in both A and B", "A and B are the same directory", "A and B are of
 * different runs: seed 1 against 2". */
int merge_plan(const char *const *dirs, int n, merge_shard *shards, char *err, size_t errlen);

#endif
