/* test_dss_calib.c - the DSS calibration models: the physical model against
 * the ray-traced sensor, its Jacobian and inverse; fits that recover known
 * parameters; the polynomial on exact polynomial data; the family end to end
 * (determinism, physical better than polynomial); every error path. */
#include "test_util.h"

#include "config.h"
#include "calreport.h"
#include "dss_labfit.h"
#include "dss_calib.h"
#include "dss_model.h"
#include "rotation.h"
#include "dss_unit.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit.h>

static sunmc_config dss_test_config(const char *const *extra, int n_extra)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    const char *sets[8] = {"sensor.family=dss"};
    for (int i = 0; i < n_extra; i++)
        sets[1 + i] = extra[i];
    assert_int_equal(config_build(&st, NULL, sets, 1 + n_extra, err, sizeof err), SUNMC_OK);
    sunmc_config c = st.cfg;
    config_state_free(&st);
    return c;
}

static const dss_deviations test_dev = {0.17, -0.08, 0.06, 9.0, -7.0, 8.0, -6.0, 0.004, 7.0, -5.0};

/* The model with the unit's true parameters. */
static void true_model(const sunmc_config *c, const dss_sensor *s, dss_model *m)
{
    dss_model_init(m, &dss_cfg(c)->design);
    m->p[DSS_P_X0] = s->pinhole_mm[0];
    m->p[DSS_P_Y0] = s->pinhole_mm[1];
    m->p[DSS_P_H] = s->pinhole_mm[2];
    m->p[DSS_P_T] = s->glass_t_mm;
    m->p[DSS_P_N] = s->glass_n;
    m->p[DSS_P_C1] = test_dev.c1_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_C2] = test_dev.c2_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_C3] = test_dev.c3_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_S1] = test_dev.sun_b1_arcsec * RAD_PER_ARCSEC;
    m->p[DSS_P_S2] = test_dev.sun_b2_arcsec * RAD_PER_ARCSEC;
    dss_model_prepare(m);
}

/* Closed-form model = ray-traced sensor; compensation returns the truth. */
static void test_model_matches_sensor(void **state)
{
    sunmc_config c = dss_test_config(NULL, 0);
    dss_sensor s;
    dss_sensor_init(&s, &dss_cfg(&c)->design, &test_dev, 0);
    dss_model m;
    true_model(&c, &s, &m);
    int n = 0;
    for (double b1 = -60; b1 <= 60; b1 += 3.7)
        for (double b2 = -60; b2 <= 60; b2 += 3.7) {
            double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG, x, y, sp[2], a, b, a0, b0;
            if (dss_sensor_read(&s, r1, r2, NULL, &x, &y) != SUNMC_OK)
                continue;
            n++;
            assert_int_equal(dss_model_spot(&m, r1, r2, sp, NULL), SUNMC_OK);
            assert_near(sp[0], x, 1e-9);
            assert_near(sp[1], y, 1e-9);
            assert_int_equal(dss_model_compensate(&m, x, y, &a, &b), SUNMC_OK);
            dss_sensor_truth(&s, r1, r2, &a0, &b0);
            assert_near(a * ARCSEC_PER_RAD, a0 * ARCSEC_PER_RAD, 1e-6);
            assert_near(b * ARCSEC_PER_RAD, b0 * ARCSEC_PER_RAD, 1e-6);
        }
    assert_true(n > 700);
}

