/* test_thermal_derivations.c - units at another temperature than the lab's
 * (ess_thermal.h, dss_thermal.h), against derivations made here.
 *
 * ESS: the sensor reads tan(alpha_m) = (H + dH) tan(alpha) / H (ideal fine
 * code, beta = 0; the etching rule is H's), so a spacer grown by
 * dH = H a dT reads alpha_m - alpha = atan((1 + e) tan a) - a with
 * e = dH / H, to first order e sin(a) cos(a) = (dH / 2H) sin(2 alpha):
 * sunmc's error (reading - truth); the ESS paper's error, truth - reading,
 * is -(dH / 2H) sin(2 alpha).  At dT = 0 nothing moves, to the bit.
 * DSS: the pinhole height grows with the spacer, the pitch with the detector
 * (lengths in pixels shrink by it), the glass with its own expansion and
 * dn/dT. */
#include "test_util.h"
#include "test_tsv.h"

#include "config.h"
#include "dss_config.h"
#include "dss_thermal.h"
#include "ess_config.h"
#include "ess_sensor.h"
#include "ess_thermal.h"
#include "psd_config.h"
#include "psd_thermal.h"
#include "report.h"
#include "status.h"
#include "thermal.h"
#include "units.h"

#include <string.h>

/* A local config's family part is read and written by memcpy here: a
 * typed access through ess_cfg() to a config copied by value in the same
 * function may be moved across that copy (strict aliasing: an ess_config
 * lvalue does not alias a sunmc_config store), and GCC did. */
static sunmc_config ideal_ess(void)
{
    sunmc_config c = test_family_config("ess");
    ess_config e;
    memcpy(&e, c.fam.bytes, sizeof e);
    e.design.harmonics = 1; /* given, a3 = a5 = 0: an ideal fine code */
    e.design.a3_ratio = 0;
    e.design.a5_ratio = 0;
    memcpy(c.fam.bytes, &e, sizeof e);
    return c;
}

static double design_H_mm(const sunmc_config *c)
{
    ess_config e;
    memcpy(&e, c->fam.bytes, sizeof e);
    return e.design.H_mm;
}

static double reading_deg(const ess_sensor *s, double alpha_deg)
{
    double a = alpha_deg * RAD_PER_DEG, sv[3] = {0, sin(a), cos(a)}, out;
    assert_int_equal(ess_sensor_output(s, sv, NULL, &out), SUNMC_OK);
    return out * DEG_PER_RAD;
}

static void test_ess_spacer_closed_form(void **state)
{
    (void)state;
    const double temps[] = {-30, 60};
    for (int k = 0; k < 2; k++) {
        sunmc_config c = ideal_ess();
        c.mask_cte_ppm_k = 0; /* the spacer alone */
        double H = design_H_mm(&c), dT = temps[k] - c.cal_temp_c;
        double dH_mm = H * c.spacer_cte_ppm_k * 1e-6 * dT;
        ess_deviations none = {0}, hot;
        ess_deviations_at_temp(&c, &none, temps[k], &hot);
        assert_near(hot.dH_um, dH_mm * 1e3, 1e-9);
        ess_sensor s0, sT;
        ess_sensor_init(&s0, &ess_cfg(&c)->design, &none);
        ess_sensor_init(&sT, &ess_cfg(&c)->design, &hot);
        double e = dH_mm / H, worst = 0;
        for (double a = -60.2; a <= 60; a += 1.19) {
            double ar = a * RAD_PER_DEG;
            double got = (reading_deg(&sT, a) - reading_deg(&s0, a)) * RAD_PER_DEG;
            double first = 0.5 * e * sin(2 * ar);
            assert_near(got, atan((1 + e) * tan(ar)) - ar, 1e-12);
            assert_near(got, first, 2 * e * e); /* the next order */
            worst = fmax(worst, fabs(first));
        }
        /* a few hundredths of a degree: the size the issue measured */
        assert_true(worst * DEG_PER_RAD > 0.01 && worst * DEG_PER_RAD < 0.04);
    }
}

