/* sampling.h - the design of the tolerance draws (run.sampling): plain
 * random, Latin hypercube or Sobol', each randomised per block of
 * run.sampling_block units so that every estimate keeps a valid interval.
 *
 * Units are grouped into blocks of B = run.sampling_block: unit u is point
 * i = u mod B of block b = u / B.  Each block is an independent randomised
 * design whose randomisation is keyed by (seed, b, stream id) only, so a
 * unit's draws still depend only on (seed, u, stream) and the output is
 * the same for any thread count, unit range, shard split or rank count.
 *   lhs:   coordinate j of a tolerance (stream s) is (pi(i) + V) / B, pi a
 *          keyed pseudo-random permutation of 0..B-1 (a Feistel network
 *          with cycle walking, composed with a random cyclic shift so that
 *          pi(i) is exactly uniform), V uniform from the unit's own stream.
 *   sobol: the first B points of Sobol's sequence (GSL's gsl_qrng_sobol,
 *          with the origin as point 0), digitally shifted: the 30-bit
 *          coordinate XOR a random word of the block, plus V / 2^30.
 *          Dimension k is the tolerance draw's place in the family's list
 *          (count draws per entry); coordinates past SAMPLING_SOBOL_DIMS
 *          fall back to lhs.
 * Either way each unit's coordinate is exactly uniform on (0, 1), the
 * blocks are independent, and the block totals give the variance of a mean
 * (report.c): the units within a block are not independent, so an interval
 * from the units as if they were would be wrong.
 */
#ifndef SUNMC_SAMPLING_H
#define SUNMC_SAMPLING_H

#include "config.h"
#include "rng.h"

#include <stdint.h>

/* Sobol' dimensions GSL provides. */
#define SAMPLING_SOBOL_DIMS 40
/* Largest run.sampling_block (the Sobol' table holds this many points). */
#define SAMPLING_BLOCK_MAX 4096

/* The uniform coordinate of unit `unit` for draw j of the tolerance on
 * stream id `stream` (RNG_STREAM_TOLERANCE + list id), whose place among
 * all draws of the family's list is k; seed is the stream's seed
 * (unit_stream_seed), r the unit's own stream (one uniform drawn from it).
 * c->sampling must be lhs or sobol. */
double sampling_uniform(const sunmc_config *c, uint64_t seed, long unit, uint32_t stream, int j,
                        int k, rng_stream *r);

/* The block of unit `unit` under c's design (-1 for random sampling: the
 * units are independent). */
long sampling_block_of(const sunmc_config *c, long unit);

#endif
