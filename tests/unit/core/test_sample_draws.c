/* test_sample_draws.c - the random draws, against their distributions: for each
 * tolerance distribution the range, mean, spread and sign of many draws (the
 * truncated normal's spread from its closed form); every ESS and DSS
 * deviation drawn with its own spread and independent of every other one and
 * of the neighbouring unit (correlations near 0); the measured roll = true
 * roll + its own measurement error, independent of the campaign noise; the
 * campaign's encoder errors on both axes, the row-current and centroid noise
 * with their sigma, different from unit to unit, repeated readings averaged.
 *
 * Windows: over N independent draws a mean is within 4.5 sigma/sqrt(N), a
 * standard deviation within 4.5 sigma/sqrt(2N), a correlation within
 * 4.5/sqrt(N) (false alarm below 1e-5 each). */
#include "test_util.h"

#include "dss_unit.h"
#include "family.h"
#include "ess_unit.h"
#include "rng.h"
#include "status.h"
#include "tolerance.h"
#include "units.h"

#define Z 4.5

typedef struct {
    double mean, sd, min, max, neg; /* neg: fraction below 0 */
} moments;

static moments moments_of(const double *x, long n)
{
    moments m = {0, 0, INFINITY, -INFINITY, 0};
    for (long i = 0; i < n; i++) {
        m.mean += x[i];
        m.min = fmin(m.min, x[i]);
        m.max = fmax(m.max, x[i]);
        m.neg += x[i] < 0;
    }
    m.mean /= (double)n;
    for (long i = 0; i < n; i++)
        m.sd += (x[i] - m.mean) * (x[i] - m.mean);
    m.sd = sqrt(m.sd / (double)(n - 1));
    m.neg /= (double)n;
    return m;
}

static double correlation(const double *x, const double *y, long n)
{
    double mx = 0, my = 0, sxy = 0, sxx = 0, syy = 0;
    for (long i = 0; i < n; i++) {
        mx += x[i];
        my += y[i];
    }
    mx /= (double)n;
    my /= (double)n;
    for (long i = 0; i < n; i++) {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
        syy += (y[i] - my) * (y[i] - my);
    }
    return sxy / sqrt(sxx * syy);
}

/* mean 0, spread sd, half the draws negative, within the statistical window */
static void expect_centred(const moments *m, double sd, long n, const char *what)
{
    if (!(fabs(m->mean) <= Z * sd / sqrt((double)n)))
        fail_msg("%s: mean %g, expected 0 +- %g", what, m->mean, Z * sd / sqrt((double)n));
    if (!(fabs(m->sd - sd) <= Z * sd / sqrt(2.0 * (double)n)))
        fail_msg("%s: sd %g, expected %g +- %g", what, m->sd, sd, Z * sd / sqrt(2.0 * (double)n));
    if (!(fabs(m->neg - 0.5) <= Z * 0.5 / sqrt((double)n)))
        fail_msg("%s: %g of the draws negative, expected half", what, m->neg);
}

#define ND 20000

/* Draws of tolerance t as the families make them: one stream per unit. */
static void draws(const tolerance *t, double trunc, double *x)
{
    for (long u = 0; u < ND; u++) {
        rng_stream r;
        rng_stream_init(&r, 1234, (uint64_t)u, RNG_STREAM_TOLERANCE + 3);
        x[u] = tolerance_draw(t, trunc, &r);
    }
}

