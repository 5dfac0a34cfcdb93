/* test_psd_labdiag.c - issue 39: the data against the design
 * (psd_labcal_diagnose), on synthetic data whose measured ratios are a
 * known transform of the design's nominal ones (channels of the corner
 * layout, (1 -+ x)(1 -+ y)/4, whose ratios are x and y exactly):
 *  - the design itself: no defect, scale 1, no turn;
 *  - alpha's sign flipped: mirrored across a line 90 deg from X; beta's:
 *    0 deg;
 *  - turned by 20 deg: the turn recovered; scaled by 0.4: the scale;
 *  - the travel falling linearly from 30 deg to half at 40 deg: compressed
 *    from the first bin whose median is below 0.8, 35-40 deg;
 *  - a dead centre (the travel halved within 8 deg, as a quadrant's gap
 *    does): not judged, the centre's bins are the offset's;
 *  - two central rows off by 0.2 in x: both named by line. */
#include "test_util.h"

#include "psd_config.h"
#include "psd_lab.h"
#include "psd_model.h"
#include "rotation.h"
#include "units.h"

#define STEP 2
#define NA (80 / STEP + 1)
#define N (NA * NA)

enum { IDENTITY, MIRROR_A, MIRROR_B, TURN, SCALE, SQUEEZE, DEAD_CENTRE, OUTLIERS };

typedef struct {
    double v[7][N];
    int line[N];
    lab_columns d;
} data;

static void transform(int kind, double theta_deg, const double p[2], double q[2])
{
    double c = cos(20 * RAD_PER_DEG), s = sin(20 * RAD_PER_DEG), f = 1.0;
    q[0] = p[0];
    q[1] = p[1];
    switch (kind) {
    case MIRROR_A: q[0] = -p[0]; break;
    case MIRROR_B: q[1] = -p[1]; break;
    case TURN:
        q[0] = c * p[0] - s * p[1];
        q[1] = s * p[0] + c * p[1];
        break;
    case SCALE: f = 0.4; break;
    case SQUEEZE: f = theta_deg > 30 ? fmax(0.3, 1 - 0.5 * (theta_deg - 30) / 10) : 1; break;
    case DEAD_CENTRE: f = theta_deg < 8 ? 0.5 : 1; break;
    default: break;
    }
    q[0] *= f;
    q[1] *= f;
}

static void make(data *t, const sunmc_config *c, int kind)
{
    const psd_config *pc = psd_cfg(c);
    double p0[PSD_NP] = {0};
    psd_phys nom;
    psd_phys_set(&nom, &pc->design, p0);
    int i = 0;
    for (int a = 0; a < NA; a++)
        for (int b = 0; b < NA; b++, i++) {
            double al = -40 + STEP * a, be = -40 + STEP * b, ut[3], p[2], q[2];
            const double z[3] = {0, 0, 1};
            psd_table_sun(pc, al * RAD_PER_DEG, be * RAD_PER_DEG, ut);
            assert_int_equal(psd_phys_predicted(&nom, ut, &p[0], &p[1]), 0);
            transform(kind, angle_between(ut, z) * DEG_PER_RAD, p, q);
            if (kind == OUTLIERS && (i == N / 2 || i == N / 2 + 1))
                q[0] += 0.2;
            t->v[0][i] = al;
            t->v[1][i] = be;
            t->v[2][i] = (1 - q[0]) * (1 - q[1]) / 4;
            t->v[3][i] = (1 + q[0]) * (1 + q[1]) / 4;
            t->v[4][i] = (1 + q[0]) * (1 - q[1]) / 4;
            t->v[5][i] = (1 - q[0]) * (1 + q[1]) / 4;
            t->v[6][i] = 1.0;
            t->line[i] = i + 3;
            double x, y, r[4] = {t->v[2][i], t->v[3][i], t->v[4][i], t->v[5][i]};
            assert_int_equal(psd_poly_ratios(&pc->design, r, &x, &y), 0);
            assert_true(fabs(x - q[0]) < 1e-12 && fabs(y - q[1]) < 1e-12);
        }
    t->d = (lab_columns){.path = "t.csv", .n = N, .n_cols = 7, .line = t->line};
    for (int k = 0; k < 7; k++)
        t->d.v[k] = t->v[k];
}

static psd_data_diag diagnose(int kind)
{
    static data t;
    sunmc_config c = test_family_config("psd");
    make(&t, &c, kind);
    char err[SUNMC_ERRLEN];
    psd_labcal *k = psd_labcal_alloc(&c, &t.d, err, sizeof err);
    assert_non_null(k);
    psd_data_diag g;
    assert_int_equal(psd_labcal_diagnose(k, &g), 0);
    psd_labcal_free(k);
    return g;
}

static void test_design_itself(void **state)
{
    psd_data_diag g = diagnose(IDENTITY);
    assert_int_equal(g.defects, 0);
    assert_false(g.mirrored);
    assert_true(fabs(g.scale - 1) < 1e-6);
    assert_true(fabs(g.turn_deg) < 1e-6);
    assert_true(isnan(g.compressed_from_deg));
    assert_int_equal(g.outliers, 0);
    /* the inner half of a field reaching acos(cos^2 40 deg) (beta outer) */
    double c40 = cos(40 * RAD_PER_DEG);
    assert_true(fabs(g.inner_deg - 0.5 * acos(c40 * c40) * DEG_PER_RAD) < 1e-9);
}

static void test_mirrors(void **state)
{
    psd_data_diag a = diagnose(MIRROR_A), b = diagnose(MIRROR_B);
    assert_true(a.mirrored && b.mirrored);
    assert_true(fabs(fabs(a.turn_deg) - 90) < 1e-6);
    assert_true(fabs(b.turn_deg) < 1e-6);
    assert_int_equal(a.defects, 1);
}

static void test_turn_and_scale(void **state)
{
    psd_data_diag t = diagnose(TURN), s = diagnose(SCALE);
    assert_false(t.mirrored);
    assert_true(fabs(t.turn_deg - 20) < 1e-6);
    assert_int_equal(t.defects, 1);
    assert_true(fabs(s.scale - 0.4) < 1e-6);
    assert_int_equal(s.defects, 1);
}

static void test_squeeze(void **state)
{
    psd_data_diag g = diagnose(SQUEEZE);
    /* travel 1 - 0.5 (theta - 30) / 10 of the map's beyond the inner field
     * (27.0 deg): below 0.8 from 34 deg, the first bin whose median is
     * below it 35-40 (30-35's is about 0.87) */
    assert_true(fabs(g.compressed_from_deg - 35) < 1e-9);
    assert_true(g.outer_ratio < 0.6);
    assert_int_equal(g.defects, 1);
}

static void test_dead_centre_not_judged(void **state)
{
    psd_data_diag g = diagnose(DEAD_CENTRE);
    assert_true(isnan(g.compressed_from_deg));
}

static void test_outliers_by_line(void **state)
{
    psd_data_diag g = diagnose(OUTLIERS);
    assert_int_equal(g.outliers, 2);
    assert_int_equal(g.outlier_line[0], N / 2 + 3);
    assert_int_equal(g.outlier_line[1], N / 2 + 4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_design_itself),   cmocka_unit_test(test_mirrors),
        cmocka_unit_test(test_turn_and_scale),  cmocka_unit_test(test_squeeze),
        cmocka_unit_test(test_dead_centre_not_judged), cmocka_unit_test(test_outliers_by_line),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
