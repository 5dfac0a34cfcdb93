/* test_report_worse.c - "made worse": the share of units whose RMS after
 * calibration exceeds their RMS before (issue 25), counted independently
 * from units.tsv's per-unit columns, with its Wilson interval recomputed
 * here; on tilt-only type-A units (every other tolerance 0, no fine-code
 * harmonics), where today's fit amplifies the campaign noise. */
#include "test_tsv.h"
#include "test_util.h"

#define TILT_ONLY                                                                                \
    " --set tolerance.dH_um=0 --set tolerance.dd_um=0 --set tolerance.slit_width_um=0"         \
    " --set tolerance.harmonic_phase_deg=0 --set tolerance.gain_pct=0 --set tolerance.etch_um=0" \
    " --set tolerance.install_x_arcsec=0 --set tolerance.install_y_arcsec=0"                   \
    " --set tolerance.install_z_arcsec=0 --set tolerance.sun_x_arcsec=0"                       \
    " --set tolerance.sun_y_arcsec=0 --set design.harmonics=given --set design.a3_ratio=0"     \
    " --set design.a5_ratio=0"

/* Wilson score interval of k of n at z (independent of stats.c). */
static void wilson(long k, long n, double z, double *lo, double *hi)
{
    double p = (double)k / (double)n, z2n = z * z / (double)n;
    double centre = (p + z2n / 2) / (1 + z2n);
    double half = z * sqrt(p * (1 - p) / (double)n + z2n / (4.0 * (double)n)) / (1 + z2n);
    *lo = centre - half;
    *hi = centre + half;
}

static void worse_share_counts_units(void **state)
{
    char out[16384], cmd[4096], path[1024];
    snprintf(cmd, sizeof cmd, "%s run configs/ess_type_a.ini --units 60 --quiet --out %s" TILT_ONLY
             " --set validation.alpha_step_deg=1.3",
             test_sunmc(), test_tmp("tilt"));
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s exited %d: %s", cmd, rc, out);
    snprintf(path, sizeof path, "%s/summary.tsv", test_tmp("tilt"));
    tsv *s = tsv_load(path);
    snprintf(path, sizeof path, "%s/units.tsv", test_tmp("tilt"));
    tsv *u = tsv_load(path);
    assert_non_null(s);
    assert_non_null(u);
    int some_worse = 0, some_better = 0;
    for (int r = 0; r < s->nr; r++) {
        char before[128], after[128], band[32];
        snprintf(band, sizeof band, "%s", tsv_str(s, r, "band"));
        *strchr(band, ':') = '_';
        snprintf(before, sizeof before, "rms_before_alpha_%s_deg", band);
        snprintf(after, sizeof after, "rms_after_alpha_%s_deg", band);
        long k = 0, n = 0;
        for (int i = 0; i < u->nr; i++) {
            double b = tsv_num(u, i, before), a = tsv_num(u, i, after);
            if (isfinite(a) && isfinite(b)) {
                n++;
                k += a > b;
            }
        }
        assert_int_equal(n, (long)tsv_num(s, r, "stat_units"));
        assert_near(tsv_num(s, r, "worse"), (double)k / (double)n, 1e-5);
        double lo, hi;
        wilson(k, n, 1.959963984540054, &lo, &hi);
        assert_near(tsv_num(s, r, "worse_ci_lo"), lo, 1e-5);
        assert_near(tsv_num(s, r, "worse_ci_hi"), hi, 1e-5);
        some_worse += k > 0;
        some_better += k < n;
    }
    assert_true(some_worse && some_better); /* the count is not trivially 0 or n */
    tsv_free(s);
    tsv_free(u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(worse_share_counts_units),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