static void tolerance_distributions(void **state)
{
    (void)state;
    static double x[ND];
    const double v = 2.5;
    tolerance t = {v, DIST_FIXED};
    draws(&t, 3, x);
    for (long i = 0; i < ND; i++)
        assert_true(x[i] == v);

    /* uniform on [-v, v]: sd v / sqrt(3), reaching both ends */
    t.dist = DIST_UNIFORM;
    draws(&t, 3, x);
    moments m = moments_of(x, ND);
    expect_centred(&m, v / sqrt(3.0), ND, "uniform");
    assert_true(m.min >= -v && m.max <= v);
    assert_true(m.min < -0.999 * v && m.max > 0.999 * v);

    /* normal: sd v; 4.55 % beyond 2 v */
    t.dist = DIST_NORMAL;
    draws(&t, 3, x);
    m = moments_of(x, ND);
    expect_centred(&m, v, ND, "normal");
    long beyond = 0;
    for (long i = 0; i < ND; i++)
        beyond += fabs(x[i]) > 2 * v;
    double p2 = erfc(2 / sqrt(2.0));
    assert_near((double)beyond / ND, p2, Z * sqrt(p2 * (1 - p2) / ND));

    /* truncated at 1.5 sigma: |x| <= 1.5 v, reaching it; variance
     * v^2 (1 - 2 c phi(c) / (2 Phi(c) - 1)) */
    const double cut = 1.5;
    t.dist = DIST_TRUNCNORMAL;
    draws(&t, cut, x);
    m = moments_of(x, ND);
    double phi = exp(-cut * cut / 2) / sqrt(2 * M_PI), mass = erf(cut / sqrt(2.0));
    double sd_trunc = v * sqrt(1 - 2 * cut * phi / mass);
    expect_centred(&m, sd_trunc, ND, "truncnormal");
    assert_true(m.min >= -cut * v && m.max <= cut * v);
    assert_true(m.min < -0.99 * cut * v && m.max > 0.99 * cut * v);
}

/* Seeds that differ only in their high 32 bits draw differently. */
static void seed_high_bits(void **state)
{
    (void)state;
    rng_stream a, b;
    rng_stream_init(&a, 7, 0, RNG_STREAM_TOLERANCE);
    rng_stream_init(&b, 7 + (1ULL << 32), 0, RNG_STREAM_TOLERANCE);
    int same = 0;
    for (int i = 0; i < 16; i++)
        same += rng_uniform(&a) == rng_uniform(&b);
    assert_int_equal(same, 0);
}

#define NU 3000

/* Pairwise correlations of the columns x[k][NU] below the window; the same
 * column of neighbouring units uncorrelated too. */
static void expect_independent(double (*x)[NU], int nk, const char *const *names)
{
    double lim = Z / sqrt((double)NU);
    for (int i = 0; i < nk; i++) {
        for (int j = i + 1; j < nk; j++) {
            double r = correlation(x[i], x[j], NU);
            if (!(fabs(r) < lim))
                fail_msg("%s and %s correlated: %.3f", names[i], names[j], r);
        }
        double r = correlation(x[i], x[i] + 1, NU - 1);
        if (!(fabs(r) < lim))
            fail_msg("%s of unit u and u+1 correlated: %.3f", names[i], r);
    }
}

/* Config path with tolerance keys[k] normal of sigma[k], plus extra sets. */
static void build_normal(config_state *st, const char *path, const char *const *keys,
                         const double *sigma, int n, const char *const *extra, int n_extra)
{
    char sets[48][64];
    const char *setp[48];
    assert_true(2 * n + n_extra <= 48);
    for (int k = 0; k < n; k++) {
        snprintf(sets[2 * k], 64, "tolerance.%s=%g", keys[k], sigma[k]);
        snprintf(sets[2 * k + 1], 64, "tolerance.%s_dist=normal", keys[k]);
    }
    for (int i = 0; i < 2 * n; i++)
        setp[i] = sets[i];
    for (int i = 0; i < n_extra; i++)
        setp[2 * n + i] = extra[i];
    test_build(st, path, setp, 2 * n + n_extra);
}

