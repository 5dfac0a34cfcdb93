/* sampling.c - randomised Latin hypercube and Sobol' blocks (sampling.h). */
#include "sampling.h"

#include <gsl/gsl_qrng.h>
#include <pthread.h>

/* Sobol' coordinates are 30-bit fractions in GSL. */
#define SOBOL_BITS 30
#define FEISTEL_ROUNDS 4

static uint32_t sobol_table[SAMPLING_BLOCK_MAX][SAMPLING_SOBOL_DIMS];
static int sobol_ok;
static pthread_once_t sobol_once = PTHREAD_ONCE_INIT;

/* Point 0 the origin, point i >= 1 GSL's i-th: the first 2^m points then
 * form a (t, m, s)-net. */
static void sobol_fill(void)
{
    gsl_qrng *q = gsl_qrng_alloc(gsl_qrng_sobol, SAMPLING_SOBOL_DIMS);
    if (!q)
        return;
    double x[SAMPLING_SOBOL_DIMS];
    for (int i = 1; i < SAMPLING_BLOCK_MAX; i++) {
        if (gsl_qrng_get(q, x) != 0) {
            gsl_qrng_free(q);
            return;
        }
        for (int d = 0; d < SAMPLING_SOBOL_DIMS; d++)
            sobol_table[i][d] = (uint32_t)(x[d] * (double)(1u << SOBOL_BITS));
    }
    gsl_qrng_free(q);
    sobol_ok = 1;
}

/* A 64-bit mixer (splitmix64's finaliser) for the Feistel rounds. */
static uint64_t mix64(uint64_t x)
{
    x ^= x >> 30;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 27;
    x *= 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

/* A keyed permutation of 0..n-1: a balanced Feistel network on 2h bits
 * (4^h >= n), applied again while the value is n or more (cycle walking:
 * a permutation of 0..4^h-1 restricted to 0..n-1 this way is one of
 * 0..n-1), then a cyclic shift by `shift`. */
static uint32_t permute(uint32_t i, uint32_t n, uint64_t key, uint32_t shift)
{
    int h = 1;
    while ((1u << (2 * h)) < n)
        h++;
    uint32_t mask = (1u << h) - 1, x = i;
    do {
        uint32_t l = x >> h, r = x & mask;
        for (int round = 0; round < FEISTEL_ROUNDS; round++) {
            uint32_t f = (uint32_t)mix64(key + ((uint64_t)round << 32) + r) & mask;
            uint32_t t = r;
            r = l ^ f;
            l = t;
        }
        x = (l << h) | r;
    } while (x >= n);
    return (x + shift) % n;
}

/* The block's randomisation of draw j of a tolerance, from the block's
 * own stream (seed, block, RNG_STREAM_DESIGN + list id): three uniforms
 * per draw, 53 bits each, the permutation key, the digital shift's word
 * and the cyclic shift. */
static void block_keys(uint64_t seed, long block, uint32_t stream, int j, uint64_t *key,
                       uint32_t *xor_word, double *shift)
{
    rng_stream b;
    uint32_t id = RNG_STREAM_DESIGN + (stream - RNG_STREAM_TOLERANCE);
    rng_stream_init(&b, seed, (uint64_t)block, id);
    for (int k = 0; k < 3 * j; k++)
        (void)rng_uniform(&b);
    *key = (uint64_t)(rng_uniform(&b) * 0x1.0p53);
    *xor_word = (uint32_t)(rng_uniform(&b) * 0x1.0p32);
    *shift = rng_uniform(&b);
}

double sampling_uniform(const sunmc_config *c, uint64_t seed, long unit, uint32_t stream, int j,
                        int k, rng_stream *r)
{
    uint32_t nb = (uint32_t)c->sampling_block, i = (uint32_t)(unit % c->sampling_block), xw;
    uint64_t key;
    double v = rng_uniform(r), shift;
    block_keys(seed, unit / c->sampling_block, stream, j, &key, &xw, &shift);
    if (c->sampling == CONFIG_SAMPLING_SOBOL && k < SAMPLING_SOBOL_DIMS) {
        pthread_once(&sobol_once, sobol_fill);
        if (sobol_ok) {
            uint32_t x = sobol_table[i][k] ^ (xw >> (32 - SOBOL_BITS));
            return ((double)x + v) / (double)(1u << SOBOL_BITS);
        }
    }
    uint32_t p = permute(i, nb, key, (uint32_t)(shift * nb));
    return ((double)p + v) / (double)nb;
}

long sampling_block_of(const sunmc_config *c, long unit)
{
    return c->sampling == CONFIG_SAMPLING_RANDOM ? -1 : unit / c->sampling_block;
}
