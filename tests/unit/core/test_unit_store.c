/* test_unit_store.c - a unit's validation readings read once and shared
 * (unit_store.h, family.h: unit_read / unit_finish): the readings of one
 * config are the bytes another config with another campaign reads, and
 * finishing that config's unit from them gives unit_run's bytes; which
 * configs share readings (a campaign or encoder change does; a tolerance,
 * the validation grid, the seed, a pick-freeze, the DSS's mount or the
 * PSD's table order does not), for ESS, DSS, PSD and the toy; mc_run_store
 * and mc_run_each give mc_run's bytes in 1 and 2 threads, reading each unit
 * once; the range beyond the store's capacity runs without it; and the
 * skipped systematic pass leaves the after RMS as it was. */
#include "test_util.h"

#include "family.h"
#include "montecarlo.h"
#include "rng.h"
#include "status.h"
#include <string.h>
#include "unit_store.h"
#include "registry.h"
#include "toy_family.h"

#include <stdlib.h>

#define UNITS 6

/* ESS type A on a coarse validation grid (fast), plus sets. */
static sunmc_config ess(const char *const *more, int n)
{
    const char *sets[8] = {"validation.alpha_step_deg=1.3", "run.seed=5"};
    for (int i = 0; i < n && i < 6; i++)
        sets[2 + i] = more[i];
    config_state st;
    test_build(&st, "configs/ess_type_a.ini", sets, 2 + n);
    sunmc_config c = st.cfg;
    config_state_free(&st);
    return c;
}

static void *ws_of(const sunmc_config *c)
{
    char err[SUNMC_ERRLEN];
    void *ws = c->family->workspace_alloc(c, err, sizeof err);
    if (!ws)
        fail_msg("%s", err);
    return ws;
}

/* Readings of config a finish config b's units to unit_run's bytes, and
 * are the bytes b reads itself. */
static void check_shared(const sunmc_config *a, const sunmc_config *b)
{
    const sensor_family *fam = a->family;
    assert_true(unit_readings_same(a, b));
    size_t nb = fam->readings_bytes(a);
    assert_int_equal(nb, fam->readings_bytes(b));
    unsigned char *ra = malloc(nb), *rb = malloc(nb);
    void *wa = ws_of(a), *wb = ws_of(b);
    for (long u = 0; u < UNITS; u++) {
        unit_result fresh, shared;
        assert_int_equal(fam->unit_read(a, u, wa, ra), SUNMC_OK);
        assert_int_equal(fam->unit_read(b, u, wb, rb), SUNMC_OK);
        assert_memory_equal(ra, rb, nb);
        assert_int_equal(fam->unit_run(b, u, wb, &fresh), SUNMC_OK);
        assert_int_equal(fam->unit_finish(b, u, wb, ra, &shared), SUNMC_OK);
        assert_memory_equal(&fresh, &shared, sizeof fresh);
        assert_true(isfinite(fresh.rms_after[0][0]));
    }
    fam->workspace_free(wa);
    fam->workspace_free(wb);
    free(ra);
    free(rb);
}

static void readings_ignore_the_campaign(void **state)
{
    (void)state;
    sunmc_config a = ess(NULL, 0);
    const char *other[] = {"campaign.alpha_step_deg=0.3", "campaign.beta_deg=-40, 40",
                           "campaign.repeats=2", "noise.encoder_arcsec=3",
                           "calibration.roll_sigma_arcsec=20"};
    sunmc_config b = ess(other, 5);
    check_shared(&a, &b);
    /* at three operating temperatures, one the lab's (20 C): the lab's
     * block and one for each of the other two */
    const char *hot[] = {"environment.operating_temp_c=-20, 20, 60"};
    const char *hot_b[] = {"environment.operating_temp_c=-20, 20, 60",
                           "campaign.alpha_step_deg=0.3"};
    a = ess(hot, 1);
    b = ess(hot_b, 2);
    sunmc_config lab = ess(NULL, 0);
    assert_int_equal(a.family->readings_bytes(&a), 3 * lab.family->readings_bytes(&lab));
    check_shared(&a, &b);
}

