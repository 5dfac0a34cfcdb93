/* rng.c - Philox4x32-10 streams over Random123's philox.h. */
#include "rng.h"

#include <Random123/philox.h>
#include <math.h>

void rng_stream_init(rng_stream *r, uint64_t seed, uint64_t unit, uint32_t stream)
{
    r->key[0] = (uint32_t)seed;
    r->key[1] = (uint32_t)(seed >> 32);
    r->ctr[0] = (uint32_t)unit;
    r->ctr[1] = (uint32_t)(unit >> 32);
    r->ctr[2] = stream;
    r->ctr[3] = 0;
    r->left = 0;
}

static uint32_t next_word(rng_stream *r)
{
    if (r->left == 0) {
        philox4x32_ctr_t c = {{r->ctr[0], r->ctr[1], r->ctr[2], r->ctr[3]}};
        philox4x32_key_t k = {{r->key[0], r->key[1]}};
        philox4x32_ctr_t out = philox4x32(c, k);
        for (int i = 0; i < 4; i++)
            r->buf[i] = out.v[i];
        r->ctr[3]++;
        r->left = 4;
    }
    return r->buf[4 - r->left--];
}

double rng_uniform(rng_stream *r)
{
    uint64_t hi = next_word(r) >> 5; /* 27 bits */
    uint64_t lo = next_word(r) >> 6; /* 26 bits */
    /* (k + 0.5) / 2^53 lies strictly inside (0, 1). */
    return ((double)((hi << 26) | lo) + 0.5) * 0x1.0p-53;
}

double rng_normal(rng_stream *r)
{
    double u1 = rng_uniform(r);
    double u2 = rng_uniform(r);
    return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}
