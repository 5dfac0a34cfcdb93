/* test_rng.c - Philox streams, tolerance distributions and rotations. */
#include "test_util.h"

#include "config.h"
#include "rng.h"
#include "rotation.h"
#include "tolerance.h"
#include "units.h"

/* Known answer: Philox4x32-10 with key 0 and counter 0 gives the words
 * 6627e8d5 e169c58d bc57ac4c 9b00dbd8 (Random123 kat_vectors); our first
 * uniform is built from the first two words as (hi>>5 <<26 | lo>>6 + 0.5)/2^53. */
static void test_philox_known_answer(void **state)
{
    rng_stream r;
    rng_stream_init(&r, 0, 0, 0);
    uint64_t hi = 0x6627e8d5u >> 5, lo = 0xe169c58du >> 6;
    double expect = ((double)((hi << 26) | lo) + 0.5) / 9007199254740992.0;
    assert_near(rng_uniform(&r), expect, 0);
}

/* Draws depend only on (seed, unit, stream): any order gives the same. */
static void test_streams_independent_of_order(void **state)
{
    double fwd[50], back[50];
    for (int u = 0; u < 50; u++) {
        rng_stream r;
        rng_stream_init(&r, 42, (uint64_t)u, 7);
        fwd[u] = rng_normal(&r);
    }
    for (int u = 49; u >= 0; u--) {
        rng_stream r;
        rng_stream_init(&r, 42, (uint64_t)u, 7);
        back[u] = rng_normal(&r);
    }
    assert_memory_equal(fwd, back, sizeof fwd);
    rng_stream a, b;
    rng_stream_init(&a, 42, 3, 7);
    rng_stream_init(&b, 42, 3, 8);
    assert_true(rng_uniform(&a) != rng_uniform(&b));
}

/* Box-Muller's normal i from a stream's uniforms: pair i / 2 takes two,
 * the even normal is the cosine, the odd one the sine. */
static void box_muller_of_uniforms(rng_stream *u, int n, double *z)
{
    for (int i = 0; i < n; i += 2) {
        double u1 = rng_uniform(u), u2 = rng_uniform(u);
        z[i] = sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
        if (i + 1 < n)
            z[i + 1] = sqrt(-2.0 * log(u1)) * sin(2.0 * M_PI * u2);
    }
}

/* rng_normal_fill gives exactly the draws of as many rng_normal calls, in
 * any split of the sequence (odd parts leave the pair's sine as the
 * stream's spare; every draw takes the same vector code). */
static void test_normal_fill_equals_single_draws(void **state)
{
    enum { N = 301 };
    double one[N], all[N], parts[N], ref[N];
    rng_stream a, b, c;
    rng_stream_init(&a, 9, 4, 0x200);
    rng_stream_init(&b, 9, 4, 0x200);
    rng_stream_init(&c, 9, 4, 0x200);
    for (int i = 0; i < N; i++)
        one[i] = rng_normal(&a);
    rng_normal_fill(&b, all, N);
    rng_normal_fill(&c, parts, 5);
    rng_normal_fill(&c, parts + 5, 130);
    rng_normal_fill(&c, parts + 135, 1);
    rng_normal_fill(&c, parts + 136, 0);
    rng_normal_fill(&c, parts + 136, N - 136);
    assert_memory_equal(one, all, sizeof one);
    assert_memory_equal(one, parts, sizeof one);
    /* Box-Muller of the stream's uniforms, both of each pair, to the last
     * few bits */
    rng_stream u;
    rng_stream_init(&u, 9, 4, 0x200);
    box_muller_of_uniforms(&u, N, ref);
    for (int i = 0; i < N; i++)
        assert_near(one[i], ref[i], 1e-14);
    /* a stream left mid-block by a uniform: the fill takes the same words,
     * and leaves the stream where single draws would; a uniform between
     * the two normals of a pair takes the words after the pair's */
    rng_stream d, e;
    rng_stream_init(&d, 9, 5, 0x201);
    rng_stream_init(&e, 9, 5, 0x201);
    assert_true(rng_uniform(&d) == rng_uniform(&e));
    rng_normal_fill(&d, all, 37);
    box_muller_of_uniforms(&e, 38, ref);
    for (int i = 0; i < 37; i++)
        assert_near(all[i], ref[i], 1e-14);
    assert_true(rng_uniform(&d) == rng_uniform(&e));
    assert_near(rng_normal(&d), ref[37], 1e-14);
    assert_true(rng_uniform(&d) == rng_uniform(&e));
    assert_true(rng_uniform(&d) == rng_uniform(&e));
}

/* The two normals of a pair are independent standard normals: their
 * squares sum to twice an Exp(1) (P(z0^2 + z1^2 > 2 t) = e^-t), and
 * they do not correlate, nor do their squares. */