/* Analytic Jacobian against central differences. */
static void test_model_jacobian(void **state)
{
    sunmc_config c = dss_test_config(NULL, 0);
    dss_sensor s;
    dss_sensor_init(&s, &dss_cfg(&c)->design, &test_dev, 0);
    dss_model m;
    true_model(&c, &s, &m);
    const double steps[DSS_NP] = {1e-6, 1e-6, 1e-6, 1e-6, 1e-7, 1e-7,
                                  1e-7, 1e-6, 1e-7, 1e-7, 1e-7, 1e-7};
    for (double b1 = -50; b1 <= 50; b1 += 25)
        for (double b2 = -50; b2 <= 50; b2 += 25) {
            double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG, sp[2], J[2][DSS_NP];
            assert_int_equal(dss_model_spot(&m, r1, r2, sp, J), SUNMC_OK);
            for (int j = 0; j < DSS_NP; j++) {
                dss_model mp = m, mm = m;
                mp.p[j] += steps[j];
                mm.p[j] -= steps[j];
                dss_model_prepare(&mp);
                dss_model_prepare(&mm);
                double sp_p[2], sp_m[2];
                dss_model_spot(&mp, r1, r2, sp_p, NULL);
                dss_model_spot(&mm, r1, r2, sp_m, NULL);
                for (int a = 0; a < 2; a++) {
                    double num = (sp_p[a] - sp_m[a]) / (2 * steps[j]);
                    assert_near(J[a][j], num, 1e-5 * (1 + fabs(num)));
                }
            }
        }
}

/* Noise-free campaign of one unit through the workspace. */
static dss_calib_workspace *campaign(const sunmc_config *c, const dss_deviations *dev, long unit,
                                     dss_unit *u)
{
    const dss_config *dc = dss_cfg(c);
    dss_unit_build(c, dev, u);
    dss_calib_workspace *cw = dss_calib_alloc(&dc->design, dss_campaign_size(c), dc->cal_model,
                                              dc->poly_order, dc->fit_glass_index);
    assert_non_null(cw);
    size_t seen = dss_unit_campaign(c, u, unit, cw->b1_rad, cw->b2_rad, cw->x_px, cw->y_px,
                                    cw->weight, NULL, NULL);
    assert_true(seen > 400 && seen < cw->n); /* the corners are off the detector */
    return cw;
}

static const char *const quiet[] = {"noise.centroid_px=0", "noise.encoder_arcsec=0",
                                    "noise.s_curve=off"};
/* ...and the detector's fixed pattern and the glass's ghost, which no
 * model follows (dss_pattern.h) */
static const char *const no_pattern[] = {"tolerance.prnu_pct=0", "tolerance.dsnu_pct=0",
                                         "tolerance.glass_ghost=0"};

/* Noise-free data: the physical fit recovers every parameter. */
static void physical_fit_recovers(const char *disc)
{
    const char *sets[] = {quiet[0], quiet[1], quiet[2], disc};
    sunmc_config c = dss_test_config(sets, 4);
    dss_unit u;
    dss_calib_workspace *cw = campaign(&c, &test_dev, 0, &u);
    dss_calibration cal;
    fit_result fr;
    assert_int_equal(dss_calibrate(cw, c.max_iterations, &cal, &fr), SUNMC_OK);
    double par[UNIT_MAX_PAR];
    double corr;
    int i, j;
    assert_int_equal(dss_calib_correlation(cw, &corr, &i, &j), SUNMC_OK);
    dss_par_values(&c, &cal, corr, i, j, fr.rcond, par, UNIT_MAX_PAR);
    assert_near(par[0], test_dev.dx_px, 1e-6);
    assert_near(par[1], test_dev.dy_px, 1e-6);
    assert_near(par[2], test_dev.dh_px, 1e-4);
    assert_near(par[3], test_dev.glass_thickness_um, 1e-2);
    assert_near(par[4], test_dev.c1_arcsec, 1e-4);
    assert_near(par[5], test_dev.c2_arcsec, 1e-4);
    assert_near(par[6], test_dev.c3_arcsec, 1e-4);
    assert_near(par[7], test_dev.glass_index, 1e-5);
    /* the conditioning finding of dss_calib.h: H and n are the worst pair */
    assert_true(corr > 0.95);
    assert_int_equal(i, DSS_P_H);
    assert_int_equal(j, DSS_P_N);
    assert_true(dss_calib_residual_rms(cw, &cal) * ARCSEC_PER_RAD < 1e-6);
    dss_calib_free(cw);
}

static void test_physical_fit_recovers(void **state)
{
    physical_fit_recovers("design.sun_disc_deg=0");
}

/* The sun's disc in the data and the model: the fit is not biased by it. */
static void test_physical_fit_recovers_disc(void **state)
{
    physical_fit_recovers("design.sun_disc_deg=0.533");
}

