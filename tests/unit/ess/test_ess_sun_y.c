/* test_ess_sun_y.c - calibration.sun_y = measured: the sun simulator's
 * tilt toward Y fixed at a measurement instead of fitted.  Exact recovery
 * with the tilt known, one parameter fewer, standard errors of b and c
 * against the Schur complement of the full fit's covariance (an
 * independent derivation), the measurement's stream, params.ini both
 * ways, the report's advice, and the key's error paths. */
#include "test_measured.h"

#include "config.h"
#include "ess_labfit.h"
#include "ess_calib.h"
#include "ess_config.h"
#include "ess_model.h"
#include "budget.h"
#include "ess_sensor.h"
#include "params_io.h"
#include "registry.h"
#include "rng.h"
#include "sensitivity.h"
#include "status.h"
#include "units.h"

#include <gsl/gsl_matrix.h>
#include <stdlib.h>

#define THETA0_RAD (2.0 * RAD_PER_DEG)
#define SUN_Y_ARCSEC 34.0

/* A truth of kind `kind` with every parameter of its size on a unit. */
static void truth_model(ess_model *m, int kind)
{
    ess_model_init_kind(m, kind, THETA0_RAD, 12 * RAD_PER_ARCSEC);
    m->p[ESS_P_A] = 1.0004;
    m->p[ESS_P_B] = -2.0e-4;
    m->p[ESS_P_C] = 1.0e-4;
    m->p[ESS_P_KS] = 120 * RAD_PER_ARCSEC;
    m->p[ESS_P_KC] = -80 * RAD_PER_ARCSEC;
    m->p[ESS_P_INST_Y] = 100 * RAD_PER_ARCSEC;
    m->p[ESS_P_INST_Z] = -60 * RAD_PER_ARCSEC;
    m->p[ESS_P_SUN_Y] = SUN_Y_ARCSEC * RAD_PER_ARCSEC;
    for (int j = ESS_NP; j < m->np; j++)
        m->p[j] = (j % 2 ? 7.0 : -5.0) * RAD_PER_ARCSEC;
    ess_model_prepare(m);
}

/* The shipped campaign (0.7 deg x beta -30, 0, 30) read by truth, plus a
 * deterministic pseudo-noise of amplitude noise_arcsec. */
static ess_calib_workspace *campaign(const ess_model *truth, int fix, double noise_arcsec)
{
    const double betas[] = {-30, 0, 30};
    long na = 178;
    ess_calib_workspace *cw = ess_calib_alloc_fix((size_t)(na * 3), truth->kind, fix);
    assert_non_null(cw);
    size_t i = 0;
    rng_stream r;
    rng_stream_init(&r, 7, 0, 0);
    for (int k = 0; k < 3; k++)
        for (long j = 0; j < na; j++, i++) {
            cw->alpha_rad[i] = (-61.95 + 0.7 * (double)j) * RAD_PER_DEG;
            cw->beta_rad[i] = betas[k] * RAD_PER_DEG;
            cw->weight[i] = 1;
            cw->raw_rad[i] = ess_model_predict(truth, cw->alpha_rad[i], cw->beta_rad[i], NULL) +
                             noise_arcsec * RAD_PER_ARCSEC * rng_normal(&r);
        }
    cw->sun_y_rad = truth->p[ESS_P_SUN_Y];
    return cw;
}

/* Noise-free data, the tilt measured exactly: every parameter back to
 * rounding, the tilt untouched, one parameter fewer in the fit. */
static void recovers_exactly(void **state)
{
    for (int kind = ESS_MODEL_PAPER; kind <= ESS_MODEL_EXTENDED; kind++) {
        ess_model truth, fit;
        truth_model(&truth, kind);
        ess_calib_workspace *cw = campaign(&truth, 1, 0);
        assert_int_equal(cw->np_fit, ess_model_np(kind) - 1);
        assert_int_equal((int)cw->fw->p, ess_model_np(kind) - 1);
        fit_result fr;
        assert_int_equal(ess_calibrate(cw, THETA0_RAD, truth.roll_rad, 0.2, 100, &fit, &fr),
                         SUNMC_OK);
        assert_true(fit.sun_y_fixed);
        assert_true(fit.p[ESS_P_SUN_Y] == truth.p[ESS_P_SUN_Y]);
        assert_near(fit.p[ESS_P_B], truth.p[ESS_P_B], 1e-11);
        assert_near(fit.p[ESS_P_C], truth.p[ESS_P_C], 1e-11);
        for (int j = 0; j < fit.np; j++)
            assert_near(fit.p[j], truth.p[j], 1e-10);
        ess_calib_free(cw);
        /* a wrong measurement goes into b and c: at beta = 0 a tilt error e
         * is b = -c = tan(e) (within the 1 - cos 30 deg the lines add) */
        cw = campaign(&truth, 1, 0);
        double e = 10 * RAD_PER_ARCSEC;
        cw->sun_y_rad += e;
        assert_int_equal(ess_calibrate(cw, THETA0_RAD, truth.roll_rad, 0.2, 100, &fit, &fr),
                         SUNMC_OK);
        assert_true(fabs(fit.p[ESS_P_B] - truth.p[ESS_P_B] + tan(e)) < 0.2 * e);
        assert_true(fabs(fit.p[ESS_P_C] - truth.p[ESS_P_C] - tan(e)) < 0.2 * e);
        ess_calib_free(cw);
    }
}

