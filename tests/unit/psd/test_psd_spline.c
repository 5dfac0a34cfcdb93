/* test_psd_spline.c - issue 39: the four-channel sensor's spline and
 * hybrid models (psd_spline.c).
 *  - hybrid on exact physics: the correction is zero (every coefficient
 *    below 1e-12) and the compensated angles are the physical model's;
 *  - hybrid on a physics 3 % off in height: the correction takes up the
 *    error (from about 1,000" to below 1");
 *  - spline: a campaign of single-axis sweeps gets one spline per axis,
 *    a two-axis grid the tensor product; both reproduce the truth on their
 *    rows, and a reading beyond the field is refused (SUNMC_EDOM). */
#include "test_util.h"

#include "psd_model.h"
#include "psd_sensor.h"
#include "rotation.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

enum { NA = 21, NB = 11, N = NA * NB };

typedef struct {
    psd_design d;
    double m[4][N], ut[3 * N], w[N], scratch[8 * N];
    psd_rows rows;
} campaign;

/* The nominal tetra-lateral sensor, noiseless, on a grid of NA alphas
 * (+-20 deg) and NB betas (+-20 deg), or on the two axes only. */
static void campaign_make(campaign *cp, int axes_only)
{
    memset(cp, 0, sizeof *cp);
    psd_design *d = &cp->d;
    d->detector = PSD_LATERAL;
    d->lateral = PSD_TETRA;
    d->h_mm = 4;
    d->active_mm = 9;
    d->aperture_um = 500;
    d->pincushion = 0.04;
    d->glass_index = 1.5;
    d->fov_deg = 45;
    d->signal_fs = 0.6;
    d->dark_fs = 0.02;
    psd_deviations dev;
    memset(&dev, 0, sizeof dev);
    psd_sensor s;
    psd_sensor_build(d, &dev, &s);
    for (int r = 0; r < N; r++) {
        double a = -20 + 40.0 * (r % NA) / (NA - 1), b = -20 + 40.0 * (r / NA) / (NB - 1);
        if (axes_only && r % 2)
            a = 0; /* half the rows sweep beta at alpha = 0 */
        else if (axes_only)
            b = 0;
        sun_vector_of(a * RAD_PER_DEG, b * RAD_PER_DEG, cp->ut + 3 * r);
        double mm[4];
        assert_int_equal(psd_sensor_read(&s, cp->ut + 3 * r, mm), SUNMC_OK);
        for (int q = 0; q < 4; q++)
            cp->m[q][r] = mm[q];
        cp->w[r] = 1;
    }
    cp->rows.n = N;
    for (int q = 0; q < 4; q++)
        cp->rows.m[q] = cp->m[q];
    cp->rows.ut = cp->ut;
    cp->rows.w = cp->w;
    cp->rows.design = d;
    cp->rows.scratch = cp->scratch;
    cp->rows.smooth = 1e-3;
}

/* Largest angle error (rad) of k over the campaign's rows. */
static double worst(const psd_cal *k, const campaign *cp)
{
    double e = 0;
    for (int r = 0; r < N; r++) {
        double m[4] = {cp->m[0][r], cp->m[1][r], cp->m[2][r], cp->m[3][r]}, a, b, ta, tb;
        assert_int_equal(psd_cal_angles(k, m, &a, &b), SUNMC_OK);
        sun_angles_of(cp->ut + 3 * r, &ta, &tb);
        e = fmax(e, fmax(fabs(a - ta), fabs(b - tb)));
    }
    return e;
}

static void test_hybrid_zero_on_exact_physics(void **state)
{
    static campaign cp;
    campaign_make(&cp, 0);
    psd_cal k;
    psd_cal_nominal(&k, &cp.d);
    double before = worst(&k, &cp);
    assert_true(before < 1e-12);
    k.model = PSD_MODEL_HYBRID;
    assert_int_equal(psd_spline_fit(&k, &cp.rows, cp.scratch), SUNMC_OK);
    assert_int_equal(k.spline.dims, 2);
    for (int j = 0; j < 2; j++)
        for (int q = 0; q < k.spline.n_coef; q++)
            assert_true(fabs(k.spline.coef[j][q]) < 1e-12);
    assert_true(worst(&k, &cp) < 1e-12);
}

