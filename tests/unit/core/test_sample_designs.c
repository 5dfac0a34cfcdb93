/* test_sample_designs.c - issue 28, item 2: run.sampling = random | lhs | sobol
 * for the tolerance draws (sampling.h).  Checked: each design block
 * stratifies every coordinate (one unit per 1/B of the range: Latin
 * hypercube by construction, Sobol' as a (t, m, s)-net); every unit's draw
 * keeps the tolerance's distribution (Kolmogorov-Smirnov over many
 * blocks); the output does not depend on threads or how the units are
 * split; and the intervals from the block totals cover the true mean (a
 * large plain run) in at least 18 of 20 independent replicates for the
 * mean RMS before and after, the p95 and the yield, on the toy family
 * (tests/toy_family.h) with reading noise, which stays random. */
#include "test_util.h"

#include "deviation.h"
#include "montecarlo.h"
#include "registry.h"
#include "report.h"
#include "sampling.h"
#include "status.h"
#include "toy_family.h"

#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdlib.h>

#define BLOCK 32
#define TRUTH_UNITS 200000
#define REP_UNITS 512
#define REPLICATES 20
#define MIN_COVERED 18

static char dir[] = "/tmp/sunmc_test_sample_designs_XXXXXX";
static char ini[300];

static int setup(void **state)
{
    (void)state;
    if (sensor_family_register(&toy_family) != 0 || !mkdtemp(dir))
        return -1;
    snprintf(ini, sizeof ini, "%s/toy.ini", dir);
    return test_write_file(ini, "[sensor]\nfamily = toy\n"
                                "[tolerance]\nscale_pct = 0.1\noffset_arcsec = 30\n"
                                "bow_arcsec = 40\nbow_arcsec_dist = truncnormal\n"
                                "[noise]\nreading_arcsec = 60\n"
                                "[report]\nspec_arcsec = 62\nbands_deg = 0:40\n");
}

static int teardown(void **state)
{
    (void)state;
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd);
}

static void build_design(config_state *st, const char *design, long seed)
{
    char s1[64], s2[64], s3[64];
    snprintf(s1, sizeof s1, "run.sampling=%s", design);
    snprintf(s2, sizeof s2, "run.sampling_block=%d", BLOCK);
    snprintf(s3, sizeof s3, "run.seed=%ld", seed);
    const char *sets[] = {s1, s2, s3};
    test_build(st, ini, sets, 3);
}

/* The toy's three draws of unit u as uniforms on (0, 1) (the tolerances
 * scale 1 %, offset 30 arcsec uniform; the bow's truncated normal through
 * its CDF). */
static void unit_uniforms(const sunmc_config *c, long u, double p[3])
{
    toy_deviations d;
    toy_sample(c, u, &d);
    p[0] = (d.scale_pct / 0.1 + 1) / 2;
    p[1] = (d.offset_arcsec / 30.0 + 1) / 2;
    double ts = c->truncation_sigmas, lo = gsl_cdf_ugaussian_P(-ts);
    p[2] = (gsl_cdf_ugaussian_P(d.bow_arcsec / 40.0) - lo) / (1 - 2 * lo);
}

/* Each block of B units puts exactly one unit in each 1/B of every
 * coordinate (a block starting at a multiple of B, as blocks do). */
static void blocks_stratify(void **state)
{
    (void)state;
    const char *designs[] = {"lhs", "sobol"};
    for (int k = 0; k < 2; k++) {
        config_state st;
        build_design(&st, designs[k], 7);
        for (long b = 0; b < 5; b++) {
            int hit[3][BLOCK] = {{0}};
            for (long i = 0; i < BLOCK; i++) {
                double p[3];
                unit_uniforms(&st.cfg, (b + 16) * BLOCK + i, p);
                for (int j = 0; j < 3; j++) {
                    int cell = (int)(p[j] * BLOCK);
                    assert_true(cell >= 0 && cell < BLOCK);
                    hit[j][cell]++;
                }
            }
            for (int j = 0; j < 3; j++)
                for (int cell = 0; cell < BLOCK; cell++)
                    if (hit[j][cell] != 1)
                        fail_msg("%s block %ld coordinate %d: %d units in cell %d", designs[k],
                                 b + 16, j, hit[j][cell], cell);
        }
        config_state_free(&st);
    }
}