static void ess_deviations_independent(void **state)
{
    (void)state;
    /* Every tolerance normal with its own sigma (in its key's unit). */
    static const char *const keys[15] = {"dH_um", "dd_um", "dphi_deg", "slit_width_um",
                                         "harmonic_phase_deg", "gain_pct", "etch_um",
                                         "install_x_arcsec", "install_y_arcsec",
                                         "install_z_arcsec", "sun_x_arcsec", "sun_y_arcsec",
                                         "spacer_cte_ppm_k", "mask_cte_ppm_k", "dial_tilt_deg"};
    static const double sigma[15] = {2,  1,  0.01, 1.5, 30,  0.7, 0.2, 60,
                                      300, 90, 40,  50,  2.5, 0.8, 0.02};
    const char *extra[] = {"calibration.roll_sigma_arcsec=25", "tolerance.truncation_sigmas=3"};
    config_state st;
    build_normal(&st, "configs/ess_type_a.ini", keys, sigma, 15, extra, 2);
    static double x[ESS_N_DEV + 1][NU];
    for (long u = 0; u < NU; u++) {
        ess_deviations d;
        double v[ESS_N_DEV];
        ess_deviations_sample(&st.cfg, (uint64_t)st.cfg.seed, u, &d);
        ess_deviations_values(&d, v);
        for (int k = 0; k < ESS_N_DEV; k++)
            x[k][u] = v[k];
        x[ESS_N_DEV][u] = d.roll_measured_arcsec - d.install_x_arcsec; /* measurement error */
    }
    /* deviation columns: dH dd dphi slit phase gain1-4 etch1-4 inst_x,y,z sun_x,y
     * spacer_cte mask_cte dial_tilt roll */
    static const int key_of[ESS_N_DEV - 1] = {0, 1, 2, 3, 4, 5, 5, 5,  5,  6,  6,
                                              6, 6, 7, 8, 9, 10, 11, 12, 13, 14};
    for (int k = 0; k < ESS_N_DEV - 1; k++) {
        moments m = moments_of(x[k], NU);
        expect_centred(&m, sigma[key_of[k]], NU, ess_deviation_names[k]);
    }
    moments m = moments_of(x[ESS_N_DEV], NU);
    expect_centred(&m, 25.0, NU, "roll measurement error");
    const char *names[ESS_N_DEV + 1];
    for (int k = 0; k < ESS_N_DEV; k++)
        names[k] = ess_deviation_names[k];
    names[ESS_N_DEV] = "roll measurement error";
    /* roll_measured = install_x + error is correlated with install_x by
     * construction: leave it out, keep its error. */
    double (*cols)[NU] = malloc(ESS_N_DEV * sizeof *cols);
    const char *cn[ESS_N_DEV];
    int nk = 0;
    for (int k = 0; k <= ESS_N_DEV; k++) {
        if (k == ESS_N_DEV - 1)
            continue;
        memcpy(cols[nk], x[k], sizeof cols[nk]);
        cn[nk++] = names[k];
    }
    expect_independent(cols, nk, cn);
    free(cols);
    config_state_free(&st);
}

static void dss_deviations_independent(void **state)
{
    (void)state;
    static const char *const keys[DSS_N_DEV] = {
        "dh_px",         "dx_px",         "dy_px",           "c1_arcsec",
        "c2_arcsec",     "c3_arcsec",     "glass_thickness_um", "glass_index",
        "sun_b1_arcsec", "sun_b2_arcsec", "spacer_cte_ppm_k", "detector_cte_ppm_k",
        "glass_cte_ppm_k", "glass_dn_dt_ppm_k", "detector_tilt_x_arcsec", "detector_tilt_y_arcsec",
        "prnu_pct",      "dsnu_pct",      "glass_ghost"};
    static const double sigma[DSS_N_DEV] = {0.5, 0.2, 0.3, 10, 20, 30, 5, 0.004, 15, 25,
                                            2,   0.5, 1.5, 0.7, 40, 70, 0.8, 0.2, 0.6};
    config_state st;
    build_normal(&st, "configs/dss.ini", keys, sigma, DSS_N_DEV, NULL, 0);
    static double x[DSS_N_DEV][NU];
    for (long u = 0; u < NU; u++) {
        dss_deviations d;
        double v[DSS_N_DEV];
        dss_deviations_sample(&st.cfg, (uint64_t)st.cfg.seed, u, &d);
        dss_deviations_values(&d, v);
        for (int k = 0; k < DSS_N_DEV; k++)
            x[k][u] = v[k];
    }
    for (int k = 0; k < DSS_N_DEV; k++) {
        assert_string_equal(dss_deviation_names[k], keys[k]);
        moments m = moments_of(x[k], NU);
        expect_centred(&m, sigma[k], NU, keys[k]);
    }
    expect_independent(x, DSS_N_DEV, keys);
    config_state_free(&st);
}

#define NC 600

/* ESS campaign noise: encoder errors on both axes with their sigma, not
 * shared between units, independent of the roll measurement. */
