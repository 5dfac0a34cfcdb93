/* test_psd_edges.c - the four-channel sensor where mistakes hide (issue 43),
 * each against a computation made here:
 *  - a lateral PSD's spot leaving the active area in x, in y and at a
 *    corner: the ratios are the centroid of the light left on the area and
 *    the sum its lit share, against a midpoint integration of the disc over
 *    the square done in the test;
 *  - the 20-term polynomial (calibration.poly_form = fss20): exactly the
 *    terms x^i y^j with i + j <= 5 but x^2 y^2, and the full form all 21;
 *  - the repeatability: rows about their point's mean, per axis, with
 *    n - 1 per point, against a hand computation on a small table;
 *  - the validation grid: -alpha_max + alpha_offset + i step, as many
 *    points as fit within +alpha_max, for offsets at both ends of the key;
 *    the campaign's rows: campaign.repeats readings per point, in turn;
 *  - weights are precisions: the polynomial fit with a row of weight 3 is
 *    the fit with that row three times;
 *  - a lab's points are its distinct (alpha, beta) pairs, and the report's
 *    repeatability of a point's mean is a row's over sqrt(rows per point). */
#include "test_util.h"

#include "psd_config.h"
#include "psd_lab.h"
#include "psd_model.h"
#include "psd_sensor.h"
#include "psd_unit.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

static psd_design duo_design(void)
{
    psd_design d;
    memset(&d, 0, sizeof d);
    d.detector = PSD_LATERAL;
    d.lateral = PSD_DUO;
    d.h_mm = 4;
    d.active_mm = 9;
    d.aperture_um = 500;
    d.glass_index = 1.5;
    d.fov_deg = 45;
    d.polarity = PSD_POSITIVE;
    d.signal_fs = 1;
    return d;
}

/* The disc of radius R at spot over the square |x|, |y| <= L2, by the
 * midpoint rule on an N x N grid over the disc's box: lit share, and the
 * light's centroid in units of L2. */
static void integrate(double R, double L2, const double spot[2], double *share, double *X,
                      double *Y)
{
    const long N = 2400;
    double cell = 2 * R / (double)N, a = 0, sx = 0, sy = 0;
    for (long i = 0; i < N; i++) {
        double x = spot[0] - R + (i + 0.5) * cell;
        if (fabs(x) > L2)
            continue;
        for (long j = 0; j < N; j++) {
            double y = spot[1] - R + (j + 0.5) * cell;
            double dx = x - spot[0], dy = y - spot[1];
            if (fabs(y) <= L2 && dx * dx + dy * dy <= R * R) {
                a += 1;
                sx += x;
                sy += y;
            }
        }
    }
    *share = a * cell * cell / (M_PI * R * R);
    *X = sx / a / L2;
    *Y = sy / a / L2;
}

static void clipped_centroid_against_integration(void **state)
{
    psd_design d = duo_design();
    psd_sensor s;
    psd_sensor_nominal(&d, &s);
    double R = s.R_mm, L2 = 0.5 * d.active_mm;
    /* off the +x edge only, off the -y edge only, off the (+x, +y) corner,
     * off the (-x, -y) corner, and most of the spot gone past the -x edge */
    const double spots[][2] = {{L2 - 0.4 * R, 0.7},       {-1.1, -(L2 - 0.3 * R)},
                               {L2 - 0.5 * R, L2 - 0.2 * R}, {-(L2 - 0.6 * R), -(L2 + 0.1 * R)},
                               {-(L2 + 0.7 * R), 0.3 * R}};
    for (size_t k = 0; k < sizeof spots / sizeof spots[0]; k++) {
        double i[4], x, y, share, X, Y;
        psd_sensor_currents(&s, spots[k], 1.0, i);
        psd_ratios(d.detector, d.lateral, i, &x, &y);
        integrate(R, L2, spots[k], &share, &X, &Y);
        assert_near(x, X, 2e-4);
        assert_near(y, Y, 2e-4);
        assert_near(i[0] + i[1], share, 2e-3 * share);
        assert_near(i[2] + i[3], share, 2e-3 * share);
        /* the clipped spot reads inside its own position, never past it */
        assert_true(fabs(x) <= fabs(spots[k][0]) / L2 + 1e-12);
        assert_true(fabs(y) <= fabs(spots[k][1]) / L2 + 1e-12);
    }
    /* wholly on the area: the spot's own position, the whole light */
    double on[2] = {L2 - R - 1e-3, -(L2 - R - 1e-3)}, i[4], x, y;
    psd_sensor_currents(&s, on, 0.8, i);
    psd_ratios(d.detector, d.lateral, i, &x, &y);
    assert_near(x, on[0] / L2, 1e-14);
    assert_near(y, on[1] / L2, 1e-14);
    assert_near(i[0] + i[1], 0.8, 1e-14);
}