static void readings_differ(void **state)
{
    (void)state;
    sunmc_config a = ess(NULL, 0);
    const char *diff[][1] = {{"tolerance.dH_um=30"},
                             {"validation.alpha_step_deg=1.1"},
                             {"run.seed=6"},
                             {"noise.row_current_pct=2"},
                             {"environment.operating_temp_c=60"}};
    for (size_t i = 0; i < sizeof diff / sizeof diff[0]; i++) {
        sunmc_config b = ess(diff[i], 1);
        assert_false(unit_readings_same(&a, &b));
    }
    sunmc_config b = a;
    b.pick.n = 1;
    b.pick.seed = 9;
    b.pick.stream[0] = 1;
    assert_false(unit_readings_same(&a, &b));
    b.no_systematic = 1; /* what the units skip, not what they read */
    b.pick = a.pick;
    assert_true(unit_readings_same(&a, &b));
    /* a family that does not split its units shares nothing and has no
     * store: the toy without its halves */
    static sensor_family whole;
    whole = toy_family;
    whole.unit_read = NULL;
    sunmc_config t = a;
    t.family = &whole;
    assert_false(unit_readings_same(&t, &t));
    unit_store *s = NULL;
    char err[SUNMC_ERRLEN];
    assert_int_equal(unit_store_alloc(&t, 8, &s, err, sizeof err), SUNMC_OK);
    assert_null(s);
    assert_true(unit_store_bytes(&t, 8) == 0);
    assert_false(unit_store_bind(NULL, &a, 0, 1));
}

/* The DSS: its campaign's grid and repeats and its fit leave the readings
 * as they are; the mount (a campaign key) and the centroid noise do not. */
static void dss_readings(void **state)
{
    (void)state;
    const char *base[] = {"validation.b_step_deg=9"};
    const char *other[] = {"validation.b_step_deg=9", "campaign.b_step_deg=8",
                           "campaign.repeats=2", "calibration.model=polynomial",
                           "noise.encoder_arcsec=4"};
    config_state st;
    test_build(&st, "configs/dss.ini", base, 1);
    sunmc_config a = st.cfg;
    config_state_free(&st);
    test_build(&st, "configs/dss.ini", other, 5);
    sunmc_config b = st.cfg;
    config_state_free(&st);
    check_shared(&a, &b);
    const char *diff[][2] = {{"validation.b_step_deg=9", "campaign.mount=aligned"},
                             {"validation.b_step_deg=9", "noise.centroid_px=0.2"}};
    for (int i = 0; i < 2; i++) {
        test_build(&st, "configs/dss.ini", diff[i], 2);
        assert_false(unit_readings_same(&a, &st.cfg));
        config_state_free(&st);
    }
}

/* The PSD: its campaign's grid and repeats and its fit leave the readings
 * as they are; the table's order (a campaign key) does not. */
static void psd_readings(void **state)
{
    (void)state;
    const char *other[] = {"campaign.alpha_step_deg=4", "campaign.repeats=2",
                           "calibration.model=polynomial"};
    const char *order[] = {"campaign.table_order=alpha_outer"};
    config_state st;
    test_build(&st, "configs/psd.ini", NULL, 0);
    sunmc_config a = st.cfg;
    config_state_free(&st);
    test_build(&st, "configs/psd.ini", other, 3);
    sunmc_config b = st.cfg;
    config_state_free(&st);
    check_shared(&a, &b);
    test_build(&st, "configs/psd.ini", order, 1);
    assert_false(unit_readings_same(&a, &st.cfg));
    config_state_free(&st);
}

/* The toy, with reading noise: its readings do not depend on its
 * campaign's step, and a store serves a run of either. */