/* Fixing a parameter at its fitted value leaves the solution where it was,
 * and the covariance of the rest is the inverse of J^T J without the
 * tilt's row and column: the Schur complement of the full covariance,
 * C_bb - C_bs C_ss^-1 C_sb.  On the shipped campaign that shrinks b's and
 * c's standard errors several-fold (|r| with the tilt 0.98-0.99). */
static void covariance_is_schur_complement(void **state)
{
    for (int kind = ESS_MODEL_PAPER; kind <= ESS_MODEL_EXTENDED; kind++) {
        ess_model truth, full, fixed;
        truth_model(&truth, kind);
        ess_calib_workspace *cf = campaign(&truth, 0, 20);
        fit_result fr;
        assert_int_equal(ess_calibrate(cf, THETA0_RAD, truth.roll_rad, 0.2, 100, &full, &fr),
                         SUNMC_OK);
        assert_int_equal(fit_covariance(cf->fw), SUNMC_OK);
        ess_calib_workspace *cx = campaign(&truth, 1, 20);
        cx->sun_y_rad = full.p[ESS_P_SUN_Y];
        assert_int_equal(ess_calibrate(cx, THETA0_RAD, truth.roll_rad, 0.2, 100, &fixed, &fr),
                         SUNMC_OK);
        assert_int_equal(fit_covariance(cx->fw), SUNMC_OK);
        /* to the fits' convergence (a cost change below 1e-12): 1e-9 rad
         * is 0.0002 arcsec, a thousandth of a standard error */
        for (int j = 0; j < full.np; j++)
            assert_near(fixed.p[j], full.p[j], 1e-9);
        const gsl_matrix *C = cf->fw->covar, *X = cx->fw->covar;
        double css = gsl_matrix_get(C, ESS_P_SUN_Y, ESS_P_SUN_Y);
        for (int i = 0; i < cx->np_fit; i++)
            for (int j = 0; j < cx->np_fit; j++) {
                size_t pi = (size_t)ess_calib_param_of(cx, i), pj = (size_t)ess_calib_param_of(cx, j);
                double schur = gsl_matrix_get(C, pi, pj) - gsl_matrix_get(C, pi, ESS_P_SUN_Y) *
                                                               gsl_matrix_get(C, ESS_P_SUN_Y, pj) /
                                                               css;
                double scale = sqrt(gsl_matrix_get(C, pi, pi) * gsl_matrix_get(C, pj, pj));
                assert_near(gsl_matrix_get(X, (size_t)i, (size_t)j), schur, 1e-6 * scale);
            }
        /* b and c: the shrink is sqrt(1 - r^2) of their correlation with the tilt */
        for (int p = ESS_P_B; p <= ESS_P_C; p++) {
            double r = gsl_matrix_get(C, (size_t)p, ESS_P_SUN_Y) /
                       sqrt(gsl_matrix_get(C, (size_t)p, (size_t)p) * css);
            double shrink = sqrt(gsl_matrix_get(X, (size_t)p, (size_t)p) /
                                 gsl_matrix_get(C, (size_t)p, (size_t)p));
            assert_near(shrink, sqrt(1 - r * r), 1e-6);
            assert_true(fabs(r) > 0.97 && shrink < 0.25);
        }
        ess_calib_free(cf);
        ess_calib_free(cx);
    }
}

