/* test_budget_reference.c - the budget's reference rows against plain runs
 * (issue 29): budget.tsv's "every tolerance 0 (design + noise)" columns and
 * printed line equal a `sunmc run` of the same units with every tolerance
 * key set to 0 by hand, and its FLOOR row (before, after, yield and its
 * interval) a run with every tolerance and every noise key at 0.  The keys
 * are listed here from the configs, not taken from the budget's own
 * selection, and the budget is checked to have picked exactly them. */
#include "test_tsv.h"

static char dir[128];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "budget_reference");
}

typedef struct {
    const char *name, *config, *common;
    const char *tolerances[16], *noises[4];
} family_case;

static const family_case ess = {
    "ess",
    "configs/ess_type_a.ini",
    "--units 10 --seed 4 --set validation.alpha_step_deg=2.3 --set campaign.beta_deg=0 "
    "--set report.spec_arcsec=20",
    {"dH_um", "dd_um", "dphi_deg", "slit_width_um", "harmonic_phase_deg", "gain_pct", "etch_um",
     "install_x_arcsec", "install_y_arcsec", "install_z_arcsec", "sun_x_arcsec", "sun_y_arcsec",
     "dial_tilt_deg", NULL},
    {"noise.row_current_pct", "noise.encoder_arcsec", "calibration.roll_sigma_arcsec", NULL}};

static const family_case dss = {
    "dss",
    "configs/dss.ini",
    "--units 10 --seed 4 --set validation.b_step_deg=10",
    {"dh_px", "dx_px", "dy_px", "c1_arcsec", "c2_arcsec", "c3_arcsec", "glass_thickness_um",
     "glass_index", "sun_b1_arcsec", "sun_b2_arcsec", "glass_ghost",
     NULL},
    {"noise.centroid_px", "noise.encoder_arcsec", NULL}};

static void sunmc_ok(const char *args, char *out, size_t len)
{
    int st = test_sunmc_in(dir, args, out, len);
    if (st != 0)
        fail_msg("sunmc %s: exit %d\n%s", args, st, out);
}

/* `run` of the case with the tolerances (and the noise, if floor) at 0. */
static void plain_run(const family_case *f, int floor, const char *out_name)
{
    char args[3072], out[8192];
    int n = snprintf(args, sizeof args, "run %s %s --quiet --out $D/%s", f->config, f->common,
                     out_name);
    for (int i = 0; f->tolerances[i]; i++)
        n += snprintf(args + n, sizeof args - (size_t)n, " --set tolerance.%s=0",
                      f->tolerances[i]);
    for (int i = 0; floor && f->noises[i]; i++)
        n += snprintf(args + n, sizeof args - (size_t)n, " --set %s=0", f->noises[i]);
    sunmc_ok(args, out, sizeof out);
}

/* The summary.tsv row of angle and band. */
static int summary_row(const tsv *s, const char *angle, const char *band)
{
    for (int r = 0; r < s->nr; r++)
        if (strcmp(tsv_str(s, r, "angle"), angle) == 0 && strcmp(tsv_str(s, r, "band"), band) == 0)
            return r;
    fail_msg("summary.tsv has no row %s %s", angle, band);
    return -1;
}