/* Sobol' blocks are nets in two dimensions too: B = 32 points put one in
 * each 8 x 4 and each 4 x 8 box of (scale, offset) (Sobol's first two
 * coordinates are a (0, 2)-sequence in base 2), which a Latin hypercube
 * does not. */
static void sobol_is_a_net(void **state)
{
    (void)state;
    config_state st;
    build_design(&st, "sobol", 3);
    for (long b = 0; b < 4; b++) {
        int wide[8][4] = {{0}}, tall[4][8] = {{0}};
        for (long i = 0; i < BLOCK; i++) {
            double p[3];
            unit_uniforms(&st.cfg, b * BLOCK + i, p);
            wide[(int)(p[0] * 8)][(int)(p[1] * 4)]++;
            tall[(int)(p[0] * 4)][(int)(p[1] * 8)]++;
        }
        for (int x = 0; x < 8; x++)
            for (int y = 0; y < 4; y++) {
                assert_int_equal(wide[x][y], 1);
                assert_int_equal(tall[y][x], 1);
            }
    }
    config_state_free(&st);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Every unit's coordinate is uniform: KS over 2000 blocks of the units at
 * one place i of their block (one unit per block: independent draws), for
 * each place i tried, at the 1 % critical value 1.63 / sqrt(n). */
static void marginals_uniform(void **state)
{
    (void)state;
    const char *designs[] = {"lhs", "sobol"};
    enum { NB = 2000 };
    const long places[] = {0, 1, 17, BLOCK - 1};
    for (int k = 0; k < 2; k++) {
        config_state st;
        build_design(&st, designs[k], 11);
        for (int q = 0; q < 4; q++)
            for (int j = 0; j < 3; j++) {
                static double x[NB];
                double d = 0;
                for (long b = 0; b < NB; b++) {
                    double p[3];
                    unit_uniforms(&st.cfg, b * BLOCK + places[q], p);
                    x[b] = p[j];
                }
                qsort(x, NB, sizeof *x, cmp_double);
                for (int i = 0; i < NB; i++)
                    d = fmax(d, fmax(fabs(x[i] - (double)i / NB), fabs(x[i] - (double)(i + 1) / NB)));
                if (d > 1.63 / sqrt(NB))
                    fail_msg("%s place %ld coordinate %d: KS %.3f", designs[k], places[q], j, d);
            }
        config_state_free(&st);
    }
}

/* The summary of units [0, n) run with 1 or 2 threads, or as two parts
 * [0, m) and [m, n) accumulated in unit order: the same bytes. */
static void split_independent(void **state)
{
    (void)state;
    enum { N = 300, M = 100 };
    config_state st;
    build_design(&st, "sobol", 5);
    const sunmc_config *c = &st.cfg;
    static unit_result one[N], two[N], parts[N];
    char err[SUNMC_ERRLEN];
    assert_int_equal(mc_run(c, 0, N, 1, one, NULL, NULL, err, sizeof err), SUNMC_OK);
    assert_int_equal(mc_run(c, 0, N, 2, two, NULL, NULL, err, sizeof err), SUNMC_OK);
    assert_int_equal(mc_run(c, M, N, 2, parts + M, NULL, NULL, err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(mc_run(c, 0, M, 1, parts, NULL, NULL, err, sizeof err), SUNMC_OK);
    assert_memory_equal(one, two, sizeof one);
    assert_memory_equal(one, parts, sizeof one);
    summary_row whole[CONFIG_BANDS_MAX], acc_rows[CONFIG_BANDS_MAX];
    assert_int_equal(report_summarize(c, one, N, whole), SUNMC_OK);
    report_acc *acc = report_acc_new(c);
    assert_int_equal(report_acc_add(acc, one, 77), SUNMC_OK);
    assert_int_equal(report_acc_add(acc, one + 77, N - 77), SUNMC_OK);
    report_acc_rows(acc, acc_rows);
    assert_memory_equal(whole, acc_rows, (size_t)report_n_rows(c) * sizeof *whole);
    report_acc_free(acc);
    config_state_free(&st);
}

/* Random sampling: today's draws, whatever run.sampling_block says. */
static void random_ignores_block(void **state)
{
    (void)state;
    config_state a, b;
    const char *s1[] = {"run.sampling=random", "run.sampling_block=2"};
    const char *s2[] = {"run.sampling=random", "run.sampling_block=4096"};
    test_build(&a, ini, s1, 2);
    test_build(&b, ini, s2, 2);
    for (long u = 0; u < 50; u++) {
        toy_deviations x, y;
        toy_sample(&a.cfg, u, &x);
        toy_sample(&b.cfg, u, &y);
        assert_memory_equal(&x, &y, sizeof x);
    }
    config_state_free(&a);
    config_state_free(&b);
}

typedef struct {
    double before, after, p95, yield;
} estimates;

static void estimate_run(const sunmc_config *c, long n, summary_row *r)
{
    unit_result *res = calloc((size_t)n, sizeof *res);
    char err[SUNMC_ERRLEN];
    assert_non_null(res);
    assert_int_equal(mc_run(c, 0, n, 0, res, NULL, NULL, err, sizeof err), SUNMC_OK);
    assert_int_equal(report_summarize(c, res, n, r), SUNMC_OK);
    free(res);
}

static int covers(stats_interval ci, double truth)
{
    return ci.lo <= truth && truth <= ci.hi;
}

/* 20 replicates of each design (seeds 1001..1020, 512 units = 16 blocks of
 * 32) against the truth of a plain run of 2e5 units (seed 1): each
 * estimate's interval covers it at least 18 times.  At 95 % the count of
 * misses is Binomial(20, 0.05): P(>= 3) = 7.5 %, per estimate and design;
 * the truth's own error is at most a fifth of a replicate's half-width. */
static void intervals_cover(void **state)
{
    (void)state;
    config_state st;
    build_design(&st, "random", 1);
    summary_row truth[CONFIG_BANDS_MAX];
    estimate_run(&st.cfg, getenv("SAMPLING_TRUTH") ? atol(getenv("SAMPLING_TRUTH")) : TRUTH_UNITS, truth);
    config_state_free(&st);
    /* the band's yield and the spec's (verdict.h: every band, every point) */
    const double t[5] = {truth[0].rms_before_mean, truth[0].rms_after_mean,
                         truth[0].rms_after_p95, truth[0].yield, truth[0].spec_yield};
    print_message("truth: before %.4f [%.4f %.4f] after %.4f [%.4f %.4f] p95 %g yield %g\n", t[0],
                  truth[0].rms_before_mean_ci.lo, truth[0].rms_before_mean_ci.hi, t[1],
                  truth[0].rms_after_mean_ci.lo, truth[0].rms_after_mean_ci.hi, t[2], t[3]);
    assert_true(t[3] > 0.3 && t[3] < 0.9); /* a yield with something to estimate */
    print_message("spec yield %g\n", t[4]);
    assert_true(t[4] > 0.1 && t[4] < 0.9);
    const char *designs[] = {"random", "lhs", "sobol"};
    for (int k = 0; k < 3; k++) {
        int hits[5] = {0};
        int reps = getenv("SAMPLING_REPS") ? atoi(getenv("SAMPLING_REPS")) : REPLICATES;
        for (int rep = 0; rep < reps; rep++) {
            summary_row r[CONFIG_BANDS_MAX];
            build_design(&st, designs[k], 1001 + rep);
            estimate_run(&st.cfg, REP_UNITS, r);
            config_state_free(&st);
            if (getenv("SAMPLING_VERBOSE"))
                print_message("%s %d before %.4f [%.4f %.4f] after %.4f [%.4f %.4f]\n",
                              designs[k], rep, r[0].rms_before_mean, r[0].rms_before_mean_ci.lo,
                              r[0].rms_before_mean_ci.hi, r[0].rms_after_mean,
                              r[0].rms_after_mean_ci.lo, r[0].rms_after_mean_ci.hi);
            hits[0] += covers(r[0].rms_before_mean_ci, t[0]);
            hits[1] += covers(r[0].rms_after_mean_ci, t[1]);
            hits[2] += covers(r[0].rms_after_p95_ci, t[2]);
            hits[3] += covers(r[0].yield_ci, t[3]);
            hits[4] += covers(r[0].spec_yield_ci, t[4]);
        }
        const char *names[] = {"mean before", "mean after", "p95", "yield", "spec yield"};
        for (int j = 0; j < 5; j++) {
            print_message("%-6s %-11s covered %2d of %d\n", designs[k], names[j], hits[j],
                          REPLICATES);
            if (hits[j] < MIN_COVERED && reps == REPLICATES)
                fail_msg("%s: %s covered in %d of %d replicates", designs[k], names[j], hits[j],
                         REPLICATES);
        }
    }
}

/* A design with fewer than two blocks has no interval of its means (NaN,
 * which the table flags), never a made-up one. */
static void one_block_no_interval(void **state)
{
    (void)state;
    config_state st;
    build_design(&st, "lhs", 1);
    summary_row r[CONFIG_BANDS_MAX];
    estimate_run(&st.cfg, BLOCK, r);
    assert_true(isnan(r[0].rms_after_mean_ci.lo) && isnan(r[0].rms_after_mean_ci.hi));
    assert_true(isfinite(r[0].rms_after_mean));
    config_state_free(&st);
    build_design(&st, "lhs", 1);
    estimate_run(&st.cfg, BLOCK + 1, r);
    assert_true(isfinite(r[0].rms_after_mean_ci.lo));
    config_state_free(&st);
}

/* A bad design in a file: FILE:LINE, exit 2, nothing written. */
static void refused_in_file(void **state)
{
    (void)state;
    char bad[400], out[300], cmd[1200], text[4096];
    snprintf(bad, sizeof bad, "%s/bad.ini", dir);
    snprintf(out, sizeof out, "%s/out", dir);
    assert_int_equal(test_write_file(bad, "[sensor]\nfamily = ess\n[run]\nsampling = halton\n"), 0);
    snprintf(cmd, sizeof cmd, "%s run %s --units 2 --out %s --quiet", test_sunmc(), bad, out);
    assert_int_equal(test_run(cmd, text, sizeof text), 2);
    char where[420];
    snprintf(where, sizeof where, "%s:4:", bad);
    if (!strstr(text, where) || !strstr(text, "random|lhs|sobol"))
        fail_msg("no %s naming the choices in: %s", where, text);
    assert_int_equal(test_write_file(bad, "[sensor]\nfamily = ess\n[run]\nsampling_block = 1\n"), 0);
    assert_int_equal(test_run(cmd, text, sizeof text), 2);
    snprintf(where, sizeof where, "%s:4:", bad);
    assert_non_null(strstr(text, where));
    snprintf(cmd, sizeof cmd, "test -e %s", out);
    assert_int_not_equal(system(cmd), 0);
    /* sensitivity's bootstrap needs independent units: refused, exit 2 */
    snprintf(cmd, sizeof cmd,
             "%s sensitivity configs/ess_type_a.ini --units 10 --set run.sampling=lhs --out %s --quiet",
             test_sunmc(), out);
    assert_int_equal(test_run(cmd, text, sizeof text), 2);
    assert_non_null(strstr(text, "run.sampling = random"));
    snprintf(cmd, sizeof cmd, "test -e %s", out);
    assert_int_not_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(blocks_stratify),     cmocka_unit_test(sobol_is_a_net),
        cmocka_unit_test(marginals_uniform),   cmocka_unit_test(split_independent),
        cmocka_unit_test(random_ignores_block), cmocka_unit_test(one_block_no_interval),
        cmocka_unit_test(refused_in_file),     cmocka_unit_test(intervals_cover),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
