/* cmd_calibrate.c - `sunmc calibrate` (fit a real sensor's turntable data,
 * report, write params.ini) and `sunmc compensate` (apply params.ini). */
#include "calreport.h"
#include "csv.h"
#include "dss_calfit.h"
#include "ess_calfit.h"
#include "cli.h"
#include "output.h"
#include "params_io.h"
#include "status.h"
#include "units.h"

#include <stdlib.h>
#include <string.h>

static const char calibrate_help[] =
    "usage: sunmc calibrate --sensor ess|dss --config CONFIG DATA.csv [--out DIR]\n"
    "                       [--set SECTION.KEY=VALUE]...\n"
    "Fits the family's calibration model (the Monte Carlo's own fit) to turntable data and\n"
    "prints the parameters with standard errors, the correlation matrix, condition numbers,\n"
    "residual RMS and predicted accuracy per band, cross-validation and warnings.\n"
    "Design values come from CONFIG (and --set).  DATA.csv: a header line, '#' comments,\n"
    "columns in any order, extra columns ignored:\n"
    "  ess: alpha_deg,beta_deg,output_deg[,weight]   (turntable inner/outer angle, raw output)\n"
    "       the known installation roll is calibration.roll_measured_arcsec (default 0)\n"
    "  dss: b1_deg,b2_deg,x_px,y_px[,weight]\n"
    "--out DIR writes params.ini (for `sunmc compensate`), residuals.tsv, bands.tsv,\n"
    "crossval.tsv and field.tsv (propagated sigma across the field), all or nothing.\n"
    "Exit status 2 for bad data (FILE:LINE: message), 1 when the fit fails.\n";

static const char compensate_help[] =
    "usage: sunmc compensate PARAMS.ini RAW.csv > COMPENSATED.csv\n"
    "Applies a calibration written by `sunmc calibrate` to raw readings.  RAW.csv needs the\n"
    "column output_deg (ess) or x_px,y_px (dss); the output repeats every input column and\n"
    "adds the compensated angle(s): compensated_deg (ess).\n";

/* Read the ESS campaign columns into a new workspace; *line_out gets each
 * row's file line.  Every value is checked before the number of rows. */
/* Columns names[0..n-2] (required) and names[n-1] = "weight" (optional,
 * default 1, must not be negative) of t into freshly allocated v[k]
 * (n_rows each; the caller frees them, also on error). */
static int read_columns(const csv_table *t, const char *path, const char *const *names, int n,
                        double **v, char *err, size_t errlen)
{
    int st = SUNMC_OK;
    for (int k = 0; k < n && st == SUNMC_OK; k++) {
        int col;
        st = csv_column(t, names[k], k < n - 1, &col, err, errlen);
        if (st != SUNMC_OK)
            break;
        v[k] = malloc((t->n_rows + 1) * sizeof(double));
        if (!v[k])
            st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
        else if (col >= 0)
            st = csv_doubles(t, col, v[k], err, errlen);
        else
            for (size_t i = 0; i < t->n_rows; i++)
                v[k][i] = 1.0;
    }
    for (size_t i = 0; i < t->n_rows && st == SUNMC_OK; i++)
        if (v[n - 1][i] < 0)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                            "%s:%d: column 'weight': %g is negative (1 / relative variance; 0 "
                            "drops the row)",
                            path, t->line[i], v[n - 1][i]);
    return st;
}

static int read_ess_campaign(const char *path, ess_calib_workspace **cw_out, int **line_out,
                             char *err, size_t errlen)
{
    csv_table *t;
    int st = csv_read(path, &t, err, errlen);
    if (st != SUNMC_OK)
        return st;
    const char *names[4] = {"alpha_deg", "beta_deg", "output_deg", "weight"};
    double *v[4] = {NULL, NULL, NULL, NULL};
    st = read_columns(t, path, names, 4, v, err, errlen);
    char why[128];
    snprintf(why, sizeof why, "the ess model has %d parameters: need at least %d rows", ESS_NP,
             ESS_NP + 1);
    if (st == SUNMC_OK)
        st = csv_require_rows(t, ESS_NP + 1, why, err, errlen);
    ess_calib_workspace *cw = NULL;
    int *line = NULL;
    if (st == SUNMC_OK) {
        cw = ess_calib_alloc(t->n_rows);
        line = malloc(t->n_rows * sizeof *line);
        if (!cw || !line)
            st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
    }
    if (st == SUNMC_OK)
        for (size_t i = 0; i < t->n_rows; i++) {
            line[i] = t->line[i];
            cw->alpha_rad[i] = v[0][i] * RAD_PER_DEG;
            cw->beta_rad[i] = v[1][i] * RAD_PER_DEG;
            cw->raw_rad[i] = v[2][i] * RAD_PER_DEG;
            cw->weight[i] = v[3][i];
        }
    for (int k = 0; k < 4; k++)
        free(v[k]);
    csv_free(t);
    if (st != SUNMC_OK) {
        ess_calib_free(cw);
        free(line);
        return st;
    }
    *cw_out = cw;
    *line_out = line;
    return SUNMC_OK;
}

