/* test_dss_kernels.c - the DSS unit's fast kernels (issue 27) against the
 * straightforward forms they replace: per-run tables and shared truth
 * vectors give the same bits; the tangent-space field-angle inversion
 * returns the angle the angle-form formulas put in; the warm-started
 * noise-free compensation lands on the truth; the fit started at the
 * damping floor lands on GSL's start's solution in fewer steps. */
#include "test_util.h"

#include "dss_calib.h"
#include "dss_model.h"
#include "optics.h"
#include "optics_lane.h"
#include "dss_score.h"
#include "dss_sensor.h"
#include "dss_unit.h"
#include "family.h"
#include "registry.h"
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
    dss_scurve_design(g, amp);
    dss_deviations d;
    dss_deviations_sample(&st.cfg, 1, 2, &d);
    dss_sensor a, b;
    dss_sensor_init(&a, g, &d, 1);
    dss_sensor_init_amp(&b, g, &d, 1, amp);
    assert_true(memcmp(&a, &b, sizeof a) == 0);
    assert_near(dss_spot_px(g), g->pinhole_um / g->pixel_um, 0.0);
    config_state_free(&st);
}


/* r of field angle th (rad) by the angle-form formulas of dss_sensor.h and
 * optics.h (not the tangent form the kernel is written in): the glass
 * formula f = (H - t) tan th + t sin th / sqrt(n^2 - sin^2 th) times the
 * sun disc's gain 1 + C d / q, f / s = (H - t) / c + t / g and
 * d = 2 (H - t) / c^3 + t ((1 - 2 n^2) / g^3 + 3 c^2 n^2 / g^5). */
static double forward_r(double th, double H, double t, double n, double C)
{
    double s = sin(th), c = cos(th), g = sqrt(n * n - s * s);
    double q = (H - t) / c + t / g;
    double d = 2.0 * (H - t) / (c * c * c) +
               t * ((1.0 - 2.0 * n * n) / (g * g * g) + 3.0 * c * c * n * n / pow(g, 5.0));
    return s * q * (1.0 + C * d / q);
}

/* The tangent-space inversion returns the angle the forward formula was
 * given, to 1e-14 rad, up to 80 deg, with and without glass and sun
 * disc; in at most 4 steps up to 60 deg from the paraxial start, and in at
 * most 2 from a start 1e-5 off (the warm start of the noise-free pass). */
static void test_field_tan_inverse(void **state)
{
    const double set[][4] = {{3.0, 0.4, 1.52, 0.0}, {3.0, 0.4, 1.52, 7.6e-5},
                             {2.0, 0.8, 1.8, 2e-5}, {3.0, 0.0, 1.5, 7.6e-5},
                             {3.0, 0.4, 1.0, 0.0}};
    _Alignas(VM_ALIGN) double r[64], th[64], T[64], sl[64], start[64];
    long failed[64];
    for (size_t k = 0; k < sizeof set / sizeof set[0]; k++) {
        double H = set[k][0], t = set[k][1], n = set[k][2], C = set[k][3];
        for (int part = 0; part < 2; part++) {
            double top = part ? 80.0 : 60.0;
            for (size_t i = 0; i < vm_pad(NK); i++) {
                th[i] = top * RAD_PER_DEG * (double)(i % NK + 1) / (double)NK;
                r[i] = forward_r(th[i], H, t, n, C);
            }
            int steps = dss_field_tan_chunk(NK, r, H, t, n, C, NULL, T, sl, failed);
            if (!part)
                assert_true(steps <= 4);
            for (size_t i = 0; i < vm_pad(NK); i++) {
                assert_int_equal(failed[i], 0);
                assert_near(atan(T[i]), th[i], 1e-14);
                start[i] = T[i] * (1.0 + 1e-5) + 1e-5;
                assert_true(sl[i] >= H - t);
            }
            assert_true(dss_field_tan_chunk(NK, r, H, t, n, C, start, T, NULL, failed) <= 2);
            for (size_t i = 0; i < NK; i++)
                assert_near(atan(T[i]), th[i], 1e-14);
        }
    }
}

/* Without the disc it agrees with the scalar Newton in the angle
 * (optics_field_angle); a start outside [0, tan 1.5] is replaced by the
 * paraxial one; a distance that is not finite fails at once with NaN; one
 * beyond the clamp fails. */