/* Holding the index at design leaves a bias of tenths of an arcsecond. */
static void test_fixed_index_bias(void **state)
{
    const char *sets[] = {quiet[0], quiet[1], quiet[2], "calibration.fit_glass_index=off"};
    sunmc_config c = dss_test_config(sets, 4);
    dss_unit u;
    dss_calib_workspace *cw = campaign(&c, &test_dev, 0, &u);
    assert_int_equal(cw->n_free, DSS_P_TX - 1); /* no index, no tilt */
    dss_calibration cal;
    fit_result fr;
    assert_int_equal(dss_calibrate(cw, c.max_iterations, &cal, &fr), SUNMC_OK);
    assert_near(cal.phys.p[DSS_P_N], dss_cfg(&c)->design.glass_index, 0);
    double rms = dss_calib_residual_rms(cw, &cal) * ARCSEC_PER_RAD;
    assert_true(rms > 0.05 && rms < 2.0);
    dss_calib_free(cw);
}

/* The polynomial fit recovers a polynomial exactly: readings whose truth is
 * the on-board angles plus a known order-2 polynomial. */
static void test_polynomial_exact(void **state)
{
    const char *sets[] = {"calibration.model=polynomial", "calibration.poly_order=2"};
    sunmc_config c = dss_test_config(sets, 2);
    dss_config *dc = dss_cfg(&c);
    dss_calib_workspace *cw = dss_calib_alloc(&dc->design, 400, DSS_MODEL_POLYNOMIAL, 2, 0);
    assert_non_null(cw);
    dss_poly truth;
    dss_onboard ob;
    dss_onboard_init(&ob, &dc->design);
    dss_poly_init(&truth, 2, &ob, dc->design.fov_deg * RAD_PER_DEG);
    const double ca[6] = {1e-4, -2e-4, 3e-5, 5e-5, -4e-5, 2e-5};
    const double cb[6] = {-3e-4, 1e-5, 2e-4, -1e-5, 6e-5, -7e-5};
    memcpy(truth.ca, ca, sizeof ca);
    memcpy(truth.cb, cb, sizeof cb);
    size_t i = 0;
    for (int k1 = 0; k1 < 20; k1++)
        for (int k2 = 0; k2 < 20; k2++, i++) {
            cw->x_px[i] = -900 + 95.0 * k1;
            cw->y_px[i] = -880 + 93.0 * k2;
            double a, b;
            dss_poly_compensate(&truth, cw->x_px[i], cw->y_px[i], &a, &b);
            cw->b2_rad[i] = -a; /* the table that sets truth (a, b) */
            cw->b1_rad[i] = atan(tan(b) * cos(cw->b2_rad[i]));
            cw->weight[i] = 1;
        }
    cw->weight[7] = 0;
    cw->x_px[7] = NAN; /* a dropped reading may hold anything */
    dss_calibration cal;
    fit_result fr;
    assert_int_equal(dss_calibrate(cw, 100, &cal, &fr), SUNMC_OK);
    assert_int_equal(cal.kind, DSS_MODEL_POLYNOMIAL);
    for (int k = 0; k < 6; k++) {
        assert_near(cal.poly.ca[k], ca[k], 1e-12);
        assert_near(cal.poly.cb[k], cb[k], 1e-12);
    }
    dss_calib_free(cw);
}

/* The basis in closed form: by total degree, u^(d-j) v^j for j = 0..d. */
static void test_polynomial_basis(void **state)
{
    (void)state;
    const double u = 0.3, v = -0.7;
    const double want[10] = {1,         u,         v,         u * u,         u * v,
                             v * v,     u * u * u, u * u * v, u * v * v, v * v * v};
    double t[10];
    assert_int_equal(dss_poly_n_terms(3), 10);
    dss_poly_basis(3, u, v, t);
    for (int k = 0; k < 10; k++)
        assert_near(t[k], want[k], 1e-15);
}

/* The family end to end on a few units: physical calibration reaches a
 * small fraction of an arcsecond noise-free and beats the polynomial by a
 * large factor; results do not depend on the order units run in. */