static int has_term(const psd_poly *q, int ex, int ey)
{
    int n = 0;
    for (int k = 0; k < q->nt; k++)
        n += q->ex[k] == ex && q->ey[k] == ey;
    return n;
}

static void fss20_term_list(void **state)
{
    psd_poly q;
    assert_int_equal(psd_poly_init(&q, 5, PSD_POLY_FSS20), 20);
    assert_int_equal(q.nt, 20);
    for (int ex = 0; ex <= 5; ex++)
        for (int ey = 0; ex + ey <= 5; ey++)
            assert_int_equal(has_term(&q, ex, ey), ex == 2 && ey == 2 ? 0 : 1);
    assert_int_equal(psd_poly_init(&q, 5, PSD_POLY_FULL), 21);
    for (int ex = 0; ex <= 5; ex++)
        for (int ey = 0; ex + ey <= 5; ey++)
            assert_int_equal(has_term(&q, ex, ey), 1);
    /* the smallest order: 1, x, y */
    assert_int_equal(psd_poly_init(&q, 1, PSD_POLY_FULL), 3);
    assert_int_equal(has_term(&q, 0, 0) + has_term(&q, 1, 0) + has_term(&q, 0, 1), 3);
}

/* Seven rows: point A (3 rows), point B (2 rows), point C (1 row), one row
 * of A with weight 0 and one of B that cannot be read (NaN): A's alpha
 * errors 1, 2, 6 (mean 3), beta 0, 1, 2 (mean 1); B's alpha 3, 5 (mean 4),
 * beta 4, 4 (mean 4); C's 7, -2.  Within: A 4 + 1 + 9 + 1 + 0 + 1 = 16,
 * B 1 + 1 = 2, C 0: 18 over (2 + 1 + 0) degrees of freedom and two axes:
 * repeat = sqrt(18 / 6) = sqrt(3).  Means' RMS: alpha sqrt((9 + 16 + 49) / 3),
 * beta sqrt((1 + 16 + 4) / 3). */
static void repeatability_by_hand(void **state)
{
    enum { N = 8 };
    const double ea[N] = {1, 2, 3, 6, 5, 7, 100, NAN}, eb[N] = {0, 1, 4, 2, 4, -2, 100, 0};
    const long pt[N] = {0, 0, 1, 0, 1, 2, 0, 1};
    const double w[N] = {1, 1, 1, 1, 1, 1, 0, 1};
    double err[3 * N], scratch[8 * N];
    long point[N];
    for (int i = 0; i < N; i++) {
        err[3 * i] = ea[i] * 1e-5;
        err[3 * i + 1] = eb[i] * 1e-5;
        err[3 * i + 2] = 0;
        point[i] = pt[i];
    }
    lab_columns d = {.path = "t.csv", .n = N, .n_cols = 7};
    psd_labcal k;
    memset(&k, 0, sizeof k);
    k.d = &d;
    k.err = err;
    k.scratch = scratch;
    k.point = point;
    k.n_points = 3;
    memset(scratch, 0, sizeof scratch);
    psd_point_stats ps;
    psd_labcal_point_stats(&k, w, &ps);
    assert_int_equal(ps.points, 3);
    assert_int_equal(ps.rows, 6);
    assert_near(ps.per_point, 2.0, 1e-15);
    assert_near(ps.repeat_rad, sqrt(3.0) * 1e-5, 1e-18);
    assert_near(ps.mean_rms_rad[0], sqrt(74.0 / 3) * 1e-5, 1e-18);
    assert_near(ps.mean_rms_rad[1], sqrt(21.0 / 3) * 1e-5, 1e-18);
    /* one row per point: no repeatability */
    const long single[N] = {0, 1, 2, 3, 4, 5, 6, 7};
    memcpy(point, single, sizeof point);
    k.n_points = N;
    psd_labcal_point_stats(&k, w, &ps);
    assert_true(isnan(ps.repeat_rad));
    assert_near(ps.per_point, 1.0, 0);
}