static void test_hybrid_corrects_wrong_height(void **state)
{
    static campaign cp;
    campaign_make(&cp, 0);
    psd_cal k;
    psd_cal_nominal(&k, &cp.d);
    k.p[PSD_P_DH] = 0.03 * cp.d.h_mm;
    psd_phys_set(&k.phys, &cp.d, k.p);
    double before = worst(&k, &cp);
    assert_true(before > 500 * RAD_PER_ARCSEC);
    k.model = PSD_MODEL_HYBRID;
    assert_int_equal(psd_spline_fit(&k, &cp.rows, cp.scratch), SUNMC_OK);
    assert_true(worst(&k, &cp) < 1 * RAD_PER_ARCSEC);
}

static void test_spline_axes_and_grid(void **state)
{
    static campaign cp;
    for (int axes = 0; axes < 2; axes++) {
        campaign_make(&cp, axes);
        psd_cal k;
        memset(&k, 0, sizeof k);
        k.model = PSD_MODEL_SPLINE;
        k.design = &cp.d;
        assert_int_equal(psd_spline_fit(&k, &cp.rows, cp.scratch), SUNMC_OK);
        assert_int_equal(k.spline.dims, axes ? 1 : 2);
        assert_true(worst(&k, &cp) < (axes ? 1.0 : 30.0) * RAD_PER_ARCSEC);
        /* a spot beyond the field the campaign saw */
        double m[4], a, b;
        psd_sensor s;
        psd_deviations dev;
        memset(&dev, 0, sizeof dev);
        psd_sensor_build(&cp.d, &dev, &s);
        double u[3];
        sun_vector_of(25 * RAD_PER_DEG, 0, u);
        assert_int_equal(psd_sensor_read(&s, u, m), SUNMC_OK);
        assert_int_equal(psd_cal_angles(&k, m, &a, &b), SUNMC_EDOM);
    }
}

/* The table of the same spline at a fixed step: its nodes on the spline,
 * its error within the spline's plus the interpolation's; a finer step
 * errs less; beyond the field refused. */
static void test_table_of_spline(void **state)
{
    static campaign cp;
    for (int axes = 0; axes < 2; axes++) {
        campaign_make(&cp, axes);
        psd_cal k;
        memset(&k, 0, sizeof k);
        k.model = PSD_MODEL_TABLE;
        k.design = &cp.d;
        double e[2];
        for (int t = 0; t < 2; t++) {
            cp.rows.table_log = (axes ? 5 : 3) + t;
            assert_int_equal(psd_spline_fit(&k, &cp.rows, cp.scratch), SUNMC_OK);
            assert_int_equal(k.table.dims, axes ? 1 : 2);
            assert_int_equal(k.table.nodes, (1 << cp.rows.table_log) + 1);
            assert_int_equal(psd_table_log(&k.table), cp.rows.table_log);
            e[t] = worst(&k, &cp);
        }
        assert_true(e[1] < e[0]);
        assert_true(e[1] < (axes ? 60.0 : 300.0) * RAD_PER_ARCSEC);
        double m[4], a, b, u[3];
        psd_sensor s;
        psd_deviations dev;
        memset(&dev, 0, sizeof dev);
        psd_sensor_build(&cp.d, &dev, &s);
        sun_vector_of(0, -25 * RAD_PER_DEG, u);
        assert_int_equal(psd_sensor_read(&s, u, m), SUNMC_OK);
        assert_int_equal(psd_cal_angles(&k, m, &a, &b), SUNMC_EDOM);
    }
}

int main(void)
{
    gsl_set_error_handler_off();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hybrid_zero_on_exact_physics),
        cmocka_unit_test(test_hybrid_corrects_wrong_height),
        cmocka_unit_test(test_spline_axes_and_grid),
        cmocka_unit_test(test_table_of_spline),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
