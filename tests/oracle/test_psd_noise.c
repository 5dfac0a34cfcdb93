/* test_psd_noise.c - issue 38: the lab noise the public two-axis PSD set
 * shows and the simulator did not have.  A noise the channels share
 * (noise.common_pct, weights noise.common_signs): the covariance of many
 * readings of one point against its closed form sigma_own^2 delta_jk +
 * sigma_c^2 w_j w_k.  The table's setting error per scan line
 * (noise.table_line_arcsec): one offset per line, the same for every row
 * of the line, drawn per unit from a stream of its own (deterministic,
 * different across units and between the campaign and the validation),
 * with the stated sigma; nothing drawn at 0. */
#include "test_util.h"

#include "family.h"
#include "psd_config.h"
#include "psd_sensor.h"
#include "psd_unit.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

static void build(config_state *st, const char *const *sets, int n)
{
    char err[SUNMC_ERRLEN];
    if (config_build(st, "configs/psd_aeroztark.ini", sets, n, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
}

#define READS 40000

/* The covariance of READS readings of unit 0 at (3, -2) deg. */
static void covariance(const sunmc_config *c, double cov[4][4])
{
    psd_deviations dev;
    psd_sensor s;
    psd_unit_sample(c, 0, 1.0, &dev);
    psd_sensor_build(&psd_cfg(c)->design, &dev, &s);
    rng_stream r;
    unit_stream_init(&r, c, 0, RNG_STREAM_CAL_NOISE);
    double sum[4] = {0}, sxy[4][4] = {{0}};
    for (int i = 0; i < READS; i++) {
        double m[4];
        assert_int_equal(psd_unit_read(c, &s, 3 * RAD_PER_DEG, -2 * RAD_PER_DEG, &r, m),
                         SUNMC_OK);
        for (int j = 0; j < 4; j++) {
            sum[j] += m[j];
            for (int k = 0; k < 4; k++)
                sxy[j][k] += m[j] * m[k];
        }
    }
    for (int j = 0; j < 4; j++)
        for (int k = 0; k < 4; k++)
            cov[j][k] = (sxy[j][k] - sum[j] * sum[k] / READS) / (READS - 1);
}

static void test_shared_noise_covariance(void **state)
{
    const char *sets[] = {"noise.channel_pct=0.03", "noise.common_pct=0.05",
                          "noise.common_signs=1, 0.5, -1, -1", "noise.adc_bits=24"};
    config_state st;
    build(&st, sets, 4);
    double cov[4][4], own = 0.03e-2, sh = 0.05e-2, w[4] = {1, 0.5, -1, -1};
    covariance(&st.cfg, cov);
    for (int j = 0; j < 4; j++)
        for (int k = 0; k < 4; k++) {
            double want = sh * sh * w[j] * w[k] + (j == k ? own * own : 0.0);
            /* a covariance of 40000 draws: sd about sqrt(2 / N) of the scale */
            double tol = 4.0 * sqrt(2.0 / READS) * (own * own + sh * sh);
            if (fabs(cov[j][k] - want) > tol)
                fail_msg("cov[%d][%d] = %.4g, closed form %.4g (tolerance %.2g)", j, k,
                         cov[j][k], want, tol);
        }
    config_state_free(&st);
    /* off: the channels' own noise alone, uncorrelated */
    const char *off[] = {"noise.channel_pct=0.03", "noise.common_pct=0", "noise.adc_bits=24"};
    build(&st, off, 3);
    covariance(&st.cfg, cov);
    assert_true(fabs(cov[0][1]) < 4.0 * sqrt(1.0 / READS) * own * own);
    assert_true(fabs(cov[0][0] - own * own) < 4.0 * sqrt(2.0 / READS) * own * own);
    config_state_free(&st);
}

static void test_common_signs_need_four(void **state)
{
    const char *sets[] = {"noise.common_signs=1, 1, -1"};
    config_state st;
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, "configs/psd_aeroztark.ini", sets, 1, err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "noise.common_signs: 3 values, the sensor has 4 channels"));
    const char *five[] = {"noise.common_signs=1, 1, -1, -1, 1"};
    assert_int_equal(config_build(&st, "configs/psd_aeroztark.ini", five, 1, err, sizeof err),
                     SUNMC_EINPUT);
}