static void ess_campaign_noise(void **state)
{
    (void)state;
    const char *sets[] = {"campaign.alpha_min_deg=-3", "campaign.alpha_max_deg=3",
                          "campaign.alpha_step_deg=1", "campaign.beta_deg=0, 10",
                          "noise.encoder_arcsec=2", "calibration.roll_sigma_arcsec=5"};
    config_state st;
    test_build(&st, "configs/ess_type_a.ini", sets, 6);
    const sunmc_config *c = &st.cfg;
    size_t n = ess_campaign_size(c);
    assert_int_equal((int)n, 14);
    static double ea[NC][14], eb[NC][14], roll_err[NC];
    ess_calib_workspace *cw = ess_calib_alloc(n);
    assert_non_null(cw);
    ess_campaign_point pt[14];
    for (long u = 0; u < NC; u++) {
        ess_deviations d;
        ess_unit un;
        ess_deviations_sample(c, (uint64_t)c->seed, u, &d);
        ess_unit_build(c, &d, &un);
        int gross;
        ess_unit_campaign(c, &un, u, cw, pt, &gross);
        for (size_t i = 0; i < n; i++) {
            double a = (-3.0 + (double)(i % 7)) * RAD_PER_DEG, b = (i < 7 ? 0.0 : 10.0) * RAD_PER_DEG;
            ea[u][i] = (pt[i].a_true_rad - a) * ARCSEC_PER_RAD;
            eb[u][i] = (pt[i].b_true_rad - b) * ARCSEC_PER_RAD;
        }
        roll_err[u] = d.roll_measured_arcsec - d.install_x_arcsec;
    }
    static double col_a[NC], col_b[NC], col_a2[NC];
    for (int i = 0; i < (int)n; i += 5) {
        for (long u = 0; u < NC; u++) {
            col_a[u] = ea[u][i];
            col_b[u] = eb[u][i];
            col_a2[u] = ea[u][(i + 1) % n];
        }
        moments m = moments_of(col_a, NC);
        expect_centred(&m, 2.0, NC, "encoder error, alpha");
        m = moments_of(col_b, NC);
        expect_centred(&m, 2.0, NC, "encoder error, beta");
        double lim = Z / sqrt((double)NC);
        assert_true(fabs(correlation(col_a, col_b, NC)) < lim);
        assert_true(fabs(correlation(col_a, col_a2, NC)) < lim);
        assert_true(fabs(correlation(col_a, roll_err, NC)) < lim);
        assert_true(fabs(correlation(col_b, roll_err, NC)) < lim);
        assert_true(fabs(correlation(col_a, col_a + 1, NC - 1)) < lim); /* unit u vs u + 1 */
    }
    ess_calib_free(cw);
    config_state_free(&st);
}

/* The fine-row currents' noise: sigma = row_current_pct of a1, per row. */
static void ess_row_noise_sigma(void **state)
{
    (void)state;
    const char *sets[] = {"noise.row_current_pct=1.5"};
    config_state st;
    test_build(&st, "configs/ess_type_a.ini", sets, 1);
    static double x[ESS_FINE_ROWS][ND / 4];
    rng_stream r;
    rng_stream_init(&r, 9, 0, RNG_STREAM_VAL_NOISE);
    for (long i = 0; i < ND / 4; i++) {
        double noise[ESS_FINE_ROWS];
        ess_row_noise(&st.cfg, &r, noise);
        for (int m = 0; m < ESS_FINE_ROWS; m++)
            x[m][i] = noise[m];
    }
    for (int m = 0; m < ESS_FINE_ROWS; m++) {
        moments mo = moments_of(x[m], ND / 4);
        expect_centred(&mo, 0.015, ND / 4, "row current noise");
        if (m > 0)
            assert_true(fabs(correlation(x[m], x[0], ND / 4)) < Z / sqrt(ND / 4.0));
    }
    config_state_free(&st);
}

/* Repeated readings at a campaign point are averaged: without noise the
 * average of three equal readings is the reading. */
