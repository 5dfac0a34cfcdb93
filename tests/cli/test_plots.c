/* test_plots.c - `sunmc curve` (closed form, errors) and every gnuplot
 * script on the output it documents (run, sweep, budget, design,
 * sensitivity, ESS and DSS curves on and off the grid, ESS and DSS
 * calibrate directories): exit 0, no warning, a non-empty PNG, and the
 * texts a reader relies on (the product in the title, not a path). */
#include "test_util.h"

#define SMALL "--set validation.alpha_step_deg=2.3 --set campaign.beta_deg=0 --quiet"

static int setup(void **state)
{
    char out[16384], cmd[4096];
    const char *runs[][2] = {
        {"run configs/ess_type_a.ini --units 12", "run"},
        {"sweep configs/ess_type_a.ini --vary campaign.alpha_step_deg=1,0.3 --units 4", "sweep1"},
        {"sweep configs/ess_type_a.ini --vary design.H_mm=4,5 --vary tolerance.dH_um=1,2 --units 4",
         "sweep2"},
        {"budget configs/ess_type_a.ini --units 10 --set report.budget_units=10 --set "
         "report.budget_steps=1",
         "budget"},
        {"curve configs/ess_type_a.ini --unit 3", "curve"},
        {"sensitivity configs/ess_type_a.ini --units 10", "sens"},
        {"design configs/ess_type_a.ini --units 10 --set campaign.search_steps_deg=0.7,1 "
         "--set campaign.search_max_lines=2 --set campaign.search_screen_units=10 "
         "--set campaign.search_max_units=10 --set report.yield_target=0.5",
         "design"},
    };
    for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
        snprintf(cmd, sizeof cmd, "%s %s --out %s " SMALL, test_sunmc(), runs[i][0],
                 test_tmp(runs[i][1]));
        if (test_run(cmd, out, sizeof out) != 0) {
            fprintf(stderr, "setup failed: %s\n%s\n", cmd, out);
            return -1;
        }
    }
    /* the DSS refraction map on the validation grid as shipped (offset: no
     * line at 0), and a simulated unit calibrated as a lab would, per family */
    const char *fmt[] = {
        "%1$s run configs/dss.ini --units 6 --out %2$s/drun --quiet",
        /* before and after calibration over 10 times apart: a log axis */
        "%1$s sweep configs/dss.ini --vary noise.centroid_px=0.005,0.02 --units 4 "
        "--out %2$s/dsweep --quiet",
        /* two bands of the same width: every figure of the run takes the same */
        "%1$s run configs/dss.ini --units 6 --set report.bands_deg=0:25,25:50 "
        "--set report.spec_bands=25:50 --out %2$s/dband --quiet",
        /* every unit fails a 1-arcsec spec: the yield panel's legend goes on top */
        "%1$s run configs/dss.ini --units 6 --set report.spec_arcsec=1 --out %2$s/dlow --quiet",
        "%1$s curve configs/dss.ini --only glass_index=0 --set noise.s_curve=off "
        "--set design.onboard_refraction=ignored --out %2$s/dmap --quiet",
        "%1$s simulate configs/ess_type_a.ini --unit 3 --out %2$s/esim --quiet && %1$s calibrate "
        "--config configs/ess_type_a.ini %2$s/esim/campaign.csv --out %2$s/ecal",
        "%1$s simulate configs/psd.ini --unit 3 --out %2$s/psim --quiet && %1$s calibrate "
        "--config configs/psd.ini %2$s/psim/campaign.csv --out %2$s/pcal",
        "%1$s simulate configs/dss.ini --unit 3 --out %2$s/dsim --quiet && %1$s calibrate "
        "--config configs/dss.ini %2$s/dsim/campaign.csv --out %2$s/dcal",
    };
    char base[1024];
    snprintf(base, sizeof base, "%s", test_tmp("."));
    for (size_t i = 0; i < sizeof fmt / sizeof fmt[0]; i++) {
        snprintf(cmd, sizeof cmd, fmt[i], test_sunmc(), base);
        if (test_run(cmd, out, sizeof out) != 0) {
            fprintf(stderr, "setup failed: %s\n%s\n", cmd, out);
            return -1;
        }
    }
    return 0;
}