static int calibration_header(params_file *p, const char *sensor, const char *model,
                              const char *data, const char *config, size_t rows,
                              const calreport *rep, char *err, size_t errlen)
{
    unsigned long long h;
    int st = params_file_fnv1a64(data, &h, err, errlen);
    if (st != SUNMC_OK)
        return st;
    char hex[32];
    snprintf(hex, sizeof hex, "%016llx", h);
    st = params_set_text(p, "calibration", "sunmc_version", SUNMC_VERSION, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "sensor", sensor, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "model", model, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "data_file", data, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "data_fnv1a64", hex,
                             "FNV-1a 64 of the data file's bytes");
    if (st == SUNMC_OK)
        st = params_set_double(p, "calibration", "data_rows", (double)rows, NULL);
    if (st == SUNMC_OK)
        st = params_set_text(p, "calibration", "config", config, NULL);
    if (st == SUNMC_OK)
        st = params_set_double(p, "calibration", "residual_sigma_arcsec", rep->sigma_arcsec,
                               "in-sample");
    if (st == SUNMC_OK && rep->n_folds > 0)
        st = params_set_double(p, "calibration", "crossval_rms_arcsec", rep->cv_rms_out_arcsec,
                               "held-out error: the honest accuracy estimate");
    if (st != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "cannot record the data file or config name in params.ini (too long, "
                          "or holds '#')");
    return SUNMC_OK;
}

static int calibrate_ess(const cli_options *o, const sunmc_config *c)
{
    const ess_config *ec = ess_cfg(c);
    const char *data = o->positional[0];
    char err[SUNMC_ERRLEN];
    ess_calib_workspace *cw;
    int *line;
    int st = read_ess_campaign(data, &cw, &line, err, sizeof err);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc calibrate: %s\n", err);
        return cli_exit_code(st);
    }
    calreport *rep = malloc(sizeof *rep);
    ess_calfit_result *res = malloc(sizeof *res);
    params_file *pf = malloc(sizeof *pf);
    if (!rep || !res || !pf) {
        free(rep);
        free(res);
        free(pf);
        ess_calib_free(cw);
        free(line);
        fprintf(stderr, "sunmc calibrate: out of memory\n");
        return 1;
    }
    st = ess_calfit_run(c, cw, line, res, rep, err, sizeof err);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc calibrate: %s: %s\n", data, err);
    } else {
        calreport_print(stdout, rep);
        if (!rep->fit_ok) {
            fprintf(stderr, "sunmc calibrate: the fit failed (%s): nothing written\n",
                    fit_reason(&rep->fit));
            st = SUNMC_EFIT;
        }
    }
    if (st == SUNMC_OK && o->out) {
        params_init(pf);
        st = calibration_header(pf, "ess", ESS_CALFIT_MODEL, data, o->config, cw->n, rep, err,
                                sizeof err);
        if (st == SUNMC_OK && ess_params_fill(pf, res, rep, ec->design.theta0_deg) != SUNMC_OK)
            st = sunmc_fail(err, sizeof err, SUNMC_EINPUT, "params.ini: too many entries");
        double amin = ec->cal_alpha_min_deg, amax = ec->cal_alpha_max_deg;
        for (size_t i = 0; i < cw->n; i++) {
            amin = fmin(amin, cw->alpha_rad[i] * DEG_PER_RAD);
            amax = fmax(amax, cw->alpha_rad[i] * DEG_PER_RAD);
        }
        out_set os;
        static const char *const names[5] = {"params.ini", "residuals.tsv", "bands.tsv",
                                             "crossval.tsv", "field.tsv"};
        FILE *f[5] = {NULL};
        if (st == SUNMC_OK)
            st = out_begin(&os, o->out, err, sizeof err);
        if (st == SUNMC_OK) {
            st = out_open_all(&os, names, f, 5, err, sizeof err);
            FILE *fp = f[0], *fr = f[1], *fb = f[2], *fx = f[3], *ff = f[4];
            if (st == SUNMC_OK) {
                params_write(fp, pf,
                             "sunmc calibration of an encoded sun sensor (ESS paper eq. 12-14):\n"
                             "read by `sunmc compensate`; units are in the key names, standard "
                             "errors in the comments");
                ess_calfit_write_residuals(fr, cw, line, &res->m);
                calreport_write_bands(fb, rep);
                calreport_write_folds(fx, rep);
                ess_calfit_write_field(ff, res, amin, amax);
                st = out_commit(&os, err, sizeof err);
            } else {
                out_abort(&os);
            }
        }
        if (st != SUNMC_OK)
            fprintf(stderr, "sunmc calibrate: %s\n", err);
    }
    free(rep);
    free(res);
    free(pf);
    ess_calib_free(cw);
    free(line);
    return cli_exit_code(st);
}