static void load_config(config_state *st, const char *const *sets, int n)
{
    char err[SUNMC_ERRLEN];
    if (config_build(st, "configs/ess_type_a.ini", sets, n, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    /* fitted against measured tilts, without priors */
    st->cfg.cal_priors = CONFIG_PRIORS_OFF;
}

/* The measurement: the true tilt plus calibration.sun_y_sigma_arcsec of
 * normal error from its own stream (mean 0, sd sigma over units), 0 when
 * the tilt is fitted, and no deviation moves when the mode changes. */
static void measurement_stream(void **state)
{
    config_state sf, sm;
    const char *sets[] = {"calibration.sun_y=measured", "calibration.sun_y_sigma_arcsec=7"};
    load_config(&sf, NULL, 0);
    load_config(&sm, sets, 2);
    const sunmc_config *fitted = &sf.cfg, *meas = &sm.cfg;
    const long n = 4000;
    double sum = 0, sum2 = 0, cross = 0;
    for (long u = 0; u < n; u++) {
        ess_deviations a, b;
        ess_deviations_sample(fitted, 1, u, &a);
        ess_deviations_sample(meas, 1, u, &b);
        assert_memory_equal(&a, &b, sizeof a);
        assert_true(ess_sun_y_measured_arcsec(fitted, 1, u, &a) == 0.0);
        double e = ess_sun_y_measured_arcsec(meas, 1, u, &b) - b.sun_y_arcsec;
        sum += e;
        sum2 += e * e;
        cross += e * (b.roll_measured_arcsec - b.install_x_arcsec);
    }
    double mean = sum / n, sd = sqrt(sum2 / n - mean * mean);
    /* its own stream: uncorrelated with the roll's measurement error (sd 5) */
    assert_true(fabs(cross / n / (7.0 * 5.0)) < 4.5 / sqrt((double)n));
    /* 4.5 standard errors: mean 7/sqrt(n), sd 7/sqrt(2 n) */
    assert_true(fabs(mean) < 4.5 * 7 / sqrt((double)n));
    assert_true(fabs(sd - 7) < 4.5 * 7 / sqrt(2.0 * n));
    config_state_free(&sf);
    config_state_free(&sm);
}

/* The measurement is an input of `sensitivity` and `budget` only when the
 * tilt is measured: fitted, its stream is never drawn. */
static void noise_source_only_when_measured(void **state)
{
    const char *sets[] = {"calibration.sun_y=measured"};
    for (int measured = 0; measured <= 1; measured++) {
        config_state st;
        load_config(&st, sets, measured);
        test_measurement_source(&st.cfg, "sun_y_measurement", RNG_STREAM_SUN_Y,
                                "calibration.sun_y_sigma_arcsec", measured);
        config_state_free(&st);
    }
}

/* params.ini of a measured tilt: [fixed] sun_y_measured_arcsec, no
 * fit_sun_y_arcsec in [parameters]; loaded back, the same model. */
static void params_round_trip(void **state)
{
    ess_model truth, fit, back;
    truth_model(&truth, ESS_MODEL_PAPER);
    ess_calib_workspace *cw = campaign(&truth, 1, 0);
    fit_result fr;
    assert_int_equal(ess_calibrate(cw, THETA0_RAD, truth.roll_rad, 0.2, 100, &fit, &fr),
                     SUNMC_OK);
    ess_labfit_result res = {.m = fit};
    static params_file p;
    params_init(&p);
    snprintf(p.path, sizeof p.path, "%s", "sun_y_params.ini");
    assert_int_equal(ess_params_fill(&p, &res, NULL, 2.0), SUNMC_OK);
    assert_null(params_find(&p, "parameters", "fit_sun_y_arcsec"));
    const params_entry *e = params_find(&p, "fixed", ESS_SUN_Y_MEASURED_KEY);
    assert_non_null(e);
    assert_near(strtod(e->value, NULL), SUN_Y_ARCSEC, 1e-9);
    assert_int_equal(params_set_text(&p, "calibration", "sensor", "ess", ""), SUNMC_OK);
    assert_int_equal(params_set_text(&p, "calibration", "model", ESS_CALFIT_MODEL, ""), SUNMC_OK);
    char err[SUNMC_ERRLEN];
    assert_int_equal(ess_params_load(&p, &back, err, sizeof err), SUNMC_OK);
    assert_true(back.sun_y_fixed);
    for (int j = 0; j < fit.np; j++)
        assert_near(back.p[j], fit.p[j], 1e-15 + 1e-14 * fabs(fit.p[j]));
    ess_calib_free(cw);
}

/* calibrate's fit with the tilt measured (extended model, whose
 * parameters after the tilt shift by one in the fit's vector): the
 * covariance goes to the model's slots, 0 in the tilt's row; params.ini's
 * standard errors are the right parameters'. */
static void calfit_maps_covariance(void **state)
{
    ess_model truth;
    truth_model(&truth, ESS_MODEL_EXTENDED);
    ess_calib_workspace *cw = campaign(&truth, 1, 20);
    config_state st;
    const char *sets[] = {"calibration.model=extended", "calibration.sun_y=measured",
                          "calibration.sun_y_measured_arcsec=34",
                          "calibration.roll_measured_arcsec=12"};
    load_config(&st, sets, 4);
    static ess_labfit_result res;
    static calreport rep;
    static params_file p;
    char err[SUNMC_ERRLEN];
    assert_int_equal(ess_labfit_run(&st.cfg, cw, NULL, &res, &rep, err, sizeof err), SUNMC_OK);
    assert_int_equal(rep.np, ESS_NP_EXT - 1);
    assert_int_equal(rep.dof, (int)cw->n - (ESS_NP_EXT - 1));
    for (int j = 0; j < ESS_NP_EXT; j++)
        assert_true(res.cov[ESS_P_SUN_Y][j] == 0 && res.cov[j][ESS_P_SUN_Y] == 0);
    /* the report's standard errors (in each name's unit) are the fit's */
    for (int i = 0; i < cw->np_fit; i++) {
        int q = ess_calib_param_of(cw, i);
        assert_string_equal(rep.name[i], ess_param_names[q]);
        const char *name = ess_param_names[q];
        double scale = strstr(name, "_deg") ? DEG_PER_RAD
                       : strstr(name, "_arcsec") ? ARCSEC_PER_RAD
                                                 : 1.0;
        assert_near(sqrt(res.cov[q][q]) * scale, rep.se[i], 1e-9 * rep.se[i]);
    }
    params_init(&p);
    assert_int_equal(ess_params_fill(&p, &res, &rep, 2.0), SUNMC_OK);
    for (int i = 0; i < cw->np_fit; i++) {
        const params_entry *e = params_find(&p, "parameters", rep.name[i]);
        char want[64];
        snprintf(want, sizeof want, "standard error %.3g", rep.se[i]);
        assert_non_null(e);
        if (!strstr(e->comment, want))
            fail_msg("%s: '%s' lacks '%s'", rep.name[i], e->comment, want);
    }
    config_state_free(&st);
    ess_calib_free(cw);
}

/* calibrate: with the tilt measured the report has 7 parameters, one more
 * degree of freedom, and no longer advises measuring the tilt; fitted, it
 * does (naming the key). */
static void calibrate_report(void **state)
{
    const char *d = test_tmp("cal");
    assert_int_equal(mkdir(d, 0700), 0);
    char out[65536];
    assert_int_equal(test_sunmc_in(d, "simulate configs/ess_type_a.ini --unit 3 --set "
                                      "calibration.sun_y=measured --out $D/sim --quiet",
                                   out, sizeof out),
                     0);
    assert_int_equal(test_sunmc_in(d, "calibrate --config configs/ess_type_a.ini "
                                      "--set calibration.priors=off "
                                      "$D/sim/campaign.csv --out $D/fitted",
                                   out, sizeof out),
                     0);
    assert_non_null(strstr(out, "526 degrees of freedom"));
    assert_non_null(strstr(out, "--set calibration.sun_y=measured --set "
                                "calibration.sun_y_measured_arcsec=VALUE"));
    assert_int_equal(
        test_sunmc_in(d, "calibrate --config configs/ess_type_a.ini --set calibration.sun_y=measured "
                         "--set calibration.sun_y_measured_arcsec=34 $D/sim/campaign.csv --out "
                         "$D/measured",
                      out, sizeof out),
        0);
    assert_non_null(strstr(out, "527 degrees of freedom"));
    assert_null(strstr(out, "fit_sun_y_arcsec"));
    assert_null(strstr(out, "sun simulator's tilt"));
    assert_non_null(strstr(out, "paper        7 parameters"));
    assert_non_null(strstr(out, "extended    17 parameters"));
    /* the campaign file carries the unit's simulated measurement */
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "grep -q '^# measured sun-simulator tilt toward Y: "
             "calibration.sun_y_measured_arcsec = ' %s/sim/campaign.csv",
             d);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
}

/* Bad values of the keys: FILE:LINE, exit 2, nothing written. */
static void bad_values(void **state)
{
    static const char *const cases[][2] = {
        {"sun_y = measure\n", "calibration.sun_y = 'measure' is not allowed: one of fitted|measured"},
        {"sun_y_sigma_arcsec = -1\n", "calibration.sun_y_sigma_arcsec"},
        {"sun_y_sigma_arcsec = 3601\n", "calibration.sun_y_sigma_arcsec"},
        {"sun_y_measured_arcsec = 36001\n", "calibration.sun_y_measured_arcsec"},
        {"sun_y_measured_arcsec = -36001\n", "calibration.sun_y_measured_arcsec"},
    };
    test_bad_calibration_lines("ess", cases, sizeof cases / sizeof *cases);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(recovers_exactly),
        cmocka_unit_test(covariance_is_schur_complement),
        cmocka_unit_test(measurement_stream),
        cmocka_unit_test(noise_source_only_when_measured),
        cmocka_unit_test(params_round_trip),
        cmocka_unit_test(calfit_maps_covariance),
        cmocka_unit_test(calibrate_report),
        cmocka_unit_test(bad_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
