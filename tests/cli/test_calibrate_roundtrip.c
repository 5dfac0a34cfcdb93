/* test_calibrate_roundtrip.c - the lab commands end to end: simulate ->
 * calibrate -> compensate reproduces `run`'s unit (ESS and DSS), bad data
 * and bad usage exit 2 with nothing written. */
#include "test_util.h"
#include "test_tsv.h"

#include "calreport.h"
#include "config.h"
#include "csv.h"
#include "dss_labfit.h"
#include "rotation.h"
#include "ess_labfit.h"
#include "ess_unit.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[512]; /* this suite's directory in the private temporary one */

static int setup(void **state)
{
    gsl_set_error_handler_off();
    return test_private_dir(dir, sizeof dir, "calcli");
}

/* ---- the command line ---- */

/* Value of column `col` in row `row` (0-based data row) of a TSV file. */
static double tsv_value(const char *path, int row, const char *col)
{
    tsv *t = tsv_load(path);
    if (row >= t->nr)
        fail_msg("%s has no data row %d", path, row);
    double v = tsv_num(t, row, col);
    tsv_free(t);
    return v;
}

static double params_value(const char *path, const char *key)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[1024];
    double v = NAN;
    size_t n = strlen(key);
    while (fgets(line, sizeof line, f))
        if (strncmp(line, key, n) == 0 && (line[n] == ' ' || line[n] == '='))
            v = strtod(strchr(line, '=') + 1, NULL);
    fclose(f);
    return v;
}

static int file_exists(const char *p)
{
    struct stat s;
    return stat(p, &s) == 0;
}