/* The dial's pitch grows as H shrinks: equal expansions cancel. */
static void test_ess_dial_cancels_spacer(void **state)
{
    (void)state;
    sunmc_config c = ideal_ess();
    c.mask_cte_ppm_k = c.spacer_cte_ppm_k;
    ess_deviations d = {0}, t;
    d.dH_um = 1.5;
    ess_deviations_at_temp(&c, &d, -30, &t);
    assert_near(t.dH_um, 1.5, 1e-9);
    c.mask_cte_ppm_k = 0;
    ess_deviations_at_temp(&c, &d, -30, &t);
    double Hr = design_H_mm(&c) + 1.5e-3;
    assert_near(t.dH_um, 1.5 + Hr * c.spacer_cte_ppm_k * 1e-6 * -50 * 1e3, 1e-9);
}

/* dT = 0: the same bits, whatever the materials. */
static void test_zero_dt_unchanged(void **state)
{
    (void)state;
    sunmc_config e = ideal_ess();
    e.cal_temp_c = -12.5;
    ess_deviations d = {0}, t;
    d.dH_um = 1.3;
    d.dd_um = -0.7;
    ess_deviations_at_temp(&e, &d, -12.5, &t);
    assert_memory_equal(&d, &t, sizeof d);
    sunmc_config c = test_family_config("dss");
    c.cal_temp_c = 33;
    dss_deviations g = {0.17, -0.08, 0.06, 9.0, -7.0, 8.0, -6.0, 0.004, 7.0, -5.0,
                          1.0, 0.5, -2.0, 0.3}, h;
    dss_deviations_at_temp(&c, &g, 33, &h);
    assert_memory_equal(&g, &h, sizeof g);
}

/* DSS: each material alone, written out. */
static void test_dss_materials(void **state)
{
    (void)state;
    sunmc_config c = test_family_config("dss");
    const dss_design *g = &dss_cfg(&c)->design;
    double p = g->pixel_um * 1e-3, dT = 40;
    double T = c.cal_temp_c + dT;
    dss_deviations d = {0}, t;
    d.dh_px = 0.2;
    d.dx_px = 0.5;
    d.glass_thickness_um = 3;
    d.glass_index = 0.001;
    c.spacer_cte_ppm_k = 23.1;
    c.detector_cte_ppm_k = c.glass_cte_ppm_k = c.glass_dn_dt_ppm_k = 0;
    dss_deviations_at_temp(&c, &d, T, &t);
    double h = g->h_mm + 0.2 * p;
    assert_near(t.dh_px, 0.2 + h * 23.1e-6 * dT / p, 1e-9);
    assert_near(t.glass_thickness_um, 3, 1e-9);
    assert_near(t.dx_px, 0.5, 1e-12);
    /* ~0.5 px over 40 K at h = 3 mm: the figure */
    assert_true(t.dh_px - 0.2 > 0.4 && t.dh_px - 0.2 < 0.6);
    c.spacer_cte_ppm_k = 0;
    c.detector_cte_ppm_k = 2.6;
    dss_deviations_at_temp(&c, &d, T, &t);
    double s = 1 + 2.6e-6 * dT;
    assert_near(t.dh_px, (h / s - g->h_mm) / p, 1e-9);
    assert_near(t.dx_px, 0.5 / s, 1e-12);
    assert_near(t.glass_thickness_um, ((g->glass_thickness_mm + 3e-3) / s - g->glass_thickness_mm) * 1e3,
                1e-9);
    c.detector_cte_ppm_k = 0;
    c.glass_cte_ppm_k = 7.1;
    c.glass_dn_dt_ppm_k = 1.6;
    dss_deviations_at_temp(&c, &d, T, &t);
    assert_near(t.glass_thickness_um,
                ((g->glass_thickness_mm + 3e-3) * (1 + 7.1e-6 * dT) - g->glass_thickness_mm) * 1e3,
                1e-9);
    assert_near(t.glass_index, 0.001 + 1.6e-6 * dT, 1e-15);
    assert_near(t.dh_px, 0.2, 1e-9);
}

/* The mean after-RMS of the row of the printed validation table (after
 * "validation at the operating temperatures") whose temperature label is
 * temp ("20" for the lab's, "-30", "worst"), angle and band; NaN when absent. */
