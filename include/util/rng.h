/* rng.h - counter-based random streams: unit u's draws depend only on
 * (seed, u, stream), never on the thread or the order units run in.
 *
 * Philox4x32-10 (Random123) keyed by the 64-bit seed; the counter is
 * (unit low, unit high, stream, index).  A stream is a cheap value on the
 * stack: no allocation, no shared state, so any thread may draw any unit.
 */
#ifndef SUNMC_RNG_H
#define SUNMC_RNG_H

#include <stddef.h>
#include <stdint.h>

/* Stream identifiers: each purpose of a unit draws from its own stream, so
 * changing one part of a config (a campaign step, say) does not reshuffle
 * the draws of another (the tolerances): common random numbers in sweeps. */
enum rng_stream_id {
    RNG_STREAM_TOLERANCE = 0x100, /* + the stream id of each deviation-list line */
    RNG_STREAM_CAL_NOISE = 0x200, /* sensor and encoder noise of the campaign */
    RNG_STREAM_VAL_NOISE = 0x201, /* noise of the validation readings */
    RNG_STREAM_ALIGNMENT = 0x202, /* the roll alignment measurement */
    RNG_STREAM_SUN_Y = 0x203,     /* the sun simulator's tilt measurement (ESS) */
    RNG_STREAM_SUN_B = 0x204,     /* the sun simulator's direction measurement (DSS) */
    RNG_STREAM_PATTERN = 0x205,   /* the detector's fixed pattern: its key (DSS) */
    RNG_STREAM_LINE_CAL = 0x206,  /* the table's setting error per campaign line (PSD) */
    RNG_STREAM_LINE_VAL = 0x207,  /* the same per validation line (PSD) */
    RNG_STREAM_LOT = 0x300,       /* + the stream id: a lot's common part (index: the lot) */
    RNG_STREAM_DESIGN = 0x400     /* + the stream id: a sampling block's keys (index: the block) */
};

typedef struct {
    uint32_t key[2];
    uint32_t ctr[4];
    uint32_t buf[4];
    int left; /* words left in buf */
    double spare;  /* the second normal of the last pair, if has_spare */
    int has_spare;
} rng_stream;

/* Start stream `stream` of unit `unit` for `seed`. */
void rng_stream_init(rng_stream *r, uint64_t seed, uint64_t unit, uint32_t stream);

/* Uniform double in the open interval (0, 1), 53 random bits. */
double rng_uniform(rng_stream *r);

/* Standard normal deviate (Box-Muller: both normals of a pair, the
 * second kept in the stream as its spare; the k-th normal of a stream is
 * the same however the draws are split into calls). */
double rng_normal(rng_stream *r);

/* The next n normal deviates of r into out: the same values as n calls of
 * rng_normal, computed a vector at a time. */
void rng_normal_fill(rng_stream *r, double *out, size_t n);

#endif
