/* test_design_yield.c - the yield's interval under a sampling design
 * (run.sampling = lhs), recomputed from units.tsv (issue 43): the pass of
 * each unit (RMS after <= spec, a failed fit failing), the design effect
 * deff = the block totals' variance over p (1 - p) / n (blocks of
 * run.sampling_block consecutive units, b / (b - 1) on the sum of squares
 * about the mean), and the Wilson interval at n_eff = floor(n / deff) units
 * when deff > 1, at the n units when deff <= 1: a design whose blocks vary
 * less than independent units never narrows it.  And the warning of a run
 * of exactly one design block, none at one unit more.  p95's interval:
 * Woodruff's, the share of units at or below p95 with the block variance
 * of that share, never below p (1 - p) / n, t over the blocks. */
#include "test_util.h"
#include "test_tsv.h"

#include <gsl/gsl_cdf.h>

static void wilson(double k, double n, double level, double *lo, double *hi)
{
    double z = gsl_cdf_ugaussian_Pinv(0.5 * (1 + level)), z2 = z * z;
    double c = (k + z2 / 2) / (n + z2), h = z / (n + z2) * sqrt(k * (n - k) / n + z2 / 4);
    *lo = fmax(0, c - h);
    *hi = fmin(1, c + h);
}

/* Type 7 quantile of sorted x[n]. */
static double quantile7(const double *x, long n, double p)
{
    double h = (double)(n - 1) * p;
    long i = (long)floor(h);
    return i + 1 < n ? x[i] + (h - (double)i) * (x[i + 1] - x[i]) : x[n - 1];
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The p95 interval of column col of u, units in blocks of block. */
static void p95_interval(const tsv *u, const char *col, long block, double level, double *lo,
                         double *hi)
{
    long n = u->nr, nb = n / block;
    double x[256], tot[64] = {0};
    assert_true(n <= 256 && nb <= 64);
    for (long i = 0; i < n; i++)
        x[i] = tsv_num(u, (int)i, col);
    double sorted[256];
    memcpy(sorted, x, (size_t)n * sizeof *x);
    qsort(sorted, (size_t)n, sizeof *sorted, cmp_d);
    double q = quantile7(sorted, n, 0.95), below = 0;
    for (long i = 0; i < n; i++) {
        long unit = atol(tsv_str(u, (int)i, "unit"));
        tot[unit / block] += x[i] <= q;
        below += x[i] <= q;
    }
    double f = below / (double)n, ss = 0;
    for (long b = 0; b < nb; b++)
        ss += (tot[b] - f * (double)block) * (tot[b] - f * (double)block);
    double v = (double)nb / (double)(nb - 1) * ss / ((double)n * (double)n);
    v = fmax(v, f * (1 - f) / (double)n);
    double h = gsl_cdf_tdist_Pinv(0.5 * (1 + level), (double)(nb - 1)) * sqrt(v);
    *lo = quantile7(sorted, n, fmax(0.95 - h, 0));
    *hi = quantile7(sorted, n, fmin(0.95 + h, 1));
}

static void yield_interval_from_units(void **state)
{
    const long block = 6, n = 48;
    char cmd[2048], out[1 << 15], path[1024];
    const char *d = test_tmp("lhs");
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units %ld --set run.sampling=lhs "
             "--set run.sampling_block=%ld --set report.spec_arcsec=26.5 --quiet --out %s",
             test_sunmc(), n, block, d);
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s: %d\n%s", cmd, rc, out);
    snprintf(path, sizeof path, "%s/units.tsv", d);
    tsv *u = tsv_load(path);
    snprintf(path, sizeof path, "%s/summary.tsv", d);
    tsv *s = tsv_load(path);
    assert_int_equal(u->nr, n);
    int below = 0, above = 0, mid = 0;
    for (int r = 0; r < s->nr; r++) {
        double spec = tsv_num(s, r, "spec_arcsec") / 3600.0, level = tsv_num(s, r, "confidence");
        assert_string_equal(tsv_str(s, r, "rms_unit"), "deg");
        assert_int_equal((long)tsv_num(s, r, "units"), n);
        char col[256];
        snprintf(col, sizeof col, "rms_after_%s_%s_%s_deg", tsv_str(s, r, "angle"),
                 tsv_str(s, r, "band_lo_deg"), tsv_str(s, r, "band_hi_deg"));
        double tot[64] = {0}, pass = 0;
        for (int i = 0; i < u->nr; i++) {
            long unit = atol(tsv_str(u, i, "unit"));
            int ok = strcmp(tsv_str(u, i, "fit_status"), "ok") == 0 && tsv_num(u, i, col) <= spec;
            tot[unit / block] += ok;
            pass += ok;
        }
        double p = pass / (double)n;
        expect_g6(tsv_num(s, r, "yield"), p, "yield");
        long nb = n / block;
        double ss = 0;
        for (long b = 0; b < nb; b++)
            ss += (tot[b] - p * (double)block) * (tot[b] - p * (double)block);
        double v = (double)nb / (double)(nb - 1) * ss / ((double)n * (double)n);
        double iid = p * (1 - p) / (double)n, deff = iid > 0 ? v / iid : 1.0;
        double lo, hi, wlo, whi;
        wilson(pass, (double)n, level, &wlo, &whi);
        if (deff > 1) {
            long ne = (long)floor((double)n / deff);
            ne = ne < 1 ? 1 : ne;
            wilson((double)lround(p * (double)ne), (double)ne, level, &lo, &hi);
            above++;
        } else {
            lo = wlo;
            hi = whi;
            below += iid > 0;
        }
        mid += p > 0.1 && p < 0.9;
        expect_g6(tsv_num(s, r, "yield_ci_lo"), lo, "yield_ci_lo");
        expect_g6(tsv_num(s, r, "yield_ci_hi"), hi, "yield_ci_hi");
        double plo, phi;
        p95_interval(u, col, block, level, &plo, &phi);
        expect_g6(tsv_num(s, r, "rms_after_p95_ci_lo"), plo, "rms_after_p95_ci_lo");
        expect_g6(tsv_num(s, r, "rms_after_p95_ci_hi"), phi, "rms_after_p95_ci_hi");
        /* never narrower than for independent units */
        assert_true(tsv_num(s, r, "yield_ci_hi") - tsv_num(s, r, "yield_ci_lo") >=
                    whi - wlo - 1e-5);
    }
    /* the spec puts some yields mid-way, and the design has a band whose
     * blocks vary less than independent units */
    assert_true(mid > 0);
    assert_true(below > 0);
    tsv_free(u);
    tsv_free(s);
}

static void one_block_warns(void **state)
{
    char cmd[2048], out[1 << 15];
    const char *warn = "with one block the means have";
    /* exactly one block (the smallest run.sampling_block, 2) */
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 2 --set run.sampling=lhs "
             "--set run.sampling_block=2",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, warn));
    /* one unit more: two blocks, no warning */
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 3 --set run.sampling=lhs "
             "--set run.sampling_block=2",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_null(strstr(out, warn));
    /* 8 units in one block of 8, 9 in two */
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 8 --set run.sampling=sobol "
             "--set run.sampling_block=8",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, warn));
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 9 --set run.sampling=sobol "
             "--set run.sampling_block=8",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_null(strstr(out, warn));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(yield_interval_from_units),
        cmocka_unit_test(one_block_warns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
