/* test_psd_fit.c - the physical model's fit and inversion as numerical
 * methods, against values worked out here with the public model only
 * (psd_phys_set, psd_phys_observed, psd_phys_predicted):
 *  - the two-stage fit stops at a minimum of its stated objective, the sum
 *    of ((observed - predicted ratio) / sens)^2 with sens the fitted
 *    height's sensitivity: along every fitted parameter the parabola
 *    through the objective at p - h, p, p + h has its vertex within a
 *    thousandth of h of p (a Jacobian that forgets how the height moves
 *    1 / sens left it 0.012 h away on dx, crawling);
 *  - from the first stage's answer the ratios' fit converges in a few
 *    iterations on typical units: at most 4 here (6 with the damping
 *    started where GSL starts it, up to 57 when it crawled);
 *  - the inversion (Newton, its Jacobian kept once the steps shrink)
 *    lands where a Newton of this file with a fresh central-difference
 *    Jacobian at every step lands, to 1e-12 in tan. */
#include "test_util.h"

#include "fit.h"
#include "psd_model.h"
#include "psd_sensor.h"
#include "rotation.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

enum { NA = 9, NB = 5, N = NA * NB };

static psd_design tetra_design(void)
{
    psd_design d;
    memset(&d, 0, sizeof d);
    d.detector = PSD_LATERAL;
    d.lateral = PSD_TETRA;
    d.h_mm = 4;
    d.active_mm = 9;
    d.aperture_um = 500;
    d.pincushion = 0.04;
    d.glass_index = 1.5;
    d.fov_deg = 45;
    d.polarity = PSD_POSITIVE;
    d.signal_fs = 0.6;
    d.dark_fs = 0.02;
    return d;
}

typedef struct {
    psd_design d;
    double m[4][N], ut[3 * N], scratch[8 * N];
    psd_rows rows;
} campaign;

/* A unit with deviations scaled by k (k = 0: nominal) read on a 9 x 5 grid
 * with a fixed pseudo-noise of amplitude noise_fs on each channel. */
static void campaign_make(campaign *cp, double k, double noise_fs)
{
    cp->d = tetra_design();
    psd_deviations dev;
    memset(&dev, 0, sizeof dev);
    dev.dh_um[0] = 30 * k;
    dev.dx_um[0] = -20 * k;
    dev.dy_um[0] = 15 * k;
    dev.rot_z_arcsec[0] = 200 * k;
    for (int q = 0; q < 4; q++) {
        dev.gain_pct[q] = 2 * k * sin(1.0 + q);
        dev.dark_pct[q] = 0.5 * k * cos(2.0 + q);
    }
    psd_sensor s;
    psd_sensor_build(&cp->d, &dev, &s);
    for (int r = 0; r < N; r++) {
        double mm[4];
        sun_vector_of((-20 + 5 * (r % NA)) * RAD_PER_DEG, (-20 + 10 * (r / NA)) * RAD_PER_DEG,
                      cp->ut + 3 * r);
        assert_int_equal(psd_sensor_read(&s, cp->ut + 3 * r, mm), SUNMC_OK);
        for (int q = 0; q < 4; q++)
            cp->m[q][r] = mm[q] + noise_fs * sin(7.3 * r + 1.9 * q + 11.0 * k);
    }
    memset(&cp->rows, 0, sizeof cp->rows);
    cp->rows.n = N;
    for (int q = 0; q < 4; q++)
        cp->rows.m[q] = cp->m[q];
    cp->rows.ut = cp->ut;
    cp->rows.design = &cp->d;
    cp->rows.scratch = cp->scratch;
}

/* The two stages, as the Monte Carlo runs them. */
static int two_stage_fit(campaign *cp, double p[PSD_NP], fit_result *res)
{
    int fr[PSD_NP];
    fit_workspace *fw = fit_workspace_alloc(2 * N, psd_phys_free(&cp->d, 0, fr));
    fit_workspace *fc = fit_workspace_alloc(PSD_RESIDUALS_PER_ROW * N, psd_phys_free_channels(0));
    assert_non_null(fw);
    assert_non_null(fc);
    cp->rows.fw_channels = fc;
    psd_phys_start(&cp->rows, p);
    int st = psd_phys_fit(fw, &cp->rows, 0, p, res);
    fit_workspace_free(fw);
    fit_workspace_free(fc);
    return st;
}

/* The objective written out: ratio differences over the fitted height's
 * sensitivity, squared and summed. */
static double objective(const campaign *cp, const double p[PSD_NP])
{
    psd_phys m;
    psd_phys_set(&m, &cp->d, p);
    double c = 0;
    for (int r = 0; r < N; r++) {
        double rd[4] = {cp->m[0][r], cp->m[1][r], cp->m[2][r], cp->m[3][r]}, xo, yo, xp, yp;
        assert_int_equal(psd_phys_observed(&m, rd, &xo, &yo), SUNMC_OK);
        assert_int_equal(psd_phys_predicted(&m, cp->ut + 3 * r, &xp, &yp), SUNMC_OK);
        c += ((xo - xp) / m.sens) * ((xo - xp) / m.sens) + ((yo - yp) / m.sens) * ((yo - yp) / m.sens);
    }
    return c;
}

