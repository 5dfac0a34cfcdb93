/* test_core_engine.c - the family-neutral engine's small pieces against values
 * worked out here: grid counts (decimal steps that binary rounds below a
 * whole number), which band holds a point on a band edge (the lower edge
 * belongs to the band below, 0 deg to the first band), the per-band RMS
 * (square root of the mean square, times the unit scale), a failed unit's
 * NaN after values; and the Monte Carlo loop with a counting family: every
 * unit of a range run once with its own number into its own slot, a unit's
 * failure and a workspace failure reported (the failing unit named) and no
 * unit run without a workspace, progress counted up to the range's size. */
#include "test_util.h"

#include "family.h"
#include "montecarlo.h"
#include "status.h"

/* ---- grids ---- */

static void grid_counts(void **state)
{
    (void)state;
    assert_int_equal(grid_count(-60, 60, 0.3, 0), 401);
    assert_int_equal(grid_count(0, 1, 0.1, 0), 11);
    /* 0.3 / 0.1 = 2.9999999999999996 in doubles: the end point still counts */
    assert_int_equal(grid_count(0, 0.3, 0.1, 0), 4);
    assert_int_equal(grid_count(0.1, 0.7, 0.2, 0), 4);
    /* an offset shifts the first point: 0.1, 0.3, 0.5, 0.7, 0.9 */
    assert_int_equal(grid_count(0, 1, 0.2, 0.1), 5);
    assert_int_equal(grid_count(0, 1, 0.2, 0.3), 4);
    /* one point when the range is a point; none when it is reversed */
    assert_int_equal(grid_count(5, 5, 1, 0), 1);
    assert_int_equal(grid_count(5, 4, 1, 0), 0);
    assert_int_equal(grid_count(0, 1, 1, 2), 0);
    /* a step that does not divide the span: the last point is below hi */
    assert_int_equal(grid_count(-62, 62, 0.7, 0), 178);
}

/* The points a curve's axis takes (grid_values): lo + offset + j step,
 * the count beyond the room given, nothing written past it. */
static void grid_value_points(void **state)
{
    (void)state;
    double v[6] = {-1, -1, -1, -1, -1, -1};
    /* 0.1, 0.3, 0.5, 0.7, 0.9: all five with room for five */
    assert_int_equal(grid_values(0, 1, 0.2, 0.1, v, 5), 5);
    for (int j = 0; j < 5; j++)
        assert_true(v[j] == 0 + 0.1 + (double)j * 0.2);
    assert_true(v[5] == -1);
    /* one short of room: four written, the count still five */
    v[4] = -1;
    assert_int_equal(grid_values(0, 1, 0.2, 0.1, v, 4), 5);
    assert_true(v[4] == -1);
    /* no room: nothing written, the count told */
    v[0] = -1;
    assert_int_equal(grid_values(-60, 60, 0.3, 0, v, 0), 401);
    assert_true(v[0] == -1);
    /* the end point 0.3 of 0.3 / 0.1 = 2.9999999999999996 is a point */
    assert_int_equal(grid_values(0, 0.3, 0.1, 0, v, 6), 4);
    assert_true(v[3] == 3 * 0.1);
    /* a reversed range: none */
    assert_int_equal(grid_values(5, 4, 1, 0, v, 6), 0);
}

/* A key's list of angles (list_values): every value in order, the count
 * beyond the room given, nothing written past it. */
static void list_value_points(void **state)
{
    (void)state;
    double_list l = {.n = 3, .v = {-20, 0, 35}};
    double v[4] = {9, 9, 9, 9};
    assert_int_equal(list_values(&l, v, 4), 3);
    assert_true(v[0] == -20 && v[1] == 0 && v[2] == 35 && v[3] == 9);
    v[2] = 9;
    assert_int_equal(list_values(&l, v, 2), 3);
    assert_true(v[1] == 0 && v[2] == 9);
    l.n = CONFIG_LIST_MAX;
    v[0] = 9;
    assert_int_equal(list_values(&l, v, 0), CONFIG_LIST_MAX);
    assert_true(v[0] == 9);
}

/* ---- bands ---- */

static band_list three_bands(void)
{
    band_list b;
    memset(&b, 0, sizeof b);
    b.n = 3;
    const double lo[3] = {0, 20, 0}, hi[3] = {20, 40, 60};
    for (int i = 0; i < 3; i++) {
        b.lo[i] = lo[i];
        b.hi[i] = hi[i];
    }
    return b;
}

