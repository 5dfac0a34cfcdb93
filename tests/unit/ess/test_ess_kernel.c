/* test_ess_kernel.c - the ESS unit kernel's shortcuts (issue 27) give the
 * bits of the plain computation: coarse rows read by comparing tangents
 * instead of arctangents (per-sensor tables of the cells' edges, two rows
 * a reading), and the validation grid's cosines and sines
 * made once per run instead of once per reading; fine rows 1-3 made
 * from row 0 by series give its readings to 5e-15 rad. */
#include "test_util.h"

#include "config.h"
#include "ess_sensor.h"
#include "ess_unit.h"
#include "rng.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

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

/* The ESS defaults with the tilt and etching tolerances five-fold (still
 * within the fine rows' series). */
static sunmc_config five_fold_config(void)
{
    const char *sets[] = {"sensor.family=ess", "tolerance.dphi_deg=0.05", "tolerance.etch_um=1",
                          "tolerance.gain_pct=5"};
    char err[SUNMC_ERRLEN];
    config_state st;
    if (config_build(&st, NULL, sets, 4, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    sunmc_config c = st.cfg;
    config_state_free(&st);
    return c;
}

/* Units of design d sampled from c: every reading of the comparison
 * path from the tables (coarse_by_table: two rows a reading, a third
 * where they differ), of the comparison path with a tangent a reading,
 * and of the arctangent path are the same bits, on a grid finer than the
 * cells (cell edges crossed many times, rows straddling them); the units
 * where the comparison was taken are counted. */
static int coarse_paths_agree(const sunmc_config *c, const ess_design *d, long units, int table,
                              double b_step)
{
    int compared = 0;
    for (long unit = 0; unit < units; unit++) {
        ess_deviations dev;
        ess_deviations_sample(c, 7, unit, &dev);
        ess_sensor s, t, w;
        ess_sensor_init(&s, d, &dev);
        assert_int_equal(s.coarse_by_table, table);
        compared += s.coarse_by_compare;
        t = s;
        t.coarse_by_table = 0;
        w = s;
        w.coarse_by_compare = 0;
        for (double a = -61.99; a <= 62; a += 0.0731)
            for (double b = -25; b <= 25; b += b_step) {
                double x = read_rad(&s, a, b), y = read_rad(&t, a, b), z = read_rad(&w, a, b);
                if (x != z || y != z)
                    fail_msg("unit %ld alpha %.4f beta %g: table %.17g, compare %.17g, atan "
                             "%.17g", unit, a, b, x, y, z);
            }
    }
    return compared;
}

/* Sampled units (tolerances x 20: tilts of a few tenths of a degree,
 * etching of tens of micrometres, still within half a cell). */
static void test_coarse_compare_matches_atan(void **state)
{
    sunmc_config c = wide_config();
    /* the comparison path was the one tested */
    assert_true(coarse_paths_agree(&c, &ess_cfg(&c)->design, 40, 1, 25) >= 30);
}

/* The rows in any order across the dial: the outermost rows are found by
 * their x, not their place in the list, and the row telling two cells
 * apart by its Gray bit.  Cells of 0.8 fine periods: a cell one off then
 * picks another period (with cells of half a period or less either cell
 * next to an edge picks the same one, and a wrong straddling row would
 * not show). */
static void test_coarse_table_rows_shuffled(void **state)
{
    sunmc_config c = wide_config();
    ess_design d = ess_cfg(&c)->design;
    d.coarse_resolution_deg = 0.8 * d.theta0_deg;
    const double x[] = {-3.0, -4.2, -0.6, -1.8, -3.6, -1.2, -2.4};
    assert_int_equal(d.coarse_rows_x_mm.n, 7);
    for (int j = 0; j < 7; j++)
        d.coarse_rows_x_mm.v[j] = x[j];
    ess_sensor s;
    ess_deviations dev = {0};
    ess_sensor_init(&s, &d, &dev);
    assert_int_equal(s.coarse_row_min, 1);
    assert_int_equal(s.coarse_row_max, 2);
    /* cells 3 | 4 (011 | 100) differ in bit 2: row 7 - 1 - 2; 4 | 5 in bit 0 */
    assert_true(s.coarse_step_x_mm[3] == x[4]);
    assert_true(s.coarse_step_x_mm[4] == x[6]);
    assert_true(coarse_paths_agree(&c, &d, 20, 1, 25) >= 15);
}

/* The tables are made for up to ESS_COARSE_TABLE_CELLS cells (8 rows),
 * not beyond (9 rows read each cell's tangent a reading): both give the
 * arctangent path's bits. */
static void test_coarse_table_limit(void **state)
{
    sunmc_config c = five_fold_config();
    ess_design d = ess_cfg(&c)->design;
    assert_int_equal(ESS_COARSE_TABLE_CELLS, 256);
    d.coarse_rows_x_mm.n = 8;
    d.coarse_resolution_deg = 0.5;
    for (int j = 0; j < 8; j++)
        d.coarse_rows_x_mm.v[j] = -4.2 + 0.5 * j;
    assert_true(coarse_paths_agree(&c, &d, 6, 1, 50) >= 5);
    d.coarse_rows_x_mm.n = 9;
    d.coarse_resolution_deg = 0.25;
    d.coarse_rows_x_mm.v[8] = -4.5;
    assert_true(coarse_paths_agree(&c, &d, 6, 0, 50) >= 5);
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

/* A noisy reading (row noise noise_frac of the currents). */
static double read_noisy_rad(const ess_sensor *s, double alpha_deg, double beta_deg,
                             const double noise[ESS_FINE_ROWS])
{
    double a = alpha_deg * RAD_PER_DEG, b = beta_deg * RAD_PER_DEG;
    double sv[3] = {sin(b), cos(b) * sin(a), cos(b) * cos(a)};
    double out = NAN;
    assert_int_equal(ess_sensor_output(s, sv, noise, &out), SUNMC_OK);
    return out;
}

/* Fine rows 1-3 from row 0 (fine_dt, series): every reading, noisy or
 * not, within 5e-15 rad (1e-9 arcsec) of the one made of each row's own
 * arctangent, cosine and sine, over sampled units and the whole dial
 * (cell and period edges crossed many times); the series path was the
 * one taken. */
static void test_fine_series_matches_atan(void **state)
{
    sunmc_config c = five_fold_config();
    ess_config *ec = ess_cfg(&c);
    int series = 0;
    double worst = 0;
    const double noise[ESS_FINE_ROWS] = {1e-3, -2e-3, 5e-4, 1.5e-3};
    for (long unit = 0; unit < 30; unit++) {
        ess_deviations dev;
        ess_deviations_sample(&c, 11, unit, &dev);
        ess_sensor s, t;
        ess_sensor_init(&s, &ec->design, &dev);
        series += s.fine_by_series;
        t = s;
        t.fine_by_series = 0;
        for (double a = -61.99; a <= 62; a += 0.0931)
            for (double b = -40; b <= 40; b += 20) {
                double x = read_rad(&s, a, b) - read_rad(&t, a, b);
                double y = read_noisy_rad(&s, a, b, noise) - read_noisy_rad(&t, a, b, noise);
                worst = fmax(worst, fmax(fabs(x), fabs(y)));
                if (fabs(x) > 5e-15 || fabs(y) > 5e-15)
                    fail_msg("unit %ld alpha %.4f beta %g: series - atan %.3g, noisy %.3g", unit,
                             a, b, x, y);
            }
    }
    assert_int_equal(series, 30);
    print_message("fine rows by series: largest difference %.3g rad\n", worst);
}

/* The series are taken while the rows' tangents differ by at most
 * ESS_FINE_SERIES_TAN and turn the phase by at most ESS_FINE_SERIES_PHASE,
 * and not beyond: fine row 3's etching error at the phase limit (2 deg
 * periods: the tighter one), just below and just above; and on a 20-deg
 * period the tangents' limit binds. */
static void test_fine_series_limit(void **state)
{
    sunmc_config c = base_config();
    ess_config *ec = ess_cfg(&c);
    double margin = 1.0 + 1e-4; /* ess_sensor_init's */
    double lim_um = ESS_FINE_SERIES_PHASE * ec->design.theta0_deg * RAD_PER_DEG / (2 * M_PI) *
                    ec->design.H_mm / MM_PER_UM / margin;
    assert_true(lim_um / ec->design.H_mm * MM_PER_UM < ESS_FINE_SERIES_TAN);
    ess_deviations dev = {0};
    ess_sensor s;
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.fine_by_series, 1);
    dev.etch_um[3] = lim_um * (1 - 1e-9);
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.fine_by_series, 1);
    assert_near(s.fine_dt[3], -lim_um * (1 - 1e-9) * MM_PER_UM / ec->design.H_mm, 1e-18);
    dev.etch_um[3] = -lim_um * (1 + 1e-9);
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.fine_by_series, 0);
    /* beyond it the rows' own arctangents read the dial as before */
    double out = read_rad(&s, 33.3, 0) * DEG_PER_RAD;
    assert_true(fabs(out - 33.3) < 0.1 * ec->design.theta0_deg);
    /* a tilt: row m's tangent differs by (x_m - x_0) tan(dphi) / H */
    memset(&dev, 0, sizeof dev);
    dev.dphi_deg = 0.01;
    ess_sensor_init(&s, &ec->design, &dev);
    double dx = ec->design.fine_rows_x_mm.v[2] - ec->design.fine_rows_x_mm.v[0];
    assert_near(s.fine_dt[2], -dx * tan(0.01 * RAD_PER_DEG) / ec->design.H_mm, 1e-18);
    /* a long period: the tangents' limit */
    ec->design.theta0_deg = 20;
    double tan_um = ESS_FINE_SERIES_TAN * ec->design.H_mm / MM_PER_UM / margin;
    memset(&dev, 0, sizeof dev);
    dev.etch_um[1] = tan_um * (1 - 1e-9);
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.fine_by_series, 1);
    dev.etch_um[1] = tan_um * (1 + 1e-9);
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.fine_by_series, 0);
}