static void run_unit(const sunmc_config *c, long unit, unit_result *r)
{
    char err[SUNMC_ERRLEN];
    void *ws = c->family->workspace_alloc(c, err, sizeof err);
    assert_non_null(ws);
    assert_int_equal(c->family->unit_run(c, unit, ws, r), SUNMC_OK);
    c->family->workspace_free(ws);
}

static void test_family_units(void **state)
{
    const char *sets[] = {quiet[0], quiet[1], quiet[2], no_pattern[0], no_pattern[1], no_pattern[2]};
    sunmc_config c = dss_test_config(sets, 6);
    const char *psets[] = {quiet[0],      quiet[1],      quiet[2],
                           no_pattern[0], no_pattern[1], no_pattern[2],
                           "calibration.model=polynomial"};
    sunmc_config cp = dss_test_config(psets, 7);
    int band_all = 2; /* 0:60 */
    for (long unit = 0; unit < 3; unit++) {
        unit_result r, rp;
        run_unit(&c, unit, &r);
        run_unit(&cp, unit, &rp);
        assert_int_equal(r.fit_status, UNIT_FIT_OK);
        assert_int_equal(rp.fit_status, UNIT_FIT_OK);
        for (int a = 0; a < 3; a++) {
            /* the on-board formula corrects the nominal glass: what is left
             * before calibration is the unit's deviations, tens of arcsec */
            assert_true(r.rms_before[a][band_all] > 5 && r.rms_before[a][band_all] < 1000);
            assert_true(r.rms_after[a][band_all] < 0.01);
            assert_true(rp.rms_after[a][band_all] > 100 * r.rms_after[a][band_all]);
            assert_true(rp.rms_after[a][band_all] < r.rms_before[a][band_all]);
        }
    }
    /* determinism: unit 2 alone equals unit 2 after other units on the same
     * workspace, and a noisy config too */
    sunmc_config cn = dss_test_config(NULL, 0);
    unit_result a, b;
    run_unit(&cn, 2, &a);
    char err[SUNMC_ERRLEN];
    void *ws = cn.family->workspace_alloc(&cn, err, sizeof err);
    unit_result tmp;
    cn.family->unit_run(&cn, 5, ws, &tmp);
    cn.family->unit_run(&cn, 2, ws, &b);
    cn.family->workspace_free(ws);
    assert_memory_equal(&a, &b, sizeof a);
    assert_true(a.rms_after[0][band_all] > 1.0); /* centroid noise is in */
}

