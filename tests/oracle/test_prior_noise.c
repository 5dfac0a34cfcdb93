/* test_prior_noise.c - issue 43: the reading noise the priors' pilot
 * assumes is that of a campaign point's mean.  calibration.priors weighs
 * each prior row sigma_row / sigma_j, sigma_row one data row's noise; a row
 * is the mean of campaign.repeats readings, so its noise is the single
 * reading's over sqrt(repeats).  A pilot that ignored the averaging gave
 * the priors sqrt(repeats) too little weight and nothing noticed.  Closed
 * forms of each family's single reading, then the repeats' scaling. */
#include "test_util.h"

#include "dss_config.h"
#include "dss_prior.h"
#include "ess_config.h"
#include "ess_prior.h"

static void build(config_state *st, const char *path, const char *const *sets, int n)
{
    char err[SUNMC_ERRLEN];
    if (config_build(st, path, sets, n, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
}

/* ESS: the phase noise of a row current (theta0 per 2 pi of phase, the
 * current's relative sigma over sqrt 2 of the differential pair) and the
 * encoder's, in quadrature; over sqrt(repeats) for a point's mean. */
static void test_ess_noise_of_the_mean(void **state)
{
    const char *sets[] = {"noise.row_current_pct=0.5", "noise.encoder_arcsec=2",
                          "campaign.repeats=1"};
    config_state st;
    build(&st, "configs/ess_type_a.ini", sets, 3);
    const ess_config *e = ess_cfg(&st.cfg);
    double phase = e->design.theta0_deg * 3600.0 / (2 * M_PI) * 0.005 / sqrt(2.0);
    double one = sqrt(phase * phase + 4.0);
    assert_near(ess_reading_noise_arcsec(&st.cfg), one, 1e-12 * one);
    config_state_free(&st);
    for (int r = 2; r <= 9; r += 7) {
        char rep[64];
        snprintf(rep, sizeof rep, "campaign.repeats=%d", r);
        sets[2] = rep;
        build(&st, "configs/ess_type_a.ini", sets, 3);
        assert_near(ess_reading_noise_arcsec(&st.cfg), one / sqrt((double)r), 1e-12 * one);
        config_state_free(&st);
    }
}

/* DSS: the centroid's sigma and the encoder's, seen at the focal distance
 * h in pixels, in quadrature; over sqrt(repeats). */
static void test_dss_noise_of_the_mean(void **state)
{
    const char *sets[] = {"noise.centroid_px=0.03", "noise.encoder_arcsec=5", "campaign.repeats=1"};
    config_state st;
    build(&st, "configs/dss.ini", sets, 3);
    const dss_config *d = dss_cfg(&st.cfg);
    double enc_px = 5.0 / 206264.80624709636 * d->design.h_mm / (d->design.pixel_um * 1e-3);
    double one = sqrt(0.03 * 0.03 + enc_px * enc_px);
    assert_near(dss_reading_noise_px(&st.cfg), one, 1e-12 * one);
    config_state_free(&st);
    sets[2] = "campaign.repeats=4";
    build(&st, "configs/dss.ini", sets, 3);
    assert_near(dss_reading_noise_px(&st.cfg), one / 2, 1e-12 * one);
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ess_noise_of_the_mean),
        cmocka_unit_test(test_dss_noise_of_the_mean),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