/* The validation grid's table (ess_val_alloc): the angles of the grid and
 * their cosines and sines; a unit's noise-free validation reading from it
 * is the bits of ess_unit_read at the same angles (cosines on the spot). */
/* A noise at 0 draws nothing from its stream (ess_readings.c), and the
 * readings are those the draws scaled by 0 give: with the row noise at 0
 * and the encoder's at 3", a campaign point's true table angles still
 * carry the encoder errors, the stream's first two normals; with both at
 * 0 they are the recorded angles and every reading is the noise-free one;
 * a validation without row noise reads raw = raw0. */
static void test_zero_noise_draws_nothing(void **state)
{
    const char *sets[] = {"sensor.family=ess", "noise.row_current_pct=0",
                          "noise.encoder_arcsec=3"};
    char err[SUNMC_ERRLEN];
    config_state st;
    assert_int_equal(config_build(&st, NULL, sets, 3, err, sizeof err), SUNMC_OK);
    sunmc_config c = st.cfg;
    config_state_free(&st);
    ess_deviations dev;
    ess_deviations_sample(&c, 7, 3, &dev);
    ess_unit u;
    ess_unit_build(&c, &dev, &u);
    double a[3] = {0.1, -0.4, 0.7}, b[3] = {0.0, 0.2, -0.3}, z[2];
    ess_campaign_point p[3], q[3];
    rng_stream r;
    rng_stream_init(&r, 11, 3, RNG_STREAM_CAL_NOISE);
    ess_campaign_batch(&c, &u, &r, 3, a, b, p);
    rng_stream_init(&r, 11, 3, RNG_STREAM_CAL_NOISE);
    rng_normal_fill(&r, z, 2);
    double enc = 3 * RAD_PER_ARCSEC;
    assert_true(p[0].a_true_rad == a[0] + enc * z[0]);
    assert_true(p[0].b_true_rad == b[0] + enc * z[1]);
    c.encoder_arcsec = 0;
    rng_stream_init(&r, 11, 3, RNG_STREAM_CAL_NOISE);
    ess_campaign_batch(&c, &u, &r, 3, a, b, q);
    for (int i = 0; i < 3; i++) {
        assert_true(q[i].a_true_rad == a[i] && q[i].b_true_rad == b[i]);
        double raw = NAN, truth = NAN;
        double quiet[ESS_FINE_ROWS] = {0, 0, 0, 0};
        if (q[i].seen) {
            assert_int_equal(ess_unit_read(&u, a[i], b[i], quiet, &raw, &truth), SUNMC_OK);
            assert_true(q[i].raw_rad == raw);
        }
    }
    double ta[4] = {0.05, -0.2, 0.3, 0.9}, tb[4] = {0, 0.1, -0.1, 0.2};
    double ca[8], sa[8], cb[8], sb[8], raw[4], raw0[4], truth[4];
    int status[4];
    ess_table_trig t = {ca, sa, cb, sb};
    ess_table_trig_fill(4, ta, tb, &t);
    rng_stream_init(&r, 11, 3, RNG_STREAM_VAL_NOISE);
    ess_validation_batch(&c, &u, &r, 4, &t, raw, raw0, truth, status);
    for (int i = 0; i < 4; i++)
        assert_true(raw[i] == raw0[i]);
}

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
    u.sensor.phase0_by_series = 0; /* raw0 by atan2, as a reading alone */
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