static void toy_readings(void **state)
{
    (void)state;
    const char *sa[] = {"sensor.family=toy", "noise.reading_arcsec=3"};
    const char *sb[] = {"sensor.family=toy", "noise.reading_arcsec=3", "campaign.step_deg=2.5"};
    const char *sc[] = {"sensor.family=toy", "noise.reading_arcsec=3", "validation.step_deg=4"};
    config_state st;
    test_build(&st, NULL, sa, 2);
    sunmc_config a = st.cfg;
    config_state_free(&st);
    test_build(&st, NULL, sb, 3);
    sunmc_config b = st.cfg;
    config_state_free(&st);
    check_shared(&a, &b);
    test_build(&st, NULL, sc, 3);
    assert_false(unit_readings_same(&a, &st.cfg));
    config_state_free(&st);
}

/* A pick-freeze of a stream only the campaign draws from (campaign noise,
 * the roll measurement: family_noise.campaign_only) reads the same bytes
 * as no pick; one of the validation noise or of a tolerance does not. */
static void picks_of_campaign_streams(void **state)
{
    (void)state;
    sunmc_config a = ess(NULL, 0), b = a;
    b.pick.n = 1;
    b.pick.seed = 9;
    b.pick.stream[0] = RNG_STREAM_CAL_NOISE;
    check_shared(&a, &b);
    b.pick.stream[0] = RNG_STREAM_ALIGNMENT;
    check_shared(&a, &b);
    b.pick.stream[0] = RNG_STREAM_VAL_NOISE;
    assert_false(unit_readings_same(&a, &b));
    uint32_t dh = 0;
    for (int e = 0; e < a.family->n_deviations; e++)
        if (strcmp(a.family->deviations[e].name, "dH_um") == 0)
            dh = RNG_STREAM_TOLERANCE + a.family->deviations[e].stream;
    assert_true(dh != 0);
    b.pick.stream[0] = dh;
    assert_false(unit_readings_same(&a, &b));
    /* the streams the readings draw from, compared with their seed */
    sunmc_config c = b;
    c.pick.n = 2;
    c.pick.stream[1] = RNG_STREAM_CAL_NOISE;
    assert_true(unit_readings_same(&b, &c));
    c.pick.seed = 10;
    assert_false(unit_readings_same(&b, &c));
}

/* unit_store_alloc_upto: a store at its byte limit is made, one byte
 * over it is not (and that is no error). */
static void store_upto_limit(void **state)
{
    (void)state;
    sunmc_config a = ess(NULL, 0);
    double bytes = unit_store_bytes(&a, 5);
    assert_true(bytes > 0);
    unit_store *s = NULL;
    char err[SUNMC_ERRLEN];
    assert_int_equal(unit_store_alloc_upto(&a, 5, bytes, &s, err, sizeof err), SUNMC_OK);
    assert_non_null(s);
    unit_store_free(s);
    s = (unit_store *)&a; /* overwritten with NULL */
    assert_int_equal(unit_store_alloc_upto(&a, 5, bytes - 1, &s, err, sizeof err), SUNMC_OK);
    assert_null(s);
}

/* mc_run_store and mc_run_each give mc_run's bytes, reading each unit once
 * for configs that share readings. */
