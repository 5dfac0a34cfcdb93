/* test_dss_labfit.c - `sunmc calibrate`'s DSS report: the propagated
 * sigma (implicit-function derivative) against finite differences. */
#include "test_util.h"

#include "calreport.h"
#include "config.h"
#include "csv.h"
#include "dss_labfit.h"
#include "rotation.h"
#include "ess_labfit.h"
#include "ess_unit.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[512]; /* this suite's directory in the private temporary one */

static int setup(void **state)
{
    gsl_set_error_handler_off();
    return test_private_dir(dir, sizeof dir, "dsscal");
}

/* ---- DSS: propagated sigma, simulate -> calibrate -> compensate, and an
 * independent pinhole + flat-glass model ---- */

/* dss_labfit_sigma (implicit-function derivative) against a derivative of
 * the compensated angles taken by perturbing each parameter, re-preparing
 * the model and inverting the same spot (dss_model_compensate). */
static void test_dss_sigma_matches_finite_differences(void **state)
{
    config_state st;
    char cerr[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, "configs/dss.ini", NULL, 0, cerr, sizeof cerr), SUNMC_OK);
    dss_model m;
    dss_model_init(&m, &dss_cfg(&st.cfg)->design);
    m.p[DSS_P_X0] += 0.003;
    m.p[DSS_P_C1] += 20 * RAD_PER_ARCSEC;
    m.p[DSS_P_C3] -= 30 * RAD_PER_ARCSEC;
    dss_model_prepare(&m);
    int idx[DSS_NP], nf = DSS_NP;
    double var[DSS_NP], cov[DSS_NP * DSS_NP] = {0};
    for (int k = 0; k < DSS_NP; k++) {
        idx[k] = k;
        var[k] = (k >= DSS_P_C1 && k <= DSS_P_C3) ? pow(2 * RAD_PER_ARCSEC, 2)
                                                  : (k == DSS_P_N ? 1e-6 : 1e-8);
        cov[k * nf + k] = var[k];
    }
    const double bs[][2] = {{0, 0}, {0.3, -0.2}, {-0.7, 0.5}, {0.9, 0.1}};
    for (int t = 0; t < 4; t++) {
        double sg[2], spot[2];
        assert_int_equal(dss_labfit_sigma(&m, cov, idx, nf, bs[t][0], bs[t][1], sg), SUNMC_OK);
        assert_int_equal(dss_model_spot(&m, bs[t][0], bs[t][1], spot, NULL), SUNMC_OK);
        double v[2] = {0, 0};
        for (int k = 0; k < nf; k++) {
            double h = 1e-3 * sqrt(var[k]), g[2][2];
            for (int s = 0; s < 2; s++) {
                dss_model q = m;
                q.p[k] += s ? h : -h;
                dss_model_prepare(&q);
                assert_int_equal(dss_model_compensate(&q, spot[0], spot[1], &g[s][0], &g[s][1]),
                                 SUNMC_OK);
            }
            for (int a = 0; a < 2; a++) {
                double d = (g[1][a] - g[0][a]) / (2 * h);
                v[a] += d * d * var[k];
            }
        }
        for (int a = 0; a < 2; a++) {
            assert_true(sqrt(v[a]) > 0.1 * RAD_PER_ARCSEC); /* not trivially zero */
            assert_near(sg[a], sqrt(v[a]), 1e-4 * sqrt(v[a]));
        }
    }
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dss_sigma_matches_finite_differences),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
