/* rng.c - Philox4x32-10 streams over Random123's philox.h. */
#include "rng.h"
#include "vmath.h"

#include <Random123/philox.h>
#include <string.h>

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
    r->spare = 0.0;
    r->has_spare = 0;
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

/* Uniform in (0, 1) from two words, 53 random bits. */
static double uniform_of(uint32_t hi_word, uint32_t lo_word)
{
    uint64_t hi = hi_word >> 5, lo = lo_word >> 6;
    return ((double)((hi << 26) | lo) + 0.5) * 0x1.0p-53;
}

double rng_uniform(rng_stream *r)
{
    /* 27 + 26 bits; (k + 0.5) / 2^53 lies strictly inside (0, 1). */
    uint32_t hi = next_word(r);
    return uniform_of(hi, next_word(r));
}

#if defined(VM_LIBMVEC)
#include <immintrin.h>
#define PHILOX_AVX2 1

/* The same blocks eight at a time with AVX2 (an x86-64-v3 CPU): GCC's
 * vectorisation of the loop below widens the 32-bit lanes for each
 * 32 x 32 -> 64-bit product with shuffles; here the products of the even
 * and of the odd lanes are two vpmuludq and the high and low words are
 * blended back.  Integer arithmetic: the same words as the loop, bit for
 * bit (test_rng checks Random123's known answers). */
__attribute__((target("avx2"))) VM_NOSAN static void
philox_blocks_avx2(const uint32_t key[2], const uint32_t ctr[4], size_t nb,
                   uint32_t w[4][NORMAL_CHUNK])
{
    const __m256i m0 = _mm256_set1_epi64x(0xD2511F53), m1 = _mm256_set1_epi64x(0xCD9E8D57);
    const __m256i w0 = _mm256_set1_epi32((int)0x9E3779B9u), w1 = _mm256_set1_epi32((int)0xBB67AE85u);
    for (size_t b0 = 0; b0 < vm_pad(nb); b0 += 8) {
        __m256i x0 = _mm256_set1_epi32((int)ctr[0]), x1 = _mm256_set1_epi32((int)ctr[1]);
        __m256i x2 = _mm256_set1_epi32((int)ctr[2]);
        __m256i x3 = _mm256_add_epi32(_mm256_set1_epi32((int)(ctr[3] + (uint32_t)b0)),
                                      _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
        __m256i k0 = _mm256_set1_epi32((int)key[0]), k1 = _mm256_set1_epi32((int)key[1]);
        for (int round = 0; round < 10; round++) {
            __m256i e0 = _mm256_mul_epu32(x0, m0), o0 = _mm256_mul_epu32(_mm256_srli_epi64(x0, 32), m0);
            __m256i e1 = _mm256_mul_epu32(x2, m1), o1 = _mm256_mul_epu32(_mm256_srli_epi64(x2, 32), m1);
            __m256i lo0 = _mm256_blend_epi32(e0, _mm256_slli_epi64(o0, 32), 0xAA);
            __m256i hi0 = _mm256_blend_epi32(_mm256_srli_epi64(e0, 32), o0, 0xAA);
            __m256i lo1 = _mm256_blend_epi32(e1, _mm256_slli_epi64(o1, 32), 0xAA);
            __m256i hi1 = _mm256_blend_epi32(_mm256_srli_epi64(e1, 32), o1, 0xAA);
            x0 = _mm256_xor_si256(_mm256_xor_si256(hi1, x1), k0);
            x2 = _mm256_xor_si256(_mm256_xor_si256(hi0, x3), k1);
            x1 = lo1;
            x3 = lo0;
            k0 = _mm256_add_epi32(k0, w0);
            k1 = _mm256_add_epi32(k1, w1);
        }
        _mm256_storeu_si256((__m256i *)(w[0] + b0), x0);
        _mm256_storeu_si256((__m256i *)(w[1] + b0), x1);
        _mm256_storeu_si256((__m256i *)(w[2] + b0), x2);
        _mm256_storeu_si256((__m256i *)(w[3] + b0), x3);
    }
}
#endif

/* Philox4x32-10 (Random123's philox4x32, written out so that GCC
 * vectorises it over counters): word j of block counter (c0, c1, c2,
 * c3 + b) for b < vm_pad(nb) <= NORMAL_CHUNK into w[j][b]. */
VM_KERNEL static void philox_blocks_generic(const uint32_t key[2], const uint32_t ctr[4], size_t nb,
                                    uint32_t w[4][NORMAL_CHUNK])
{
    uint32_t c0 = ctr[0], c1 = ctr[1], c2 = ctr[2], c3 = ctr[3], key0 = key[0], key1 = key[1];
    uint32_t *restrict w0 = w[0], *restrict w1 = w[1], *restrict w2 = w[2], *restrict w3 = w[3];
    VM_SIMD for (uint32_t b = 0; b < (uint32_t)vm_pad(nb); b++) {
        uint32_t x0 = c0, x1 = c1, x2 = c2, x3 = c3 + b, k0 = key0, k1 = key1;
        for (int round = 0; round < 10; round++) {
            uint64_t p0 = (uint64_t)x0 * 0xD2511F53u, p1 = (uint64_t)x2 * 0xCD9E8D57u;
            uint32_t y0 = (uint32_t)(p1 >> 32) ^ x1 ^ k0, y2 = (uint32_t)(p0 >> 32) ^ x3 ^ k1;
            x1 = (uint32_t)p1;
            x3 = (uint32_t)p0;
            x0 = y0;
            x2 = y2;
            k0 += 0x9E3779B9u;
            k1 += 0xBB67AE85u;
        }
        w0[b] = x0;
        w1[b] = x1;
        w2[b] = x2;
        w3[b] = x3;
    }
}

static void philox_blocks(const uint32_t key[2], const uint32_t ctr[4], size_t nb,
                          uint32_t w[4][NORMAL_CHUNK])
{
#ifdef PHILOX_AVX2
    if (__builtin_cpu_supports("avx2")) {
        philox_blocks_avx2(key, ctr, nb, w);
        return;
    }
#endif
    philox_blocks_generic(key, ctr, nb, w);
}

/* Box-Muller on one block's words w0..w3: two uniforms as rng_uniform
 * makes them (27 + 26 bits, (m + 0.5) / 2^53, exact in doubles), u1 from
 * words 0 and 1, u2 from 2 and 3, and both normals of the pair, r cos(2 pi
 * u2) and r sin(2 pi u2) (r = sqrt(-2 ln u1)). */
typedef struct {
    double c, s;
} normal_pair;

VM_INLINE normal_pair box_muller_lane(uint32_t w0, uint32_t w1, uint32_t w2, uint32_t w3)
{
    double u1 = ((double)(int32_t)(w0 >> 5) * 0x1.0p26 + (double)(int32_t)(w1 >> 6) + 0.5) *
                0x1.0p-53;
    double u2 = ((double)(int32_t)(w2 >> 5) * 0x1.0p26 + (double)(int32_t)(w3 >> 6) + 0.5) *
                0x1.0p-53;
    double radius = sqrt(-2.0 * log(u1)), angle = 2.0 * M_PI * u2;
    normal_pair p = {radius * cos(angle), radius * sin(angle)};
    return p;
}

/* Box-Muller on k <= NORMAL_CHUNK blocks' words w[0..3][i]: block i's
 * pair into c[i] and s[i], padded to VM_PAD lanes. */
VM_KERNEL static void box_muller(size_t k, const uint32_t w[4][NORMAL_CHUNK], double *restrict c,
                                 double *restrict s)
{
    const uint32_t *w0 = w[0], *w1 = w[1], *w2 = w[2], *w3 = w[3];
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        normal_pair p = box_muller_lane(w0[i], w1[i], w2[i], w3[i]);
        c[i] = p.c;
        s[i] = p.s;
    }
}