static void ess_repeats_averaged(void **state)
{
    (void)state;
    const char *sets[] = {"noise.row_current_pct=0", "noise.encoder_arcsec=0",
                          "campaign.repeats=3"};
    config_state st;
    test_build(&st, "configs/ess_type_a.ini", sets, 3);
    ess_deviations d;
    ess_unit u;
    ess_deviations_sample(&st.cfg, 5, 2, &d);
    ess_unit_build(&st.cfg, &d, &u);
    rng_stream r;
    rng_stream_init(&r, 5, 2, RNG_STREAM_CAL_NOISE);
    for (double a_deg = -40; a_deg <= 40; a_deg += 16.5) {
        double one, truth;
        double a = a_deg * RAD_PER_DEG, b = 10 * RAD_PER_DEG;
        ess_campaign_point p;
        ess_campaign_batch(&st.cfg, &u, &r, 1, &a, &b, &p);
        assert_int_equal(p.seen, 1);
        assert_true(p.a_true_rad == a && p.b_true_rad == b);
        assert_int_equal(ess_unit_read(&u, a, b, NULL, &one, &truth), SUNMC_OK);
        assert_near(p.raw_rad, one, 1e-15);
        assert_near(p.incidence_rad, truth, 1e-15);
    }
    config_state_free(&st);
}

/* DSS campaign: centroid noise with sigma / sqrt(repeats) per axis, x and y
 * independent; encoder errors on both table axes. */
static void dss_campaign_noise(void **state)
{
    (void)state;
    /* a perfect sun simulator, so that the truth is eq. 3-4 of the table */
    const char *quiet[] = {"campaign.b_min_deg=-20", "campaign.b_max_deg=20",
                           "campaign.b_step_deg=10", "noise.centroid_px=0",
                           "noise.encoder_arcsec=0", "campaign.repeats=2",
                           "tolerance.sun_b1_arcsec=0", "tolerance.sun_b2_arcsec=0"};
    const char *noisy[] = {"campaign.b_min_deg=-20", "campaign.b_max_deg=20",
                           "campaign.b_step_deg=10", "noise.centroid_px=0.05",
                           "noise.encoder_arcsec=0", "campaign.repeats=2",
                           "tolerance.sun_b1_arcsec=0", "tolerance.sun_b2_arcsec=0"};
    const char *enc[] = {"campaign.b_min_deg=-20", "campaign.b_max_deg=20",
                         "campaign.b_step_deg=10", "noise.centroid_px=0",
                         "noise.encoder_arcsec=3", "campaign.repeats=2",
                         "tolerance.sun_b1_arcsec=0", "tolerance.sun_b2_arcsec=0"};
    config_state q, s, e;
    test_build(&q, "configs/dss.ini", quiet, 8);
    test_build(&s, "configs/dss.ini", noisy, 8);
    test_build(&e, "configs/dss.ini", enc, 8);
    size_t n = dss_campaign_size(&q.cfg);
    assert_int_equal((int)n, 25);
    static double nx[NC], ny[NC], nx1[NC], eb1[NC], eb2[NC];
    double b1[25], b2[25], x0[25], y0[25], x1[25], y1[25], w[25], ta[25], tb[25];
    for (long u = 0; u < NC; u++) {
        dss_deviations d;
        dss_unit un;
        dss_deviations_sample(&q.cfg, (uint64_t)q.cfg.seed, u, &d);
        dss_unit_build(&q.cfg, &d, &un);
        assert_int_equal((int)dss_unit_campaign(&q.cfg, &un, u, b1, b2, x0, y0, w, ta, tb), 25);
        /* noise-free, encoder-free: the readings are the spot itself */
        double xs, ys;
        assert_int_equal(dss_sensor_read(&un.sensor, b1[7], b2[7], NULL, &xs, &ys), SUNMC_OK);
        assert_near(x0[7], xs, 1e-12);
        assert_near(y0[7], ys, 1e-12);
        dss_unit_campaign(&s.cfg, &un, u, b1, b2, x1, y1, w, ta, tb);
        nx[u] = x1[7] - x0[7];
        ny[u] = y1[7] - y0[7];
        nx1[u] = x1[8] - x0[8];
        dss_unit_campaign(&e.cfg, &un, u, b1, b2, x1, y1, w, ta, tb);
        /* truth alpha = -b2_true, and at b2_true = 0 beta = b1_true */
        eb2[u] = (-ta[12] - b2[12]) * ARCSEC_PER_RAD;
        eb1[u] = (tb[12] - b1[12]) * ARCSEC_PER_RAD;
    }
    assert_true(b1[12] == 0 && b2[12] == 0);
    moments m = moments_of(nx, NC);
    expect_centred(&m, 0.05 / sqrt(2.0), NC, "centroid noise x");
    m = moments_of(ny, NC);
    expect_centred(&m, 0.05 / sqrt(2.0), NC, "centroid noise y");
    double lim = Z / sqrt((double)NC);
    assert_true(fabs(correlation(nx, ny, NC)) < lim);
    assert_true(fabs(correlation(nx, nx1, NC)) < lim);
    assert_true(fabs(correlation(nx, nx + 1, NC - 1)) < lim);
    m = moments_of(eb1, NC);
    expect_centred(&m, 3.0, NC, "encoder error b1");
    m = moments_of(eb2, NC);
    expect_centred(&m, 3.0, NC, "encoder error b2");
    assert_true(fabs(correlation(eb1, eb2, NC)) < lim);
    config_state_free(&q);
    config_state_free(&s);
    config_state_free(&e);
}