/* Error paths. */
static void test_errors(void **state)
{
    sunmc_config c = dss_test_config(NULL, 0);
    dss_config *dc = dss_cfg(&c);
    assert_null(dss_calib_alloc(&dc->design, 100, DSS_MODEL_POLYNOMIAL, 0, 0));
    assert_null(dss_calib_alloc(&dc->design, 100, DSS_MODEL_POLYNOMIAL, DSS_POLY_MAX_ORDER + 1, 0));
    assert_null(dss_calib_alloc(&dc->design, 5, DSS_MODEL_POLYNOMIAL, 3, 0)); /* 5 < 10 terms */
    assert_null(dss_calib_alloc(&dc->design, 3, DSS_MODEL_PHYSICAL, 0, 1)); /* 6 < 8 */
    /* too few usable readings */
    dss_calib_workspace *cw = dss_calib_alloc(&dc->design, 10, DSS_MODEL_PHYSICAL, 0, 1);
    assert_non_null(cw);
    dss_calibration cal;
    fit_result fr;
    assert_int_equal(dss_calibrate(cw, 100, &cal, &fr), SUNMC_EINPUT);
    dss_calib_free(cw);
    cw = dss_calib_alloc(&dc->design, 20, DSS_MODEL_POLYNOMIAL, 3, 0);
    cw->weight[0] = 1;
    assert_int_equal(dss_calibrate(cw, 100, &cal, &fr), SUNMC_EINPUT);
    dss_calib_free(cw);
    /* a spot no sun in front can make */
    dss_model m;
    dss_model_init(&m, &dc->design);
    double a, b;
    assert_int_equal(dss_model_compensate(&m, 1e9, 0, &a, &b), SUNMC_EDOM);
    double sp[2];
    assert_int_equal(dss_model_spot(&m, 0, 100 * RAD_PER_DEG, sp, NULL), SUNMC_EDOM);
    /* a sun off the detector */
    dss_sensor s;
    dss_deviations none = {0};
    dss_sensor_init(&s, &dc->design, &none, 0);
    double x, y;
    assert_int_equal(dss_sensor_read(&s, 70 * RAD_PER_DEG, 0, NULL, &x, &y), SUNMC_EDOM);
    /* a campaign too small to fit is refused with the config */
    const char *small[] = {"sensor.family=dss", "campaign.b_min_deg=-1", "campaign.b_max_deg=0",
                           "campaign.b_step_deg=1"};
    char err[SUNMC_ERRLEN] = "";
    config_state st;
    assert_int_equal(config_build(&st, NULL, small, 4, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "2 x 2 b grid = 4 readings"));
    /* a bad value of the new key names file, line and key */
    const char *bad = test_tmp("dss_bad.ini");
    assert_int_equal(test_write_file(bad,
                                     "[sensor]\nfamily = dss\n[calibration]\nfit_glass_index = maybe\n"),
                     0);
    int rc = config_build(&st, bad, NULL, 0, err, sizeof err);
    assert_int_equal(rc, SUNMC_EINPUT);
    assert_non_null(strstr(err, "dss_bad.ini:4"));
    assert_non_null(strstr(err, "fit_glass_index"));
}

/* The CLI: configs/dss.ini runs, is byte-identical across thread counts,
 * and names the model in units.tsv's columns. */
static void test_cli(void **state)
{
    char cmd[2048], out[8192];
    const char *run[2] = {test_tmp("dss_run1"), test_tmp("dss_run2")};
    for (int t = 1; t <= 2; t++) {
        snprintf(cmd, sizeof cmd, "%s run configs/dss.ini --units 12 --threads %d --out %s",
                 test_sunmc(), t, run[t - 1]);
        assert_int_equal(test_run(cmd, out, sizeof out), 0);
    }
    snprintf(cmd, sizeof cmd, "cmp %s/units.tsv %s/units.tsv && cmp %s/summary.tsv %s/summary.tsv",
             run[0], run[1], run[0], run[1]);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "head -1 %s/units.tsv | grep -q fit_glass_index", run[0]);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "%s run configs/dss.ini --units 2 --set calibration.poly_order=9",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
}

/* The identifiability table of dss_calib.h, recomputed: the singular
 * values of the column-normalised Jacobian of the nominal unit over the
 * default campaign (seen spots only), as mounted and aligned; and the
 * standard errors it implies at 0.01 px, in the parameters' units. */