/* Read a DSS campaign (b1_deg, b2_deg, x_px, y_px, optional weight) into a
 * workspace for c's model. */
static int read_dss_campaign(const char *path, const sunmc_config *c, dss_calib_workspace **out,
                             int **line_out, char *err, size_t errlen)
{
    const dss_config *dc = dss_cfg(c);
    csv_table *t;
    int st = csv_read(path, &t, err, errlen);
    if (st != SUNMC_OK)
        return st;
    const char *names[5] = {"b1_deg", "b2_deg", "x_px", "y_px", "weight"};
    double *v[5] = {NULL, NULL, NULL, NULL, NULL};
    st = read_columns(t, path, names, 5, v, err, errlen);
    int np = dc->cal_model == DSS_MODEL_PHYSICAL ? DSS_NP : dss_poly_n_terms(dc->poly_order);
    char why[128];
    snprintf(why, sizeof why, "the dss model has up to %d parameters: need at least %d rows", np,
             np + 1);
    if (st == SUNMC_OK)
        st = csv_require_rows(t, (size_t)np + 1, why, err, errlen);
    dss_calib_workspace *cw = NULL;
    int *line = NULL;
    if (st == SUNMC_OK) {
        cw = dss_calib_alloc(&dc->design, t->n_rows, dc->cal_model, dc->poly_order,
                             dc->fit_glass_index);
        line = malloc(t->n_rows * sizeof *line);
        if (!cw || !line)
            st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: cannot set up the fit", path);
    }
    if (st == SUNMC_OK)
        for (size_t i = 0; i < t->n_rows; i++) {
            line[i] = t->line[i];
            cw->b1_rad[i] = v[0][i] * RAD_PER_DEG;
            cw->b2_rad[i] = v[1][i] * RAD_PER_DEG;
            cw->x_px[i] = v[2][i];
            cw->y_px[i] = v[3][i];
            cw->weight[i] = v[4][i];
        }
    for (int k = 0; k < 5; k++)
        free(v[k]);
    csv_free(t);
    if (st != SUNMC_OK) {
        dss_calib_free(cw);
        free(line);
        return st;
    }
    *out = cw;
    *line_out = line;
    return SUNMC_OK;
}

static int calibrate_dss(const cli_options *o, const sunmc_config *c)
{
    const char *data = o->positional[0];
    char err[SUNMC_ERRLEN];
    dss_calib_workspace *cw;
    int *line;
    int st = read_dss_campaign(data, c, &cw, &line, err, sizeof err);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc calibrate: %s\n", err);
        return cli_exit_code(st);
    }
    calreport *rep = malloc(sizeof *rep);
    dss_calibration *cal = malloc(sizeof *cal);
    params_file *pf = malloc(sizeof *pf);
    if (!rep || !cal || !pf) {
        free(rep);
        free(cal);
        free(pf);
        dss_calib_free(cw);
        free(line);
        fprintf(stderr, "sunmc calibrate: out of memory\n");
        return 1;
    }
    st = dss_calfit_run(c, cw, cal, rep, err, sizeof err);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc calibrate: %s: %s\n", data, err);
    } else {
        calreport_print(stdout, rep);
        if (!rep->fit_ok) {
            fprintf(stderr, "sunmc calibrate: the fit failed (%s): nothing written\n",
                    fit_reason(&rep->fit));
            st = SUNMC_EFIT;
        }
    }
    if (st == SUNMC_OK && o->out) {
        params_init(pf);
        st = calibration_header(pf, "dss", rep->model, data, o->config, cw->n, rep, err,
                                sizeof err);
        if (st == SUNMC_OK && dss_params_fill(pf, cal, rep) != SUNMC_OK)
            st = sunmc_fail(err, sizeof err, SUNMC_EINPUT, "params.ini: too many entries");
        out_set os;
        static const char *const names[4] = {"params.ini", "residuals.tsv", "bands.tsv",
                                             "crossval.tsv"};
        FILE *f[4] = {NULL};
        if (st == SUNMC_OK)
            st = out_begin(&os, o->out, err, sizeof err);
        if (st == SUNMC_OK) {
            st = out_open_all(&os, names, f, 4, err, sizeof err);
            FILE *fp = f[0], *fr = f[1], *fb = f[2], *fx = f[3];
            if (st == SUNMC_OK) {
                params_write(fp, pf,
                             "sunmc calibration of a pinhole digital sun sensor (DSS paper):\n"
                             "read by `sunmc compensate`; units are in the key names");
                dss_calfit_write_residuals(fr, cw, line, cal);
                calreport_write_bands(fb, rep);
                calreport_write_folds(fx, rep);
                st = out_commit(&os, err, sizeof err);
            } else {
                out_abort(&os);
            }
        }
        if (st != SUNMC_OK)
            fprintf(stderr, "sunmc calibrate: %s\n", err);
    }
    free(rep);
    free(cal);
    free(pf);
    dss_calib_free(cw);
    free(line);
    return cli_exit_code(st);
}