/* The series path's harmonics (ess_lane_harmonics_q: one division) for
 * a slit whose sinc argument at normal incidence is just below and just
 * above ESS_SINC_SMALL, and none: finite, and within 5e-15 rad of the
 * path with each row's own calls and the plain sinc. */
static void test_harmonics_small_slit(void **state)
{
    sunmc_config c = base_config();
    ess_design d = ess_cfg(&c)->design;
    double z_um = 1e-8 * d.H_mm * d.theta0_deg * RAD_PER_DEG / MM_PER_UM;
    const double widths[] = {z_um * (1 - 1e-3), z_um * (1 + 1e-3), 0};
    for (int k = 0; k < 3; k++) {
        d.slit_width_um = widths[k];
        ess_deviations dev = {0};
        ess_sensor s, t;
        ess_sensor_init(&s, &d, &dev);
        assert_int_equal(s.fine_by_series, 1);
        t = s;
        t.fine_by_series = 0;
        for (double a = -61.9; a <= 62; a += 7.7) {
            double x = read_rad(&s, a, 10), y = read_rad(&t, a, 10);
            assert_true(isfinite(x));
            assert_near(x, y, 5e-15);
        }
    }
}

/* One reading through the batch (lane 0 of a chunk of one), with and
 * without its noise. */
