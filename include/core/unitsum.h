/* unitsum.h - checksums of the records of a units.bin file, so that a
 * flipped bit or an edit in a committed checkpoint or in a run's units.bin
 * is refused on --resume and on merge, naming the file and the units.
 *
 * Records are hashed in leaves of `leaf_units` consecutive units (FNV-1a
 * 64 of their bytes as written; the last leaf may be short).  A list of
 * level k holds the hashes of nodes of leaf_units * 2^k units: a node's
 * hash is FNV-1a 64 of its two children's hashes (8 bytes each, the
 * machine's order), or its left child's alone when it has no right one.
 *   - A checkpoint lists its blocks (leaf_units = run.block_units, level 0)
 *     in units.sum, one "%016llx" line per block, appended with the block.
 *   - manifest.ini lists at most UNITSUM_MAX nodes of the lowest level
 *     that fits, over leaves of UNITSUM_LEAF_UNITS: units_sum_units (the
 *     units of one node) and units_fnv1a64 (the hashes).  The list depends
 *     only on the records and the unit range, so a merge of any shard split
 *     writes the same manifest as one run. */
#ifndef SUNMC_UNITSUM_H
#define SUNMC_UNITSUM_H

#include "unitfile.h"

#include <stddef.h>

#define UNITSUM_LEAF_UNITS 64
#define UNITSUM_MAX MANIFEST_SUM_MAX
#define UNITSUM_NAME "units.sum"

typedef struct {
    long leaf_units;
    unsigned long long *leaf; /* completed leaves (and the open one at n) */
    long n, cap;
    long in_leaf;             /* units in the open leaf */
    unsigned long long cur;   /* its hash so far */
} unitsum_acc;

void unitsum_init(unitsum_acc *a, long leaf_units);
/* Add one record of `bytes` bytes (the units in order); SUNMC_ENOMEM. */
int unitsum_add(unitsum_acc *a, const void *record, size_t bytes);
/* Add the records of r[n] as unitfile_write writes them. */
int unitsum_add_results(unitsum_acc *a, const unitfile_layout *l, const unit_result *r, long n);
/* The hashes of the leaves so far (the open one included): *n of them. */
const unsigned long long *unitsum_leaves(unitsum_acc *a, long *n);
/* Reduce to the lowest level with at most UNITSUM_MAX nodes: out[*nout]
 * and *node_units (leaf_units * 2^level). */
void unitsum_finish(unitsum_acc *a, unsigned long long *out, int *nout, long *node_units);
void unitsum_free(unitsum_acc *a);

/* Check the records of units [first, end) in the units.bin file path
 * (layout l) against want[nwant], nodes of node_units units over leaves of
 * leaf_units.  SUNMC_EINPUT naming path, the units whose bytes differ and
 * `source` (where the checksums are kept) on a mismatch. */
int unitsum_verify(const char *path, const unitfile_layout *l, long first, long end,
                   long leaf_units, long node_units, const unsigned long long *want, long nwant,
                   const char *source, char *err, size_t errlen);

#endif