/* The same into out[2 i] and out[2 i + 1] (k a multiple of VM_PAD: no
 * padding lanes, out holds 2 k): the stream's order, no copy. */
VM_KERNEL static void box_muller_pairs(size_t k, const uint32_t w[4][NORMAL_CHUNK],
                                       double *restrict out)
{
    const uint32_t *w0 = w[0], *w1 = w[1], *w2 = w[2], *w3 = w[3];
    VM_SIMD for (size_t i = 0; i < k; i++) {
        normal_pair p = box_muller_lane(w0[i], w1[i], w2[i], w3[i]);
        out[2 * i] = p.c;
        out[2 * i + 1] = p.s;
    }
}

/* The words of the next k <= NORMAL_CHUNK normals of r into w[j][i] (word
 * 4 i + j of the stream from here): what is left of the current block,
 * then whole blocks; the last block's unused words stay in r's buffer,
 * exactly as next_word would leave them.  Lanes from k to vm_pad(k) get
 * words too (never used as draws). */
static void next_words(rng_stream *r, size_t k, uint32_t w[4][NORMAL_CHUNK])
{
    /* 0 <= lead <= 3 words of the current block are still to come; they
     * and k - 1 whole blocks plus 4 - lead words of one more make the 4 k,
     * so k blocks are drawn and the misalignment (lead) stays */
    _Alignas(VM_ALIGN) uint32_t b[4][NORMAL_CHUNK];
    size_t lead = (size_t)r->left;
    philox_blocks(r->key, r->ctr, k, lead == 0 ? w : b);
    if (lead > 0)
        for (size_t t = 0; t < 4 * vm_pad(k); t++) {
            size_t u = t - lead; /* block word, for t >= lead */
            w[t % 4][t / 4] = t < lead ? r->buf[4 - lead + t] : b[u % 4][u / 4];
        }
    for (int j = 0; j < 4; j++)
        r->buf[j] = lead == 0 ? w[j][k - 1] : b[j][k - 1];
    r->ctr[3] += (uint32_t)k;
}

/* Normals come in pairs, both of one block's Box-Muller: normal 2 j of
 * the pairs drawn from a point of the stream is block j's cosine, 2 j + 1
 * its sine.  A fill of odd length keeps the last sine as the stream's
 * spare, which the next normal returns, so a sequence of normals is the
 * same however it is split into fills (uniforms in between take the
 * words after the last block and leave the spare alone). */
void rng_normal_fill(rng_stream *r, double *out, size_t n)
{
    _Alignas(VM_ALIGN) uint32_t w[4][NORMAL_CHUNK];
    _Alignas(VM_ALIGN) double c[NORMAL_CHUNK], s[NORMAL_CHUNK];
    size_t done = 0;
    if (n > 0 && r->has_spare) {
        out[done++] = r->spare;
        r->has_spare = 0;
    }
    while (done < n) {
        size_t pairs = (n - done + 1) / 2;
        size_t k = pairs < NORMAL_CHUNK ? pairs : NORMAL_CHUNK;
        next_words(r, k, w);
        if (k % VM_PAD == 0 && 2 * k <= n - done) {
            /* whole pairs, no padding lanes: straight into out */
            box_muller_pairs(k, w, out + done);
            done += 2 * k;
            continue;
        }
        box_muller(k, w, c, s);
        for (size_t i = 0; i < k; i++) {
            out[done++] = c[i];
            if (done == n) {
                r->spare = s[i];
                r->has_spare = 1;
                break;
            }
            out[done++] = s[i];
        }
    }
}

double rng_normal(rng_stream *r)
{
    double z;
    rng_normal_fill(r, &z, 1);
    return z;
}
