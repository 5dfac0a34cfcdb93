/* test_lots.c - issue 28, item 1: correlated tolerances by production lot.
 * A tolerance's NAME_lot = rho makes its normal score sqrt(rho) z_lot +
 * sqrt(1 - rho) z_unit, z_lot drawn from (seed, lot = unit / run.lot_size)
 * alone: two units of a lot correlate by rho, units of different lots not
 * at all, and every unit's marginal distribution is the tolerance's own
 * (Gaussian copula).  Checked at 1e4 units: realised correlation within
 * +-0.02, marginals by the Kolmogorov-Smirnov statistic; draws depend on
 * (seed, unit) only, so shards and threads give the same bytes. */
#include "test_util.h"

#include "deviation.h"
#include "ess_sensor.h"
#include "family.h"
#include "tolerance.h"

#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdlib.h>

#define N_UNITS 10000
#define LOT 10

static char dir[128];

static int setup(void **state)
{
    (void)state;
    return test_private_dir(dir, sizeof dir, "lots");
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The ESS config with dH_um's tolerance t (its entry e of the list). */
static tolerance *dh_tolerance(sunmc_config *c, int *entry)
{
    const sensor_family *f = c->family;
    for (int e = 0; e < f->n_deviations; e++)
        if (strcmp(f->deviations[e].name, "dH_um") == 0) {
            *entry = e;
            return (tolerance *)(void *)(c->fam.bytes + f->deviations[e].tol_offset);
        }
    fail_msg("no dH_um in the ESS deviation list");
    return NULL;
}

/* dH_um of units 0..N_UNITS-1 into x. */
static void draw_units(const sunmc_config *c, double *x)
{
    const sensor_family *f = c->family;
    ess_deviations d;
    double v[256];
    for (long u = 0; u < N_UNITS; u++) {
        deviations_sample(f->deviations, f->n_deviations, c, 1, u, &d);
        deviations_values(f->deviations, f->n_deviations, &d, v, 256);
        x[u] = v[0]; /* dH_um is the list's first entry */
    }
}

/* The draw x's standard normal score under tolerance t (inverse copula). */
static double score(const tolerance *t, double ts, double x)
{
    double p = 0.5;
    if (t->dist == DIST_UNIFORM)
        p = (x / t->value + 1) / 2;
    else if (t->dist == DIST_NORMAL)
        return x / t->value;
    else {
        double lo = gsl_cdf_ugaussian_P(-ts), hi = gsl_cdf_ugaussian_P(ts);
        p = (gsl_cdf_ugaussian_P(x / t->value) - lo) / (hi - lo);
    }
    return gsl_cdf_ugaussian_Pinv(fmin(fmax(p, 1e-15), 1 - 1e-15));
}

/* Pearson correlation of the scores over every pair of units in one lot
 * (same = 1) or of units in neighbouring lots (same = 0). */
static double pair_correlation(const double *z, int same)
{
    double sxy = 0, sxx = 0, syy = 0, sx = 0, sy = 0;
    long n = 0;
    for (long a = 0; a + LOT < N_UNITS; a++)
        for (long j = 1; j < LOT; j++) {
            long b = same ? a + j : a + LOT + j - 1;
            if (same && b / LOT != a / LOT)
                continue;
            if (!same && (b >= N_UNITS || b / LOT == a / LOT))
                continue;
            sx += z[a], sy += z[b], sxx += z[a] * z[a], syy += z[b] * z[b], sxy += z[a] * z[b];
            n++;
        }
    double cov = sxy / n - sx / n * sy / n;
    return cov / sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
}

/* Kolmogorov-Smirnov statistic of x[n] against tolerance t's CDF. */
static double ks_statistic(const tolerance *t, double ts, double *x, long n)
{
    qsort(x, (size_t)n, sizeof *x, cmp_double);
    double d = 0;
    for (long i = 0; i < n; i++) {
        double F = gsl_cdf_ugaussian_P(score(t, ts, x[i]));
        d = fmax(d, fmax(fabs(F - (double)i / n), fabs(F - (double)(i + 1) / n)));
    }
    return d;
}

static void correlation_and_marginals(void **state)
{
    (void)state;
    static double x[N_UNITS], z[N_UNITS];
    const int dists[] = {DIST_UNIFORM, DIST_NORMAL, DIST_TRUNCNORMAL};
    const double rhos[] = {0.3, 0.8};
    /* 1% critical value of the KS statistic, 1.63 / sqrt(n): over units of
     * one lot each (run.lot_size = 1: independent draws through the same
     * copula) n = 1e4; with lots of 10 the draws are correlated, and n is
     * the effective 1e4 / (1 + 9 rho) */
    for (int k = 0; k < 3; k++)
        for (int r = 0; r < 2; r++) {
            sunmc_config c = test_family_config("ess");
            int e;
            tolerance *t = dh_tolerance(&c, &e);
            t->dist = dists[k];
            t->value = 2.0;
            t->lot = rhos[r];
            c.lot_size = LOT;
            draw_units(&c, x);
            for (long u = 0; u < N_UNITS; u++)
                z[u] = score(t, c.truncation_sigmas, x[u]);
            double in = pair_correlation(z, 1), across = pair_correlation(z, 0);
            if (dists[k] == DIST_NORMAL) /* the values' own Pearson correlation is rho too */
                assert_true(fabs(pair_correlation(x, 1) - rhos[r]) <= 0.02);
            double ks = ks_statistic(t, c.truncation_sigmas, x, N_UNITS);
            double ks_lots = 1.63 / sqrt(N_UNITS / (1 + (LOT - 1) * rhos[r]));
            c.lot_size = 1;
            draw_units(&c, x);
            double ks1 = ks_statistic(t, c.truncation_sigmas, x, N_UNITS);
            fprintf(stderr, "dist %d rho %.1f: within a lot %.4f, across lots %+.4f, KS %.4f "
                    "(lots of 10; at most %.4f), %.4f (lots of 1; at most %.4f)\n",
                    dists[k], rhos[r], in, across, ks, ks_lots, ks1, 1.63 / sqrt(N_UNITS));
            assert_true(fabs(in - rhos[r]) <= 0.02);
            /* across lots the pairs hang on 1000 lot draws: 3 standard errors */
            assert_true(fabs(across) <= 3 / sqrt(N_UNITS / LOT));
            assert_true(ks <= ks_lots);
            assert_true(ks1 <= 1.63 / sqrt(N_UNITS));
        }
}

/* rho = 1: every unit of a lot draws the same value, the next lot another;
 * a unit's draw is the same alone as in a sequence (shard independence). */
static void lot_depends_on_seed_and_lot_only(void **state)
{
    (void)state;
    sunmc_config c = test_family_config("ess");
    int e;
    tolerance *t = dh_tolerance(&c, &e);
    t->lot = 1.0;
    c.lot_size = 7;
    const sensor_family *f = c.family;
    ess_deviations d;
    double v[256], first = 0;
    for (long u = 14; u < 21; u++) {
        deviations_sample(f->deviations, f->n_deviations, &c, 1, u, &d);
        deviations_values(f->deviations, f->n_deviations, &d, v, 256);
        if (u == 14)
            first = v[0];
        assert_true(v[0] == first);
    }
    deviations_sample(f->deviations, f->n_deviations, &c, 1, 21, &d);
    deviations_values(f->deviations, f->n_deviations, &d, v, 256);
    assert_true(v[0] != first);
    deviations_sample(f->deviations, f->n_deviations, &c, 2, 14, &d);
    deviations_values(f->deviations, f->n_deviations, &d, v, 256);
    assert_true(v[0] != first); /* another seed, another lot draw */
    /* the other tolerances keep their independent draws: lot 0 is today's */
    t->lot = 0;
    double plain[256], lotted[256];
    deviations_sample(f->deviations, f->n_deviations, &c, 1, 15, &d);
    int n = deviations_values(f->deviations, f->n_deviations, &d, plain, 256);
    t->lot = 0.5;
    deviations_sample(f->deviations, f->n_deviations, &c, 1, 15, &d);
    deviations_values(f->deviations, f->n_deviations, &d, lotted, 256);
    assert_true(plain[0] != lotted[0]);
    for (int i = 1; i < n; i++)
        assert_true(plain[i] == lotted[i]);
}

/* The copula's transform: closed forms at the median and the tails. */
static void from_normal_closed_forms(void **state)
{
    (void)state;
    tolerance u = {2.0, DIST_UNIFORM, 0}, g = {2.0, DIST_NORMAL, 0}, tn = {2.0, DIST_TRUNCNORMAL, 0},
              fx = {1.5, DIST_FIXED, 0};
    assert_true(fabs(tolerance_from_normal(&u, 3, 0)) < 1e-15);
    assert_true(fabs(tolerance_from_normal(&u, 3, 1.0) - 2.0 * (2 * 0.8413447460685429 - 1)) <
                1e-12);
    assert_true(tolerance_from_normal(&g, 3, -1.25) == -2.5);
    assert_true(fabs(tolerance_from_normal(&tn, 3, 0)) < 1e-12);
    assert_true(tolerance_from_normal(&tn, 3, 40) <= 6.0);
    assert_true(tolerance_from_normal(&tn, 3, 40) > 5.99);
    assert_true(tolerance_from_normal(&tn, 3, -40) >= -6.0);
    assert_true(tolerance_from_normal(&fx, 3, 0.7) == 1.5);
}

/* Shards, threads: the same bytes with lots on (CLI). */
static void lots_keep_shards_byte_identical(void **state)
{
    (void)state;
    char out[16384];
#define LOTRUN "run configs/dss.ini --quiet --units 30 --set validation.b_step_deg=10 " \
               "--set run.lot_size=7 --set tolerance.dh_px_lot=0.8 --set tolerance.dx_px_lot=0.5"
    assert_int_equal(test_sunmc_in(dir, LOTRUN " --threads 1 --out $D/w", out, sizeof out), 0);
    assert_int_equal(test_sunmc_in(dir, LOTRUN " --threads 2 --units 0:11 --out $D/a", out,
                                   sizeof out), 0);
    assert_int_equal(test_sunmc_in(dir, LOTRUN " --threads 2 --units 11:30 --out $D/b", out,
                                   sizeof out), 0);
    assert_int_equal(test_sunmc_in(dir, "merge $D/m $D/a $D/b", out, sizeof out), 0);
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "cd %s && cmp w/units.bin m/units.bin && cmp w/summary.tsv "
             "m/summary.tsv && grep -q '^dh_px_lot = 0.8 ' w/config.ini", dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_int_equal(test_sunmc_in(dir, "run configs/dss.ini --set tolerance.dh_px_lot=1.5", out,
                                   sizeof out), 2);
    assert_non_null(strstr(out, "dh_px_lot"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(from_normal_closed_forms),
        cmocka_unit_test(correlation_and_marginals),
        cmocka_unit_test(lot_depends_on_seed_and_lot_only),
        cmocka_unit_test(lots_keep_shards_byte_identical),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