static void runs_with_a_store(void **state)
{
    (void)state;
    const char *more[] = {"campaign.alpha_step_deg=0.6", "campaign.beta_deg=-30, 30"};
    sunmc_config c[2] = {ess(NULL, 0), ess(more, 2)};
    unit_result plain[2][UNITS], got[UNITS];
    char err[SUNMC_ERRLEN];
    for (int i = 0; i < 2; i++)
        assert_int_equal(mc_run(&c[i], 0, UNITS, 1, plain[i], NULL, NULL, err, sizeof err),
                         SUNMC_OK);
    for (int threads = 1; threads <= 2; threads++) {
        unit_store *s;
        assert_int_equal(unit_store_alloc(&c[0], UNITS, &s, err, sizeof err), SUNMC_OK);
        assert_non_null(s);
        for (int i = 0; i < 2; i++) {
            assert_int_equal(mc_run_store(&c[i], s, 0, UNITS, threads, got, NULL, NULL, err,
                                          sizeof err), SUNMC_OK);
            assert_memory_equal(got, plain[i], sizeof got);
            assert_int_equal(unit_store_reads(s), UNITS); /* read once, for both */
        }
        /* a range wider than the store runs without it */
        unit_result wide[UNITS + 1];
        assert_int_equal(mc_run_store(&c[1], s, 0, UNITS + 1, threads, wide, NULL, NULL, err,
                                      sizeof err), SUNMC_OK);
        assert_memory_equal(wide, plain[1], sizeof plain[1]);
        assert_int_equal(unit_store_reads(s), UNITS);
        /* the next units take the same slots: read, not the slots' old units */
        unit_result want[UNITS];
        assert_int_equal(mc_run(&c[1], UNITS, 2 * UNITS, 1, want, NULL, NULL, err, sizeof err),
                         SUNMC_OK);
        assert_int_equal(mc_run_store(&c[1], s, UNITS, 2 * UNITS, threads, got, NULL, NULL, err,
                                      sizeof err), SUNMC_OK);
        assert_memory_equal(got, want, sizeof got);
        assert_int_equal(unit_store_reads(s), 2 * UNITS);
        /* other readings empty the store and are read afresh */
        const char *seed[] = {"run.seed=6"};
        sunmc_config o = ess(seed, 1);
        assert_int_equal(mc_run_store(&o, s, 0, 2, threads, got, NULL, NULL, err, sizeof err),
                         SUNMC_OK);
        assert_int_equal(unit_store_reads(s), 2 * UNITS + 2);
        assert_int_equal(mc_run_store(&c[0], s, 0, 2, threads, got, NULL, NULL, err, sizeof err),
                         SUNMC_OK);
        assert_memory_equal(got, plain[0], 2 * sizeof *got);
        assert_int_equal(unit_store_reads(s), 2 * UNITS + 4);
        unit_store_free(s);
    }
}

#define EACH 3

typedef struct {
    unit_result res[EACH][UNITS];
    int calls[EACH];
} each_ctx;

static int each_sink(int i, const unit_result *r, long n, void *ctx, char *err, size_t errlen)
{
    each_ctx *e = ctx;
    assert_int_equal(n, UNITS);
    memcpy(e->res[i], r, (size_t)n * sizeof *r);
    e->calls[i]++;
    return SUNMC_OK;
}

/* Three configs, the third with other readings (another seed): each
 * config's results are mc_run's, the store read once for the first two. */
static void run_each_config(void **state)
{
    (void)state;
    const char *more[] = {"campaign.alpha_step_deg=0.6", "campaign.beta_deg=-30, 30"};
    const char *seed[] = {"run.seed=6"};
    sunmc_config c[EACH] = {ess(NULL, 0), ess(more, 2), ess(seed, 1)};
    const sunmc_config *cp[EACH] = {&c[0], &c[1], &c[2]};
    unit_result plain[EACH][UNITS];
    char err[SUNMC_ERRLEN];
    for (int i = 0; i < EACH; i++)
        assert_int_equal(mc_run(&c[i], 0, UNITS, 1, plain[i], NULL, NULL, err, sizeof err),
                         SUNMC_OK);
    for (int threads = 1; threads <= 2; threads++)
        for (int with_store = 0; with_store <= 1; with_store++) {
            unit_store *s = NULL;
            if (with_store)
                assert_int_equal(unit_store_alloc(&c[0], UNITS, &s, err, sizeof err), SUNMC_OK);
            each_ctx *e = calloc(1, sizeof *e);
            assert_int_equal(mc_run_each(cp, EACH, s, 0, UNITS, threads, each_sink, e, NULL,
                                         NULL, err, sizeof err),
                             SUNMC_OK);
            for (int i = 0; i < EACH; i++) {
                assert_int_equal(e->calls[i], 1);
                assert_memory_equal(e->res[i], plain[i], sizeof plain[i]);
            }
            assert_int_equal(unit_store_reads(s), with_store ? UNITS : 0);
            free(e);
            unit_store_free(s);
        }
}

