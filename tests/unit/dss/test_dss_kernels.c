/* test_dss_kernels.c - the DSS unit's fast kernels (issue 27) against the
 * straightforward forms they replace: per-run tables and shared truth
 * vectors give the same bits; the tangent-space field-angle inversion
 * returns the angle a forward trace put in. */
#include "test_util.h"

#include "dss_model.h"
#include "dss_score.h"
#include "dss_sensor.h"
#include "dss_unit.h"
#include "family.h"
#include "rng.h"
#include "units.h"
#include "vmath.h"

#define NK 37 /* a chunk's worth of points, not a multiple of the pad */

/* Table angles over +-70 deg, both axes, irregular. */
static void test_angles(double *b1, double *b2, size_t n)
{
    for (size_t i = 0; i < vm_pad(n); i++) {
        b1[i] = (-70.0 + 140.0 * (double)((i * 7) % n) / (double)n) * RAD_PER_DEG;
        b2[i] = (-65.0 + 131.0 * (double)((i * 11) % n) / (double)n) * RAD_PER_DEG;
    }
}

static int same_bits(const double *a, const double *b, size_t n)
{
    return memcmp(a, b, n * sizeof *a) == 0;
}

/* dss_truth_batch_trig on dss_trig_fill's table = dss_truth_batch, bit for
 * bit, in both mount modes. */
static void test_truth_trig_same_bits(void **state)
{
    _Alignas(VM_ALIGN) double b1[64], b2[64], c1[64], s1[64], c2[64], s2[64];
    _Alignas(VM_ALIGN) double a[64], b[64], at[64], bt[64];
    double *const trig[4] = {c1, s1, c2, s2};
    double v[3] = {0.01, -0.02, 0.0};
    v[2] = sqrt(1.0 - v[0] * v[0] - v[1] * v[1]);
    test_angles(b1, b2, NK);
    dss_trig_fill(NK, b1, b2, trig);
    for (int mount = DSS_MOUNT_ALIGNED; mount <= DSS_MOUNT_AS_MOUNTED; mount++) {
        dss_truth_batch(mount, v, NK, b1, b2, a, b);
        dss_truth_batch_trig(mount, v, NK, b1, b2, c1, s1, c2, s2, at, bt);
        assert_true(same_bits(a, at, NK));
        assert_true(same_bits(b, bt, NK));
    }
    /* and the two modes differ (the test can see a swapped branch) */
    dss_truth_batch_trig(DSS_MOUNT_ALIGNED, v, NK, b1, b2, c1, s1, c2, s2, a, b);
    assert_false(same_bits(a, at, NK));
    assert_near(a[3], -b2[3], 0.0);
    assert_near(b[3], atan(tan(b1[3]) / cos(b2[3])), 1e-15);
}

/* The validation readings from the per-run table = from the angles. */
static void test_validation_trig_same_bits(void **state)
{
    config_state st;
    test_build(&st, "configs/dss.ini", NULL, 0);
    const sunmc_config *c = &st.cfg;
    _Alignas(VM_ALIGN) double b1[2 * DSS_CHUNK], b2[2 * DSS_CHUNK];
    _Alignas(VM_ALIGN) double c1[2 * DSS_CHUNK], s1[2 * DSS_CHUNK], c2[2 * DSS_CHUNK],
        s2[2 * DSS_CHUNK];
    double *const trig[4] = {c1, s1, c2, s2};
    const double *const ctrig[4] = {c1, s1, c2, s2};
    enum { N = DSS_CHUNK + NK };
    test_angles(b1, b2, N);
    dss_trig_fill(N, b1, b2, trig);
    dss_deviations d;
    dss_unit u;
    dss_deviations_sample(c, (uint64_t)c->seed, 4, &d);
    dss_unit_build(c, &d, &u);
    static dss_validation_point p[N], q[N];
    rng_stream r;
    unit_stream_init(&r, c, 4, RNG_STREAM_VAL_NOISE);
    dss_validation_batch(c, &u, &r, N, b1, b2, p);
    unit_stream_init(&r, c, 4, RNG_STREAM_VAL_NOISE);
    dss_validation_batch_trig(c, &u, &r, N, b1, b2, ctrig, q);
    int seen = 0;
    for (size_t i = 0; i < N; i++) {
        assert_int_equal(p[i].seen, q[i].seen);
        seen += p[i].seen;
        if (!p[i].seen)
            continue;
        double a[6] = {p[i].x_px, p[i].y_px, p[i].x0_px, p[i].y0_px, p[i].alpha0_rad,
                       p[i].beta0_rad};
        double b[6] = {q[i].x_px, q[i].y_px, q[i].x0_px, q[i].y0_px, q[i].alpha0_rad,
                       q[i].beta0_rad};
        assert_true(same_bits(a, b, 6));
    }
    assert_true(seen > N / 3);
    config_state_free(&st);
}

/* The truth's vector and field angle made once = the per-scoring forms. */
static void test_truth_vector_same_bits(void **state)
{
    _Alignas(VM_ALIGN) double a0[64], b0[64], a[64], b[64], vx[64], vy[64], vz[64];
    _Alignas(VM_ALIGN) double f1[64], f2[64], t1[64], t2[64];
    test_angles(a0, b0, NK);
    for (size_t i = 0; i < vm_pad(NK); i++) {
        a0[i] *= 0.8;
        b0[i] *= 0.8;
        a[i] = a0[i] + 1e-5 * sin((double)i);
        b[i] = b0[i] - 2e-5 * cos((double)i);
    }
    dss_field_chunk(NK, a0, b0, f1);
    dss_truth_vector_chunk(NK, a0, b0, vx, vy, vz, f2);
    assert_true(same_bits(f1, f2, NK));
    dss_total_error_chunk(NK, a, b, a0, b0, t1);
    dss_total_error_vec_chunk(NK, a, b, vx, vy, vz, t2);
    assert_true(same_bits(t1, t2, NK));
    for (size_t i = 0; i < NK; i++) {
        assert_near(vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i], 1.0, 1e-15);
        assert_near(vx[i] / vz[i], tan(a0[i]), 1e-12 * (1.0 + fabs(tan(a0[i]))));
        assert_true(t2[i] > 0.0 && t2[i] < 3e-5);
    }
}

/* A sensor built with the run's S-curve amplitudes = one that makes its
 * own. */
static void test_sensor_amp_same(void **state)
{
    config_state st;
    test_build(&st, "configs/dss.ini", NULL, 0);
    const dss_design *g = &dss_cfg(&st.cfg)->design;
    double amp[DSS_SCURVE_HARMONICS];
    dss_scurve_amplitudes(dss_spot_px(g), amp);
    dss_deviations d;
    dss_deviations_sample(&st.cfg, 1, 2, &d);
    dss_sensor a, b;
    dss_sensor_init(&a, g, &d, 1);
    dss_sensor_init_amp(&b, g, &d, 1, amp);
    assert_true(memcmp(&a, &b, sizeof a) == 0);
    assert_near(dss_spot_px(g), g->pinhole_um / g->pixel_um, 0.0);
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_truth_trig_same_bits),
        cmocka_unit_test(test_validation_trig_same_bits),
        cmocka_unit_test(test_truth_vector_same_bits),
        cmocka_unit_test(test_sensor_amp_same),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