int cmd_calibrate(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, calibrate_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "calibrate", "sensor config set out quiet", &o);
    if (rc)
        return rc;
    if (!o.sensor || !o.config || o.n_positional != 1) {
        fprintf(stderr, "sunmc calibrate: needs --sensor ess|dss, --config CONFIG and one data "
                        "file (see sunmc calibrate --help)\n");
        return EXIT_BAD_INPUT;
    }
    const sensor_family *fam = sensor_family_find(o.sensor);
    int is_ess = fam && strcmp(fam->name, "ess") == 0;
    if (!fam || (!is_ess && strcmp(fam->name, "dss") != 0)) {
        fprintf(stderr, "sunmc calibrate: --sensor must be ess or dss, not '%s'\n", o.sensor);
        return EXIT_BAD_INPUT;
    }
    config_state st;
    if ((rc = cli_config(&o, &st)))
        return rc;
    if (st.cfg.family != fam) {
        fprintf(stderr, "sunmc calibrate: --sensor %s, but %s is a %s config (sensor.family)\n",
                o.sensor, o.config, st.cfg.family->name);
        config_state_free(&st);
        return EXIT_BAD_INPUT;
    }
    rc = is_ess ? calibrate_ess(&o, &st.cfg) : calibrate_dss(&o, &st.cfg);
    config_state_free(&st);
    return rc;
}

/* ---- compensate ---- */

static int compensate_ess(const params_file *pf, const char *raw_path)
{
    char err[SUNMC_ERRLEN];
    ess_model m;
    int st = ess_params_load(pf, &m, err, sizeof err);
    csv_table *t = NULL;
    if (st == SUNMC_OK)
        st = csv_read(raw_path, &t, err, sizeof err);
    int co, cdup;
    if (st == SUNMC_OK)
        st = csv_column(t, "output_deg", 1, &co, err, sizeof err);
    if (st == SUNMC_OK)
        st = csv_column(t, "compensated_deg", 0, &cdup, err, sizeof err);
    if (st == SUNMC_OK && cdup >= 0)
        st = sunmc_fail(err, sizeof err, SUNMC_EINPUT,
                        "%s:%d: the input already has a column 'compensated_deg'", raw_path,
                        t->header_line);
    double *raw = NULL;
    if (st == SUNMC_OK) {
        raw = malloc((t->n_rows + 1) * sizeof *raw);
        st = raw ? csv_doubles(t, co, raw, err, sizeof err)
                 : sunmc_fail(err, sizeof err, SUNMC_ENOMEM, "out of memory");
    }
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc compensate: %s\n", err);
        free(raw);
        csv_free(t);
        return cli_exit_code(st);
    }
    long failed = 0;
    int first_failed = 0;
    for (int j = 0; j < t->n_cols; j++)
        printf("%s,", t->names[j]);
    printf("compensated_deg\n");
    for (size_t i = 0; i < t->n_rows; i++) {
        for (int j = 0; j < t->n_cols; j++)
            printf("%s,", t->field[i * (size_t)t->n_cols + (size_t)j]);
        double a;
        if (ess_model_compensate(&m, raw[i] * RAD_PER_DEG, &a) == SUNMC_OK)
            printf("%.15g\n", a * DEG_PER_RAD);
        else {
            printf("nan\n");
            if (!failed++)
                first_failed = t->line[i];
        }
    }
    if (failed)
        fprintf(stderr, "sunmc compensate: %s:%d: %ld readings could not be compensated (nan): "
                        "the model is not invertible there\n", raw_path, first_failed, failed);
    free(raw);
    csv_free(t);
    return fflush(stdout) == 0 && !ferror(stdout) ? 0 : 1;
}