static void validation_grid_offset(void **state)
{
    /* alpha_offset_deg within [-10, 10]: both ends, 0 and the default */
    const char *offs[] = {"-10", "0", "0.7", "10"};
    for (size_t t = 0; t < sizeof offs / sizeof offs[0]; t++) {
        char set_off[64];
        snprintf(set_off, sizeof set_off, "validation.alpha_offset_deg=%s", offs[t]);
        const char *sets[] = {"sensor.family=psd", "validation.alpha_max_deg=20",
                              "validation.alpha_step_deg=3", "validation.beta_deg=-5,5",
                              set_off};
        config_state st;
        test_build(&st, NULL, sets, 5);
        double off = atof(offs[t]);
        /* -20 + off + 3 i <= 20 */
        long na = (long)floor((40 - off) / 3 + 1e-9) + 1;
        assert_int_equal(psd_validation_points(&st.cfg), 2 * na);
        for (long i = 0; i < 2 * na; i++) {
            double a, b;
            psd_validation_angles(&st.cfg, i, &a, &b);
            assert_near(a * DEG_PER_RAD, -20 + off + 3.0 * (double)(i % na), 1e-9);
            assert_near(b * DEG_PER_RAD, i < na ? -5 : 5, 1e-9);
            assert_true(a * DEG_PER_RAD <= 20 + 1e-9);
        }
        config_state_free(&st);
    }
}

static void campaign_rows_repeat(void **state)
{
    /* campaign.repeats from its smallest (1) to its largest (1000) */
    const char *reps[] = {"1", "3", "1000"};
    for (int t = 0; t < 3; t++) {
        char set_rep[64];
        snprintf(set_rep, sizeof set_rep, "campaign.repeats=%s", reps[t]);
        const char *sets[] = {"sensor.family=psd", "campaign.alpha_max_deg=20",
                              "campaign.alpha_step_deg=5", "campaign.beta_deg=-10,0,10", set_rep};
        config_state st;
        test_build(&st, NULL, sets, 5);
        long r = atol(reps[t]);
        assert_int_equal(psd_campaign_rows(&st.cfg), 9 * 3 * r);
        for (long i = 0; i < 9 * 3 * r; i++) {
            double a, b;
            psd_campaign_angles(&st.cfg, i, &a, &b);
            long pt = i / r;
            assert_near(a * DEG_PER_RAD, -20 + 5.0 * (double)(pt % 9), 1e-9);
            assert_near(b * DEG_PER_RAD, -10 + 10.0 * (double)(pt / 9), 1e-9);
        }
        config_state_free(&st);
    }
}

/* Rows of a unit with a little scatter, on a grid; the fit with row
 * weights w against the fit with each row given w times at weight 1. */
static void poly_weights_are_counts(void **state)
{
    enum { NA = 9, NB = 5, N = NA * NB, MAXR = 3 * N };
    psd_design d = duo_design();
    psd_deviations dev;
    memset(&dev, 0, sizeof dev);
    dev.dx_um[0] = 40;
    dev.gain_pct[1] = 3;
    psd_sensor s;
    psd_sensor_build(&d, &dev, &s);
    static double m1[4][N], u1[3 * N], w1[N], m2[4][MAXR], u2[3 * MAXR];
    long n2 = 0;
    for (int r = 0; r < N; r++) {
        double a = (-20 + 5 * (r % NA)) * RAD_PER_DEG, b = (-10 + 5 * (r / NA)) * RAD_PER_DEG;
        double u[3] = {tan(a), tan(b), 1}, nu = sqrt(u[0] * u[0] + u[1] * u[1] + 1), mm[4];
        for (int k = 0; k < 3; k++)
            u1[3 * r + k] = u[k] / nu;
        assert_int_equal(psd_sensor_read(&s, u1 + 3 * r, mm), SUNMC_OK);
        w1[r] = 1 + r % 3;
        for (int k = 0; k < 4; k++)
            m1[k][r] = mm[k] * (1 + 2e-3 * sin(7.0 * r + k));
        for (int c = 0; c < (int)w1[r]; c++, n2++)
            for (int k = 0; k < 4; k++) {
                m2[k][n2] = m1[k][r];
                if (k < 3)
                    u2[3 * n2 + k] = u1[3 * r + k];
            }
    }
    psd_rows r1 = {.n = N, .m = {m1[0], m1[1], m1[2], m1[3]}, .ut = u1, .w = w1, .design = &d};
    psd_rows r2 = {.n = (size_t)n2, .m = {m2[0], m2[1], m2[2], m2[3]}, .ut = u2, .design = &d};
    psd_poly q1, q2;
    static double work[PSD_POLY_MAX_TERMS * (PSD_POLY_MAX_TERMS + 2)];
    psd_poly_init(&q1, 3, PSD_POLY_FULL);
    psd_poly_init(&q2, 3, PSD_POLY_FULL);
    assert_int_equal(psd_poly_fit(&q1, &r1, work), SUNMC_OK);
    assert_int_equal(psd_poly_fit(&q2, &r2, work), SUNMC_OK);
    for (int k = 0; k < q1.nt; k++) {
        assert_near(q1.ca[k], q2.ca[k], 1e-9 * (fabs(q2.ca[k]) + 1e-3));
        assert_near(q1.cb[k], q2.cb[k], 1e-9 * (fabs(q2.cb[k]) + 1e-3));
    }
    /* and uniform weights are no weights */
    for (int r = 0; r < N; r++)
        w1[r] = 0.25;
    psd_poly_init(&q2, 3, PSD_POLY_FULL);
    r1.w = NULL;
    assert_int_equal(psd_poly_fit(&q2, &r1, work), SUNMC_OK);
    r1.w = w1;
    assert_int_equal(psd_poly_fit(&q1, &r1, work), SUNMC_OK);
    for (int k = 0; k < q1.nt; k++)
        assert_near(q1.ca[k], q2.ca[k], 1e-9 * (fabs(q2.ca[k]) + 1e-3));
}