/* Which bands a point at abs_deg goes into, as a bit mask. */
static int bands_of(const band_list *bands, double abs_deg)
{
    band_acc a;
    band_acc_reset(&a);
    band_acc_add(&a, bands, abs_deg, 1.0);
    int mask = 0;
    for (int i = 0; i < bands->n; i++) {
        assert_true(a.n[i] == 0 || a.n[i] == 1);
        mask |= (int)a.n[i] << i;
    }
    return mask;
}

static void band_edges(void **state)
{
    (void)state;
    band_list b = three_bands();
    assert_int_equal(bands_of(&b, 0.0), 1 | 4);       /* 0 deg is in the first band */
    assert_int_equal(bands_of(&b, 10.0), 1 | 4);
    assert_int_equal(bands_of(&b, 20.0), 1 | 4);      /* an upper edge is inside */
    assert_int_equal(bands_of(&b, 20.0 + 1e-6), 2 | 4); /* just above it is the next band */
    assert_int_equal(bands_of(&b, 40.0), 2 | 4);
    assert_int_equal(bands_of(&b, 40.0 + 1e-6), 4);
    assert_int_equal(bands_of(&b, 60.0), 4);
    assert_int_equal(bands_of(&b, 60.0 + 1e-6), 0);
    /* a band starting above 0 does not hold its lower edge or 0 */
    band_list c = b;
    c.n = 1;
    c.lo[0] = 5;
    c.hi[0] = 10;
    assert_int_equal(bands_of(&c, 0.0), 0);
    assert_int_equal(bands_of(&c, 5.0), 0);
    assert_int_equal(bands_of(&c, 5.0 + 1e-6), 1);
    assert_int_equal(bands_of(&c, 10.0), 1);
}

static void band_rms(void **state)
{
    (void)state;
    band_list b = three_bands();
    band_acc a;
    band_acc_reset(&a);
    band_acc_add(&a, &b, 5.0, 3.0);   /* bands 0 and 2 */
    band_acc_add(&a, &b, 15.0, -4.0); /* bands 0 and 2 */
    band_acc_add(&a, &b, 50.0, 12.0); /* band 2 */
    assert_int_equal(a.n[0], 2);
    assert_int_equal(a.n[1], 0);
    assert_int_equal(a.n[2], 3);
    assert_near(a.sum2[0], 25.0, 1e-12);
    assert_near(a.sum2[2], 169.0, 1e-12);
    double out[3];
    band_acc_rms(&a, &b, 2.0, out);
    assert_near(out[0], 2.0 * sqrt(25.0 / 2.0), 1e-12);
    assert_true(isnan(out[1])); /* an empty band */
    assert_near(out[2], 2.0 * sqrt(169.0 / 3.0), 1e-12);
}

/* unit_result_set_rms / _sys: before always, after and after_sys from
 * their own accumulators, NaN for a failed fit. */
static void unit_rms(void **state)
{
    (void)state;
    band_list b = three_bands();
    band_acc before, after, sys;
    band_acc_reset(&before);
    band_acc_reset(&after);
    band_acc_reset(&sys);
    band_acc_add(&before, &b, 10.0, 8.0);
    band_acc_add(&after, &b, 10.0, 2.0);
    band_acc_add(&after, &b, 30.0, 1.0);
    band_acc_add(&sys, &b, 30.0, 0.5);
    for (int failed = 0; failed <= 1; failed++) {
        unit_result r;
        memset(&r, 0, sizeof r);
        r.fit_status = failed ? UNIT_FIT_FAILED : UNIT_FIT_OK;
        unit_result_set_rms(&r, 1, &before, &after, &b, 10.0);
        unit_result_set_sys(&r, 1, &sys, &b, 10.0);
        assert_near(r.rms_before[1][0], 80.0, 1e-12);
        assert_true(isnan(r.rms_before[1][1]));
        assert_near(r.rms_before[1][2], 80.0, 1e-12);
        assert_true(r.rms_before[0][0] == 0.0); /* another angle untouched */
        if (failed) {
            for (int i = 0; i < 3; i++) {
                assert_true(isnan(r.rms_after[1][i]));
                assert_true(isnan(r.rms_after_sys[1][i]));
            }
        } else {
            assert_near(r.rms_after[1][0], 20.0, 1e-12);
            assert_near(r.rms_after[1][1], 10.0, 1e-12);
            assert_near(r.rms_after[1][2], 10.0 * sqrt(2.5), 1e-12);
            assert_true(isnan(r.rms_after_sys[1][0]));
            assert_near(r.rms_after_sys[1][1], 5.0, 1e-12);
            assert_near(r.rms_after_sys[1][2], 5.0, 1e-12);
        }
    }
}