static void test_field_tan_edges(void **state)
{
    _Alignas(VM_ALIGN) double r[64], T[64], start[64];
    long failed[64];
    for (size_t i = 0; i < vm_pad(NK); i++) {
        r[i] = 5.0 * (double)(i % NK) / (double)NK;
        start[i] = (i % 2) ? -1.0 : 1e9;
    }
    dss_field_tan_chunk(NK, r, 3.0, 0.4, 1.52, 0.0, start, T, NULL, failed);
    for (size_t i = 0; i < NK; i++) {
        double ref;
        assert_int_equal(optics_field_angle(r[i], 3.0, 0.4, 1.52, &ref), SUNMC_OK);
        assert_int_equal(failed[i], 0);
        assert_near(atan(T[i]), ref, 1e-14);
    }
    assert_true(T[0] == 0.0); /* r = 0: on the axis, exactly */
    r[3] = NAN;
    r[5] = INFINITY;
    r[7] = 1e6;
    int steps = dss_field_tan_chunk(NK, r, 3.0, 0.4, 1.52, 0.0, NULL, T, NULL, failed);
    assert_true(isnan(T[3]) && isnan(T[5]));
    assert_int_equal(failed[3], 1);
    assert_int_equal(failed[5], 1);
    assert_int_equal(failed[7], 1);
    assert_int_equal(failed[8], 0);
    assert_int_equal(steps, OPTICS_FIELD_MAX_ITER);
}

/* A model with every parameter off nominal, as a fit leaves it. */
static void off_model(dss_model *m, int mount, double disc_c)
{
    config_state st;
    test_build(&st, "configs/dss.ini", NULL, 0);
    dss_design d = dss_cfg(&st.cfg)->design;
    d.mount = mount;
    dss_model_init(m, &d);
    const double v[DSS_NP] = {0.3, -0.2, 0.5, 8.0, 9.0, -7.0, 6.0, 0.004, 12.0, -9.0};
    for (int j = 0; j < DSS_NP; j++)
        dss_param_set(m, j, v[j]);
    m->disc_c_rad2 = disc_c;
    dss_model_prepare(m);
    config_state_free(&st);
}

/* The pair compensation: its noisy spots give the bits dss_model_compensate
 * gives; the noise-free ones, started from their noisy twins, give the
 * model's truth to 1e-13 rad (both mounts, with and without the disc). */
static void test_compensate_pair(void **state)
{
    enum { N = 2 * DSS_CHUNK + 5 };
    static double x[N], y[N], x0[N], y0[N], b1[N], b2[N];
    static double a[N], b[N], a0[N], b0[N];
    static int st[N], st0[N];
    for (int mount = DSS_MOUNT_ALIGNED; mount <= DSS_MOUNT_AS_MOUNTED; mount++)
        for (int disc = 0; disc < 2; disc++) {
            dss_model m;
            off_model(&m, mount, disc ? dss_disc_coefficient(2.0, 0.6) : 0.0);
            for (size_t i = 0; i < N; i++) {
                double sp[2];
                b1[i] = (-55.0 + 110.0 * (double)((i * 7) % N) / N) * RAD_PER_DEG;
                b2[i] = (-55.0 + 110.0 * (double)((i * 13) % N) / N) * RAD_PER_DEG;
                assert_int_equal(dss_model_spot(&m, b1[i], b2[i], sp, NULL), SUNMC_OK);
                x0[i] = sp[0];
                y0[i] = sp[1];
                x[i] = sp[0] + 0.01 * sin(3.0 * (double)i);
                y[i] = sp[1] - 0.01 * cos(5.0 * (double)i);
            }
            assert_int_equal(dss_model_compensate_pair_batch(&m, N, x, y, x0, y0, a, b, st, a0,
                                                             b0, st0),
                             SUNMC_OK);
            for (size_t i = 0; i < N; i++) {
                double as, bs, at, bt;
                assert_int_equal(dss_model_compensate(&m, x[i], y[i], &as, &bs), SUNMC_OK);
                assert_true(as == a[i] && bs == b[i]);
                dss_model_truth(&m, b1[i], b2[i], &at, &bt);
                assert_near(a0[i], at, 1e-13);
                assert_near(b0[i], bt, 1e-13);
                assert_true(fabs(a[i] - at) > 1e-9); /* the noise is seen */
            }
        }
}

/* The physical fit from the nominal design at the damping floor (the DSS
 * fit's mu0) reaches GSL's start's solution in fewer steps: the same
 * parameters to 1e-5 (px, um, arcsec; 1e-8 in the index) and cost to
 * 1e-9 of it, in at most 3 iterations where GSL's start takes at least 4. */