static void test_normal_pairs_independent(void **state)
{
    enum { N = 200000 };
    rng_stream r;
    rng_stream_init(&r, 3, 1, 0x200);
    double s01 = 0, s00 = 0, s11 = 0, q01 = 0, q0 = 0, q1 = 0;
    int over = 0;
    for (int i = 0; i < N; i++) {
        double z[2];
        rng_normal_fill(&r, z, 2);
        s00 += z[0] * z[0];
        s11 += z[1] * z[1];
        s01 += z[0] * z[1];
        q01 += z[0] * z[0] * z[1] * z[1];
        q0 += z[0] * z[0];
        q1 += z[1] * z[1];
        over += z[0] * z[0] + z[1] * z[1] > 2.0;
    }
    /* sd of a mean of N products of independent normals: 1 / sqrt(N) = 0.0022 */
    assert_near(s01 / N, 0, 0.01);
    assert_near(s00 / N, 1, 0.01);
    assert_near(s11 / N, 1, 0.01);
    /* E z0^2 z1^2 = 1 for independent ones (sd of the mean 3 / sqrt(N)) */
    assert_near(q01 / N - (q0 / N) * (q1 / N), 0, 0.03);
    /* e^-1 = 0.3679, sd of the fraction 0.0011 */
    assert_near((double)over / N, exp(-1.0), 0.005);
}

/* Moments of 200000 draws (fixed seed: deterministic). */
static void test_moments(void **state)
{
    rng_stream r;
    rng_stream_init(&r, 1, 0, 0);
    const int n = 200000;
    double su = 0, sn = 0, sn2 = 0, umin = 1, umax = 0;
    for (int i = 0; i < n; i++) {
        double u = rng_uniform(&r), z = rng_normal(&r);
        su += u;
        umin = fmin(umin, u);
        umax = fmax(umax, u);
        sn += z;
        sn2 += z * z;
    }
    assert_near(su / n, 0.5, 0.003);
    assert_true(umin > 0 && umax < 1);
    assert_near(sn / n, 0, 0.01);
    assert_near(sn2 / n, 1, 0.01);
}

static void test_tolerance_distributions(void **state)
{
    rng_stream r;
    rng_stream_init(&r, 5, 0, 0);
    tolerance fixed = {2.5, DIST_FIXED}, uni = {2, DIST_UNIFORM}, nor = {1.5, DIST_NORMAL},
              tn = {1, DIST_TRUNCNORMAL};
    double s2 = 0, tmax = 0, umax = 0;
    const int n = 100000;
    for (int i = 0; i < n; i++) {
        assert_near(tolerance_draw(&fixed, 3, &r), 2.5, 0);
        double u = tolerance_draw(&uni, 3, &r);
        assert_true(fabs(u) <= 2);
        umax = fmax(umax, fabs(u));
        double z = tolerance_draw(&nor, 3, &r);
        s2 += z * z;
        double t = tolerance_draw(&tn, 2, &r);
        assert_true(fabs(t) <= 2);
        tmax = fmax(tmax, fabs(t));
    }
    assert_true(umax > 1.99);
    assert_near(sqrt(s2 / n), 1.5, 0.015);
    assert_true(tmax > 1.95); /* reaches the cut */
}

static void test_rotations(void **state)
{
    mat3 r, rt, p, d;
    double a = 0.3;
    void (*rots[3])(double, mat3) = {rot_x, rot_y, rot_z};
    void (*drots[3])(double, mat3) = {drot_x, drot_y, drot_z};
    for (int k = 0; k < 3; k++) {
        rots[k](a, r);
        mat3_transpose(r, rt);
        mat3_mul(r, rt, p);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                assert_near(p[i][j], i == j, 1e-15);
        /* derivative by central difference */
        mat3 rp, rm;
        rots[k](a + 1e-6, rp);
        rots[k](a - 1e-6, rm);
        drots[k](a, d);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                assert_near(d[i][j], (rp[i][j] - rm[i][j]) / 2e-6, 1e-9);
    }
    /* passive: rot_y(a) (0,0,1) = (-sin a, 0, cos a), so
     * rot_x(alpha) rot_y(-beta) (0,0,1) = (sin b, cos b sin a, cos b cos a) */
    double v[3] = {0, 0, 1}, w[3];
    mat3 rx, ry, m;
    rot_y(0.3, ry);
    mat3_vec(ry, v, w);
    assert_near(w[0], -sin(0.3), 1e-15);
    assert_near(w[2], cos(0.3), 1e-15);
    rot_x(0.4, rx);
    rot_y(0.2, ry);
    mat3_mul(rx, ry, m);
    mat3_vec(m, v, w);
    assert_near(w[0], sin(-0.2), 1e-15);
    assert_near(w[1], cos(-0.2) * sin(0.4), 1e-15);
    assert_near(w[2], cos(-0.2) * cos(0.4), 1e-15);
    sun_direction(0.1, 0.2, w);
    assert_near(w[0] * w[0] + w[1] * w[1] + w[2] * w[2], 1, 1e-15);
    assert_near(atan2(w[1], w[2] / cos(0.1)), 0.2, 1e-15);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_philox_known_answer), cmocka_unit_test(test_streams_independent_of_order),
        cmocka_unit_test(test_normal_fill_equals_single_draws),
        cmocka_unit_test(test_normal_pairs_independent),
        cmocka_unit_test(test_moments),             cmocka_unit_test(test_tolerance_distributions),
        cmocka_unit_test(test_rotations),
    };
    return cmocka_run_group_tests_name("rng_rotation", tests, NULL, NULL);
}