static double thermal_row_after(const char *out, const char *temp, const char *angle,
                                const char *band)
{
    const char *p = strstr(out, "validation at the operating temperatures");
    for (p = p ? strchr(p, '\n') : NULL; p && *p; p = strchr(p + 1, '\n')) {
        char t[32], a[32], b[32], lab[32];
        double before, after;
        const char *line = p + 1;
        if (sscanf(line, "%31s %31s %31s", t, a, b) != 3)
            continue;
        const char *rest = line;
        if (strcmp(a, "(lab)") == 0) {
            if (sscanf(line, "%31s %31s %31s %31s", t, lab, a, b) != 4)
                continue;
        }
        if (strcmp(t, temp) || strcmp(a, angle) || strcmp(b, band))
            continue;
        rest = strchr(line, '|');
        if (rest && sscanf(rest, "| %lf [%*[^]]] | %lf", &before, &after) == 2)
            return after;
    }
    return NAN;
}

/* Output of `sunmc run CFG --units N --quiet EXTRA`. */
static void run_out(const char *cfg, long units, const char *extra, char *out, size_t len)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, "%s run %s --units %ld --quiet %s", test_sunmc(), cfg, units, extra);
    assert_int_equal(test_run(cmd, out, len), 0);
}

/* rms_after_mean of summary.tsv's operating row at temp_c, alpha 0:30, of
 * 40 units of ESS type A run with EXTRA, as printed there (into out[64]). */
static void summary_after_at(const char *extra, double temp_c, char *out)
{
    char cmd[512], log[4096], path[300];
    const char *dir = test_tmp("orbit");
    snprintf(cmd, sizeof cmd, "rm -rf %s && %s run configs/ess_type_a.ini --units 40 --quiet --out %s %s",
             dir, test_sunmc(), dir, extra);
    assert_int_equal(test_run(cmd, log, sizeof log), 0);
    snprintf(path, sizeof path, "%s/summary.tsv", dir);
    tsv *t = tsv_load(path);
    assert_non_null(t);
    int cond = tsv_col(t, "condition"), found = 0;
    for (int r = 0; r < t->nr; r++)
        if (!strcmp(t->cell[r][cond], "operating") && tsv_num(t, r, "temp_c") == temp_c &&
            !strcmp(tsv_str(t, r, "angle"), "alpha") && !strcmp(tsv_str(t, r, "band"), "0:30")) {
            snprintf(out, 64, "%s", tsv_str(t, r, "rms_after_mean"));
            found++;
        }
    tsv_free(t);
    assert_int_equal(found, 1);
}

/* One run over -30, 0, 30, 60: the worst after-RMS over the range is above
 * the lab's (both families), each temperature's row is what a run at that
 * temperature alone gives, and the lab's table is today's, to the byte. */
static void test_run_in_orbit(void **state)
{
    (void)state;
    static char list[65536], one[65536], none[65536];
    run_out("configs/ess_type_a.ini", 40, "--set environment.operating_temp_c=-30,0,30,60", list,
            sizeof list);
    double lab = thermal_row_after(list, "20", "alpha", "0:62");
    double worst = thermal_row_after(list, "worst", "alpha", "0:62");
    assert_true(lab > 0.005 && lab < 0.01);
    assert_true(worst > 1.5 * lab);
    assert_true(thermal_row_after(list, "-30", "alpha", "0:62") > 1.5 * lab);
    assert_true(thermal_row_after(list, "60", "alpha", "0:62") > 1.5 * lab);
    assert_true(worst >= thermal_row_after(list, "0", "alpha", "0:62"));
    assert_non_null(strstr(list, "yield over -30..60 C (at every temperature), alpha 0:62: "));
    /* summary.tsv's row at 60 C to the byte (the printed table's digits
     * follow its intervals' widths, which differ between the two runs) */
    char a60[64], l60[64];
    summary_after_at("--set environment.operating_temp_c=60", 60, a60);
    summary_after_at("--set environment.operating_temp_c=-30,0,30,60", 60, l60);
    assert_string_equal(a60, l60);
    /* the lab's table: the same bytes as without the keys */
    run_out("configs/ess_type_a.ini", 40, "", none, sizeof none);
    assert_null(strstr(none, "validation at the operating"));
    const char *cut = strstr(list, "\nvalidation at the operating");
    /* the spec's yield closes both: the lab's there, the worst here */
    const char *spec_line = strstr(none, "YIELD under the spec");
    assert_non_null(cut);
    assert_non_null(spec_line);
    assert_int_equal((size_t)(spec_line - none), (size_t)(cut - list));
    assert_memory_equal(none, list, (size_t)(cut - list));
    /* a range item gives the same run */
    run_out("configs/ess_type_a.ini", 40, "--set environment.operating_temp_c=-30:60:30", one,
            sizeof one);
    assert_string_equal(one, list);
    run_out("configs/dss.ini", 20, "--set environment.operating_temp_c=30", list, sizeof list);
    double dlab = thermal_row_after(list, "20", "total", "0:60");
    assert_true(dlab > 0);
    assert_true(thermal_row_after(list, "30", "total", "0:60") > 2 * dlab);
}