static void test_cli_simulate_calibrate_compensate_reproduces_run(void **state)
{
    char cmd[4096], out[1 << 14];
    const char *cfg = "configs/ess_type_a.ini";
    snprintf(cmd, sizeof cmd, "%s run %s --units 3:4 --quiet --out %s/run", test_sunmc(), cfg, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "%s simulate %s --unit 3 --out %s/u3", test_sunmc(), cfg, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    const char *roll = strstr(out, "calibration.roll_measured_arcsec=");
    assert_non_null(roll);
    char rollset[128];
    sscanf(roll, "%127s", rollset);

    /* The campaign file is exactly the Monte Carlo's campaign. */
    config_state st;
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, cfg, NULL, 0, err, sizeof err), SUNMC_OK);
    ess_deviations dev;
    ess_unit u;
    ess_deviations_sample(&st.cfg, (uint64_t)st.cfg.seed, 3, &dev);
    ess_unit_build(&st.cfg, &dev, &u);
    ess_calib_workspace *cw = ess_calib_alloc(ess_campaign_size(&st.cfg));
    int gross;
    ess_unit_campaign(&st.cfg, &u, 3, cw, NULL, &gross);
    char path[600];
    snprintf(path, sizeof path, "%s/u3/campaign.csv", dir);
    csv_table *t;
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_OK);
    assert_int_equal((int)t->n_rows, (int)cw->n);
    double *col = malloc(t->n_rows * sizeof *col);
    int c;
    assert_int_equal(csv_column(t, "alpha_deg", 1, &c, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_doubles(t, c, col, err, sizeof err), SUNMC_OK);
    for (size_t i = 0; i < cw->n; i++)
        assert_true(col[i] * RAD_PER_DEG == cw->alpha_rad[i]);
    assert_int_equal(csv_column(t, "output_deg", 1, &c, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_doubles(t, c, col, err, sizeof err), SUNMC_OK);
    for (size_t i = 0; i < cw->n; i++)
        assert_near(col[i] * RAD_PER_DEG, cw->raw_rad[i], 1e-15);
    free(col);
    csv_free(t);
    ess_calib_free(cw);
    config_state_free(&st);
    assert_near(strtod(strchr(rollset, '=') + 1, NULL), dev.roll_measured_arcsec, 1e-12);

    snprintf(cmd, sizeof cmd, "%s calibrate --sensor ess --config %s --set %s %s/u3/campaign.csv "
                              "--out %s/u3cal",
             test_sunmc(), cfg, rollset, dir, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "cross-validation"));

    /* Fitted parameters equal run's units.tsv row of the unit. */
    char units[600], params[600];
    snprintf(units, sizeof units, "%s/run/units.tsv", dir);
    snprintf(params, sizeof params, "%s/u3cal/params.ini", dir);
    const char *same[][2] = {{"fit_a", "a"},
                             {"fit_b", "b"},
                             {"fit_c", "c"},
                             {"fit_k_deg", "k_deg"},
                             {"fit_install_y_arcsec", "fit_install_y_arcsec"},
                             {"fit_install_z_arcsec", "fit_install_z_arcsec"},
                             {"fit_sun_y_arcsec", "fit_sun_y_arcsec"}};
    for (int i = 0; i < 7; i++) {
        double want = tsv_value(units, 0, same[i][0]), got = params_value(params, same[i][1]);
        assert_near(got, want, 2e-9 * fmax(fabs(want), 1e-3));
    }

    /* Compensating the validation readings reproduces run's RMS after. */
    /* (stderr apart: it carries compensate's accuracy against truth_deg) */
    snprintf(cmd, sizeof cmd, "{ %s compensate %s/u3cal/params.ini %s/u3/validation.csv > %s/comp.csv "
             "2>/dev/null; }", test_sunmc(), dir, dir, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(path, sizeof path, "%s/comp.csv", dir);
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_OK);
    double *truth = malloc(t->n_rows * sizeof *truth), *comp = malloc(t->n_rows * sizeof *comp);
    int ct, cc;
    assert_int_equal(csv_column(t, "truth_deg", 1, &ct, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_column(t, "compensated_deg", 1, &cc, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_doubles(t, ct, truth, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_doubles(t, cc, comp, err, sizeof err), SUNMC_OK);
    const double lo[3] = {0, 30, 0}, hi[3] = {30, 60, 62};
    const char *colname[3] = {"rms_after_alpha_0_30_deg", "rms_after_alpha_30_60_deg",
                              "rms_after_alpha_0_62_deg"};
    for (int b = 0; b < 3; b++) {
        double sum = 0;
        long n = 0;
        for (size_t i = 0; i < t->n_rows; i++) {
            double x = fabs(truth[i]);
            if ((lo[b] == 0 ? x <= hi[b] + 1e-9 : x > lo[b] + 1e-9 && x <= hi[b] + 1e-9)) {
                sum += (comp[i] - truth[i]) * (comp[i] - truth[i]);
                n++;
            }
        }
        double want = tsv_value(units, 0, colname[b]);
        assert_near(sqrt(sum / (double)n), want, 1e-5 * want);
    }
    free(truth);
    free(comp);
    csv_free(t);
}

/* A bad data file: exit 2, "FILE:LINE: ..." naming what, no output dir. */
static void expect_bad_data(const char *name, const char *text, const char *want)
{
    char path[600], outdir[600], cmd[4096], out[8192], full[800];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    snprintf(outdir, sizeof outdir, "%s/out_%s", dir, name);
    assert_int_equal(test_write_file(path, text), 0);
    snprintf(cmd, sizeof cmd, "%s calibrate --sensor ess --config configs/ess_type_a.ini %s --out %s",
             test_sunmc(), path, outdir);
    int rc = test_run(cmd, out, sizeof out);
    snprintf(full, sizeof full, "%s%s", path, want);
    if (rc != 2 || !strstr(out, full))
        fail_msg("exit %d, output '%s', expected 2 and '%s'", rc, out, full);
    assert_false(file_exists(outdir));
}

static void test_cli_bad_data(void **state)
{
    /* 9 good rows after the header. */
    char good[2048] = "alpha_deg,beta_deg,output_deg\n";
    for (int i = 0; i < 9; i++) {
        char row[64];
        snprintf(row, sizeof row, "%d,0,%d.001\n", -40 + 10 * i, -40 + 10 * i);
        strcat(good, row);
    }
    expect_bad_data("nocol.csv", "# lab file\nalpha_deg,output_deg\n1,1\n", ":2: missing column 'beta_deg'");
    expect_bad_data("nonnum.csv", "alpha_deg,beta_deg,output_deg\n1,0,1\n2,zero,2\n",
                    ":3: column 'beta_deg': 'zero' is not a number");
    expect_bad_data("nan.csv", "alpha_deg,beta_deg,output_deg\n1,0,NaN\n",
                    ":2: column 'output_deg': 'NaN' is not a finite number");
    expect_bad_data("inf.csv", "alpha_deg,beta_deg,output_deg\n1,0,1\n1,inf,1\n",
                    ":3: column 'beta_deg': 'inf' is not a finite number");
    expect_bad_data("dup.csv", "alpha_deg,beta_deg,output_deg,beta_deg\n1,0,1,0\n",
                    ":1: duplicate column 'beta_deg'");
    expect_bad_data("few.csv", "alpha_deg,beta_deg,output_deg\n1,0,1\n2,0,2\n",
                    ":3: only 2 data rows; the ess model has 8 parameters");
    expect_bad_data("fields.csv", "alpha_deg,beta_deg,output_deg\n1,0,1\n2,0\n",
                    ":3: 2 fields, but the header (line 1) has 3");
    char negw[4096];
    snprintf(negw, sizeof negw, "%s", "weight,alpha_deg,beta_deg,output_deg\n1,0,0,0\n-1,1,0,1\n");
    expect_bad_data("negw.csv", negw, ":3: column 'weight': -1 is negative");
    /* Enough rows, but not enough usable ones. */
    char gross[4096];
    snprintf(gross, sizeof gross, "%s%s", good, "");
    for (char *p = strstr(gross, "\n") + 1; *p; p = strchr(p, '\n') + 1)
        if (p[0] == '-' && p[1] == '2') /* row alpha -20: make it gross */
            p[strcspn(p, ",") + 3] = '9';
    {
        char path[600], cmd[4096], out[8192], outdir[600];
        snprintf(path, sizeof path, "%s/gross.csv", dir);
        snprintf(outdir, sizeof outdir, "%s/out_gross", dir);
        assert_int_equal(test_write_file(path, gross), 0);
        snprintf(cmd, sizeof cmd, "%s calibrate --sensor ess --config configs/ess_type_a.ini %s "
                                  "--out %s", test_sunmc(), path, outdir);
        /* the gross row is seen before the fit: 1 of 9 is more than the 10 %
         * of rows the design may fail to explain */
        assert_int_equal(test_run(cmd, out, sizeof out), 2);
        assert_non_null(strstr(out, "gross.csv:4: at alpha_deg = -20, beta_deg = 0: output_deg "
                                    "= 920.001 where the design reads -20"));
        assert_non_null(strstr(out, "1 of 9 rows are inconsistent with their table angles"));
        assert_false(file_exists(outdir));
    }
    /* Enough rows, one weighted 0: too few usable ones for the fit. */
    {
        char w0[4096] = "alpha_deg,beta_deg,output_deg,weight\n";
        for (int i = 0; i < 9; i++) {
            char row[64];
            snprintf(row, sizeof row, "%d,0,%d.001,%d\n", -40 + 10 * i, -40 + 10 * i, i != 2);
            strcat(w0, row);
        }
        char path[600], cmd[4096], out[8192];
        snprintf(path, sizeof path, "%s/w0.csv", dir);
        assert_int_equal(test_write_file(path, w0), 0);
        snprintf(cmd, sizeof cmd, "%s calibrate --sensor ess --config configs/ess_type_a.ini %s",
                 test_sunmc(), path);
        assert_int_equal(test_run(cmd, out, sizeof out), 2);
        assert_non_null(strstr(out, "only 8 usable data rows"));
    }
    /* Usage errors. */
    char cmd[4096], out[8192];
    snprintf(cmd, sizeof cmd, "%s calibrate --sensor xyz --config configs/ess_type_a.ini a.csv",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "--sensor must be ess, dss or psd"));
    snprintf(cmd, sizeof cmd, "%s calibrate --sensor ess a.csv", test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "needs --config CONFIG and one data file"));
    snprintf(cmd, sizeof cmd, "%s calibrate --sensor ess --config configs/ess_type_a.ini %s/none.csv",
             test_sunmc(), dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 1); /* unreadable: an I/O error */
    snprintf(cmd, sizeof cmd, "%s simulate configs/ess_type_a.ini --out %s/x", test_sunmc(), dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
}

static void test_cli_compensate_bad_input(void **state)
{
    char params[600], raw[600], cmd[4096], out[8192];
    snprintf(params, sizeof params, "%s/p.ini", dir);
    snprintf(raw, sizeof raw, "%s/raw.csv", dir);
    const char *good_params = "[calibration]\nsensor = ess\nmodel = ess_eq12_finecode\n"
                              "sunmc_version = 0.1.0\n"
                              "[design]\ntheta0_deg = 2\n[fixed]\nroll_measured_arcsec = 0\n"
                              "[parameters]\na = 1\nb = 0\nc = 0\nks_deg = 0\nkc_deg = 0.01\n"
                              "fit_install_y_arcsec = 0\nfit_install_z_arcsec = 0\n"
                              "fit_sun_y_arcsec = 0\n";
    assert_int_equal(test_write_file(params, good_params), 0);
    /* The identity-but-fine-code model: compensate inverts raw = x - kc cos(w x). */
    assert_int_equal(test_write_file(raw, "# raw\nid,output_deg\n7,10\n8,-20.5\n"), 0);
    snprintf(cmd, sizeof cmd, "%s compensate %s %s", test_sunmc(), params, raw);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "id,output_deg,compensated_deg\n7,10,"));
    double x = strtod(strstr(out, "7,10,") + 5, NULL);
    double w = 2 * M_PI / 0.5; /* 1/deg */
    assert_near(x - 0.01 * cos(w * x), 10.0, 1e-12);

    assert_int_equal(test_write_file(raw, "id,output\n7,10\n"), 0);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "raw.csv:1: missing column 'output_deg'"));
    assert_null(strstr(out, "compensated_deg\n")); /* nothing written */
    assert_int_equal(test_write_file(raw, "output_deg\n1\nx1\n"), 0);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "raw.csv:3: column 'output_deg': 'x1' is not a number"));
    assert_null(strstr(out, "compensated_deg"));

    assert_int_equal(test_write_file(raw, "output_deg\n1\n"), 0);
    char bad[2048];
    snprintf(bad, sizeof bad, "%s", good_params);
    *(strstr(bad, "\nb = 0") + 1) = '#'; /* b missing */
    assert_int_equal(test_write_file(params, bad), 0);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "missing key parameters.b"));
    snprintf(bad, sizeof bad, "%s", good_params);
    memcpy(strstr(bad, "\nc = 0"), "\nc = z", 6);
    assert_int_equal(test_write_file(params, bad), 0);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "p.ini:12: key parameters.c: 'z' is not a number"));
    snprintf(bad, sizeof bad, "%s", good_params);
    memcpy(strstr(bad, "sensor = ess"), "sensor = xyz", 12);
    assert_int_equal(test_write_file(params, bad), 0);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "p.ini:2: sensor 'xyz' is not available"));
}

