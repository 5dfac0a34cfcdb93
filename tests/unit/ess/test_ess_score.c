/* test_ess_score.c - an ESS unit's validation scores (ess_score.c) against
 * the same sums made here one reading at a time from the definitions: the
 * bands on the true angle, unseen readings left out, gross ones counted
 * and left out, the systematic part without readings whose noise-free
 * twin is gross, a reading the fit cannot compensate failing the fit. */
#include "test_util.h"

#include "ess_score.h"
#include "status.h"
#include "units.h"

#include <stdlib.h>

#define N_READ 150 /* two whole chunks of 64 and a part */
#define NOISE_RAD (2e-4 * RAD_PER_DEG)

typedef struct {
    double alpha[N_READ], beta[N_READ], raw[N_READ], raw0[N_READ], truth[N_READ];
    int status[N_READ];
    ess_val_readings v;
} readings;

static void model(ess_model *m)
{
    ess_model_init(m, 2.0 * RAD_PER_DEG, 0.0);
    m->p[ESS_P_A] = 1.0004;
    m->p[ESS_P_B] = -2.0e-4;
    m->p[ESS_P_C] = 1.0e-4;
    m->p[ESS_P_KS] = 3.0e-4;
    m->p[ESS_P_KC] = -2.0e-4;
    ess_model_prepare(m);
}

/* Readings over -62 .. 62 deg: raw0 the model's reading of the truth with a
 * ripple of 1e-4 deg, raw
 * with an alternating error; every 17th unseen, every 23rd gross, reading
 * 40 with a gross noise-free twin only. */
static void make_readings(const ess_model *m, readings *r)
{
    memset(r, 0, sizeof *r);
    for (int i = 0; i < N_READ; i++) {
        double t = (-62.0 + 124.0 * i / (N_READ - 1)) * RAD_PER_DEG;
        r->truth[i] = t;
        /* an error of the sensor the model does not know: the systematic part */
        r->raw0[i] = ess_model_structural(m, tan(t)) + 1e-4 * RAD_PER_DEG * sin(7.0 * t);
        r->raw[i] = r->raw0[i] + NOISE_RAD * (i % 2 ? 1.0 : -0.5) * (1 + i % 5);
        r->status[i] = i % 17 == 3 ? ESS_READING_UNSEEN
                       : i % 23 == 5 ? ESS_READING_GROSS
                                     : ESS_READING_OK;
    }
    r->raw0[40] += 1.5 * RAD_PER_DEG; /* gross by itself (half period 1 deg) */
    r->v.n = N_READ;
    r->v.alpha_rad = r->alpha;
    r->v.beta_rad = r->beta;
    r->v.raw_rad = r->raw;
    r->v.raw0_rad = r->raw0;
    r->v.truth_rad = r->truth;
    r->v.status = r->status;
}

static int in_band(const band_list *b, int i, double abs_deg)
{
    return abs_deg <= b->hi[i] + BAND_EPS && (b->lo[i] == 0.0 || abs_deg > b->lo[i] + BAND_EPS);
}

/* Expected RMS (deg) per band, one reading at a time; which: 0 before, 1
 * after, 2 systematic part. */
static void expected(const band_list *b, const ess_model *m, const readings *r, int which,
                     double *rms)
{
    double half = 1.0 * RAD_PER_DEG;
    for (int k = 0; k < b->n; k++) {
        double s = 0;
        long n = 0;
        for (int i = 0; i < N_READ; i++) {
            if (r->status[i] != ESS_READING_OK)
                continue;
            double x = r->raw[i], est = x;
            if (which == 2) {
                if (!(fabs(r->raw0[i] - r->truth[i]) < half))
                    continue;
                x = r->raw0[i];
            }
            if (which > 0)
                assert_int_equal(ess_model_compensate(m, x, &est), SUNMC_OK);
            if (in_band(b, k, fabs(r->truth[i]) * DEG_PER_RAD)) {
                s += (est - r->truth[i]) * (est - r->truth[i]);
                n++;
            }
        }
        rms[k] = sqrt(s / n) * DEG_PER_RAD;
    }
}

static long gross_count(const readings *r)
{
    long n = 0;
    for (int i = 0; i < N_READ; i++)
        n += r->status[i] == ESS_READING_GROSS;
    return n;
}

