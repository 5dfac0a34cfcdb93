/* test_prior_keys.c - the pilot cache's keys (prior_cache.h) hold every
 * input of a pilot: the same config on other campaign angles (ESS betas,
 * DSS table angles) or another nominal design (DSS) is another pilot, whose
 * priors are those made fresh; the same inputs again are the same bits. */
#include "test_util.h"

#include "dss_calib.h"
#include "dss_prior.h"
#include "dss_unit.h"
#include "ess_calib.h"
#include "ess_prior.h"
#include "ess_unit.h"
#include "prior_cache.h"
#include "status.h"
#include "units.h"

#include <stdlib.h>

/* The ESS pilot of config c on its campaign with every beta moved by
 * shift_deg (0: as configured), its priors into p. */
static void ess_pilot(const sunmc_config *c, double shift_deg, calib_prior *p)
{
    char err[SUNMC_ERRLEN];
    ess_calib_workspace *cw = ess_calib_alloc_fix(ess_campaign_size(c), ess_cfg(c)->cal_model, 0);
    assert_non_null(cw);
    ess_campaign_angles(c, cw);
    for (size_t i = 0; i < cw->n; i++)
        cw->beta_rad[i] += shift_deg * RAD_PER_DEG;
    assert_int_equal(ess_prior_pilot(c, cw, p, err, sizeof err), SUNMC_OK);
    ess_calib_free(cw);
}

static void test_ess_betas_in_key(void **state)
{
    sunmc_config c = test_family_config("ess");
    calib_prior a, b, b_fresh, a_again;
    prior_cache_clear();
    ess_pilot(&c, 0.0, &a);
    ess_pilot(&c, 5.0, &b);
    prior_cache_clear();
    ess_pilot(&c, 5.0, &b_fresh);
    ess_pilot(&c, 0.0, &a_again);
    assert_memory_equal(&b, &b_fresh, sizeof b);
    assert_memory_equal(&a, &a_again, sizeof a);
    int differ = 0;
    for (int j = 0; j < a.np; j++)
        differ |= a.mean[j] != b.mean[j];
    assert_true(differ);
}

/* The DSS pilot with the nominal pinhole height moved by dh_mm. */
static void dss_pilot(const sunmc_config *c, double dh_mm, calib_prior *p)
{
    char err[SUNMC_ERRLEN];
    dss_calib_workspace *cw = dss_calib_alloc_config(dss_cfg(c), dss_campaign_size(c));
    assert_non_null(cw);
    dss_campaign_angles(c, cw->b1_rad, cw->b2_rad);
    cw->design.h_mm += dh_mm;
    assert_int_equal(dss_prior_apply(c, cw, p, err, sizeof err), SUNMC_OK);
    dss_calib_free(cw);
}

static void test_dss_design_in_key(void **state)
{
    sunmc_config c = test_family_config("dss");
    calib_prior a, b, b_fresh;
    prior_cache_clear();
    dss_pilot(&c, 0.0, &a);
    dss_pilot(&c, 0.01, &b);
    prior_cache_clear();
    dss_pilot(&c, 0.01, &b_fresh);
    assert_memory_equal(&b, &b_fresh, sizeof b);
    int differ = 0;
    for (int j = 0; j < a.np; j++)
        differ |= a.mean[j] != b.mean[j];
    assert_true(differ);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ess_betas_in_key),
        cmocka_unit_test(test_dss_design_in_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