/* An operating temperature equal to the lab's holds the lab's result, row
 * for row of summary.tsv (every family); one 40 K warmer does not. */
static void test_lab_temperature_slot(void **state)
{
    (void)state;
    const char *cfgs[] = {"configs/ess_type_a.ini", "configs/dss.ini", "configs/psd.ini"};
    for (size_t f = 0; f < sizeof cfgs / sizeof *cfgs; f++) {
        char cmd[512], out[4096], path[300];
        const char *dir = test_tmp("slot");
        snprintf(cmd, sizeof cmd,
                 "rm -rf %s && %s run %s --units 20 --quiet --out %s "
                 "--set environment.operating_temp_c=20,60",
                 dir, test_sunmc(), cfgs[f], dir);
        assert_int_equal(test_run(cmd, out, sizeof out), 0);
        snprintf(path, sizeof path, "%s/summary.tsv", dir);
        tsv *t = tsv_load(path);
        int cond = tsv_col(t, "condition"), after = tsv_col(t, "rms_after_mean"), compared = 0;
        for (int r = 0; r < t->nr; r++) {
            if (!strcmp(t->cell[r][cond], "operating") && tsv_num(t, r, "temp_c") == 60)
                for (int q = 0; q < t->nr; q++) /* 40 K warmer: not the lab's unit */
                    if (!strcmp(t->cell[q][cond], "lab") &&
                        !strcmp(tsv_str(t, q, "angle"), tsv_str(t, r, "angle")) &&
                        !strcmp(tsv_str(t, q, "band"), tsv_str(t, r, "band")))
                        assert_string_not_equal(t->cell[r][after], t->cell[q][after]);
            if (strcmp(t->cell[r][cond], "operating") || tsv_num(t, r, "temp_c") != 20)
                continue;
            for (int q = 0; q < t->nr; q++)
                if (!strcmp(t->cell[q][cond], "lab") &&
                    !strcmp(tsv_str(t, q, "angle"), tsv_str(t, r, "angle")) &&
                    !strcmp(tsv_str(t, q, "band"), tsv_str(t, r, "band"))) {
                    assert_true(tsv_num(t, r, "rms_after_mean") > 0);
                    assert_string_equal(t->cell[r][after], t->cell[q][after]);
                    assert_string_equal(tsv_str(t, r, "rms_before_mean"),
                                        tsv_str(t, q, "rms_before_mean"));
                    compared++;
                }
        }
        if (compared < 3)
            fail_msg("%s: %d rows at the lab's temperature compared", cfgs[f], compared);
        tsv_free(t);
    }
}

/* The rows over the range from made-up units, against sums written here:
 * a unit's worst is its largest RMS over the temperatures, it passes only
 * where it passes at each, and a NaN at one temperature fails it. */