static void read_pair(const ess_sensor *s, double alpha_deg, double beta_deg,
                      const double noise[ESS_FINE_ROWS], double *out, double *out0)
{
    double a = alpha_deg * RAD_PER_DEG, b = beta_deg * RAD_PER_DEG;
    _Alignas(VM_ALIGN) double x[VM_PAD], y[VM_PAD], z[VM_PAD], o[VM_PAD], o0[VM_PAD];
    _Alignas(VM_ALIGN) double nz[ESS_FINE_ROWS][VM_PAD];
    const double *np[ESS_FINE_ROWS] = {nz[0], nz[1], nz[2], nz[3]};
    int st[VM_PAD];
    for (int i = 0; i < VM_PAD; i++) {
        x[i] = sin(b);
        y[i] = cos(b) * sin(a);
        z[i] = cos(b) * cos(a);
        for (int m = 0; m < ESS_FINE_ROWS; m++)
            nz[m][i] = noise[m];
    }
    assert_int_equal(ess_sensor_output_chunk(s, 1, x, y, z, np, o, o0, st), SUNMC_OK);
    assert_int_equal(st[0], SUNMC_OK);
    *out = o[0];
    *out0 = o0[0];
}

/* The noise-free phase turned from the noisy one by series
 * (phase0_by_series) against its own atan2: the noisy readings the same
 * bits, the noise-free ones within 2.5e-16 rad (an ulp of the largest
 * angles), over sampled units (tolerances five-fold), the whole dial and
 * row noise of 1.5 % (shipped) and 10 % of the fundamental. */
static void test_phase0_series_matches_atan2(void **state)
{
    sunmc_config c = five_fold_config();
    ess_config *ec = ess_cfg(&c);
    double worst = 0;
    long differ = 0, n = 0;
    rng_stream r;
    rng_stream_init(&r, 5, 0, RNG_STREAM_VAL_NOISE);
    for (long unit = 0; unit < 12; unit++) {
        ess_deviations dev;
        ess_deviations_sample(&c, 13, unit, &dev);
        ess_sensor s, t;
        ess_sensor_init(&s, &ec->design, &dev);
        assert_int_equal(s.phase0_by_series, 1);
        t = s;
        t.phase0_by_series = 0;
        double sigma = unit % 2 ? 0.1 : 0.015;
        for (double a = -61.99; a <= 62; a += 0.1731)
            for (double b = -25; b <= 25; b += 25) {
                double nz[ESS_FINE_ROWS], x, x0, y, y0;
                rng_normal_fill(&r, nz, ESS_FINE_ROWS);
                for (int m = 0; m < ESS_FINE_ROWS; m++)
                    nz[m] *= sigma;
                read_pair(&s, a, b, nz, &x, &x0);
                read_pair(&t, a, b, nz, &y, &y0);
                if (x != y || !(fabs(x0 - y0) <= 2.5e-16))
                    fail_msg("unit %ld alpha %.4f beta %g: noisy %.17g %.17g, noise-free "
                             "series %.17g atan2 %.17g", unit, a, b, x, y, x0, y0);
                worst = fmax(worst, fabs(x0 - y0));
                differ += x0 != y0;
                n++;
            }
    }
    print_message("noise-free phase by series: %ld of %ld readings moved, at most %.3g rad\n",
                  differ, n, worst);
}