/* Run a gnuplot script on dir and check the PNG is a real, non-empty PNG. */
static void check_script(const char *script, const char *dir, const char *extra)
{
    char out[8192], cmd[4096], png[1024];
    snprintf(png, sizeof png, "%s/%s.png", dir, script);
    remove(png);
    snprintf(cmd, sizeof cmd, "gnuplot -e \"run='%s'; out='%s'%s\" scripts/%s.gp", dir, png,
             extra, script);
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0 || strstr(out, "rror") || strstr(out, "arning"))
        fail_msg("%s exited %d: %s", cmd, rc, out);
    FILE *f = fopen(png, "rb");
    assert_non_null(f);
    unsigned char sig[8];
    assert_int_equal(fread(sig, 1, 8, f), 8);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fclose(f);
    assert_memory_equal(sig, "\x89PNG\r\n\x1a\n", 8);
    assert_true(size > 5000); /* axes, labels and curves, not a blank canvas */
}

static void yield_gp(void **state) { check_script("yield", test_tmp("run"), ""); }
static void hist_gp(void **state) { check_script("hist", test_tmp("run"), ""); }
static void sweep_gp_one_axis(void **state) { check_script("sweep", test_tmp("sweep1"), ""); }
static void sweep_gp_two_axes(void **state) { check_script("sweep", test_tmp("sweep2"), ""); }
static void budget_gp(void **state) { check_script("budget", test_tmp("budget"), ""); }
static void convergence_gp(void **state) { check_script("convergence", test_tmp("run"), ""); }
static void sensitivity_gp(void **state) { check_script("sensitivity", test_tmp("sens"), ""); }
static void curve_gp(void **state)
{
    char extra[600];
    snprintf(extra, sizeof extra, "; what='source'; run2='%s'", test_tmp("curve"));
    check_script("curve", test_tmp("curve"), "");
    check_script("curve", test_tmp("curve"), extra);
}
static void map_gp(void **state) { check_script("map", test_tmp("curve"), "; what='before'"); }
/* the DSS Fig. 5 recipe of docs/studies.md: line cuts on an offset grid
 * (nearest line to 0), each panel's own scale and the shared one */
static void map_gp_cut_offset_grid(void **state)
{
    check_script("map", test_tmp("dmap"), "; what='before'; cut=1");
    check_script("map", test_tmp("dmap"), "; what='source'; scale='shared'");
}
static void design_gp(void **state) { check_script("design", test_tmp("design"), ""); }
static void convergence_gp_dss(void **state) { check_script("convergence", test_tmp("drun"), ""); }
static void calib_gp(void **state)
{
    check_script("calib", test_tmp("ecal"), "");
    check_script("calib", test_tmp("dcal"), "");
}

/* Run a shell command made from fmt and one path. */
static int sh(const char *fmt, const char *path, char *out, size_t len)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, fmt, path);
    return test_run(cmd, out, len);
}

static void plots_sh(void **state)
{
    char out[8192];
    assert_int_equal(sh("bash scripts/plots.sh %s", test_tmp("sweep2"), out, sizeof out), 0);
    assert_int_equal(sh("test -s %s/sweep.png", test_tmp("sweep2"), out, sizeof out), 0);
    assert_int_equal(sh("bash scripts/plots.sh %s", test_tmp("curve"), out, sizeof out), 0);
    assert_int_equal(sh("test -s %s/curve_source.png", test_tmp("curve"), out, sizeof out), 0);
    /* make plots RUN=<a calibrate directory> draws its residuals */
    assert_int_equal(sh("bash scripts/plots.sh %s", test_tmp("ecal"), out, sizeof out), 0);
    assert_int_equal(sh("test -s %s/calib.png", test_tmp("ecal"), out, sizeof out), 0);
    assert_int_equal(sh("bash scripts/plots.sh %s", test_tmp("dcal"), out, sizeof out), 0);
    assert_int_equal(sh("test -s %s/calib.png", test_tmp("dcal"), out, sizeof out), 0);
    assert_int_equal(sh("mkdir -p %s", test_tmp("empty"), out, sizeof out), 0);
    assert_int_equal(sh("bash scripts/plots.sh %s", test_tmp("empty"), out, sizeof out), 2);
    assert_int_equal(sh("bash scripts/plots.sh %s", test_tmp("missing"), out, sizeof out), 2);
}