/* The DSS campaign's centroid noise and the validation's are independent
 * streams: across units, each of the first campaign noises is uncorrelated
 * with each of the first validation noises (the validation's draws taken as
 * the unit takes them, from its validation stream). */
static void dss_campaign_validation_independent(void **state)
{
    (void)state;
    const char *sets[] = {"campaign.b_min_deg=-20", "campaign.b_max_deg=20",
                          "campaign.b_step_deg=10", "noise.centroid_px=0.05",
                          "noise.encoder_arcsec=0", "campaign.repeats=1"};
    config_state st;
    test_build(&st, "configs/dss.ini", sets, 6);
    const sunmc_config *c = &st.cfg;
    enum { K = 4 };
    static double cn[2 * K][NC], vn[2 * K][NC];
    double b1[25], b2[25], x[25], y[25], w[25];
    for (long u = 0; u < NC; u++) {
        dss_deviations d;
        dss_unit un;
        dss_deviations_sample(c, (uint64_t)c->seed, u, &d);
        dss_unit_build(c, &d, &un);
        assert_int_equal((int)dss_unit_campaign(c, &un, u, b1, b2, x, y, w, NULL, NULL), 25);
        rng_stream r;
        unit_stream_init(&r, c, u, RNG_STREAM_VAL_NOISE);
        dss_validation_point v[K];
        dss_validation_batch(c, &un, &r, K, b1 + 6, b2 + 6, v);
        for (int k = 0; k < K; k++) {
            double xs, ys;
            assert_int_equal(dss_sensor_read(&un.sensor, b1[k], b2[k], NULL, &xs, &ys), SUNMC_OK);
            cn[2 * k][u] = x[k] - xs;
            cn[2 * k + 1][u] = y[k] - ys;
            assert_true(v[k].seen);
            vn[2 * k][u] = v[k].x_px - v[k].x0_px;
            vn[2 * k + 1][u] = v[k].y_px - v[k].y0_px;
        }
    }
    double lim = Z / sqrt((double)NC);
    for (int i = 0; i < 2 * K; i++) {
        moments m = moments_of(cn[i], NC);
        expect_centred(&m, 0.05, NC, "campaign centroid noise");
        m = moments_of(vn[i], NC);
        expect_centred(&m, 0.05, NC, "validation centroid noise");
        for (int j = 0; j < 2 * K; j++)
            if (!(fabs(correlation(cn[i], vn[j], NC)) < lim))
                fail_msg("campaign noise %d and validation noise %d correlate: %g", i, j,
                         correlation(cn[i], vn[j], NC));
    }
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(tolerance_distributions),
        cmocka_unit_test(seed_high_bits),
        cmocka_unit_test(ess_deviations_independent),
        cmocka_unit_test(dss_deviations_independent),
        cmocka_unit_test(ess_campaign_noise),
        cmocka_unit_test(ess_row_noise_sigma),
        cmocka_unit_test(ess_repeats_averaged),
        cmocka_unit_test(dss_campaign_noise), cmocka_unit_test(dss_campaign_validation_independent),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