static void test_cli_dss_reproduces_run(void **state)
{
    char cmd[4096], out[1 << 14], units[600], params[600];
    const char *cfg = "configs/dss.ini";
    snprintf(cmd, sizeof cmd, "%s run %s --units 3:4 --quiet --out %s/drun", test_sunmc(), cfg, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "%s simulate %s --unit 3 --out %s/d3", test_sunmc(), cfg, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "%s calibrate --config %s %s/d3/campaign.csv --out %s/d3cal",
             test_sunmc(), cfg, dir, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "held out b1<0,b2<0"));
    snprintf(units, sizeof units, "%s/drun/units.tsv", dir);
    snprintf(params, sizeof params, "%s/d3cal/params.ini", dir);
    /* every fitted parameter under the same name in units.tsv and params.ini
     * (the paper's model: the detector tilt's two only with
     * calibration.fit_detector_tilt = on) */
    for (int i = 0; i < DSS_P_TX; i++) {
        double want = tsv_value(units, 0, dss_param_names[i]);
        double got = params_value(params, dss_param_names[i]);
        assert_near(got, want, 1e-6 * fmax(fabs(want), 1e-3));
    }
    /* Compensating validation.csv reproduces run's after-compensation RMS
     * of the unit, per angle and band (bands 0:20, 20:40, 0:60 of dss.ini). */
    snprintf(cmd, sizeof cmd, "{ %s compensate %s %s/d3/validation.csv > %s/d3comp.csv 2>/dev/null; }",
             test_sunmc(), params, dir, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    {
        char cpath[600], err[SUNMC_ERRLEN];
        snprintf(cpath, sizeof cpath, "%s/d3comp.csv", dir);
        csv_table *t;
        assert_int_equal(csv_read(cpath, &t, err, sizeof err), SUNMC_OK);
        const char *names[4] = {"truth_alpha_deg", "truth_beta_deg", "compensated_alpha_deg",
                                "compensated_beta_deg"};
        double *col[4];
        for (int k = 0; k < 4; k++) {
            int c;
            col[k] = malloc(t->n_rows * sizeof(double));
            assert_int_equal(csv_column(t, names[k], 1, &c, err, sizeof err), SUNMC_OK);
            assert_int_equal(csv_doubles(t, c, col[k], err, sizeof err), SUNMC_OK);
        }
        const double lo[3] = {0, 20, 0}, hi[3] = {20, 40, 60};
        const char *an[2] = {"alpha", "beta"}, *bn[3] = {"0_20", "20_40", "0_60"};
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 3; b++) {
                double sum = 0;
                long n = 0;
                for (size_t i = 0; i < t->n_rows; i++) {
                    double al = col[0][i] * RAD_PER_DEG, be = col[1][i] * RAD_PER_DEG;
                    double fd = atan(hypot(tan(al), tan(be))) * DEG_PER_RAD;
                    if (lo[b] == 0 ? fd <= hi[b] : fd > lo[b] && fd <= hi[b]) {
                        double e = (col[2 + a][i] - col[a][i]) * ARCSEC_PER_DEG;
                        sum += e * e;
                        n++;
                    }
                }
                char cn[80];
                snprintf(cn, sizeof cn, "rms_after_%s_%s_arcsec", an[a], bn[b]);
                double want = tsv_value(units, 0, cn);
                assert_true(n > 0);
                assert_near(sqrt(sum / (double)n), want, 1e-5 * want); /* units.tsv: 6 digits */
            }
        for (int k = 0; k < 4; k++)
            free(col[k]);
        csv_free(t);
    }
    /* The report's predicted accuracy carries the propagated calibration
     * uncertainty (a finite cal.sigma column in bands.tsv). */
    {
        char bpath[600];
        snprintf(bpath, sizeof bpath, "%s/d3cal/bands.tsv", dir);
        for (int r = 0; r < 6; r++) {
            double cs = tsv_value(bpath, r, "cal_sigma_rms_arcsec");
            double res = tsv_value(bpath, r, "residual_rms_arcsec");
            double pr = tsv_value(bpath, r, "predicted_rms_arcsec");
            assert_true(cs > 0 && cs < res);
            assert_true(pr > res);
        }
    }
    snprintf(cmd, sizeof cmd, "%s compensate %s %s/d3/campaign.csv", test_sunmc(), params, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "b1_deg,b2_deg,x_px,y_px,weight,compensated_alpha_deg,"
                                "compensated_beta_deg\n"));
    /* Bad DSS data: exit 2, FILE:LINE, nothing written. */
    char path[600], outdir[600];
    snprintf(path, sizeof path, "%s/dbad.csv", dir);
    snprintf(outdir, sizeof outdir, "%s/dbad_out", dir);
    assert_int_equal(test_write_file(path, "b1_deg,b2_deg,x_px\n1,2,3\n"), 0);
    snprintf(cmd, sizeof cmd, "%s calibrate --sensor dss --config %s %s --out %s", test_sunmc(),
             cfg, path, outdir);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "dbad.csv:1: missing column 'y_px'"));
    assert_false(file_exists(outdir));
    /* Without --sensor the family is the config's: the same DSS refusal. */
    snprintf(cmd, sizeof cmd, "%s calibrate --config %s %s --out %s", test_sunmc(), cfg, path,
             outdir);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "dbad.csv:1: missing column 'y_px'"));
    assert_false(file_exists(outdir));
    /* The config's family must match --sensor: exit 2 naming both. */
    snprintf(cmd, sizeof cmd, "%s calibrate --sensor ess --config %s %s", test_sunmc(), cfg, path);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "--sensor ess, but"));
    assert_non_null(strstr(out, "is a dss config"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cli_simulate_calibrate_compensate_reproduces_run),
        cmocka_unit_test(test_cli_bad_data),
        cmocka_unit_test(test_cli_compensate_bad_input),
        cmocka_unit_test(test_cli_dss_reproduces_run),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
