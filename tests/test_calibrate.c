/* test_calibrate.c - `sunmc calibrate`'s ESS fit and report: the
 * propagated uncertainty against finite differences, standard errors
 * against repeated noise, data from an independent model with known truth
 * (recovered, and as good as an independent least-squares fit), warnings
 * (alias, correlation, non-convergence), refusals and cross-validation.
 * The command line is in test_calibrate_cli.c, the DSS's propagated sigma
 * in test_dss_calfit.c. */
#include "test_util.h"

#include "calreport.h"
#include "config.h"
#include "csv.h"
#include "dss_calfit.h"
#include "dss_rotation.h"
#include "ess_calfit.h"
#include "ess_unit.h"
#include "family.h"
#include "fit.h"
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
    return test_private_dir(dir, sizeof dir, "cal");
}

static void build_config(config_state *st, const char *const *sets, int n)
{
    char err[SUNMC_ERRLEN];
    if (config_build(st, NULL, sets, n, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
}

/* ---- an independent ESS model (shares no code with sunmc) ---- */

typedef struct {
    double a, b, c, k_rad, t_rad;   /* eq. 12 (d = 1) and the fine-code term k sin(w x + t) */
    double k3_rad, t3_rad;          /* an unmodelled 3rd harmonic of the fine-code error */
    double iy, iz, sun_y, roll;     /* installation and sun tilt, rad */
    double omega;
} indep_truth;

/* Passive frame rotations applied to vector v in place. */
static void frame_x(double a, double v[3])
{
    double y = cos(a) * v[1] + sin(a) * v[2], z = -sin(a) * v[1] + cos(a) * v[2];
    v[1] = y;
    v[2] = z;
}
static void frame_y(double a, double v[3])
{
    double x = cos(a) * v[0] + sin(a) * v[2], z = -sin(a) * v[0] + cos(a) * v[2];
    v[0] = x;
    v[2] = z;
}
static void frame_z(double a, double v[3])
{
    double x = cos(a) * v[0] + sin(a) * v[1], y = -sin(a) * v[0] + cos(a) * v[1];
    v[0] = x;
    v[1] = y;
}

static double indep_incidence(const indep_truth *m, double al, double be)
{
    double v[3] = {0, sin(m->sun_y), cos(m->sun_y)};
    frame_y(be, v);
    frame_x(al, v);
    frame_z(m->iz, v);
    frame_y(m->iy, v);
    frame_x(m->roll, v);
    return atan2(v[1], v[2]);
}

static double indep_raw(const indep_truth *m, double incidence)
{
    double T = tan(incidence);
    double ad = atan((m->a * T + m->b) / (m->c * T + 1.0));
    return ad - m->k_rad * sin(m->omega * ad + m->t_rad) -
           m->k3_rad * sin(3.0 * m->omega * ad + m->t3_rad);
}

/* xorshift64* and Box-Muller: the test's own noise. */
static double test_normal(uint64_t *s)
{
    double u[2];
    for (int i = 0; i < 2; i++) {
        *s ^= *s >> 12;
        *s ^= *s << 25;
        *s ^= *s >> 27;
        u[i] = ((double)((*s * 2685821657736338717ULL) >> 11) + 0.5) / 9007199254740992.0;
    }
    return sqrt(-2.0 * log(u[0])) * cos(2.0 * M_PI * u[1]);
}

static indep_truth truth_default(double k3_deg)
{
    indep_truth m = {.a = 1.00048, .b = 6e-5, .c = -7e-5, .k_rad = 0.036 * RAD_PER_DEG,
                     .t_rad = -1.7, .k3_rad = k3_deg * RAD_PER_DEG, .t3_rad = 0.4,
                     .iy = 230 * RAD_PER_ARCSEC, .iz = -40 * RAD_PER_ARCSEC,
                     .sun_y = 25 * RAD_PER_ARCSEC, .roll = 12 * RAD_PER_ARCSEC,
                     .omega = 2 * M_PI / (0.5 * RAD_PER_DEG)};
    return m;
}

/* Fill cw with the campaign grid of c from model m: recorded angles on the
 * grid, true ones off by encoder noise enc_rad, raw noise sigma_rad. */
static ess_calib_workspace *indep_campaign(const sunmc_config *c, const indep_truth *m,
                                           double sigma_rad, double enc_rad, uint64_t seed)
{
    const ess_config *ec = ess_cfg(c);
    size_t n = ess_campaign_size(c);
    ess_calib_workspace *cw = ess_calib_alloc(n);
    assert_non_null(cw);
    long na = grid_count(ec->cal_alpha_min_deg, ec->cal_alpha_max_deg, ec->cal_alpha_step_deg, 0);
    size_t i = 0;
    for (int k = 0; k < ec->cal_beta_deg.n; k++)
        for (long j = 0; j < na; j++, i++) {
            double al = (ec->cal_alpha_min_deg + (double)j * ec->cal_alpha_step_deg) * RAD_PER_DEG;
            double be = ec->cal_beta_deg.v[k] * RAD_PER_DEG;
            double inc = indep_incidence(m, al + enc_rad * test_normal(&seed),
                                         be + enc_rad * test_normal(&seed));
            cw->alpha_rad[i] = al;
            cw->beta_rad[i] = be;
            cw->raw_rad[i] = indep_raw(m, inc) + sigma_rad * test_normal(&seed);
            cw->weight[i] = 1.0;
        }
    return cw;
}

/* RMS (rad) of compensate(raw) - truth on a validation grid of m. */
typedef int (*comp_fn)(const void *model, double raw, double *alpha);

static int comp_sunmc(const void *model, double raw, double *alpha)
{
    return ess_model_compensate(model, raw, alpha);
}

static double validation_rms(const indep_truth *m, const void *model, comp_fn comp,
                             double sigma_rad, uint64_t seed)
{
    double sum = 0;
    long n = 0;
    const double betas[] = {-25, -10, 10, 25};
    for (int k = 0; k < 4; k++)
        for (double a = -61.95; a <= 62; a += 0.13) {
            double inc = indep_incidence(m, a * RAD_PER_DEG, betas[k] * RAD_PER_DEG);
            double raw = indep_raw(m, inc) + sigma_rad * test_normal(&seed), out;
            assert_int_equal(comp(model, raw, &out), 0);
            sum += (out - inc) * (out - inc);
            n++;
        }
    return sqrt(sum / (double)n);
}

/* ---- unit tests of the pieces ---- */

static void test_compensate_gradient_matches_finite_differences(void **state)
{
    ess_model m;
    ess_model_init(&m, 2 * RAD_PER_DEG, 0);
    m.p[ESS_P_A] = 1.0005;
    m.p[ESS_P_B] = 5e-5;
    m.p[ESS_P_C] = -8e-5;
    m.p[ESS_P_KS] = -7e-5;
    m.p[ESS_P_KC] = -6.9e-4;
    ess_model_prepare(&m);
    const double alphas_deg[] = {-61, -30.3, -0.2, 0.37, 15, 44.4, 61.9};
    const double step[ESS_NP] = {1e-7, 1e-7, 1e-7, 1e-8, 1e-8, 1e-6, 1e-6, 1e-6};
    for (int ia = 0; ia < 7; ia++) {
        double alpha = alphas_deg[ia] * RAD_PER_DEG, h[ESS_NP_MAX];
        double raw = ess_model_structural(&m, tan(alpha));
        ess_compensate_gradient(&m, alpha, h);
        double check;
        assert_int_equal(ess_model_compensate(&m, raw, &check), SUNMC_OK);
        assert_near(check, alpha, 1e-12);
        for (int j = 0; j < ESS_NP; j++) {
            ess_model mp = m, mm = m;
            mp.p[j] += step[j];
            mm.p[j] -= step[j];
            ess_model_prepare(&mp);
            ess_model_prepare(&mm);
            double ap, am;
            assert_int_equal(ess_model_compensate(&mp, raw, &ap), SUNMC_OK);
            assert_int_equal(ess_model_compensate(&mm, raw, &am), SUNMC_OK);
            double fd = (ap - am) / (2 * step[j]);
            assert_near(h[j], fd, 1e-6 * fmax(1.0, fabs(fd)));
        }
        /* The installation does not enter compensation. */
        assert_true(h[ESS_P_INST_Y] == 0 && h[ESS_P_INST_Z] == 0 && h[ESS_P_SUN_Y] == 0);
    }
}

/* Compensation where the fitted fine-code ripple is nearly as steep as
 * the angle itself (w k = 0.995: a unit with a3/a1 = -0.25 fits this):
 * the slope of raw(alpha_d) falls to 0.005 and Halley's step carries the
 * rounding of raw / 0.005, above its 1e-15 rad test.  Every reading must
 * still be inverted (it was nan in `sunmc curve`), to what the arithmetic
 * allows; at w k >= 1 the term has no inverse and every reading is
 * refused (both sides of the limit). */
static void test_compensate_near_flat_ripple(void **state)
{
    ess_model m;
    ess_model_init(&m, 2 * RAD_PER_DEG, 0);
    const double wk[] = {0.995, 0.9999};
    for (int q = 0; q < 2; q++) {
        double k = wk[q] / m.omega, t = 0.3;
        m.p[ESS_P_KS] = k * cos(t);
        m.p[ESS_P_KC] = k * sin(t);
        ess_model_prepare(&m);
        long failed = 0;
        for (double a = -62.0; a <= 62.0; a += 0.0137) {
            double ad = a * RAD_PER_DEG, x;
            double raw = ad - m.p[ESS_P_KS] * sin(m.omega * ad) - m.p[ESS_P_KC] * cos(m.omega * ad);
            if (ess_model_compensate(&m, raw, &x) != SUNMC_OK) {
                failed++;
                continue;
            }
            /* eq. 13 with a = 1, b = c = 0 is the identity */
            assert_near(x, ad, 1e-15 / (1.0 - wk[q]) * 64);
        }
        assert_int_equal(failed, 0);
    }
    m.p[ESS_P_KS] = 1.0 / m.omega;
    m.p[ESS_P_KC] = 0;
    ess_model_prepare(&m);
    double x;
    assert_int_equal(ess_model_compensate(&m, 0.1, &x), SUNMC_EDOM);
    /* a reading that is not a number is refused, not looped on */
    m.p[ESS_P_KS] = 0.995 / m.omega;
    ess_model_prepare(&m);
    assert_int_equal(ess_model_compensate(&m, NAN, &x), SUNMC_EDOM);
}

static void test_covariance_closed_form(void **state)
{
    /* cov = [[4, 2], [2, 9]], s2 = 0.25, scale (1, 10): se = (1, 15),
     * corr = 1/3, eigenvalues of [[1, 1/3], [1/3, 1]] are 4/3, 2/3: cond 2. */
    calreport r;
    calreport_init(&r, "ess", "test");
    r.np = 2;
    snprintf(r.name[0], sizeof r.name[0], "p");
    snprintf(r.name[1], sizeof r.name[1], "q");
    gsl_matrix *cov = gsl_matrix_alloc(2, 2);
    gsl_matrix_set(cov, 0, 0, 4);
    gsl_matrix_set(cov, 0, 1, 2);
    gsl_matrix_set(cov, 1, 0, 2);
    gsl_matrix_set(cov, 1, 1, 9);
    const double scale[2] = {1, 10};
    assert_int_equal(calreport_covariance(&r, cov, 0.25, scale), SUNMC_OK);
    assert_near(r.se[0], 1.0, 1e-15);
    assert_near(r.se[1], 15.0, 1e-14);
    assert_near(r.corr[0][1], 1.0 / 3.0, 1e-15);
    assert_near(r.corr[1][0], 1.0 / 3.0, 1e-15);
    assert_near(r.corr[0][0], 1.0, 1e-15);
    assert_near(r.cond_correlation, 2.0, 1e-12);
    calreport_check_correlations(&r, 0.3);
    assert_int_equal(r.nw, 1);
    assert_non_null(strstr(r.w[0].reason, "parameters p and q are nearly unidentifiable"));
    calreport_check_correlations(&r, 0.34);
    assert_int_equal(r.nw, 1);
    gsl_matrix_set(cov, 1, 1, -1); /* not a covariance */
    assert_int_equal(calreport_covariance(&r, cov, 1, scale), SUNMC_EFIT);
    gsl_matrix_free(cov);
}

/* ---- the independent model: recovery, honest errors, CV, prediction ---- */

static void test_independent_model_recovered(void **state)
{
    const char *sets[] = {"calibration.roll_measured_arcsec=12"};
    config_state st;
    build_config(&st, sets, 1);
    indep_truth m = truth_default(0);
    const double sigma = 3 * RAD_PER_ARCSEC;
    const double truth_int[ESS_NP] = {m.a,  m.b,  m.c,     m.k_rad * cos(m.t_rad), m.k_rad * sin(m.t_rad),
                                      m.iy, m.iz, m.sun_y};
    /* Repeated noise: each parameter within 5 standard errors, and the
     * standard errors honest: mean (error / se)^2 near 1. */
    const int reps = 10;
    double chi = 0, cv_in2 = 0, cv_out2 = 0;
    int nchi = 0;
    static calreport rep;
    ess_calfit_result res;
    char err[SUNMC_ERRLEN];
    for (int r = 0; r < reps; r++) {
        ess_calib_workspace *cw = indep_campaign(&st.cfg, &m, sigma, 0, 1000 + (uint64_t)r);
        assert_int_equal(ess_calfit_run(&st.cfg, cw, NULL, &res, &rep, err, sizeof err), SUNMC_OK);
        assert_true(rep.fit_ok);
        assert_int_equal(rep.dof, (int)cw->n - ESS_NP);
        for (int j = 0; j < ESS_NP; j++) {
            double e = (res.m.p[j] - truth_int[j]) / sqrt(res.cov[j][j]);
            assert_true(fabs(e) < 5);
            chi += e * e;
            nchi++;
        }
        /* Residual sigma estimates the noise. */
        assert_near(rep.sigma_arcsec, 3.0, 0.3);
        cv_in2 += rep.cv_rms_in_arcsec * rep.cv_rms_in_arcsec;
        cv_out2 += rep.cv_rms_out_arcsec * rep.cv_rms_out_arcsec;
        if (r == 0) {
            /* Compensated error against the truth: the noise through the
             * compensation, and the report's prediction says so. */
            double v = validation_rms(&m, &res.m, comp_sunmc, sigma, 77) * ARCSEC_PER_RAD;
            assert_true(v < 2 * 3.0);
            int all = rep.bands.n - 1; /* 0:62 */
            assert_near(rep.predicted_rms[0][all], v, 0.2 * v);
            /* Cross-validation: one fold per beta line of the default
             * campaign (-30, 0, 30). */
            assert_int_equal(rep.n_folds, 3);
            assert_string_equal(rep.fold[0].label, "beta = -30 deg");
            /* b, c and the sun's tilt trade off: named as a warning,
             * with the cause (beta lines at +-30 deg: 1 - cos = 1 - sqrt(3)/2
             * = 0.134). */
            assert_true(fabs(rep.corr[ESS_P_B][ESS_P_SUN_Y]) > CALREPORT_CORR_WARN);
            int named = 0;
            for (int w = 0; w < rep.nw; w++)
                named |= strstr(rep.w[w].reason, "b and fit_sun_y_arcsec") != NULL &&
                         strstr(rep.w[w].reason, "1 - cos(beta) = 0.13 at this campaign's "
                                                 "widest |beta| = 30 deg") != NULL;
            assert_true(named);
        }
        ess_calib_free(cw);
    }
    double ratio = chi / nchi;
    if (!(ratio > 0.4 && ratio < 1.8))
        fail_msg("mean (error / standard error)^2 = %g over %d, expected near 1", ratio, nchi);
    /* Held-out lines close to in-sample when the model is right, over the
     * noise draws (one draw's ratio spreads 1.03-1.50): at least 1 (the
     * held-out points did not pull the fit), yet not far above, although
     * an outer line held out is predicted 30 deg in beta beyond the two
     * lines of 178 points it is fitted on (pooled 1.296 on the default
     * 0.7 deg x (-30, 0, 30); 1.21 on 0.8 deg, 1.09 on 0.2 deg x (-20, 0,
     * 20): the ratio of these 10 draws moves with the campaign). */
    double cv_ratio = sqrt(cv_out2 / cv_in2);
    if (!(cv_ratio >= 1 && cv_ratio < 1.3))
        fail_msg("cross-validation held-out / in-sample RMS %g over %d draws", cv_ratio, reps);
    config_state_free(&st);
}

/* The independent least-squares fit: own model, GSL with finite-difference
 * Jacobian, parameters (a, b, c, ks, kc, iy, iz, sun_y). */
typedef struct {
    const ess_calib_workspace *cw;
    double roll, omega;
} indep_fit_data;

static void indep_from_x(const gsl_vector *x, double roll, double omega, indep_truth *m)
{
    memset(m, 0, sizeof *m);
    m->a = gsl_vector_get(x, 0);
    m->b = gsl_vector_get(x, 1);
    m->c = gsl_vector_get(x, 2);
    double ks = gsl_vector_get(x, 3), kc = gsl_vector_get(x, 4);
    m->k_rad = hypot(ks, kc);
    m->t_rad = atan2(kc, ks);
    m->iy = gsl_vector_get(x, 5);
    m->iz = gsl_vector_get(x, 6);
    m->sun_y = gsl_vector_get(x, 7);
    m->roll = roll;
    m->omega = omega;
}

static int indep_f(const gsl_vector *x, void *params, gsl_vector *f)
{
    const indep_fit_data *d = params;
    indep_truth m;
    indep_from_x(x, d->roll, d->omega, &m);
    for (size_t i = 0; i < d->cw->n; i++)
        gsl_vector_set(f, i,
                       indep_raw(&m, indep_incidence(&m, d->cw->alpha_rad[i], d->cw->beta_rad[i])) -
                           d->cw->raw_rad[i]);
    return GSL_SUCCESS;
}

static int comp_indep(const void *model, double raw, double *alpha)
{
    const indep_truth *m = model;
    double x = raw;
    for (int i = 0; i < 100; i++) {
        double f = x - m->k_rad * sin(m->omega * x + m->t_rad) - raw;
        double fp = 1 - m->k_rad * m->omega * cos(m->omega * x + m->t_rad);
        x -= f / fp;
    }
    *alpha = atan((m->b - tan(x)) / (m->c * tan(x) - m->a));
    return 0;
}

static void test_as_good_as_independent_least_squares(void **state)
{
    /* Data with physics the model lacks (a 3rd fine-code harmonic) and
     * encoder noise: sunmc's compensated error against the truth must be as
     * small as an independent least-squares fit of the same model reaches. */
    const char *sets[] = {"calibration.roll_measured_arcsec=12"};
    config_state st;
    build_config(&st, sets, 1);
    indep_truth m = truth_default(0.004);
    const double sigma = 4 * RAD_PER_ARCSEC, enc = 2 * RAD_PER_ARCSEC;
    ess_calib_workspace *cw = indep_campaign(&st.cfg, &m, sigma, enc, 4242);
    static calreport rep;
    ess_calfit_result res;
    char err[SUNMC_ERRLEN];
    assert_int_equal(ess_calfit_run(&st.cfg, cw, NULL, &res, &rep, err, sizeof err), SUNMC_OK);
    assert_true(rep.fit_ok);
    double rms_sunmc = validation_rms(&m, &res.m, comp_sunmc, sigma, 99);

    indep_fit_data d = {cw, m.roll, m.omega};
    gsl_multifit_nlinear_fdf fdf = {.f = indep_f, .df = NULL, .fvv = NULL, .n = cw->n, .p = 8,
                                    .params = &d};
    gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
    gsl_multifit_nlinear_workspace *w =
        gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, cw->n, 8);
    gsl_vector *x0 = gsl_vector_calloc(8);
    gsl_vector_set(x0, 0, 1.0);
    int info;
    assert_int_equal(gsl_multifit_nlinear_init(x0, &fdf, w), GSL_SUCCESS);
    assert_int_equal(gsl_multifit_nlinear_driver(200, 1e-12, 1e-12, 0, NULL, NULL, &info, w),
                     GSL_SUCCESS);
    indep_truth fit;
    indep_from_x(gsl_multifit_nlinear_position(w), m.roll, m.omega, &fit);
    double rms_indep = validation_rms(&m, &fit, comp_indep, sigma, 99);
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(x0);
    /* The unmodelled harmonic shows: both are well above the noise alone. */
    assert_true(rms_indep * ARCSEC_PER_RAD > 6);
    if (!(rms_sunmc <= 1.01 * rms_indep))
        fail_msg("sunmc %.3f arcsec vs independent fit %.3f arcsec", rms_sunmc * ARCSEC_PER_RAD,
                 rms_indep * ARCSEC_PER_RAD);
    ess_calib_free(cw);
    config_state_free(&st);
}

static void test_weight_equals_repeated_rows(void **state)
{
    /* A weight w is 1 / relative variance: a row of weight 1 must pull the
     * fit exactly as two copies of it do against rows of weight 1/2
     * (the sums of squares are proportional, so the minimiser is the same).
     * Derived independently of the code's sqrt(weight) scaling. */
    config_state st;
    build_config(&st, NULL, 0);
    indep_truth m = truth_default(0.004);
    ess_calib_workspace *cw = indep_campaign(&st.cfg, &m, 4 * RAD_PER_ARCSEC,
                                             2 * RAD_PER_ARCSEC, 777);
    size_t n = cw->n, heavy = 0;
    for (size_t i = 0; i < n; i++)
        heavy += i % 3 == 0;
    ess_calib_workspace *dup = ess_calib_alloc(n + heavy);
    assert_non_null(dup);
    size_t k = n;
    for (size_t i = 0; i < n; i++) {
        dup->alpha_rad[i] = cw->alpha_rad[i];
        dup->beta_rad[i] = cw->beta_rad[i];
        dup->raw_rad[i] = cw->raw_rad[i];
        dup->weight[i] = 1.0;
        cw->weight[i] = i % 3 == 0 ? 1.0 : 0.5;
        if (i % 3 == 0) {
            dup->alpha_rad[k] = cw->alpha_rad[i];
            dup->beta_rad[k] = cw->beta_rad[i];
            dup->raw_rad[k] = cw->raw_rad[i];
            dup->weight[k++] = 1.0;
        }
    }
    static calreport rep;
    ess_calfit_result rw, rd;
    char err[SUNMC_ERRLEN];
    assert_int_equal(ess_calfit_run(&st.cfg, cw, NULL, &rw, &rep, err, sizeof err), SUNMC_OK);
    assert_true(rep.fit_ok);
    assert_int_equal(ess_calfit_run(&st.cfg, dup, NULL, &rd, &rep, err, sizeof err), SUNMC_OK);
    assert_true(rep.fit_ok);
    double worst = 0;
    for (int j = 0; j < rw.m.np; j++) {
        worst = fmax(worst, fabs(rw.m.p[j] - rd.m.p[j]));
    }
    if (!(worst < 1e-9))
        fail_msg("weighted fit and repeated rows differ by %.3g (rad or ratio)", worst);
    ess_calib_free(dup);
    ess_calib_free(cw);
    config_state_free(&st);
}

/* ---- warnings and refusals ---- */

static void test_alias_warning(void **state)
{
    /* Step 1 deg = 2 fine-error periods: one phase, both directions weak;
     * 0.25 deg: two opposite phases, one direction weak. */
    const char *steps[][2] = {{"campaign.alpha_step_deg=1", "2"},
                              {"campaign.alpha_step_deg=0.25", "1"},
                              {"campaign.alpha_step_deg=0.2", "0"}};
    for (int s = 0; s < 3; s++) {
        config_state st;
        build_config(&st, &steps[s][0], 1);
        indep_truth m = truth_default(0);
        ess_calib_workspace *cw = indep_campaign(&st.cfg, &m, RAD_PER_ARCSEC, 0, 5);
        static calreport rep;
        ess_calfit_result res;
        char err[SUNMC_ERRLEN];
        assert_int_equal(ess_calfit_run(&st.cfg, cw, NULL, &res, &rep, err, sizeof err), SUNMC_OK);
        int want = atoi(steps[s][1]), got = 0;
        assert_int_equal(cw->alias.n_weak, want);
        for (int w = 0; w < rep.nw; w++)
            if (strstr(rep.w[w].reason, "fine-code term aliased by the campaign step")) {
                got++;
                assert_non_null(strstr(rep.w[w].action, "not a multiple of theta0/8"));
            }
        assert_int_equal(got, want);
        /* The regularised directions are not free: they leave the dof. */
        assert_int_equal(rep.dof, (int)cw->n - ESS_NP + want);
        ess_calib_free(cw);
        config_state_free(&st);
    }
}

/* y = x0 + x1 t exactly at the start: zero residuals, no step lowers the
 * cost.  The start is the solution (0 iterations, the gradient test), not
 * a failed fit -- a perfect unit fitted from its nominal model. */
static int line_fdf(const double *x, void *params, double *f, double *J, size_t ld)
{
    const double *t = params;
    for (size_t i = 0; i < 4; i++) {
        f[i] = x[0] + x[1] * t[i] - (2.0 + 0.5 * t[i]);
        J[i] = 1.0;
        J[ld + i] = t[i];
    }
    return GSL_SUCCESS;
}

static void test_fit_start_at_minimum(void **state)
{
    fit_workspace *fw = fit_workspace_alloc(4, 2);
    assert_non_null(fw);
    double t[4] = {-1, 0, 1, 3}, x[2] = {2.0, 0.5};
    fit_result res;
    assert_int_equal(fit_solve(fw, line_fdf, t, x, 50, &res), SUNMC_OK);
    assert_int_equal(res.status, GSL_SUCCESS);
    assert_int_equal(res.info, 2);
    assert_int_equal(res.iterations, 0);
    assert_near(res.chisq, 0, 0);
    assert_near(x[0], 2.0, 0);
    assert_near(x[1], 0.5, 0);
    /* A start off the line still iterates to it. */
    x[0] = 1.0, x[1] = 0.0;
    assert_int_equal(fit_solve(fw, line_fdf, t, x, 50, &res), SUNMC_OK);
    assert_true(res.iterations > 0);
    assert_near(x[0], 2.0, 1e-9);
    assert_near(x[1], 0.5, 1e-9);
    fit_workspace_free(fw);
}

static void test_nonconvergence_warning(void **state)
{
    config_state st;
    build_config(&st, NULL, 0);
    st.cfg.max_iterations = 1; /* below the key's range: only to force it */
    indep_truth m = truth_default(0);
    ess_calib_workspace *cw = indep_campaign(&st.cfg, &m, RAD_PER_ARCSEC, 0, 6);
    static calreport rep;
    ess_calfit_result res;
    char err[SUNMC_ERRLEN];
    assert_int_equal(ess_calfit_run(&st.cfg, cw, NULL, &res, &rep, err, sizeof err), SUNMC_OK);
    assert_false(rep.fit_ok);
    assert_int_equal(rep.fit.status, GSL_EMAXITER);
    int found = 0;
    for (int w = 0; w < rep.nw; w++)
        found |= strstr(rep.w[w].reason, "the fit did not converge: did not converge within "
                                         "calibration.max_iterations") != NULL;
    assert_true(found);
    ess_calib_free(cw);
    config_state_free(&st);
}

static void test_refuses_n_le_p(void **state)
{
    config_state st;
    build_config(&st, NULL, 0);
    ess_calib_workspace *cw = ess_calib_alloc(ESS_NP + 2);
    const int line[ESS_NP + 2] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    for (size_t i = 0; i < cw->n; i++) {
        cw->alpha_rad[i] = (-40.0 + 9.0 * (double)i) * RAD_PER_DEG;
        cw->beta_rad[i] = 0;
        cw->raw_rad[i] = cw->alpha_rad[i];
        cw->weight[i] = 1;
    }
    cw->raw_rad[2] += 3 * RAD_PER_DEG; /* gross: dropped */
    cw->weight[4] = 0;                 /* dropped by the lab */
    static calreport rep;
    ess_calfit_result res;
    char err[SUNMC_ERRLEN];
    assert_int_equal(ess_calfit_run(&st.cfg, cw, line, &res, &rep, err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "only 8 usable data rows"));
    assert_int_equal(res.n_gross, 1);
    assert_non_null(strstr(rep.w[0].reason, "(lines 5)"));
    ess_calib_free(cw);
    config_state_free(&st);
}

static void test_single_beta_line_has_no_cross_validation(void **state)
{
    const char *sets[] = {"campaign.beta_deg=0"};
    config_state st;
    build_config(&st, sets, 1);
    indep_truth m = truth_default(0);
    m.iz = 0; /* invisible with one beta line */
    ess_calib_workspace *cw = indep_campaign(&st.cfg, &m, RAD_PER_ARCSEC, 0, 8);
    static calreport rep;
    ess_calfit_result res;
    char err[SUNMC_ERRLEN];
    assert_int_equal(ess_calfit_run(&st.cfg, cw, NULL, &res, &rep, err, sizeof err), SUNMC_OK);
    assert_int_equal(rep.n_folds, 0);
    assert_non_null(strstr(rep.cv_note, "1 beta line"));
    ess_calib_free(cw);
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compensate_gradient_matches_finite_differences),
        cmocka_unit_test(test_compensate_near_flat_ripple),
        cmocka_unit_test(test_covariance_closed_form),
        cmocka_unit_test(test_independent_model_recovered),
        cmocka_unit_test(test_as_good_as_independent_least_squares),
        cmocka_unit_test(test_weight_equals_repeated_rows),
        cmocka_unit_test(test_alias_warning),
        cmocka_unit_test(test_fit_start_at_minimum),
        cmocka_unit_test(test_nonconvergence_warning),
        cmocka_unit_test(test_refuses_n_le_p),
        cmocka_unit_test(test_single_beta_line_has_no_cross_validation),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