static void check_bands(const band_list *b, int sys)
{
    sunmc_config c = test_family_config("ess");
    c.bands_deg = *b;
    c.no_systematic = !sys;
    ess_model m;
    model(&m);
    readings *r = malloc(sizeof *r);
    make_readings(&m, r);
    unit_result res;
    memset(&res, 0, sizeof res);
    ess_score_validation(&c, &m, NULL, &r->v, &res);
    assert_int_equal(res.fit_status, UNIT_FIT_OK);
    assert_int_equal(res.gross_val, gross_count(r));
    assert_true(gross_count(r) > 0);
    double e[3][CONFIG_BANDS_MAX];
    for (int w = 0; w < 3; w++)
        expected(b, &m, r, w, e[w]);
    for (int k = 0; k < b->n; k++) {
        assert_near(res.rms_before[0][k], e[0][k], 1e-12 * e[0][k]);
        assert_near(res.rms_after[0][k], e[1][k], 1e-9 * e[1][k]);
        if (sys)
            assert_near(res.rms_after_sys[0][k], e[2][k], 1e-9 * e[2][k]);
        else
            assert_true(isnan(res.rms_after_sys[0][k]));
        assert_true(res.rms_after[0][k] > 1e-5);
        assert_true(!sys || res.rms_after_sys[0][k] > 1e-5);
    }
    free(r);
}

/* The shipped three bands (Table 1's), with and without the systematic pass. */
static void test_three_bands(void **state)
{
    band_list b = {3, {0, 30, 0}, {30, 60, 62}};
    check_bands(&b, 1);
    check_bands(&b, 0);
}

/* Two and four bands take the general path: the same sums. */
static void test_other_band_counts(void **state)
{
    band_list two = {2, {0, 20}, {20, 62}};
    check_bands(&two, 1);
    band_list four = {4, {0, 10, 0, 45}, {10, 45, 62, 62}};
    check_bands(&four, 1);
}

/* The shipped bands' scores of make_readings' readings for a unit whose
 * fit status is fit_status before scoring, reading nan_at (-1: none) not a
 * number (free f->r). */
typedef struct {
    sunmc_config c;
    ess_model m;
    readings *r;
    unit_result res;
} scored;

static void score_case(int fit_status, int nan_at, scored *f)
{
    f->c = test_family_config("ess");
    band_list b = {3, {0, 30, 0}, {30, 60, 62}};
    f->c.bands_deg = b;
    model(&f->m);
    f->r = malloc(sizeof *f->r);
    make_readings(&f->m, f->r);
    if (nan_at >= 0)
        f->r->raw[nan_at] = NAN;
    memset(&f->res, 0, sizeof f->res);
    f->res.fit_status = fit_status;
    ess_score_validation(&f->c, &f->m, NULL, &f->r->v, &f->res);
}

/* A reading the fit cannot compensate (not a number) fails the unit's fit:
 * after and systematic part NaN; before is still scored. */
static void test_uncompensable_fails_fit(void **state)
{
    scored f;
    score_case(UNIT_FIT_OK, 100, &f); /* 21.2 deg: bands 0:30 and 0:62 */
    const band_list b = f.c.bands_deg;
    const ess_model m = f.m;
    readings *r = f.r;
    const unit_result res = f.res;
    assert_int_equal(res.fit_status, UNIT_FIT_FAILED);
    for (int k = 0; k < 3; k++) {
        assert_true(isnan(res.rms_after[0][k]));
        assert_true(isnan(res.rms_after_sys[0][k]));
    }
    double e[CONFIG_BANDS_MAX];
    expected(&b, &m, r, 0, e);
    assert_near(res.rms_before[0][1], e[1], 1e-12 * e[1]);
    assert_true(isnan(res.rms_before[0][0]));
    free(r);
}

/* A unit whose fit failed before scoring: before only. */
static void test_failed_fit_before_only(void **state)
{
    scored f;
    score_case(UNIT_FIT_FAILED, -1, &f);
    const band_list b = f.c.bands_deg;
    const ess_model m = f.m;
    readings *r = f.r;
    const unit_result res = f.res;
    double e[CONFIG_BANDS_MAX];
    expected(&b, &m, r, 0, e);
    for (int k = 0; k < 3; k++) {
        assert_near(res.rms_before[0][k], e[k], 1e-12 * e[k]);
        assert_true(isnan(res.rms_after[0][k]));
    }
    assert_int_equal(res.gross_val, gross_count(r));
    free(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_three_bands),
        cmocka_unit_test(test_other_band_counts),
        cmocka_unit_test(test_uncompensable_fails_fit),
        cmocka_unit_test(test_failed_fit_before_only),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
