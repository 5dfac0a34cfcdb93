/* checkpoint.h - completed blocks of a run with --out DIR, kept beside DIR
 * in .NAME.resume/ so that `run ... --out DIR --resume` continues after
 * SIGINT, SIGTERM, kill -9 or a power cut with the missing blocks only.
 *
 * The directory holds manifest.ini (the run's: version, family, config
 * hash, seed, unit range), units.bin (the records of the completed units,
 * appended a block at a time), units.sum (the FNV-1a 64 of each block's
 * records, a line "%016llx" per block, unitsum.h) and `progress`
 * ("units_done K" and "block_units B").  A block is committed by writing
 * its records and its checksum, syncing both, then replacing `progress` atomically (temporary file, sync,
 * rename, sync of the directory): `progress` never counts a unit whose
 * record is not on disk, and records beyond it (a block cut short) are
 * dropped on resume.  On resume every committed block is checked against
 * its checksum: a flipped bit is refused, naming the file and the units.
 * The checkpoint is removed once DIR is complete.
 */
#ifndef SUNMC_CHECKPOINT_H
#define SUNMC_CHECKPOINT_H

#include "unitfile.h"

#include <limits.h>
#include <stdio.h>

typedef struct {
    char dir[PATH_MAX];
    FILE *bin;              /* units.bin, appending */
    FILE *sum;              /* units.sum, appending: a checksum per block */
    unitfile_layout layout;
    long first;             /* the run's first unit */
    long done;              /* units committed */
    long block_units;
} checkpoint;

/* The checkpoint directory of output directory out: PARENT/.NAME.resume. */
int checkpoint_path(const char *out, char *buf, size_t len);

/* Start a new checkpoint for the run m (any earlier one is removed). */
int checkpoint_create(checkpoint *k, const char *out, const run_manifest *m, long block_units,
                      const unitfile_layout *l, char *err, size_t errlen);

/* Open the checkpoint of out to resume the run m: SUNMC_EINPUT naming what
 * differs when it is of another run (version, family, seed, config, unit
 * range or block size); k->done is the units it holds, whose records are
 * in checkpoint_units_path.  *found = 0 (and SUNMC_OK) when out has no
 * checkpoint. */
int checkpoint_open(checkpoint *k, const char *out, const run_manifest *m, long block_units,
                    const unitfile_layout *l, int *found, char *err, size_t errlen);

/* Path of the checkpoint's units.bin (for run_replay). */
void checkpoint_units_path(const checkpoint *k, char *buf, size_t len);

/* Commit the next n records (the block after the k->done units). */
int checkpoint_append(checkpoint *k, const unit_result *r, long n, char *err, size_t errlen);

void checkpoint_close(checkpoint *k);

/* Remove the checkpoint of out, if any (after DIR is complete, or for a
 * fresh run); *removed_units (may be NULL) gets the units it held, -1 when
 * there was none. */
void checkpoint_remove(const char *out, long *removed_units);

#endif