static int compensate_dss(const params_file *pf, const char *raw_path)
{
    char err[SUNMC_ERRLEN];
    dss_calibration cal;
    int st = dss_params_load(pf, &cal, err, sizeof err);
    csv_table *t = NULL;
    if (st == SUNMC_OK)
        st = csv_read(raw_path, &t, err, sizeof err);
    int cx, cy, d1, d2;
    if (st == SUNMC_OK)
        st = csv_column(t, "x_px", 1, &cx, err, sizeof err);
    if (st == SUNMC_OK)
        st = csv_column(t, "y_px", 1, &cy, err, sizeof err);
    if (st == SUNMC_OK)
        st = csv_column(t, "compensated_alpha_deg", 0, &d1, err, sizeof err);
    if (st == SUNMC_OK)
        st = csv_column(t, "compensated_beta_deg", 0, &d2, err, sizeof err);
    if (st == SUNMC_OK && (d1 >= 0 || d2 >= 0))
        st = sunmc_fail(err, sizeof err, SUNMC_EINPUT,
                        "%s:%d: the input already has a compensated_*_deg column", raw_path,
                        t->header_line);
    double *x = NULL, *y = NULL;
    if (st == SUNMC_OK) {
        x = malloc((t->n_rows + 1) * sizeof *x);
        y = malloc((t->n_rows + 1) * sizeof *y);
        st = x && y ? csv_doubles(t, cx, x, err, sizeof err)
                    : sunmc_fail(err, sizeof err, SUNMC_ENOMEM, "out of memory");
    }
    if (st == SUNMC_OK)
        st = csv_doubles(t, cy, y, err, sizeof err);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc compensate: %s\n", err);
        free(x);
        free(y);
        csv_free(t);
        return cli_exit_code(st);
    }
    long failed = 0;
    int first_failed = 0;
    for (int j = 0; j < t->n_cols; j++)
        printf("%s,", t->names[j]);
    printf("compensated_alpha_deg,compensated_beta_deg\n");
    for (size_t i = 0; i < t->n_rows; i++) {
        for (int j = 0; j < t->n_cols; j++)
            printf("%s,", t->field[i * (size_t)t->n_cols + (size_t)j]);
        double a, b;
        if (dss_compensate(&cal, x[i], y[i], &a, &b) == SUNMC_OK)
            printf("%.15g,%.15g\n", a * DEG_PER_RAD, b * DEG_PER_RAD);
        else {
            printf("nan,nan\n");
            if (!failed++)
                first_failed = t->line[i];
        }
    }
    if (failed)
        fprintf(stderr, "sunmc compensate: %s:%d: %ld readings could not be compensated (nan)\n",
                raw_path, first_failed, failed);
    free(x);
    free(y);
    csv_free(t);
    return fflush(stdout) == 0 && !ferror(stdout) ? 0 : 1;
}

int cmd_compensate(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, compensate_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "compensate", "quiet", &o);
    if (rc)
        return rc;
    if (o.n_positional != 2) {
        fprintf(stderr, "sunmc compensate: needs PARAMS.ini and RAW.csv (see sunmc compensate "
                        "--help)\n");
        return EXIT_BAD_INPUT;
    }
    params_file *pf = malloc(sizeof *pf);
    if (!pf) {
        fprintf(stderr, "sunmc compensate: out of memory\n");
        return 1;
    }
    char err[SUNMC_ERRLEN];
    const char *sensor = NULL;
    int st = params_read(o.positional[0], pf, err, sizeof err);
    if (st == SUNMC_OK)
        st = params_get_text(pf, "calibration", "sensor", &sensor, err, sizeof err);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc compensate: %s\n", err);
        free(pf);
        return cli_exit_code(st);
    }
    if (strcmp(sensor, "ess") == 0)
        rc = compensate_ess(pf, o.positional[1]);
    else if (strcmp(sensor, "dss") == 0)
        rc = compensate_dss(pf, o.positional[1]);
    else {
        const params_entry *e = params_find(pf, "calibration", "sensor");
        fprintf(stderr, "sunmc compensate: %s:%d: sensor '%s' is not available\n",
                o.positional[0], e->line, sensor);
        rc = EXIT_BAD_INPUT;
    }
    free(pf);
    return rc;
}