static void points_are_angle_pairs(void **state)
{
    enum { N = 7 };
    const char *sets[] = {"sensor.family=psd"};
    config_state st;
    test_build(&st, NULL, sets, 1);
    double a[N] = {0, 0, 0, 5, 0, 5, 0}, b[N] = {0, 0, 5, 0, 5, 0, 0}, ch[N], w[N];
    for (int i = 0; i < N; i++) {
        ch[i] = 0.1 + 0.01 * i;
        w[i] = 1;
    }
    int line[N] = {2, 3, 4, 5, 6, 7, 8};
    lab_columns d = {.path = "t.csv", .n = N, .n_cols = 7, .v = {a, b, ch, ch, ch, ch, w},
                     .line = line};
    char err[SUNMC_ERRLEN];
    psd_labcal *k = psd_labcal_alloc(&st.cfg, &d, err, sizeof err);
    assert_non_null(k);
    assert_int_equal(k->n_points, 3);
    /* (0,0) x 4, (0,5) x 2, (5,0) x 2: beta lines are not merged */
    assert_int_equal(k->point[0], k->point[1]);
    assert_int_equal(k->point[0], k->point[6]);
    assert_int_equal(k->point[2], k->point[4]);
    assert_int_equal(k->point[3], k->point[5]);
    assert_int_not_equal(k->point[0], k->point[2]);
    assert_int_not_equal(k->point[0], k->point[3]);
    assert_int_not_equal(k->point[2], k->point[3]);
    psd_labcal_free(k);
    config_state_free(&st);
}

/* The report's two numbers: a single reading's scatter A and its point's
 * mean's B = A / sqrt(rows per point). */
static void repeatability_of_the_mean(void **state)
{
    char cmd[4096], out[1 << 16];
    const char *d = test_tmp("rep");
    snprintf(cmd, sizeof cmd,
             "%s simulate configs/psd.ini --unit 3 --set campaign.repeats=4 --quiet --out %s && "
             "grep -v '^#' %s/campaign.csv > %s/c.csv && %s calibrate --config configs/psd.ini "
             "%s/c.csv",
             test_sunmc(), d, d, d, test_sunmc(), d);
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s: %d\n%s", cmd, rc, out);
    /* stderr's copy of the warning: the report on stdout reaches the pipe
     * in 4096-byte blocks, one of which may split its line around stderr */
    const char *p = strstr(out, "WARNING: repeatability: ");
    assert_non_null(p);
    p += strlen("WARNING: ");
    double per, one, mean;
    assert_int_equal(sscanf(p, "repeatability: %lf rows per point; a single reading scatters %lf "
                               "arcsec per axis about its point's mean (%lf",
                            &per, &one, &mean),
                     3);
    assert_near(per, 4, 1e-12);
    assert_true(one > 0);
    assert_near(mean, one / 2, 1e-3 * one);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(clipped_centroid_against_integration),
        cmocka_unit_test(fss20_term_list),
        cmocka_unit_test(repeatability_by_hand),
        cmocka_unit_test(validation_grid_offset),
        cmocka_unit_test(campaign_rows_repeat),
        cmocka_unit_test(poly_weights_are_counts),
        cmocka_unit_test(points_are_angle_pairs),
        cmocka_unit_test(repeatability_of_the_mean),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