static void test_worst_over_range(void **state)
{
    (void)state;
    sunmc_config c = test_family_config("ess");
    c.op_temps_c = (double_list){2, {-30, 60}};
    assert_int_equal(thermal_n_temps(&c), 2);
    const sensor_family *fam = c.family;
    int nb = c.bands_deg.n, nr = report_n_rows(&c);
    assert_int_equal(nr, 4 * nb);
    double spec = c.spec_arcsec / fam->arcsec_per_rms_unit;
    enum { NU = 5 };
    /* after at -30 and 60 per unit, in units of the spec */
    const double at[NU][2] = {{0.5, 0.9}, {1.2, 0.3}, {0.8, 0.8}, {0.2, NAN}, {0.95, 1.01}};
    static unit_result res[NU];
    memset(res, 0, sizeof res);
    for (int u = 0; u < NU; u++) {
        res[u].unit = u;
        for (int b = 0; b < nb; b++) {
            res[u].rms_before[0][b] = res[u].rms_after[0][b] = 0.1 * spec;
            res[u].rms_after_sys[0][b] = 0.1 * spec;
            for (int t = 0; t < 2; t++) {
                res[u].rms_before_t[t][0][b] = 2 * spec;
                res[u].rms_after_t[t][0][b] = at[u][t] * spec;
            }
        }
    }
    test_read_all(res, NU);
    summary_row rows[4 * CONFIG_BANDS_MAX];
    assert_int_equal(report_summarize(&c, res, NU, rows), SUNMC_OK);
    const summary_row *w = &rows[report_primary_row(&c, 0, 0)];
    assert_int_equal(w->condition, REPORT_WORST);
    assert_true(isnan(w->temp_c));
    assert_near(w->yield, 2.0 / NU, 1e-15); /* units 0 and 2 */
    assert_int_equal(w->stat_units, 4);      /* unit 3 has no value at 60 */
    assert_near(w->rms_after_mean, (0.9 + 1.2 + 0.8 + 1.01) / 4 * spec, 1e-12 * spec);
    assert_near(w->rms_after_max, 1.2 * spec, 1e-15);
    const summary_row *hot = &rows[(2 * 1 + 0) * nb]; /* set 2: 60 C, band 0 */
    assert_int_equal(hot->condition, REPORT_OPERATING);
    assert_near(hot->temp_c, 60, 0);
    assert_near(hot->yield, 3.0 / NU, 1e-15); /* 0, 1, 2 */
    assert_near(rows[0].yield, 1.0, 0);       /* the lab's */
    assert_int_equal(rows[0].condition, REPORT_LAB);
    assert_near(unit_primary_after(&c, &res[1], 0, 0), 1.2 * spec, 1e-15);
    assert_true(isnan(unit_primary_after(&c, &res[3], 0, 0)));
    /* the lab's temperature alone: no operating temperature, the lab's rows */
    c.op_temps_c = (double_list){1, {c.cal_temp_c}};
    assert_int_equal(thermal_n_temps(&c), 0);
    assert_int_equal(report_n_rows(&c), nb);
    assert_int_equal(report_primary_row(&c, 0, 2), 2);
    assert_near(unit_primary_after(&c, &res[1], 0, 0), 0.1 * spec, 0);
}