/* The texts a reader relies on: the histogram divides the widest band's
 * before by its after column (not the rms_after_sys_ columns that follow),
 * the yield legend names band and yield in words, the sweep's the band
 * variable. */
static void plot_texts(void **state)
{
    char out[8192];
    const char *checks[] = {
        "gnuplot -e \"run='%1$s'; svg=1; out='%1$s/h.svg'\" scripts/hist.gp && "
        "grep -q 'ESS type A, 12 units: times of accuracy improvement' %1$s/h.svg && "
        "grep -q 'alpha error, band |alpha| 0:62 deg' %1$s/h.svg",
        /* issue 41: hist and convergence of one run show one band (the
         * widest, the last of equally wide ones), the DSS's named as the
         * field angle; the yield panel is the spec's verdict, its rule named */
        "d=%1$s/../dband && gnuplot -e \"run='$d'; svg=1; out='$d/h.svg'\" scripts/hist.gp && "
        "gnuplot -e \"run='$d'; svg=1; out='$d/c.svg'\" scripts/convergence.gp && "
        "grep -q 'band field angle 25:50 deg' $d/h.svg && grep -q 'band field angle 25:50 deg' $d/c.svg && "
        "! grep -q '0:25' $d/h.svg && "
        "grep -q 'yield under the spec: rms &lt;= 10 arcsec in 25:50 bands' $d/c.svg",
        /* the yield panel's legend sits on the side away from the final
         * yield (SVG y grows downwards; the y label marks the panel's middle):
         * below the middle at 100 %%, above it at 0 %% */
        "ky() { grep -B1 \"<text>$2</text>\" $1 | grep -o 'translate([0-9.]*,[0-9.]*' | cut -d, -f2; }; "
        "gnuplot -e \"run='%1$s'; svg=1; out='%1$s/cy.svg'\" scripts/convergence.gp && "
        "grep -q 'final 100.0%%' %1$s/cy.svg && "
        "awk -v k=$(ky %1$s/cy.svg 'running yield') -v c=$(ky %1$s/cy.svg 'running yield under the spec') "
        "'BEGIN { exit !(k > c) }' && d=%1$s/../dlow && "
        "gnuplot -e \"run='$d'; svg=1; out='$d/cy.svg'\" scripts/convergence.gp && grep -q 'final 0.0%%' $d/cy.svg && "
        "awk -v k=$(ky $d/cy.svg 'running yield') -v c=$(ky $d/cy.svg 'running yield under the spec') "
        "'BEGIN { exit !(k < c) }'",
        /* a calibrate directory's title names its family (the PSD's was
         * drawn as "DSS calibration") */
        "for f in dcal:DSS pcal:PSD; do d=%1$s/../${f%%:*}; gnuplot -e \"run='$d'; svg=1; out='$d/k.svg'\" "
        "scripts/calib.gp && grep -q \"${f#*:} calibration of\" $d/k.svg || exit 1; done",
        /* the DSS sweep's curves differ by over 10 times: log axis; the ESS
         * sweep's (about 4 times) keep a linear one from 0 */
        "d=%1$s/../dsweep && gnuplot -e \"run='$d'; svg=1; out='$d/s.svg'\" scripts/sweep.gp && "
        "grep -q 'log scale' $d/s.svg && "
        /* with labels at 1, 2, 5 of each decade, not the powers of ten alone */
        "[ $(grep -cE '<text>(1|2|5)0*</text>' $d/s.svg) -ge 4 ] && "
        "gnuplot -e \"run='%2$s'; svg=1; out='%2$s/s3.svg'\" "
        "scripts/sweep.gp && ! grep -q 'log scale' %2$s/s3.svg",
        /* no text line wider than its canvas holds (titles wrap): at most
         * 110 characters in any figure drawn here */
        "for f in %1$s/*.svg %2$s/*.svg %1$s/../dband/*.svg %1$s/../dsweep/*.svg; do "
        "n=$(grep -o '<text[^>]*>[^<]*' $f | sed 's/<text[^>]*>//' | awk '{ if (length > m) m = length } END { print m + 0 }'); "
        "[ $n -le 110 ] || { echo \"$f: a text of $n characters\"; exit 1; }; done",
        /* the design's title names the spec's verdict its yield counts */
        "d=%1$s/../design && gnuplot -e \"run='$d'; svg=1; out='$d/d.svg'\" scripts/design.gp && "
        "grep -q 'yield under the spec: rms &lt;= 54. in all bands, every point read' $d/d.svg",
        /* the budget: the parts after calibration and the spec's rule in the
         * title, not as bars; the legend above the plot */
        "b=%1$s/../budget && gnuplot -e \"run='$b'; svg=1; out='$b/b.svg'\" scripts/budget.gp && "
        "grep -q 'after calibration: [0-9.]*%% reading noise, [-0-9.]*%% estimation' $b/b.svg && "
        "grep -q 'spec: rms &lt;= 54. in all bands, every point read' $b/b.svg && "
        "! grep -q 'NOISE_OF_READING' $b/b.svg",
        /* titles name the product, not the run directory */
        "gnuplot -e \"run='%1$s'; svg=1; out='%1$s/c.svg'\" scripts/convergence.gp && "
        "grep -q 'ESS type A: mean RMS after' %1$s/c.svg && grep -q 'band |alpha| 0:62' %1$s/c.svg && "
        "gnuplot -e \"run='%1$s'; svg=1; out='%1$s/y2.svg'\" scripts/yield.gp && "
        "grep -q '<text>ESS type A, 12 units</text>' %1$s/y2.svg && ! grep -q '%1$s' %1$s/y2.svg && "
        /* the map names the product beside the command that drew it */
        "d=%1$s/../curve && gnuplot -e \"run='$d'; svg=1; out='$d/m.svg'; what='after'\" scripts/map.gp && "
        "grep -q 'ESS type A: curve --unit 3' $d/m.svg",
        /* the sweep's x label carries the key's unit as a unit */
        "gnuplot -e \"run='%2$s'; svg=1; out='%2$s/s2.svg'\" scripts/sweep.gp && "
        "grep -q 'campaign.alpha_step \\[deg\\]' %2$s/s2.svg && grep -q 'scan short: extrapolates' %2$s/s2.svg",
        "gnuplot -e \"run='%1$s'; svg=1; out='%1$s/y.svg'\" scripts/yield.gp && "
        "grep -q 'alpha error, band 0-62 deg: yield' %1$s/y.svg && "
        /* the target named once, in the legend's title (a label on the line sat
         * where the best band's curve crosses it) */
        "grep -q 'bars are 95%% intervals; dashed: yield target 95%%' %1$s/y.svg && "
        "[ $(grep -c 'yield target' %1$s/y.svg) = 1 ]",
        /* the sweep's legend names what the ESS bands bin: |alpha| */
        "gnuplot -e \"run='%2$s'; svg=1; out='%2$s/s.svg'\" scripts/sweep.gp && "
        "grep -q 'after, |alpha| 0:62 deg' %2$s/s.svg && ! grep -q '|x|' %2$s/s.svg",
    };
    for (size_t i = 0; i < sizeof checks / sizeof checks[0]; i++) {
        char cmd[4096];
        char run[1024];
        snprintf(run, sizeof run, "%s", test_tmp("run"));
        snprintf(cmd, sizeof cmd, checks[i], run, test_tmp("sweep1"));
        if (test_run(cmd, out, sizeof out) != 0)
            fail_msg("%s: %s", cmd, out);
    }
}