static void singular_values(const char *mount, const double *want, int n_want,
                            double se_out[DSS_NP])
{
    const char *sets[] = {mount};
    sunmc_config c = dss_test_config(sets, 1);
    dss_config *dc = dss_cfg(&c);
    dss_model m;
    dss_model_init(&m, &dc->design);
    int idx[DSS_NP], nf = dss_calib_free_params(&dc->design, 1, 0, idx);
    assert_int_equal(nf, n_want);
    dss_sensor s;
    const dss_deviations none = {0};
    dss_sensor_init(&s, &dc->design, &none, 0);
    gsl_matrix *J = gsl_matrix_calloc(2 * 25 * 25, (size_t)nf);
    size_t r = 0;
    for (int i = 0; i < 25; i++)
        for (int j = 0; j < 25; j++) {
            double b1 = (-60 + 5.0 * i) * RAD_PER_DEG, b2 = (-60 + 5.0 * j) * RAD_PER_DEG;
            double x, y, sp[2], g[2][DSS_NP];
            if (dss_sensor_read(&s, b1, b2, NULL, &x, &y) != SUNMC_OK)
                continue;
            assert_int_equal(dss_model_spot(&m, b1, b2, sp, g), SUNMC_OK);
            for (int a = 0; a < 2; a++, r++)
                for (int k = 0; k < nf; k++)
                    gsl_matrix_set(J, r, (size_t)k, g[a][idx[k]] / dss_param_scale(&m, idx[k]));
        }
    assert_int_equal((int)r, 2 * 581);
    gsl_matrix_view jv = gsl_matrix_submatrix(J, 0, 0, r, (size_t)nf);
    double nrm[DSS_NP];
    for (int k = 0; k < nf; k++) {
        gsl_vector_view col = gsl_matrix_column(&jv.matrix, (size_t)k);
        nrm[k] = gsl_blas_dnrm2(&col.vector);
        gsl_vector_scale(&col.vector, 1 / nrm[k]);
    }
    gsl_matrix *A = gsl_matrix_alloc((size_t)nf, (size_t)nf);
    gsl_blas_dgemm(CblasTrans, CblasNoTrans, 1.0, &jv.matrix, &jv.matrix, 0.0, A);
    assert_int_equal(gsl_linalg_cholesky_decomp1(A), 0);
    assert_int_equal(gsl_linalg_cholesky_invert(A), 0);
    for (int k = 0; k < DSS_NP; k++)
        se_out[k] = NAN;
    for (int k = 0; k < nf; k++)
        se_out[idx[k]] = 0.01 * sqrt(gsl_matrix_get(A, (size_t)k, (size_t)k)) / nrm[k];
    gsl_matrix *V = gsl_matrix_alloc((size_t)nf, (size_t)nf);
    gsl_vector *S = gsl_vector_alloc((size_t)nf), *w = gsl_vector_alloc((size_t)nf);
    gsl_linalg_SV_decomp(&jv.matrix, V, S, w);
    for (int k = 0; k < nf; k++)
        if (!(fabs(gsl_vector_get(S, (size_t)k) - want[k]) <= 0.02 * want[k]))
            fail_msg("%s: singular value %d is %.4g, dss_calib.h says %.4g", mount, k,
                     gsl_vector_get(S, (size_t)k), want[k]);
    gsl_matrix_free(J);
    gsl_matrix_free(A);
    gsl_matrix_free(V);
    gsl_vector_free(S);
    gsl_vector_free(w);
}

static void test_identifiability(void **state)
{
    const double mounted[] = {1.725, 1.668, 1.659, 1.0, 0.4817, 0.4135, 0.214, 0.1547, 0.1275,
                              0.0133};
    double se[DSS_NP];
    singular_values("campaign.mount=as_mounted", mounted, 10, se);
    /* nothing the default campaign leaves undetermined at 0.01 px */
    for (int k = DSS_P_C1; k <= DSS_P_C3; k++)
        assert_true(se[k] < 0.6);
    assert_true(se[DSS_P_S1] < 0.6 && se[DSS_P_S2] < 0.6);
    assert_true(se[DSS_P_X0] < 0.002 && se[DSS_P_Y0] < 0.002);
    const double aligned[] = {1.725, 1.256, 1.052, 1.0, 0.945, 0.6495, 0.1547, 0.0133};
    singular_values("campaign.mount=aligned", aligned, 8, se);
    assert_true(isnan(se[DSS_P_S1]) && isnan(se[DSS_P_S2]));
}

/* The polynomial's standard errors against GSL's ordinary least squares
 * (gsl_multifit_linear: cov = sigma^2 (X^T X)^-1, sigma^2 = chisq / (n - p))
 * on the same monomials and targets, per axis; and the cross-axis
 * correlations are zero (two separate fits). */