/* ---- the Monte Carlo loop, with a family that counts ---- */

#define MC_UNITS 40
static int runs[MC_UNITS + 10];
static int fail_unit = -1;
static int fail_workspace;
static long progress_calls, progress_last, progress_total;

static void *count_ws_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    if (fail_workspace) {
        snprintf(err, errlen, "no room for the workspace");
        return NULL;
    }
    return malloc(8);
}

static void count_ws_free(void *ws) { free(ws); }

static int count_unit_run(const sunmc_config *c, long unit, void *ws, unit_result *r)
{
    assert_non_null(ws);
#pragma omp atomic
    runs[unit]++;
    memset(r, 0, sizeof *r);
    r->unit = unit;
    r->dev[0] = 3.0 * (double)unit + 1.0;
    return unit == fail_unit ? SUNMC_EINPUT : SUNMC_OK;
}

static void count_progress(long done, long total, void *ctx)
{
    (void)ctx;
    progress_calls++;
    assert_true(done > progress_last);
    progress_last = done;
    progress_total = total;
}

static const sensor_family counting = {
    .name = "counting",
    .workspace_alloc = count_ws_alloc,
    .workspace_free = count_ws_free,
    .unit_run = count_unit_run,
};

static void reset_counts(void)
{
    memset(runs, 0, sizeof runs);
    fail_unit = -1;
    fail_workspace = 0;
    progress_calls = progress_last = progress_total = 0;
}

/* Units [7, 40) on 1 and 2 threads: each run once, as itself, in its slot;
 * progress (thread 0 only) reaches the range's size on one thread. */
static void mc_every_unit_once(void **state)
{
    (void)state;
    sunmc_config c;
    memset(&c, 0, sizeof c);
    c.family = &counting;
    unit_result res[MC_UNITS];
    char err[SUNMC_ERRLEN] = "";
    for (int threads = 1; threads <= 2; threads++) {
        reset_counts();
        memset(res, 0xff, sizeof res);
        assert_int_equal(mc_run(&c, 7, MC_UNITS, threads, res, count_progress, NULL,
                                err, sizeof err),
                         SUNMC_OK);
        for (int u = 0; u < MC_UNITS + 10; u++)
            assert_int_equal(runs[u], u >= 7 && u < MC_UNITS ? 1 : 0);
        for (int u = 7; u < MC_UNITS; u++) {
            assert_int_equal(res[u - 7].unit, u);
            assert_near(res[u - 7].dev[0], 3.0 * u + 1.0, 0);
        }
        if (threads == 1) {
            assert_int_equal(progress_calls, MC_UNITS - 7);
            assert_int_equal(progress_last, MC_UNITS - 7);
            assert_int_equal(progress_total, MC_UNITS - 7);
        }
    }
}

static void mc_failures(void **state)
{
    (void)state;
    sunmc_config c;
    memset(&c, 0, sizeof c);
    c.family = &counting;
    unit_result res[MC_UNITS];
    char err[SUNMC_ERRLEN] = "";
    /* a unit whose simulation fails: the run fails and names it */
    reset_counts();
    fail_unit = 12;
    assert_int_equal(mc_run(&c, 0, MC_UNITS, 1, res, NULL, NULL, err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "unit 12"));
    assert_int_equal(runs[12], 1);
    assert_int_equal(runs[13], 0); /* one thread: nothing after the failure runs */
    /* no workspace: the run fails with its message and no unit runs */
    for (int threads = 1; threads <= 2; threads++) {
        reset_counts();
        fail_workspace = 1;
        err[0] = '\0';
        assert_int_equal(mc_run(&c, 0, MC_UNITS, threads, res, NULL, NULL, err,
                                sizeof err),
                         SUNMC_ENOMEM);
        assert_non_null(strstr(err, "no room for the workspace"));
        for (int u = 0; u < MC_UNITS; u++)
            assert_int_equal(runs[u], 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(grid_counts),
        cmocka_unit_test(grid_value_points),
        cmocka_unit_test(list_value_points),
        cmocka_unit_test(band_edges),
        cmocka_unit_test(band_rms),           cmocka_unit_test(unit_rms),
        cmocka_unit_test(mc_every_unit_once), cmocka_unit_test(mc_failures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
