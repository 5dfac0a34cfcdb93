/* test_sweep.c - --vary parsing, grid order, applying points, and the sweep
 * command end to end (common random numbers, equality with `run`). */
#include "test_tsv.h"

#include "ess_config.h"

#include "config.h"
#include "registry.h"
#include "status.h"
#include "sweep.h"

static void parse_list(void **state)
{
    sweep_axis ax;
    char err[SUNMC_ERRLEN];
    assert_int_equal(sweep_axis_parse("campaign.alpha_step_deg=1, 0.5,0.25",
                                      sensor_family_find("ess"), &ax, err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(ax.n, 3);
    assert_near(ax.v[0], 1, 0);
    assert_near(ax.v[1], 0.5, 0);
    assert_near(ax.v[2], 0.25, 0);
    assert_string_equal(ax.dotted, "campaign.alpha_step_deg");
}

/* A list key varied over '|' alternatives; numbers too; what is refused. */
static void parse_alternatives(void **state)
{
    sweep_axis ax;
    char err[SUNMC_ERRLEN];
    const sensor_family *ess = sensor_family_find("ess");
    assert_int_equal(sweep_axis_parse("campaign.beta_deg=-20,0,20| -30, 0, 30 |-30,-10,10,30",
                                      ess, &ax, err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(ax.n, 3);
    assert_false(ax.numeric);
    assert_string_equal(ax.text[0], "-20,0,20");
    assert_string_equal(ax.text[1], "-30, 0, 30");
    assert_true(isnan(ax.v[2]));
    char label[SWEEP_LABEL_MAX];
    sweep_point_label(&ax, 1, 2, label, sizeof label);
    assert_string_equal(label, "-30,-10,10,30");
    assert_int_equal(sweep_axis_parse("campaign.alpha_step_deg=0.3|0.2", ess, &ax, err, sizeof err),
                     SUNMC_OK);
    assert_true(ax.numeric);
    assert_near(ax.v[1], 0.2, 0);
    assert_string_equal(ax.text[1], "0.2");
    assert_int_equal(sweep_axis_parse("calibration.roll_sigma_arcsec=1|x", ess, &ax, err,
                                      sizeof err),
                     SUNMC_EINPUT);
    const char *bad[] = {"campaign.beta_deg=-20,0,20", /* a list key needs '|' */
                         "campaign.beta_deg=-20,0,20||0", "report.bands_deg=0:30|0:62",
                         "sensor.family=ess|dss"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (sweep_axis_parse(bad[i], ess, &ax, err, sizeof err) != SUNMC_EINPUT)
            fail_msg("'%s' parsed", bad[i]);
        assert_non_null(strstr(err, "--vary"));
    }
    /* Applying checks each alternative as a file value would be. */
    config_state st;
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", NULL, 0, err, sizeof err), 0);
    assert_int_equal(sweep_axis_parse("campaign.beta_deg=-30,0,30|0,x", ess, &ax, err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(sweep_apply(&st, &ax, 1, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(ess_cfg(&st.cfg)->cal_beta_deg.n, 3);
    assert_near(ess_cfg(&st.cfg)->cal_beta_deg.v[2], 30, 0);
    assert_int_equal(sweep_apply(&st, &ax, 1, 1, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "campaign.beta_deg"));
    config_state_free(&st);
}

static void parse_range(void **state)
{
    sweep_axis ax;
    char err[SUNMC_ERRLEN];
    assert_int_equal(
        sweep_axis_parse("design.H_mm=3:8:0.5", sensor_family_find("ess"), &ax, err, sizeof err),
        SUNMC_OK);
    assert_int_equal(ax.n, 11);
    assert_near(ax.v[10], 8, 1e-12);
    /* 0.1 is not exact in binary: STOP must still be kept. */
    assert_int_equal(sweep_axis_parse("tolerance.dH_um=0:1:0.1", sensor_family_find("ess"), &ax,
                                      err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(ax.n, 11);
    /* A descending range. */
    assert_int_equal(
        sweep_axis_parse("design.H_mm=8:3:-2.5", sensor_family_find("ess"), &ax, err, sizeof err),
        SUNMC_OK);
    assert_int_equal(ax.n, 3);
    assert_near(ax.v[2], 3, 1e-12);
    /* Values of many digits run as given, only the sum's rounding cut:
     * 4.1235 + 2 x 0.0005 is 4.1245 exactly, never 4.12. */
    assert_int_equal(sweep_axis_parse("design.H_mm=4.1235:4.1245:0.0005", sensor_family_find("ess"),
                                      &ax, err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(ax.n, 3);
    assert_true(ax.v[1] == 4.124 && ax.v[2] == 4.1245);
}

static void parse_errors(void **state)
{
    static const char *const bad[] = {
        "campaign.alpha_step_deg",        /* no = */
        "alpha_step_deg=1",               /* no section */
        "campaign.nope_deg=1",            /* unknown key */
        "campaign.beta_deg=1,2",          /* a list key */
        "design.h_mm=3",                  /* DSS key for an ESS config */
        "design.H_mm=3:8",                /* two-part range */
        "design.H_mm=3:8:0",              /* zero step */
        "design.H_mm=3:8:-1",             /* step away from STOP */
        "design.H_mm=3,x",                /* not a number */
        "design.H_mm=0:1000:1",           /* too many values */
        "design.H_mm=",                   /* empty */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sweep_axis ax;
        char err[SUNMC_ERRLEN] = "";
        int s = sweep_axis_parse(bad[i], sensor_family_find("ess"), &ax, err, sizeof err);
        if (s != SUNMC_EINPUT)
            fail_msg("'%s' parsed (status %d)", bad[i], s);
        assert_non_null(strstr(err, "--vary"));
    }
}

static void grid_order(void **state)
{
    sweep_axis ax[2];
    char err[SUNMC_ERRLEN];
    assert_int_equal(
        sweep_axis_parse("design.H_mm=3,4", sensor_family_find("ess"), &ax[0], err, sizeof err), 0);
    assert_int_equal(sweep_axis_parse("tolerance.dH_um=1,2,4", sensor_family_find("ess"), &ax[1],
                                      err, sizeof err),
                     0);
    assert_int_equal(sweep_n_points(ax, 2), 6);
    double v[2];
    sweep_point_values(ax, 2, 0, v);
    assert_near(v[0], 3, 0);
    assert_near(v[1], 1, 0);
    sweep_point_values(ax, 2, 2, v);
    assert_near(v[0], 3, 0);
    assert_near(v[1], 4, 0);
    sweep_point_values(ax, 2, 3, v);
    assert_near(v[0], 4, 0);
    assert_near(v[1], 1, 0);
}

static void apply_point(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", NULL, 0, err, sizeof err), 0);
    sweep_axis ax;
    assert_int_equal(
        sweep_axis_parse("design.H_mm=5,60", sensor_family_find("ess"), &ax, err, sizeof err), 0);
    assert_int_equal(sweep_apply(&st, &ax, 1, 0, err, sizeof err), SUNMC_OK);
    assert_near(ess_cfg(&st.cfg)->design.H_mm, 5, 0);
    assert_string_equal(config_origin_of(&st, config_find("design", "H_mm")), "--vary design.H_mm");
    /* 60 mm is beyond the key's range: the file's message, naming the key. */
    assert_int_equal(sweep_apply(&st, &ax, 1, 1, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "design.H_mm"));
    /* A value in range that breaks a cross-key check. */
    assert_int_equal(sweep_axis_parse("campaign.alpha_max_deg=70", sensor_family_find("ess"), &ax,
                                      err, sizeof err),
                     0);
    assert_int_equal(sweep_apply(&st, &ax, 1, 0, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "campaign.alpha_max_deg=70"));
    config_state_free(&st);
}

#define SMALL "--set validation.alpha_step_deg=1.3 --set campaign.beta_deg=0 --quiet"

static void cli_errors_write_nothing(void **state)
{
    char out[8192], cmd[2048];
    const char *bad[] = {"--vary design.H_mm=3:8", "--vary design.H_mm=60",
                         "--vary design.H_mm=3 --vary design.H_mm=4", "",
                         "--vary a --vary b --vary c"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(cmd, sizeof cmd, "%s sweep configs/ess_type_a.ini %s --units 4 --out %s " SMALL,
                 test_sunmc(), bad[i], test_tmp("sweep_bad"));
        int rc = test_run(cmd, out, sizeof out);
        if (rc != 2)
            fail_msg("'%s' exited %d: %s", bad[i], rc, out);
    }
    snprintf(cmd, sizeof cmd, "test -e %s", test_tmp("sweep_bad"));
    assert_int_not_equal(system(cmd), 0);
}

/* Read data row `row` (1 = first after the header) of a TSV into text. */
static int tsv_row(const char *path, int row, char *buf, size_t len)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    int i = 0;
    while (fgets(buf, (int)len, f))
        if (i++ == row) {
            fclose(f);
            return 0;
        }
    fclose(f);
    return -1;
}

static const char *skip_fields(const char *s, int n)
{
    for (int i = 0; i < n && s; i++) {
        s = strchr(s, '\t');
        if (s)
            s++;
    }
    return s;
}

static void sweep_equals_runs(void **state)
{
    char out[16384], cmd[2048];
    const char *sweep = test_tmp("sweep/sweep.tsv"), *summary = test_tmp("run/summary.tsv");
    snprintf(cmd, sizeof cmd,
             "%s sweep configs/ess_type_a.ini --vary campaign.alpha_step_deg=1,0.3 --units 6 "
             "--out %s " SMALL,
             test_sunmc(), test_tmp("sweep"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "campaign.alpha_step_deg"));
    char hdr[4096], r1[4096], r4[4096], run[4096];
    assert_int_equal(tsv_row(sweep, 0, hdr, sizeof hdr), 0);
    assert_true(strncmp(hdr, "campaign.alpha_step_deg\tlabel\taliased\tproduct\t", 46) == 0);
    /* 2 points x 3 bands. */
    assert_int_equal(tsv_row(sweep, 6, r4, sizeof r4), 0);
    assert_int_not_equal(tsv_row(sweep, 7, r4, sizeof r4), 0);
    /* Point 0.3, band 0 is byte for byte the summary of the same run. */
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --set campaign.alpha_step_deg=0.3 --units 6 "
             "--out %s " SMALL,
             test_sunmc(), test_tmp("run"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_int_equal(tsv_row(sweep, 4, r4, sizeof r4), 0);
    assert_int_equal(tsv_row(summary, 1, run, sizeof run), 0);
    assert_true(strncmp(r4, "0.3\t0.3\t0\t", 10) == 0);
    assert_string_equal(skip_fields(r4, 3), run);
    /* Common random numbers: the error before calibration does not depend on
     * the campaign step (column rms_before_mean = 9th summary column). */
    assert_int_equal(tsv_row(sweep, 1, r1, sizeof r1), 0);
    /* The 1-deg step samples the fine-code term at one phase: aliased. */
    assert_true(strncmp(r1, "1\t1\t1\t", 6) == 0);
    double b1 = atof(skip_fields(r1, 11)), b4 = atof(skip_fields(r4, 11));
    assert_true(b1 > 0);
    assert_near(b1, b4, 0);
}

/* A sweep over beta-line alternatives runs and labels its rows. */
static void sweep_list_labels(void **state)
{
    char out[16384], cmd[2048], row[4096];
    snprintf(cmd, sizeof cmd,
             "%s sweep configs/ess_type_a.ini --vary 'campaign.beta_deg=-20,0,20|-30,-10,10,30' "
             "--units 3 --out %s --set validation.alpha_step_deg=1.3 --quiet",
             test_sunmc(), test_tmp("sweep_list"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "-30,-10,10,30"));
    const char *path = test_tmp("sweep_list/sweep.tsv");
    assert_int_equal(tsv_row(path, 0, row, sizeof row), 0);
    assert_true(strncmp(row, "campaign.beta_deg\tlabel\taliased\t", 32) == 0);
    assert_int_equal(tsv_row(path, 1, row, sizeof row), 0);
    assert_true(strncmp(row, "-20,0,20\t-20,0,20\t0\t", 20) == 0);
    assert_int_equal(tsv_row(path, 4, row, sizeof row), 0);
    assert_true(strncmp(row, "-30,-10,10,30\t-30,-10,10,30\t0\t", 30) == 0);
}

/* A point where every unit's fit fails (per-row gains of 40 %, on the
 * former 0.8 deg campaign over -62..62; the shipped 0.7 deg fits them) has
 * no statistic: its table cells say "-" and a line under the table says why,
 * never "nan"; the failed column counts the 3 units. */
static void sweep_failed_point_no_nan(void **state)
{
    char out[16384], cmd[2048];
    snprintf(cmd, sizeof cmd,
             "%s sweep configs/ess_type_a.ini --vary tolerance.gain_pct=1,40 --units 3 "
             "--set campaign.alpha_step_deg=0.8 --set campaign.alpha_min_deg=-62 "
             "--set campaign.alpha_max_deg=62 --set validation.alpha_step_deg=1.3 --quiet",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_null(strstr(out, "nan"));
    const char *row = strstr(out, "\n40 ");
    assert_non_null(row);
    long failed = -1;
    assert_int_equal(sscanf(row, " 40 alpha 0:30 - - - - 0.0%% 0.0%% 0 %ld", &failed), 1);
    assert_int_equal(failed, 3);
    assert_non_null(strstr(out, "WARNING: - = no statistic: no unit of that point has a fit"));
    /* the good point prints numbers and, alone, no such warning */
    snprintf(cmd, sizeof cmd,
             "%s sweep configs/ess_type_a.ini --vary tolerance.gain_pct=1,2 --units 3 "
             "--set validation.alpha_step_deg=1.3 --quiet",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_null(strstr(out, "no statistic"));
}

/* A sweep over the ESS calibration model: both rows, the same units
 * before calibration (common random numbers); on a 0.8-deg step (the
 * former shipped campaign, -62..62) the extended model's fundamental
 * aliases with the 4th harmonic, which the aliased column says (the
 * paper's model fits no fundamental), and its noise-free error after is
 * still well below the paper's. */
static void sweep_calibration_model(void **state)
{
    char out[16384], cmd[2048];
    snprintf(cmd, sizeof cmd,
             "%s sweep configs/ess_type_a.ini --vary 'calibration.model=paper|extended' "
             "--units 8 --out %s --set noise.row_current_pct=0 --set noise.encoder_arcsec=0 "
             "--set campaign.alpha_step_deg=0.8 --set campaign.alpha_min_deg=-62 "
             "--set campaign.alpha_max_deg=62 --set validation.alpha_step_deg=0.37 --quiet",
             test_sunmc(), test_tmp("sweep_model"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    tsv *t = tsv_load(test_tmp("sweep_model/sweep.tsv"));
    assert_string_equal(t->names[0], "calibration.model");
    assert_int_equal(t->nr, 6); /* 2 models x 3 bands */
    assert_string_equal(tsv_str(t, 2, "label"), "paper");
    assert_string_equal(tsv_str(t, 5, "label"), "extended");
    assert_string_equal(tsv_str(t, 5, "band"), "0:62");
    assert_string_equal(tsv_str(t, 2, "aliased"), "0");
    assert_string_equal(tsv_str(t, 5, "aliased"), "1");
    assert_near(tsv_num(t, 5, "alias_units"), 8, 0);
    assert_near(tsv_num(t, 2, "rms_before_mean"), tsv_num(t, 5, "rms_before_mean"), 0);
    assert_true(tsv_num(t, 2, "rms_after_mean") > 1.5 * tsv_num(t, 5, "rms_after_mean"));
    tsv_free(t);
}

/* A range whose STOP binary rounding puts just below a whole step count
 * ((0.3 - 0.1) / 0.1 = 1.9999999999999998) keeps it; a point's value is
 * applied with all its digits. */
static void range_end_and_digits(void **state)
{
    sweep_axis ax;
    char err[SUNMC_ERRLEN];
    assert_int_equal(sweep_axis_parse("tolerance.dH_um=0.1:0.3:0.1", sensor_family_find("ess"),
                                      &ax, err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(ax.n, 3);
    assert_near(ax.v[0], 0.1, 1e-15);
    assert_near(ax.v[1], 0.2, 1e-15);
    assert_near(ax.v[2], 0.3, 1e-15);
    config_state st;
    assert_int_equal(config_build(&st, "configs/ess_type_a.ini", NULL, 0, err, sizeof err), 0);
    assert_int_equal(sweep_axis_parse("design.H_mm=5.123456789,7.25", sensor_family_find("ess"),
                                      &ax, err, sizeof err),
                     0);
    assert_int_equal(sweep_apply(&st, &ax, 1, 0, err, sizeof err), SUNMC_OK);
    assert_near(ess_cfg(&st.cfg)->design.H_mm, 5.123456789, 1e-15);
    assert_int_equal(sweep_apply(&st, &ax, 1, 1, err, sizeof err), SUNMC_OK);
    assert_near(ess_cfg(&st.cfg)->design.H_mm, 7.25, 0);
    config_state_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(parse_list),     cmocka_unit_test(parse_alternatives),
        cmocka_unit_test(parse_range),
        cmocka_unit_test(parse_errors),   cmocka_unit_test(grid_order),
        cmocka_unit_test(apply_point),    cmocka_unit_test(cli_errors_write_nothing),
        cmocka_unit_test(sweep_equals_runs), cmocka_unit_test(sweep_list_labels),
        cmocka_unit_test(sweep_calibration_model), cmocka_unit_test(sweep_failed_point_no_nan),
        cmocka_unit_test(range_end_and_digits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