/* Refused temperature lists: exit 2 with the key and the reason. */
static void test_temperature_list_errors(void **state)
{
    (void)state;
    const struct {
        const char *cfg, *value, *needle;
    } bad[] = {
        {"configs/ess_type_a.ini", "0:60:0", "STEP must be non-zero"},
        {"configs/ess_type_a.ini", "60:0:10", "STEP must be non-zero"},
        {"configs/ess_type_a.ini", "0:60", "START:STOP:STEP"},
        {"configs/ess_type_a.ini", "0:a:10", "three numbers"},
        {"configs/ess_type_a.ini", "-40:120:10", "at most 16"},
        {"configs/ess_type_a.ini", "-30,200", "out of range"},
        {"configs/dss.ini", "-30:160:10", "out of range"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char cmd[512], out[4096];
        snprintf(cmd, sizeof cmd, "%s run %s --units 2 --quiet --set environment.operating_temp_c=%s",
                 test_sunmc(), bad[i].cfg, bad[i].value);
        assert_int_equal(test_run(cmd, out, sizeof out), 2);
        if (!strstr(out, bad[i].needle) || !strstr(out, "operating_temp_c"))
            fail_msg("%s: expected '%s' in: %s", bad[i].value, bad[i].needle, out);
    }
    /* 16 temperatures are allowed */
    char cmd[512], out[4096];
    snprintf(cmd, sizeof cmd, "%s config configs/ess_type_a.ini --set environment.operating_temp_c=-40:110:10",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
}

/* share_after (budget.tsv) of tolerance.spacer_cte_ppm_k = 5 of a budget
 * over the operating temperatures temps ("" for the lab's alone). */
static double budget_cte_share(const char *family_cfg, const char *temps)
{
    static char dir[128];
    char cmd[1024], out[4096];
    if (!dir[0])
        assert_int_equal(test_private_dir(dir, sizeof dir, "thermal_budget"), 0);
    snprintf(cmd, sizeof cmd,
             "%s budget %s --units 24 --quiet --set report.budget_units=10 "
             "--set report.budget_steps=1 --set tolerance.spacer_cte_ppm_k=5 %s%s --out %s/b "
             ">/dev/null && awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i } "
             "$3 == \"spacer_cte_ppm_k\" { print $c[\"share_after\"] }' %s/b/budget.tsv",
             test_sunmc(), family_cfg, temps[0] ? "--set environment.operating_temp_c=" : "",
             temps, dir, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    char *end;
    double v = strtod(out, &end);
    if (end == out)
        fail_msg("no spacer_cte_ppm_k row in the budget: %s", out);
    return v;
}

/* The unit's CTE scatter is a tolerance like the others: the budget ranks
 * it in orbit and gives it no share at the lab's temperature. */
static void test_budget_sees_cte(void **state)
{
    (void)state;
    assert_true(budget_cte_share("configs/ess_type_a.ini", "-30,60") > 0.02);
    assert_true(budget_cte_share("configs/ess_type_a.ini", "") == 0.0);
    /* an Invar spacer: the DSS floor is no longer its aluminium drift */
    assert_true(
        budget_cte_share("configs/dss.ini", "-30,60 --set environment.spacer_cte_ppm_k=1.2") > 0.1);
}

/* A unit's own CTE adds to the material's. */
static void test_unit_cte_adds(void **state)
{
    (void)state;
    sunmc_config c = ideal_ess();
    ess_deviations d = {0}, a, b;
    d.spacer_cte_ppm_k = 2.5;
    d.mask_cte_ppm_k = -1.0;
    ess_deviations_at_temp(&c, &d, 60, &a);
    c.spacer_cte_ppm_k += 2.5;
    c.mask_cte_ppm_k -= 1.0;
    d.spacer_cte_ppm_k = d.mask_cte_ppm_k = 0;
    ess_deviations_at_temp(&c, &d, 60, &b);
    assert_near(a.dH_um, b.dH_um, 1e-12);
    sunmc_config g = test_family_config("dss");
    dss_deviations e = {0}, x, y;
    e.spacer_cte_ppm_k = 1;
    e.detector_cte_ppm_k = 0.5;
    e.glass_cte_ppm_k = -2;
    e.glass_dn_dt_ppm_k = 0.3;
    dss_deviations_at_temp(&g, &e, -30, &x);
    g.spacer_cte_ppm_k += 1;
    g.detector_cte_ppm_k += 0.5;
    g.glass_cte_ppm_k -= 2;
    g.glass_dn_dt_ppm_k += 0.3;
    memset(&e, 0, sizeof e);
    dss_deviations_at_temp(&g, &e, -30, &y);
    assert_near(x.dh_px, y.dh_px, 1e-12);
    assert_near(x.glass_thickness_um, y.glass_thickness_um, 1e-12);
    assert_near(x.glass_index, y.glass_index, 1e-15);
}

/* The four-channel sensor: dark signals double every dark_doubling_k,
 * gains by the responsivity's coefficient, h with the spacer, the glass
 * with its own; the lab's temperature the same bits. */
static void test_psd_at_temp(void **state)
{
    (void)state;
    sunmc_config c = test_family_config("psd");
    psd_config *p = (psd_config *)(void *)c.fam.bytes;
    p->dark_doubling_k = 8;
    p->responsivity_tc_ppm_k = 500;
    psd_sensor s, t;
    psd_sensor_nominal(&p->design, &s);
    s.dark[1] = 0.03;
    psd_sensor_at_temp(&c, &s, c.cal_temp_c, &t);
    assert_memory_equal(&s, &t, sizeof s);
    psd_sensor_at_temp(&c, &s, c.cal_temp_c + 16, &t);
    assert_near(t.dark[1], 0.12, 1e-15);           /* two doublings */
    assert_near(t.gain[2], s.gain[2] * 1.008, 1e-15); /* 500 ppm/K over 16 K */
    assert_near(t.h_mm, s.h_mm * (1 + c.spacer_cte_ppm_k * 16e-6), 1e-15);
    assert_near(t.glass_t_mm, s.glass_t_mm * (1 + c.glass_cte_ppm_k * 16e-6), 1e-15);
    assert_near(t.glass_n, s.glass_n + c.glass_dn_dt_ppm_k * 16e-6, 1e-15);
    p->dark_doubling_k = 0; /* no drift */
    psd_sensor_at_temp(&c, &s, c.cal_temp_c - 50, &t);
    assert_near(t.dark[1], 0.03, 0);
}

/* `curve` at the first operating temperature, end to end: an ideal fine
 * code whose only change is the spacer's expansion (dial fixed) reads
 * (dH / 2H) sin 2 alpha more at 60 C than at the lab's (reading - truth),
 * to the next order; at the lab's temperature the same curve, to the byte. */
static void test_curve_closed_form(void **state)
{
    (void)state;
    static char dir[128];
    char cmd[2048], out[4096];
    assert_int_equal(test_private_dir(dir, sizeof dir, "thermal_curve"), 0);
    const char *base = "curve configs/ess_type_a.ini --only dH_um=0 --set noise.row_current_pct=0 "
                       "--set design.harmonics=given --set design.a3_ratio=0 --set "
                       "design.a5_ratio=0 --set validation.beta_deg=0 --set "
                       "environment.mask_cte_ppm_k=0 --quiet";
    snprintf(cmd, sizeof cmd,
             "%s %s --out %s/lab >/dev/null && %s %s --set environment.operating_temp_c=20 "
             "--out %s/lab20 >/dev/null && %s %s --set environment.operating_temp_c=60 --out "
             "%s/hot | grep -c 'validated at 60 C' && cmp %s/lab/curve.tsv %s/lab20/curve.tsv",
             test_sunmc(), base, dir, test_sunmc(), base, dir, test_sunmc(), base, dir, dir, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    double e = 23.1e-6 * 40; /* dH / H */
    snprintf(cmd, sizeof cmd,
             "paste %s/lab/curve.tsv %s/hot/curve.tsv | awk -F'\t' 'NR > 1 { a = $1 * %.17g; "
             "cf = 0.5 * %.17g * sin(2 * a) / %.17g; m = $8 - $3 - cf; if (m < 0) m = -m; "
             "if (m > mx) mx = m; if (cf > cm) cm = cf; n++ } END { printf \"%%d %%.9g %%.9g\", "
             "n, mx, cm }'",
             dir, dir, RAD_PER_DEG, e, RAD_PER_DEG);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    int n;
    double mx, cm;
    assert_int_equal(sscanf(out, "%d %lf %lf", &n, &mx, &cm), 3);
    assert_true(n > 900);
    assert_true(mx < 2 * e * e * DEG_PER_RAD);        /* the next order */
    assert_true(cm > 0.026 && cm < 0.0266);            /* at 45 deg: e / 2 */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ess_spacer_closed_form),
        cmocka_unit_test(test_ess_dial_cancels_spacer),
        cmocka_unit_test(test_zero_dt_unchanged),
        cmocka_unit_test(test_dss_materials),
        cmocka_unit_test(test_run_in_orbit),
        cmocka_unit_test(test_lab_temperature_slot),
        cmocka_unit_test(test_worst_over_range),
        cmocka_unit_test(test_temperature_list_errors),
        cmocka_unit_test(test_budget_sees_cte),
        cmocka_unit_test(test_unit_cte_adds),
        cmocka_unit_test(test_psd_at_temp),
        cmocka_unit_test(test_curve_closed_form),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