static void fit_stops_at_its_minimum(void **state)
{
    campaign cp;
    campaign_make(&cp, 1.0, 2e-4);
    double p[PSD_NP];
    fit_result res;
    assert_int_equal(two_stage_fit(&cp, p, &res), SUNMC_OK);
    /* steps: 0.1 um, 0.1 arcsec, 1e-5 of gain, 1e-6 of full scale; dark4
     * follows the others in the corner layout (psd_model.h), so it moves
     * with dark1 to keep the held combination */
    const int par[] = {PSD_P_DX, PSD_P_DY, PSD_P_DH, PSD_P_RZ, PSD_P_G2, PSD_P_G3, PSD_P_G4,
                       PSD_P_D1, PSD_P_D2, PSD_P_D3};
    const double h[] = {1e-4, 1e-4, 1e-4, 0.1 * RAD_PER_ARCSEC, 1e-5, 1e-5, 1e-5,
                        1e-6, 1e-6, 1e-6};
    double c0 = objective(&cp, p);
    for (size_t j = 0; j < sizeof par / sizeof *par; j++) {
        double q[PSD_NP];
        memcpy(q, p, sizeof q);
        q[par[j]] = p[par[j]] + h[j];
        if (par[j] >= PSD_P_D1 && par[j] <= PSD_P_D2)
            q[PSD_P_D4] = p[PSD_P_D4] + h[j];
        if (par[j] == PSD_P_D3)
            q[PSD_P_D4] = p[PSD_P_D4] - h[j];
        double cp1 = objective(&cp, q);
        q[par[j]] = p[par[j]] - h[j];
        if (par[j] >= PSD_P_D1 && par[j] <= PSD_P_D2)
            q[PSD_P_D4] = p[PSD_P_D4] - h[j];
        if (par[j] == PSD_P_D3)
            q[PSD_P_D4] = p[PSD_P_D4] + h[j];
        double cm1 = objective(&cp, q);
        double curv = cp1 - 2 * c0 + cm1, vertex = 0.5 * (cm1 - cp1) / curv; /* in steps */
        assert_true(curv > 0);
        if (!(fabs(vertex) < 1e-3))
            fail_msg("parameter %d: the objective's minimum lies %.3g steps from the fit's answer",
                     par[j], vertex);
    }
}

static void fit_converges_in_few_iterations(void **state)
{
    size_t most = 0;
    for (int u = 1; u <= 12; u++) {
        campaign cp;
        campaign_make(&cp, 0.25 * u, 2e-4);
        double p[PSD_NP];
        fit_result res;
        assert_int_equal(two_stage_fit(&cp, p, &res), SUNMC_OK);
        most = res.iterations > most ? res.iterations : most;
    }
    if (most > 4)
        fail_msg("the ratios' fit took %zu iterations from the first stage's answer", most);
}

/* Predicted ratios at (tan alpha, tan beta) of the table top. */
static int predict_at(const psd_phys *m, double ta, double tb, double f[2])
{
    double n = sqrt(1 + ta * ta + tb * tb), u[3] = {ta / n, tb / n, 1 / n};
    return psd_phys_predicted(m, u, &f[0], &f[1]);
}

/* Newton with a fresh central-difference Jacobian at every step. */
static int reference_invert(const psd_phys *m, double x, double y, double *ta, double *tb)
{
    const double h = 1e-6;
    *ta = -x / m->sens;
    *tb = -y / m->sens;
    for (int it = 0; it < 100; it++) {
        double f[2], ap[2], am[2], bp[2], bm[2];
        if (predict_at(m, *ta, *tb, f) || predict_at(m, *ta + h, *tb, ap) ||
            predict_at(m, *ta - h, *tb, am) || predict_at(m, *ta, *tb + h, bp) ||
            predict_at(m, *ta, *tb - h, bm))
            return SUNMC_EDOM;
        double j11 = (ap[0] - am[0]) / (2 * h), j21 = (ap[1] - am[1]) / (2 * h);
        double j12 = (bp[0] - bm[0]) / (2 * h), j22 = (bp[1] - bm[1]) / (2 * h);
        double det = j11 * j22 - j12 * j21, ex = x - f[0], ey = y - f[1];
        double da = (j22 * ex - j12 * ey) / det, db = (-j21 * ex + j11 * ey) / det;
        *ta += da;
        *tb += db;
        if (fabs(da) + fabs(db) < 1e-15)
            break;
    }
    return SUNMC_OK;
}

static void inversion_matches_full_newton(void **state)
{
    psd_design d = tetra_design();
    double p[PSD_NP] = {0};
    p[PSD_P_DX] = 0.02;
    p[PSD_P_DH] = -0.03;
    p[PSD_P_RZ] = 1e-3;
    p[PSD_P_G2] = p[PSD_P_G3] = p[PSD_P_G4] = 1;
    psd_phys m;
    psd_phys_set(&m, &d, p);
    int n = 0;
    for (double a = -40; a <= 40; a += 3.7)
        for (double b = -40; b <= 40; b += 4.1) {
            double u[3], x, y, back[3], ta, tb;
            sun_vector_of(a * RAD_PER_DEG, b * RAD_PER_DEG, u);
            if (psd_phys_predicted(&m, u, &x, &y) != SUNMC_OK)
                continue;
            int st = psd_phys_invert(&m, x, y, back);
            if (reference_invert(&m, x, y, &ta, &tb) != SUNMC_OK || st != SUNMC_OK)
                continue;
            assert_near(back[0] / back[2], ta, 1e-12);
            assert_near(back[1] / back[2], tb, 1e-12);
            assert_near(ta, u[0] / u[2], 1e-10);
            n++;
        }
    assert_true(n > 300);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fit_stops_at_its_minimum),
        cmocka_unit_test(fit_converges_in_few_iterations),
        cmocka_unit_test(inversion_matches_full_newton),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