static void test_polynomial_standard_errors(void **state)
{
    const char *sets[] = {"calibration.model=polynomial", "calibration.poly_order=2"};
    sunmc_config c = dss_test_config(sets, 2);
    dss_config *dc = dss_cfg(&c);
    const size_t n = 400;
    dss_calib_workspace *cw = dss_calib_alloc(&dc->design, n, DSS_MODEL_POLYNOMIAL, 2, 0);
    assert_non_null(cw);
    uint64_t seed = 99;
    for (size_t i = 0; i < n; i++) {
        double b1 = (-50 + 5.0 * (double)(i / 20)) * RAD_PER_DEG;
        double b2 = (-50 + 5.0 * (double)(i % 20)) * RAD_PER_DEG;
        cw->b1_rad[i] = b1;
        cw->b2_rad[i] = b2;
        /* a spot near the nominal one, with noise the polynomial cannot fit */
        double a0, be0;
        table_truth(b1, b2, &a0, &be0);
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        double e1 = ((double)(seed >> 11) / 9007199254740992.0 - 0.5) * 0.5;
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        double e2 = ((double)(seed >> 11) / 9007199254740992.0 - 0.5) * 0.5;
        cw->x_px[i] = -3.0 * tan(a0) / 5.5e-3 + e1;
        cw->y_px[i] = -3.0 * tan(be0) / 5.5e-3 + e2;
        cw->weight[i] = 1;
    }
    dss_calibration cal;
    static calreport rep;
    char err[SUNMC_ERRLEN];
    assert_int_equal(dss_labfit_run(&c, cw, &cal, &rep, err, sizeof err), SUNMC_OK);
    assert_true(rep.fit_ok);
    int nt = cal.poly.n_terms;
    assert_int_equal(rep.np, 2 * nt);
    gsl_matrix *X = gsl_matrix_alloc(n, (size_t)nt), *cov = gsl_matrix_alloc((size_t)nt, (size_t)nt);
    gsl_vector *y = gsl_vector_alloc(n), *cf = gsl_vector_alloc((size_t)nt);
    gsl_multifit_linear_workspace *w = gsl_multifit_linear_alloc(n, (size_t)nt);
    for (int a = 0; a < 2; a++) {
        for (size_t i = 0; i < n; i++) {
            double am, bm;
            /* the corrected on-board formula: the nominal glass undone */
            assert_int_equal(dss_onboard_angles(&cal.poly.onboard, cw->x_px[i], cw->y_px[i], &am,
                                                &bm),
                             SUNMC_OK);
            double a0, be0, t[DSS_POLY_MAX_TERMS], s = cal.poly.scale_rad;
            table_truth(cw->b1_rad[i], cw->b2_rad[i], &a0, &be0);
            double u = am / s, v = bm / s;
            const double mono[6] = {1, u, v, u * u, u * v, v * v};
            memcpy(t, mono, sizeof mono);
            for (int k = 0; k < nt; k++)
                gsl_matrix_set(X, i, (size_t)k, t[k]);
            gsl_vector_set(y, i, a ? be0 - bm : a0 - am);
        }
        double chisq;
        assert_int_equal(gsl_multifit_linear(X, y, cf, cov, &chisq, w), 0);
        for (int k = 0; k < nt; k++) {
            double want = sqrt(gsl_matrix_get(cov, (size_t)k, (size_t)k));
            assert_near(rep.value[a * nt + k], gsl_vector_get(cf, (size_t)k), 1e-9 * want + 1e-15);
            assert_near(rep.se[a * nt + k], want, 1e-6 * want);
        }
    }
    for (int i = 0; i < nt; i++)
        for (int j = 0; j < nt; j++)
            assert_near(rep.corr[i][nt + j], 0.0, 1e-12);
    gsl_multifit_linear_free(w);
    gsl_matrix_free(X);
    gsl_matrix_free(cov);
    gsl_vector_free(y);
    gsl_vector_free(cf);
    dss_calib_free(cw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_model_matches_sensor), cmocka_unit_test(test_model_jacobian),
        cmocka_unit_test(test_physical_fit_recovers),
        cmocka_unit_test(test_physical_fit_recovers_disc), cmocka_unit_test(test_fixed_index_bias),
        cmocka_unit_test(test_polynomial_exact),     cmocka_unit_test(test_polynomial_basis),
        cmocka_unit_test(test_family_units),
        cmocka_unit_test(test_errors),               cmocka_unit_test(test_cli),
        cmocka_unit_test(test_identifiability),
        cmocka_unit_test(test_polynomial_standard_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
