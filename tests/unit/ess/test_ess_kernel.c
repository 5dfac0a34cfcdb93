/* test_ess_kernel.c - the ESS unit kernel's shortcuts (issue 27) give the
 * bits of the plain computation: coarse rows read by comparing tangents
 * instead of arctangents, and the validation grid's cosines and sines
 * made once per run instead of once per reading. */
#include "test_util.h"

#include "config.h"
#include "ess_sensor.h"
#include "ess_unit.h"
#include "status.h"
#include "units.h"

static sunmc_config base_config(void) { return test_family_config("ess"); }

/* The ESS defaults with the tilt and etching tolerances widened. */
static sunmc_config wide_config(void)
{
    const char *sets[] = {"sensor.family=ess", "tolerance.dphi_deg=0.2", "tolerance.etch_um=10"};
    char err[SUNMC_ERRLEN];
    config_state st;
    if (config_build(&st, NULL, sets, 3, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    sunmc_config c = st.cfg;
    config_state_free(&st);
    return c;
}

static double read_rad(const ess_sensor *s, double alpha_deg, double beta_deg)
{
    double a = alpha_deg * RAD_PER_DEG, b = beta_deg * RAD_PER_DEG;
    double sv[3] = {sin(b), cos(b) * sin(a), cos(b) * cos(a)};
    double out = NAN;
    assert_int_equal(ess_sensor_output(s, sv, NULL, &out), SUNMC_OK);
    return out;
}

/* Sampled units (tolerances x 20: tilts of a few tenths of a degree,
 * etching of tens of micrometres, still within half a cell): every
 * reading of the comparison path is the arctangent path's, bit for bit,
 * on a grid finer than the cells (cell edges crossed many times). */
static void test_coarse_compare_matches_atan(void **state)
{
    sunmc_config c = wide_config();
    ess_config *ec = ess_cfg(&c);
    int compared = 0;
    for (long unit = 0; unit < 40; unit++) {
        ess_deviations dev;
        ess_deviations_sample(&c, 7, unit, &dev);
        ess_sensor s, t;
        ess_sensor_init(&s, &ec->design, &dev);
        compared += s.coarse_by_compare;
        t = s;
        t.coarse_by_compare = 0;
        for (double a = -61.99; a <= 62; a += 0.0731)
            for (double b = -25; b <= 25; b += 25) {
                double x = read_rad(&s, a, b), y = read_rad(&t, a, b);
                if (x != y)
                    fail_msg("unit %ld alpha %.4f beta %g: compare %.17g, atan %.17g", unit, a,
                             b, x, y);
            }
    }
    assert_true(compared >= 30); /* the comparison path was the one tested */
}

/* The shortcut is taken while the rows' tangents lie within half a cell
 * of fine row 0's, and not beyond: fine row 0's etching error at the
 * limit H tan(res) / 2 (no tilt), just below and just above. */
static void test_coarse_compare_limit(void **state)
{
    sunmc_config c = base_config();
    ess_config *ec = ess_cfg(&c);
    double half_cell_um = 0.5 * ec->design.coarse_resolution_deg * RAD_PER_DEG *
                          ec->design.H_mm / MM_PER_UM;
    ess_deviations dev = {0};
    ess_sensor s;
    dev.etch_um[0] = half_cell_um * (1 - 1e-9);
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.coarse_by_compare, 1);
    dev.etch_um[0] = -half_cell_um * (1 - 1e-9);
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.coarse_by_compare, 1);
    dev.etch_um[0] = half_cell_um * (1 + 1e-9);
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.coarse_by_compare, 0);
    /* a tilt alone: dphi where the farthest coarse row's spread is a half cell */
    memset(&dev, 0, sizeof dev);
    double dx = ec->design.fine_rows_x_mm.v[0] - ec->design.coarse_rows_x_mm.v[0];
    double lim_deg = atan(0.5 * ec->design.coarse_resolution_deg * RAD_PER_DEG *
                          ec->design.H_mm / fabs(dx)) * DEG_PER_RAD;
    dev.dphi_deg = lim_deg * (1 - 1e-6);
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.coarse_by_compare, 1);
    dev.dphi_deg = -lim_deg * (1 + 1e-6);
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.coarse_by_compare, 0);
    /* beyond the limit the arctangent path reads the dial as before:
     * the coarse code still picks the fine period near the true angle */
    double out = read_rad(&s, 33.3, 0) * DEG_PER_RAD;
    assert_true(fabs(out - 33.3) < 0.5 * ec->design.theta0_deg);
}

/* The validation grid's table (ess_val_alloc): the angles of the grid and
 * their cosines and sines; a unit's noise-free validation reading from it
 * is the bits of ess_unit_read at the same angles (cosines on the spot). */
static void test_validation_trig_table(void **state)
{
    sunmc_config c = base_config();
    ess_val_readings v;
    assert_int_equal(ess_val_alloc(&c, &v), SUNMC_OK);
    assert_int_equal(v.n, ess_validation_size(&c));
    for (size_t i = 0; i < v.n; i += 7) {
        assert_near(v.trig.ca[i], cos(v.alpha_rad[i]), 1e-15);
        assert_near(v.trig.sa[i], sin(v.alpha_rad[i]), 1e-15);
        assert_near(v.trig.cb[i], cos(v.beta_rad[i]), 1e-15);
        assert_near(v.trig.sb[i], sin(v.beta_rad[i]), 1e-15);
    }
    ess_deviations dev;
    ess_deviations_sample(&c, 3, 5, &dev);
    ess_unit u;
    ess_unit_build(&c, &dev, &u);
    ess_unit_read_validation(&c, &u, 5, &v);
    for (size_t i = 0; i < v.n; i++) {
        if (v.status[i] == ESS_READING_UNSEEN)
            continue;
        double raw, truth;
        assert_int_equal(ess_unit_read(&u, v.alpha_rad[i], v.beta_rad[i], NULL, &raw, &truth),
                         SUNMC_OK);
        if (raw != v.raw0_rad[i] || truth != v.truth_rad[i])
            fail_msg("reading %zu: table %.17g %.17g, on the spot %.17g %.17g", i, v.raw0_rad[i],
                     v.truth_rad[i], raw, truth);
    }
    ess_val_free(&v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_coarse_compare_matches_atan),
        cmocka_unit_test(test_coarse_compare_limit),
        cmocka_unit_test(test_validation_trig_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