static void check_family(const family_case *f)
{
    char args[2048], out[16384], path[512], name[64];
    snprintf(name, sizeof name, "%s_budget", f->name);
    snprintf(args, sizeof args,
             "budget %s %s --set report.budget_units=10 --set report.budget_steps=1 --quiet "
             "--out $D/%s",
             f->config, f->common, name);
    sunmc_ok(args, out, sizeof out);
    snprintf(path, sizeof path, "%s/%s/budget.tsv", dir, name);
    tsv *b = tsv_load(path);
    /* the budget's sources are exactly the keys listed here */
    int n_tol = 0, n_noise = 0;
    while (f->tolerances[n_tol])
        n_tol++;
    while (f->noises[n_noise])
        n_noise++;
    assert_int_equal(b->nr, 1 + n_tol + n_noise + 1 + 3); /* + the parts after calibration */
    for (int r = 1; r <= n_tol + n_noise; r++) {
        const char *src = tsv_str(b, r, "source");
        int found = 0;
        for (int i = 0; i < n_tol; i++)
            found += strcmp(tsv_str(b, r, "kind"), "tolerance") == 0 &&
                     strcmp(src, f->tolerances[i]) == 0;
        for (int i = 0; i < n_noise; i++)
            found += strcmp(tsv_str(b, r, "kind"), "noise") == 0 && strcmp(src, f->noises[i]) == 0;
        if (found != 1)
            fail_msg("budget source %s (%s) is not one of the listed keys", src,
                     tsv_str(b, r, "kind"));
    }
    assert_string_equal(tsv_str(b, 0, "source"), "FLOOR");
    const char *angle = tsv_str(b, 0, "angle"), *band = tsv_str(b, 0, "band");

    /* every tolerance 0: design + noise */
    snprintf(name, sizeof name, "%s_notol", f->name);
    plain_run(f, 0, name);
    snprintf(path, sizeof path, "%s/%s/summary.tsv", dir, name);
    tsv *s = tsv_load(path);
    int r = summary_row(s, angle, band);
    double before = tsv_num(s, r, "rms_before_mean"), after = tsv_num(s, r, "rms_after_mean");
    for (int i = 0; i < b->nr; i++) {
        expect_g6(tsv_num(b, i, "no_tolerance_before"), before, "no_tolerance_before");
        expect_g6(tsv_num(b, i, "no_tolerance_after"), after, "no_tolerance_after");
    }
    /* a tolerance-free run is not the floor: the noise is still there */
    assert_true(before > 0 && after > 0);
    const char *unit = tsv_str(s, r, "rms_unit");
    int prec = strcmp(unit, "deg") == 0 ? 4 : 2;
    char want[256];
    snprintf(want, sizeof want, "every tolerance 0 (design + noise): before %.*f, after %.*f",
             prec, before, prec, after);
    if (!strstr(out, want))
        fail_msg("the budget's table lacks '%s':\n%s", want, out);
    tsv_free(s);

    /* the floor: every tolerance and every noise 0 */
    snprintf(name, sizeof name, "%s_floor", f->name);
    plain_run(f, 1, name);
    snprintf(path, sizeof path, "%s/%s/summary.tsv", dir, name);
    s = tsv_load(path);
    r = summary_row(s, angle, band);
    expect_g6(tsv_num(b, 0, "before_alone"), tsv_num(s, r, "rms_before_mean"), "floor before");
    expect_g6(tsv_num(b, 0, "after_alone"), tsv_num(s, r, "rms_after_mean"), "floor after");
    expect_g6(tsv_num(b, 0, "yield_today"), tsv_num(s, r, "yield"), "floor yield");
    expect_g6(tsv_num(b, 0, "yield_today_ci_lo"), tsv_num(s, r, "yield_ci_lo"), "floor yield lo");
    expect_g6(tsv_num(b, 0, "yield_today_ci_hi"), tsv_num(s, r, "yield_ci_hi"), "floor yield hi");
    /* the floor's yield is not the all-sources one (ESS: spec 20") */
    if (strcmp(f->name, "ess") == 0)
        assert_true(tsv_num(b, 0, "yield_today") != tsv_num(b, 0, "all_yield"));
    /* the floor is below the tolerance-free run (noise removed) */
    assert_true(tsv_num(s, r, "rms_after_mean") < after);
    tsv_free(s);
    tsv_free(b);
}

static void ess_reference_rows(void **state)
{
    check_family(&ess);
}

static void dss_reference_rows(void **state)
{
    check_family(&dss);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ess_reference_rows),
        cmocka_unit_test(dss_reference_rows),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