/* curve --only dH_um=V with an ideal fine code and no noise: the source
 * column is atan((1 + V/H) tan a) - a, and -V mirrors it. */
static void curve_closed_form(void **state)
{
    char out[16384], cmd[4096];
    const double H_mm = 4.124, dH_um = 2.0;
    const char *ideal = "--set design.harmonics=given --set design.a3_ratio=0 "
                        "--set design.a5_ratio=0 --set noise.row_current_pct=0 "
                        "--set validation.beta_deg=0,20 --quiet";
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        snprintf(cmd, sizeof cmd, "%s curve configs/ess_type_a.ini --only dH_um=%g %s --out %s",
                 test_sunmc(), sgn * dH_um, ideal, test_tmp("cf"));
        assert_int_equal(test_run(cmd, out, sizeof out), 0);
        FILE *f = fopen(test_tmp("cf/curve.tsv"), "r");
        assert_non_null(f);
        char line[1024];
        assert_non_null(fgets(line, sizeof line, f));
        assert_non_null(strstr(line, "alpha_deg\tbeta_deg\terror_before_alpha_deg"));
        long n = 0, blank = 0;
        while (fgets(line, sizeof line, f)) {
            if (line[0] == '\n') {
                blank++;
                continue;
            }
            double a, b, eb, ea, es;
            assert_int_equal(sscanf(line, "%lf %lf %lf %lf %lf", &a, &b, &eb, &ea, &es), 5);
            double ar = a * M_PI / 180;
            double want = (atan((1 + sgn * dH_um * 1e-3 / H_mm) * tan(ar)) - ar) * 180 / M_PI;
            assert_near(es, want, 1e-7);
            assert_near(eb, want, 1e-7);
            n++;
        }
        fclose(f);
        assert_int_equal(blank, 1); /* two series */
        assert_true(n > 1000);
    }
}