/* Without the systematic pass: the same RMS before and after, the
 * systematic part NaN (it is finite with the pass); ESS and DSS. */
static void no_sys_check(const sunmc_config *c, int angles)
{
    sunmc_config q = *c;
    q.no_systematic = 1;
    unit_result full[UNITS], quick[UNITS];
    char err[SUNMC_ERRLEN];
    assert_int_equal(mc_run(c, 0, UNITS, 1, full, NULL, NULL, err, sizeof err), SUNMC_OK);
    assert_int_equal(mc_run(&q, 0, UNITS, 1, quick, NULL, NULL, err, sizeof err), SUNMC_OK);
    for (int u = 0; u < UNITS; u++)
        for (int a = 0; a < angles; a++)
            for (int b = 0; b < c->bands_deg.n; b++) {
                assert_true(full[u].rms_before[a][b] == quick[u].rms_before[a][b]);
                assert_true(full[u].rms_after[a][b] == quick[u].rms_after[a][b]);
                assert_true(isfinite(full[u].rms_after_sys[a][b]));
                assert_true(isnan(quick[u].rms_after_sys[a][b]));
            }
}

static void no_systematic_pass(void **state)
{
    (void)state;
    sunmc_config c = ess(NULL, 0);
    no_sys_check(&c, 1);
    const char *coarse[] = {"validation.b_step_deg=9"};
    config_state st;
    test_build(&st, "configs/dss.ini", coarse, 1);
    no_sys_check(&st.cfg, 3);
    config_state_free(&st);
}

/* Each operating temperature is scored on its own block of readings: at
 * the lab's 20 C the lab's RMS before, at -20 and 60 C other ones (the
 * unit's deviations move with temperature), for every family that splits. */
static void temperatures_read_their_own(void **state)
{
    (void)state;
    const char *files[] = {"configs/ess_type_a.ini", "configs/dss.ini", "configs/psd.ini"};
    const char *grid[] = {"validation.alpha_step_deg=1.3", "validation.b_step_deg=9",
                          "validation.alpha_step_deg=2.3"};
    for (int f = 0; f < 3; f++) {
        const char *sets[] = {grid[f], "environment.operating_temp_c=-20, 20, 60"};
        config_state st;
        test_build(&st, files[f], sets, 2);
        unit_result r[2];
        char err[SUNMC_ERRLEN];
        assert_int_equal(mc_run(&st.cfg, 0, 2, 1, r, NULL, NULL, err, sizeof err), SUNMC_OK);
        int a = st.cfg.family->n_angles(&st.cfg) - 1, b = st.cfg.bands_deg.n - 1;
        for (int u = 0; u < 2; u++) {
            double lab = r[u].rms_before[a][b];
            assert_true(isfinite(lab));
            assert_true(r[u].rms_before_t[1][a][b] == lab);
            assert_true(r[u].rms_before_t[0][a][b] != lab);
            assert_true(r[u].rms_before_t[2][a][b] != lab);
            assert_true(r[u].rms_before_t[0][a][b] != r[u].rms_before_t[2][a][b]);
        }
        config_state_free(&st);
    }
}

static int setup(void **state)
{
    (void)state;
    return sensor_family_register(&toy_family) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(readings_ignore_the_campaign),
        cmocka_unit_test(readings_differ),
        cmocka_unit_test(dss_readings),
        cmocka_unit_test(psd_readings),
        cmocka_unit_test(toy_readings),
        cmocka_unit_test(picks_of_campaign_streams),
        cmocka_unit_test(store_upto_limit),
        cmocka_unit_test(temperatures_read_their_own),
        cmocka_unit_test(runs_with_a_store),
        cmocka_unit_test(run_each_config),
        cmocka_unit_test(no_systematic_pass),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