/* The series is taken while the phasors' angle has a tangent within
 * ESS_PHASE0_SERIES_TAN, and not beyond (nor a quarter turn apart): an
 * ideal sensor within half a period of 0 (small angles, whose ulps show
 * the phase's last bits), one row's noise set so that the tangent
 * is just within, just beyond, well beyond the limit, and the phasor
 * reversed.  Within: within two ulps of the fine period of atan2's (the
 * series taken: some readings move); beyond: its bits (the series would
 * miss by 1e-13 rad at 0.45). */
static void test_phase0_series_limit(void **state)
{
    sunmc_config c = base_config();
    ess_config *ec = ess_cfg(&c);
    ess_deviations dev = {0};
    ess_sensor s, t;
    ess_sensor_init(&s, &ec->design, &dev);
    t = s;
    t.phase0_by_series = 0;
    const double lim = ESS_PHASE0_SERIES_TAN;
    const double es[] = {lim * (1 - 1e-6), -lim * (1 - 1e-6), lim * (1 + 1e-6),
                         -lim * (1 + 1e-6), 0.45, -0.45};
    /* two ulps of the fine period: a phase near 2 pi is a period less */
    double ulp2 = 2 * (nextafter(s.theta0_rad, 1) - s.theta0_rad);
    int moved = 0;
    for (double a_deg = 0.05; a_deg < 0.9; a_deg += 0.2) {
        /* the noise-free phasor (x0, y0) = (I2 - I0, I3 - I1) */
        double a = a_deg * RAD_PER_DEG, psi[ESS_FINE_ROWS], cur[ESS_FINE_ROWS];
        for (int m = 0; m < ESS_FINE_ROWS; m++)
            psi[m] = atan((ess_slit_eta_mm(&s, s.fine_x_mm[m], 0, tan(a)) - s.etch_mm[m]) /
                          s.H_mm);
        ess_finecode_currents(&s, psi, cos(a), NULL, cur);
        double x0 = cur[2] - cur[0], y0 = cur[3] - cur[1];
        for (int k = 0; k < 6; k++) {
            /* noise d on row 3 (y = y0 + d): e = -d x0 / (x0^2 + y0^2 + d y0) */
            double e = es[k], d = -e * (x0 * x0 + y0 * y0) / (x0 + e * y0);
            double nz[ESS_FINE_ROWS] = {0, 0, 0, d}, p, p0, q, q0;
            read_pair(&s, a_deg, 0, nz, &p, &p0);
            read_pair(&t, a_deg, 0, nz, &q, &q0);
            assert_true(p == q);
            if (fabs(e) < lim) {
                assert_near(p0, q0, ulp2);
                moved += p0 != q0;
            } else if (p0 != q0)
                fail_msg("alpha %g e %g: series %.17g, atan2 %.17g", a_deg, e, p0, q0);
        }
        /* the noisy phasor reversed: a half turn apart */
        double nz[ESS_FINE_ROWS] = {x0, y0, -x0, -y0}, p, p0, q, q0;
        read_pair(&s, a_deg, 0, nz, &p, &p0);
        read_pair(&t, a_deg, 0, nz, &q, &q0);
        assert_true(p == q && p0 == q0);
    }
    assert_true(moved > 0); /* within the limit the series was taken */
}

/* Every reading of s within 5e-15 rad of the arctangent paths' (noisy or
 * not) over directions to 88 deg from the boresight (w to 28), those
 * beyond w_safe bit for bit; some were. */