static void test_fit_floor_start(void **state)
{
    config_state st;
    test_build(&st, "configs/dss.ini", NULL, 0);
    const sunmc_config *c = &st.cfg;
    const dss_config *dc = dss_cfg(c);
    size_t n = dss_campaign_size(c);
    dss_calib_workspace *cw = dss_calib_alloc_config(dc, n);
    assert_non_null(cw);
    for (long unit = 0; unit < 6; unit++) {
        dss_deviations d;
        dss_unit u;
        dss_deviations_sample(c, (uint64_t)c->seed, unit, &d);
        dss_unit_build(c, &d, &u);
        dss_unit_campaign(c, &u, unit, cw->b1_rad, cw->b2_rad, cw->x_px, cw->y_px, cw->weight,
                          NULL, NULL);
        dss_calibration cal[2];
        fit_result fr[2];
        const double mu0[2] = {cw->fw->mu0, 1e-3};
        for (int k = 0; k < 2; k++) {
            cw->fw->mu0 = mu0[k];
            assert_int_equal(dss_calibrate(cw, c->max_iterations, &cal[k], &fr[k]), SUNMC_OK);
        }
        cw->fw->mu0 = mu0[0];
        assert_true(mu0[0] <= 1e-7);
        assert_true(fr[0].iterations <= 3);
        assert_true(fr[1].iterations >= 4);
        assert_near(fr[0].chisq, fr[1].chisq, 1e-9 * fr[1].chisq);
        for (int j = 0; j < DSS_NP; j++)
            assert_near(dss_param_value(&cal[0].phys, j), dss_param_value(&cal[1].phys, j),
                        j == DSS_P_N ? 1e-8 : 1e-5);
    }
    dss_calib_free(cw);
    config_state_free(&st);
}

/* One unit scored with report bands `bands`: its RMS before, after and
 * systematic in the band at index `at` (all three angles). */
static void score_band(const char *bands, int at, double out[3][3])
{
    config_state st;
    char set[128], err[SUNMC_ERRLEN];
    snprintf(set, sizeof set, "report.bands_deg=%s", bands);
    const char *sets[] = {set, "validation.b_step_deg=6"};
    test_build(&st, "configs/dss.ini", sets, 2);
    const sensor_family *fam = sensor_family_find("dss");
    assert_non_null(fam);
    void *ws = fam->workspace_alloc(&st.cfg, err, sizeof err);
    assert_non_null(ws);
    static unit_result res;
    assert_int_equal(fam->unit_run(&st.cfg, 3, ws, &res), SUNMC_OK);
    assert_int_equal(res.fit_status, UNIT_FIT_OK);
    for (int a = 0; a < 3; a++) {
        out[a][0] = res.rms_before[a][at];
        out[a][1] = res.rms_after[a][at];
        out[a][2] = res.rms_after_sys[a][at];
    }
    fam->workspace_free(ws);
    config_state_free(&st);
}

/* The band sums go a chunk at a time (three bands in registers, any other
 * count by a loop): a band's RMS is the same bits whichever bands are
 * listed with it, and the bands nest as sums of squares do. */
static void test_band_sums_same_bits(void **state)
{
    double one[3][3], three[3][3], four[3][3];
    score_band("0:60", 0, one);
    score_band("0:20, 20:40, 0:60", 2, three);
    score_band("0:10, 10:30, 30:60, 0:60", 3, four);
    assert_true(memcmp(one, three, sizeof one) == 0);
    assert_true(memcmp(one, four, sizeof one) == 0);
    /* 0:60 is the union of 0:10, 10:30 and 30:60: its mean square lies
     * between theirs */
    double part[3][3][3];
    for (int b = 0; b < 3; b++)
        score_band("0:10, 10:30, 30:60, 0:60", b, part[b]);
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++) {
            double lo = fmin(part[0][a][k], fmin(part[1][a][k], part[2][a][k]));
            double hi = fmax(part[0][a][k], fmax(part[1][a][k], part[2][a][k]));
            assert_true(one[a][k] > 0.0 && isfinite(one[a][k]));
            assert_true(one[a][k] >= lo * (1.0 - 1e-12) && one[a][k] <= hi * (1.0 + 1e-12));
            assert_true(lo < hi);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_truth_trig_same_bits),
        cmocka_unit_test(test_validation_trig_same_bits),
        cmocka_unit_test(test_truth_vector_same_bits),
        cmocka_unit_test(test_sensor_amp_same),
        cmocka_unit_test(test_field_tan_inverse),
        cmocka_unit_test(test_field_tan_edges),
        cmocka_unit_test(test_compensate_pair),
        cmocka_unit_test(test_fit_floor_start),
        cmocka_unit_test(test_band_sums_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
