/* rng.c - Philox4x32-10 streams over Random123's philox.h. */
#include "rng.h"
#include "vmath.h"

#include <Random123/philox.h>

/* Normals made per vectorised pass of rng_normal_fill. */
#define NORMAL_CHUNK 64

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

/* Box-Muller on n <= NORMAL_CHUNK uniform pairs, padded to VM_PAD lanes
 * (pads are 0.5) so every draw takes the same vector code. */
VM_KERNEL static void box_muller(size_t n, double *restrict u1, double *restrict u2,
                                 double *restrict out)
{
    size_t np = vm_pad(n);
    for (size_t i = n; i < np; i++)
        u1[i] = u2[i] = 0.5;
    VM_SIMD for (size_t i = 0; i < np; i++)
        out[i] = sqrt(-2.0 * log(u1[i])) * cos(2.0 * M_PI * u2[i]);
}

void rng_normal_fill(rng_stream *r, double *out, size_t n)
{
    _Alignas(VM_ALIGN) double u1[NORMAL_CHUNK], u2[NORMAL_CHUNK], z[NORMAL_CHUNK];
    for (size_t done = 0; done < n;) {
        size_t k = n - done < NORMAL_CHUNK ? n - done : NORMAL_CHUNK;
        for (size_t i = 0; i < k; i++) {
            u1[i] = rng_uniform(r);
            u2[i] = rng_uniform(r);
        }
        box_muller(k, u1, u2, z);
        for (size_t i = 0; i < k; i++)
            out[done + i] = z[i];
        done += k;
    }
}

double rng_normal(rng_stream *r)
{
    double z;
    rng_normal_fill(r, &z, 1);
    return z;
}