static void curve_errors(void **state)
{
    char out[8192], cmd[4096];
    const char *bad[] = {"configs/ess_type_a.ini",
                         "configs/ess_type_a.ini --only nope_um=1",
                         "configs/ess_type_a.ini --only dH_um",
                         "configs/ess_type_a.ini --only dH_um=abc",
                         "configs/ess_type_a.ini --only dH_um=5000",
                         "configs/ess_type_a.ini --only truncation_sigmas=2",
                         "configs/ess_type_a.ini --unit -1",
                         "configs/ess_type_a.ini --unit 1 --vary design.H_mm=3",
                         "--unit 1"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(cmd, sizeof cmd, "%s curve %s --out %s --quiet", test_sunmc(), bad[i],
                 test_tmp("bad"));
        int rc = test_run(cmd, out, sizeof out);
        if (rc != 2)
            fail_msg("'%s' exited %d: %s", bad[i], rc, out);
    }
    assert_int_not_equal(sh("test -e %s", test_tmp("bad"), out, sizeof out), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(yield_gp),          cmocka_unit_test(hist_gp),
        cmocka_unit_test(sweep_gp_one_axis), cmocka_unit_test(sweep_gp_two_axes),
        cmocka_unit_test(budget_gp),         cmocka_unit_test(convergence_gp),
        cmocka_unit_test(sensitivity_gp),         cmocka_unit_test(curve_gp),
        cmocka_unit_test(map_gp),            cmocka_unit_test(plots_sh),
        cmocka_unit_test(curve_closed_form), cmocka_unit_test(curve_errors),
        cmocka_unit_test(plot_texts),        cmocka_unit_test(map_gp_cut_offset_grid),
        cmocka_unit_test(design_gp),         cmocka_unit_test(convergence_gp_dss),
        cmocka_unit_test(calib_gp),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