static void dial_tilt_reads_agree(const ess_sensor *s0, double tan_dphi)
{
    ess_sensor s = *s0, t = *s0;
    t.fine_by_series = 0;
    t.coarse_by_compare = 0;
    const double noise[ESS_FINE_ROWS] = {1e-3, -2e-3, 5e-4, 1.5e-3};
    int wide = 0;
    for (double a = -88; a <= 88; a += 0.173)
        for (double b = -60; b <= 60; b += 30) {
            double ar = a * RAD_PER_DEG, br = b * RAD_PER_DEG;
            double w = tan(ar) - tan(br) / cos(ar) * tan_dphi;
            if (cos(ar) * cos(br) < 0.02)
                continue;
            double x = read_rad(&s, a, b), y = read_rad(&t, a, b);
            double xn = read_noisy_rad(&s, a, b, noise), yn = read_noisy_rad(&t, a, b, noise);
            if (fabs(w) > s.w_safe) {
                wide++;
                if (x != y || xn != yn)
                    fail_msg("wide alpha %.3f beta %g: %.17g against %.17g", a, b, x, y);
            } else if (fabs(x - y) > 5e-15 || fabs(xn - yn) > 5e-15)
                fail_msg("alpha %.3f beta %g: shortcut - atan %.3g", a, b, x - y);
        }
    assert_true(wide > 20);
}

/* The dial tilt (issue 38): fine row m's tangent differs from row 0's by
 * fine_dt + fine_dt_w w, w = v - u tan(dphi), so the shortcuts hold up to
 * |w| = w_safe (closed forms: the fine rows' series, the coarse
 * comparison's half cell) and the lanes beyond are read by the arctangent
 * paths; without a dial tilt w_safe is +inf. */
static void test_dial_tilt_wide_lanes(void **state)
{
    sunmc_config c = base_config();
    ess_config *ec = ess_cfg(&c);
    ess_deviations dev = {0};
    ess_sensor s;
    ess_sensor_init(&s, &ec->design, &dev);
    assert_true(s.w_safe == HUGE_VAL);
    dev.dial_tilt_deg = 0.5;
    dev.dphi_deg = 0.02;
    dev.etch_um[2] = 0.3;
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.fine_by_series, 1);
    assert_int_equal(s.coarse_by_compare, 1);
    double H = ec->design.H_mm, tt = tan(0.5 * RAD_PER_DEG), tp = tan(0.02 * RAD_PER_DEG);
    double lim = fmin(ESS_FINE_SERIES_TAN, ESS_FINE_SERIES_PHASE * ec->design.theta0_deg *
                                               RAD_PER_DEG / (2 * M_PI)) / (1 + 1e-4);
    double wf = HUGE_VAL;
    for (int m = 1; m < 4; m++) {
        double dxm = ec->design.fine_rows_x_mm.v[m] - ec->design.fine_rows_x_mm.v[0];
        assert_near(s.fine_dt_w[m], dxm * tt / H, 1e-18);
        wf = fmin(wf, (lim - fabs(s.fine_dt[m])) / fabs(s.fine_dt_w[m]));
    }
    double dx = 0.6 + 4.2; /* fine row 0 to the farthest coarse row */
    double wc = (0.5 * ec->design.coarse_resolution_deg * RAD_PER_DEG - dx * tp / H) * H / (dx * tt);
    assert_near(s.w_safe, fmin(wf, wc) * (1 - 1e-9), 1e-9 * s.w_safe);
    dial_tilt_reads_agree(&s, tp);
    /* the fine rows by their arctangents (etching beyond the series): the
     * coarse comparison's bound alone */
    dev.etch_um[3] = 20;
    ess_sensor_init(&s, &ec->design, &dev);
    assert_int_equal(s.fine_by_series, 0);
    assert_int_equal(s.coarse_by_compare, 1);
    assert_near(s.w_safe, wc * (1 - 1e-9), 1e-9 * s.w_safe);
    dial_tilt_reads_agree(&s, tp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_coarse_compare_matches_atan),
        cmocka_unit_test(test_coarse_compare_limit),
        cmocka_unit_test(test_coarse_table_rows_shuffled),
        cmocka_unit_test(test_coarse_table_limit),
        cmocka_unit_test(test_fine_series_matches_atan),
        cmocka_unit_test(test_fine_series_limit),
        cmocka_unit_test(test_validation_trig_table),
        cmocka_unit_test(test_phase0_series_matches_atan2),
        cmocka_unit_test(test_phase0_series_limit),
        cmocka_unit_test(test_harmonics_small_slit),
        cmocka_unit_test(test_zero_noise_draws_nothing),
        cmocka_unit_test(test_dial_tilt_wide_lanes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