static void test_line_offsets(void **state)
{
    const char *sets[] = {"noise.table_line_arcsec=100"};
    config_state st;
    build(&st, sets, 1);
    const sunmc_config *c = &st.cfg;
    double a[CONFIG_LIST_MAX][2], b[CONFIG_LIST_MAX][2], v[CONFIG_LIST_MAX][2];
    int nl = psd_cfg(c)->cal_beta_deg.n;
    psd_line_offsets(c, 7, FAMILY_GRID_CAMPAIGN, a);
    psd_line_offsets(c, 7, FAMILY_GRID_CAMPAIGN, b);
    assert_memory_equal(a, b, sizeof a); /* a function of (seed, unit) */
    psd_line_offsets(c, 7, FAMILY_GRID_VALIDATION, v);
    assert_true(a[0][0] != v[0][0]); /* another stream */
    psd_line_offsets(c, 8, FAMILY_GRID_CAMPAIGN, b);
    assert_true(a[0][0] != b[0][0]); /* another unit */
    for (int l = nl; l < CONFIG_LIST_MAX; l++)
        assert_true(a[l][0] == 0 && a[l][1] == 0); /* no line, no offset */
    /* sigma over many units: 2 axes x lines x 300 units of N(0, 100") */
    double s2 = 0;
    long n = 0;
    for (long u = 0; u < 300; u++) {
        psd_line_offsets(c, u, FAMILY_GRID_CAMPAIGN, a);
        for (int l = 0; l < nl; l++)
            for (int k = 0; k < 2; k++, n++)
                s2 += a[l][k] * a[l][k];
    }
    double sd = sqrt(s2 / (double)n) * ARCSEC_PER_RAD;
    assert_true(fabs(sd - 100.0) < 4.0 * 100.0 / sqrt(2.0 * (double)n));
    /* every row of a line is that line; lines in the table's order */
    long rows = psd_campaign_rows(c), per = rows / nl;
    for (long i = 0; i < rows; i++) {
        double al, be;
        psd_campaign_angles(c, i, &al, &be);
        assert_int_equal(psd_campaign_line(c, i), i / per);
        assert_near(be * DEG_PER_RAD, psd_cfg(c)->cal_beta_deg.v[i / per], 1e-9);
    }
    long nv = psd_validation_points(c), pv = nv / psd_cfg(c)->val_beta_deg.n;
    assert_int_equal(psd_validation_line(c, nv - 1), psd_cfg(c)->val_beta_deg.n - 1);
    assert_int_equal(psd_validation_line(c, pv), 1);
    assert_int_equal(psd_validation_line(c, pv - 1), 0);
    config_state_free(&st);
    /* 0: nothing drawn, every offset 0 */
    const char *zero[] = {"noise.table_line_arcsec=0"};
    build(&st, zero, 1);
    psd_line_offsets(&st.cfg, 7, FAMILY_GRID_CAMPAIGN, a);
    for (int l = 0; l < CONFIG_LIST_MAX; l++)
        assert_true(a[l][0] == 0 && a[l][1] == 0);
    config_state_free(&st);
}

/* A line's error moves every reading of the line alike: the unit's
 * campaign read with the offsets equals readings at the offset angles. */
static void test_line_error_in_the_systematic_part(void **state)
{
    const char *on[] = {"noise.table_line_arcsec=300", "noise.channel_pct=0",
                        "noise.common_pct=0", "report.model_form_every=0"};
    const char *off[] = {"noise.table_line_arcsec=0", "noise.channel_pct=0",
                         "noise.common_pct=0", "report.model_form_every=0"};
    config_state a, b;
    build(&a, on, 4);
    build(&b, off, 4);
    unit_result ra, rb;
    char err[SUNMC_ERRLEN];
    void *wa = a.cfg.family->workspace_alloc(&a.cfg, err, sizeof err);
    void *wb = b.cfg.family->workspace_alloc(&b.cfg, err, sizeof err);
    assert_non_null(wa);
    assert_non_null(wb);
    assert_int_equal(a.cfg.family->unit_run(&a.cfg, 3, wa, &ra), SUNMC_OK);
    assert_int_equal(b.cfg.family->unit_run(&b.cfg, 3, wb, &rb), SUNMC_OK);
    a.cfg.family->workspace_free(wa);
    b.cfg.family->workspace_free(wb);
    int last = a.cfg.bands_deg.n - 1;
    /* no reading noise: after = systematic, and the table's errors add to both */
    assert_near(ra.rms_after[2][last], ra.rms_after_sys[2][last], 1e-9);
    assert_true(ra.rms_after_sys[2][last] > rb.rms_after_sys[2][last] + 100.0);
    config_state_free(&a);
    config_state_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shared_noise_covariance),
        cmocka_unit_test(test_common_signs_need_four),
        cmocka_unit_test(test_line_offsets),
        cmocka_unit_test(test_line_error_in_the_systematic_part),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
