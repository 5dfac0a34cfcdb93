/* cmd_calibrate.c - `sunmc calibrate` (fit a real sensor's turntable data,
 * report, write params.ini) and `sunmc compensate` (apply params.ini). */
#include "calreport.h"
#include "cli.h"
#include "lab.h"
#include "lab_accuracy.h"
#include "lab_onboard.h"
#include "lab_params.h"
#include "params_io.h"
#include "registry.h"
#include "status.h"
#include "suggest.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* "a, b or c": the families with lab commands, for messages. */
static void lab_family_names(char *buf, size_t len)
{
    int n = 0, k = 0;
    for (int i = 0; i < sensor_family_count(); i++)
        n += sensor_family_at(i)->lab != NULL;
    buf[0] = '\0';
    for (int i = 0; i < sensor_family_count(); i++) {
        const sensor_family *f = sensor_family_at(i);
        if (!f->lab)
            continue;
        size_t used = strlen(buf);
        snprintf(buf + used, len - used, "%s%s", k == 0 ? "" : k == n - 1 ? " or " : ", ",
                 f->name);
        k++;
    }
}

/* Room for calibrate --help and compensate --help. */
#define LAB_HELP_MAX 8192

static const char calibrate_head[] =
    "usage: sunmc calibrate --config CONFIG DATA.csv [--sensor FAMILY] [--out DIR]\n"
    "                       [--set SECTION.KEY=VALUE]... [--duplicates average|refuse|keep]\n"
    "The family (%s) is CONFIG's sensor.family; --sensor, when given, must agree.\n"
    "Rows that repeat an earlier row exactly are a reading logged twice: counted once\n"
    "(--duplicates average, the default, with a warning naming them), refused, or kept.\n"
    "Fits the family's calibration model (the Monte Carlo's own fit) to turntable data and\n"
    "prints the parameters with standard errors, the correlation matrix, condition numbers,\n"
    "residual RMS and predicted accuracy per band, cross-validation and warnings.\n"
    "Design values come from CONFIG (and --set).  DATA.csv: a header line, '#' comments,\n"
    "columns in any order, extra columns ignored (conventions: docs/conventions.md;\n"
    "simulate writes them into its CSVs):\n";

static const char calibrate_tail[] =
    "--out DIR writes params.ini (for `sunmc compensate`), residuals.tsv, bands.tsv,\n"
    "crossval.tsv and the family's own files (above), all or nothing.\n"
    "Exit status 2 for bad data (FILE:LINE: message), 1 when the fit fails.\n";

static const char compensate_head[] =
    "usage: sunmc compensate PARAMS.ini RAW.csv [--config CONFIG] [--out DIR]\n"
    "                        [--onboard double|float|table:STEP] > COMPENSATED.csv\n"
    "Applies a calibration written by `sunmc calibrate` to raw readings.  RAW.csv needs the\n"
    "family's raw columns ('#' comment lines skipped); the output repeats every input column\n"
    "and adds the compensated angle(s):\n";

static const char compensate_tail[] =
    "A row the calibrated sensor cannot produce (no signal, outside the detector or the\n"
    "output's range, no inverse) gets '-' and is counted on stderr by cause.\n"
    "PARAMS.ini is read strictly: an unknown section or key, a model line naming another\n"
    "model than the file holds, a coefficient beyond the polynomial's order, a file of a\n"
    "newer major sunmc version (or none) exit 2 with FILE:LINE; a newer minor warns.\n"
    "What it achieved: when every compensated_X has its truth_X in the row (simulate's\n"
    "validation.csv; the truth columns above), stderr gets per angle and band the points\n"
    "and the RMS, p99.7 and max of compensated - truth in the family's unit (ESS deg,\n"
    "DSS and PSD arcsec; two axes add the total angle between the two directions and\n"
    "are banded by the truth's field angle, one axis by |angle|).\n"
    "  --config CONFIG  its report.bands_deg and spec (report.spec_arcsec,\n"
    "                   report.spec_statistic: meets spec yes/no per band); else one\n"
    "                   band over the data.  Must be the params.ini's family.\n"
    "  --set KEY=VALUE  changes a key of CONFIG (needs --config)\n"
    "  --out DIR        also writes DIR/accuracy.tsv (refused without truth columns)\n"
    "  --onboard FORM   compensates as `sunmc export`'s code does on board: double (the\n"
    "                   default: the model), float (its -DSUNMC_FLOAT build; the PSD's\n"
    "                   physical and polynomial models), or table:STEP (its table form,\n"
    "                   STEP in the reading axes' unit: ESS output_deg, DSS px, PSD\n"
    "                   ratio); the accuracy is then the on-board form's\n"
    "                   (docs/calibration.md, from the lab to the flight software)\n"
    "Conventions of the raw columns and table angles: see `sunmc calibrate --help`.\n";

/* Append printf-style text to buf (used bytes *n), truncating at len. */
static void help_add(char *buf, size_t len, size_t *n, const char *fmt, ...)
{
    if (*n + 1 >= len)
        return;
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(buf + *n, len - *n, fmt, ap);
    va_end(ap);
    *n = k < 0 ? *n : *n + (size_t)k < len ? *n + (size_t)k : len - 1;
}

/* "a,b,c" of a NULL-terminated list into buf; "weight" last is "[,weight]". */
static void help_columns(char *buf, size_t len, size_t *n, const char *const *cols)
{
    for (int k = 0; cols && cols[k]; k++) {
        int optional = strcmp(cols[k], "weight") == 0 && !cols[k + 1];
        help_add(buf, len, n, optional ? "[,%s]" : "%s%s", optional ? cols[k] : k ? "," : "",
                 cols[k]);
    }
}

/* calibrate --help (calibrate != 0) or compensate --help, from each
 * registered family's lab descriptor: no family is named here. */
static void lab_help(int calibrate, char *buf, size_t len)
{
    char names[256];
    lab_family_names(names, sizeof names);
    size_t n = 0;
    help_add(buf, len, &n, calibrate ? calibrate_head : compensate_head, names);
    for (int i = 0; i < sensor_family_count(); i++) {
        const family_lab *lab = sensor_family_at(i)->lab;
        if (!lab)
            continue;
        help_add(buf, len, &n, "  %s: ", sensor_family_at(i)->name);
        if (calibrate) {
            help_columns(buf, len, &n, lab->cal_columns);
            int k = 0; /* the family's files, then models.tsv (lab_write_calibration) */
            for (; lab->extra_files && lab->extra_files[k]; k++)
                help_add(buf, len, &n, "%s%s", k ? ", " : "   (--out adds ", lab->extra_files[k]);
            if (lab->cal_models_tsv)
                help_add(buf, len, &n, "%s%s", k++ ? ", " : "   (--out adds ", "models.tsv");
            help_add(buf, len, &n, "%s\n%s", k ? ")" : "", lab->cal_help ? lab->cal_help : "");
        } else {
            help_columns(buf, len, &n, lab->raw_columns);
            help_add(buf, len, &n, " -> ");
            help_columns(buf, len, &n, lab->comp_columns);
            if (lab->opt_columns) {
                help_add(buf, len, &n, "; with ");
                help_columns(buf, len, &n, lab->opt_columns);
                if (lab->opt_comp_columns) {
                    help_add(buf, len, &n, " also ");
                    help_columns(buf, len, &n, lab->opt_comp_columns);
                } else {
                    help_add(buf, len, &n, " (read to check the row)");
                }
            }
            help_add(buf, len, &n, "\n%s", lab->comp_help ? lab->comp_help : "");
        }
    }
    help_add(buf, len, &n, "%s", calibrate ? calibrate_tail : compensate_tail);
}

/* The report's warnings again on stderr when the report itself goes to a
 * file or a pipe, so that none passes unseen (whatever --quiet says). */
static void warn_stderr(const calreport *rep)
{
    if (isatty(STDOUT_FILENO))
        return;
    /* the report out first: one stream into the same pipe is not cut by
     * the other (a report longer than the pipe's buffer was) */
    fflush(stdout);
    for (int i = 0; i < rep->nw; i++)
        fprintf(stderr, "sunmc calibrate: WARNING: %s\n", rep->w[i].reason);
}

/* The mode of --duplicates (default average); -1 with a message when it is
 * none of them. */
static int duplicates_mode(const cli_options *o, char *err, size_t errlen)
{
    const char *m = o->duplicates ? o->duplicates : "average";
    int mode = strcmp(m, "average") == 0  ? LAB_DUP_AVERAGE
               : strcmp(m, "refuse") == 0 ? LAB_DUP_REFUSE
               : strcmp(m, "keep") == 0   ? LAB_DUP_KEEP
                                          : -1;
    char hint[SUGGEST_NAME_MAX + 32];
    suggest_hint(m, "average refuse keep", hint, sizeof hint);
    if (mode < 0)
        sunmc_fail(err, errlen, SUNMC_EINPUT, "--duplicates %s: one of average, refuse, keep%s",
                   m, hint);
    return mode;
}

/* Exact duplicate rows, as --duplicates says (default average); the
 * warning, if any, into warn (empty: none), for the report's warnings. */
static int duplicates(const cli_options *o, lab_columns *d, char *warn, size_t warnlen,
                      char *err, size_t errlen)
{
    warn[0] = '\0';
    int mode = duplicates_mode(o, err, errlen);
    if (mode < 0)
        return SUNMC_EINPUT;
    char note[256];
    int n = lab_duplicates(d, mode, note, sizeof note, err, errlen);
    if (n < 0)
        return -n;
    if (n > 0)
        snprintf(warn, warnlen,
                 "%s: %d row%s repeat%s an earlier row exactly (line = earlier line: %s): %s",
                 d->path, n, n == 1 ? "" : "s", n == 1 ? "s" : "", note,
                 mode == LAB_DUP_KEEP
                     ? "counted as independent readings (--duplicates=keep): every standard "
                       "error shrinks as if they were"
                     : "each counted once (--duplicates=average; =refuse refuses the file, "
                       "=keep counts them as independent readings)");
    return SUNMC_OK;
}

/* Read the data, fit, print the report; with --out write the files. */
static int calibrate(const cli_options *o, const config_state *cs, const family_lab *lab)
{
    const sunmc_config *c = &cs->cfg;
    const char *data = o->positional[0];
    char err[SUNMC_ERRLEN], why[128];
    lab_columns d;
    size_t min_rows = lab->cal_min_rows(c, why, sizeof why);
    int st = lab_columns_read(data, lab->cal_columns, min_rows, why, &d, err, sizeof err);
    if (st == SUNMC_OK)
        st = lab_check_data(lab, c, &d, err, sizeof err);
    /* a family that counts a point's rows once (PSD: quantised readings of
     * one point may repeat exactly) leaves exact repeats to its fit unless
     * --duplicates says otherwise */
    char dup_warn[CALREPORT_TEXT_MAX] = "";
    if (st == SUNMC_OK && (!lab->cal_counts_repeats_once || o->duplicates))
        st = duplicates(o, &d, dup_warn, sizeof dup_warn, err, sizeof err);
    calreport *rep = st == SUNMC_OK ? malloc(sizeof *rep) : NULL;
    if (st != SUNMC_OK || !rep) {
        fprintf(stderr, "sunmc calibrate: %s\n", st != SUNMC_OK ? err : "out of memory");
        lab_columns_free(&d);
        return st != SUNMC_OK ? cli_exit_code(st) : 1;
    }
    void *cal = NULL;
    st = lab->cal_run(c, &d, &cal, rep, err, sizeof err);
    if (st != SUNMC_OK) {
        if (dup_warn[0])
            fprintf(stderr, "sunmc calibrate: WARNING: %s\n", dup_warn);
        fprintf(stderr, "sunmc calibrate: %s: %s\n", data, err);
    } else {
        if (dup_warn[0]) /* in the report's warnings, like every other */
            calreport_warn(rep, "remove the repeated lines, or say how to count them with "
                                "--duplicates",
                           "%s", dup_warn);
        lab_drift_report(lab, cal, &d, rep);
        lab_check_fit(lab, c, &d, rep);
        lab_check_grid(lab, c, &d, rep);
        lab_check_measured(lab, cs, rep);
        calreport_print(stdout, rep);
        warn_stderr(rep);
        if (!rep->fit_ok) {
            fprintf(stderr, "sunmc calibrate: the fit %s (%s): nothing written\n",
                    rep->refused[0] ? "is refused" : "failed",
                    rep->refused[0] ? rep->refused : fit_reason(&rep->fit));
            st = SUNMC_EFIT;
        }
    }
    if (st == SUNMC_OK && o->out) {
        st = lab_write_calibration(lab, cal, c, rep, data, o->config, d.n, o->out, err,
                                   sizeof err);
        if (st != SUNMC_OK)
            fprintf(stderr, "sunmc calibrate: %s\n", err);
    }
    if (cal)
        lab->cal_free(cal);
    free(rep);
    lab_columns_free(&d);
    return cli_exit_code(st);
}

int cmd_calibrate(int argc, char **argv)
{
    char help[LAB_HELP_MAX];
    lab_help(1, help, sizeof help);
    if (cli_wants_help(argc, argv, help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "calibrate", "sensor config set out quiet duplicates FILES1", &o);
    if (rc)
        return rc;
    char names[256];
    lab_family_names(names, sizeof names);
    if (!o.config || o.n_positional != 1) {
        fprintf(stderr, "sunmc calibrate: needs --config CONFIG and one data file (see sunmc "
                        "calibrate --help)\n");
        return EXIT_BAD_INPUT;
    }
    const sensor_family *fam = o.sensor ? sensor_family_find(o.sensor) : NULL;
    if (o.sensor && (!fam || !fam->lab)) {
        char hint[SUGGEST_NAME_MAX + 32];
        suggest_hint(o.sensor, names, hint, sizeof hint);
        fprintf(stderr, "sunmc calibrate: --sensor must be %s, not '%s'%s\n", names, o.sensor,
                hint);
        return EXIT_BAD_INPUT;
    }
    char derr[SUNMC_ERRLEN];
    if (duplicates_mode(&o, derr, sizeof derr) < 0) {
        fprintf(stderr, "sunmc calibrate: %s\n", derr);
        return EXIT_BAD_INPUT;
    }
    config_state st;
    if ((rc = cli_config(&o, &st)))
        return rc;
    if (fam && st.cfg.family != fam) {
        fprintf(stderr, "sunmc calibrate: --sensor %s, but %s is a %s config (sensor.family)\n",
                o.sensor, o.config, st.cfg.family->name);
        config_state_free(&st);
        return EXIT_BAD_INPUT;
    }
    fam = st.cfg.family;
    if (!fam->lab) {
        fprintf(stderr, "sunmc calibrate: %s is a %s config: that family has no lab commands "
                        "(%s have)\n", o.config, fam->name, names);
        config_state_free(&st);
        return EXIT_BAD_INPUT;
    }
    rc = calibrate(&o, &st, fam->lab);
    config_state_free(&st);
    return rc;
}

/* ---- compensate ---- */

/* What compensate achieved against the truth columns, on stderr. */
static void accuracy_print(const lab_accuracy *a, const sensor_family *fam, const char *config)
{
    fprintf(stderr, "sunmc compensate: accuracy against %s%s%s: %ld rows, %ld without a "
                    "compensated angle; %s, bands of %s",
            a->truth[0], a->n_comp > 1 ? ", " : "", a->n_comp > 1 ? a->truth[1] : "", a->rows,
            a->missing, a->unit, fam->band_name ? fam->band_name : "|angle|");
    if (a->have_spec)
        fprintf(stderr, "; spec %s <= %g %s (%s)\n", lab_accuracy_stat_name(a), a->spec, a->unit,
                config);
    else
        fprintf(stderr, " (one band over the data: --config CONFIG gives its bands and spec)\n");
    fprintf(stderr, "  angle  band           points         rms       p99.7         max%s\n",
            a->have_spec ? "  meets spec" : "");
    for (int k = 0; k < a->n_angles; k++)
        for (int b = 0; b < a->bands.n; b++) {
            char band[48];
            snprintf(band, sizeof band, "%g:%g", a->bands.lo[b], a->bands.hi[b]);
            char v[3][32]; /* "-" for a band without rows, never "nan" */
            const double x[3] = {a->rms[k][b], a->p997[k][b], a->max[k][b]};
            for (int j = 0; j < 3; j++)
                snprintf(v[j], sizeof v[j], x[j] == x[j] ? "%.4g" : "-", x[j]);
            fprintf(stderr, "  %-6s %-12s %8ld %11s %11s %11s%s%s\n", a->angle[k], band,
                    a->n[k][b], v[0], v[1], v[2], a->have_spec ? "  " : "",
                    a->have_spec ? lab_accuracy_meets(a, k, b) : "");
        }
}

/* "--onboard X: " before why the on-board form was refused. */
static void onboard_refused(char *err, size_t len, const char *onboard)
{
    char why[SUNMC_ERRLEN];
    snprintf(why, sizeof why, "%s", err);
    snprintf(err, len, "--onboard %.64s: %.400s", onboard, why);
}

static int compensate(const family_lab *lab, const sensor_family *fam, const params_file *pf,
                      const char *raw_path, const cli_options *o, const sunmc_config *c)
{
    char err[SUNMC_ERRLEN], warn[SUNMC_ERRLEN] = "";
    int n_comp = 0;
    while (lab->comp_columns[n_comp])
        n_comp++;
    lab_accuracy acc;
    int st = lab_accuracy_init(&acc, fam, c, n_comp, err, sizeof err);
    acc.required = o->out != NULL;
    out_set os;
    int began = 0;
    if (st == SUNMC_OK && o->out)
        began = (st = out_begin(&os, o->out, err, sizeof err)) == SUNMC_OK;
    void *model = st == SUNMC_OK ? malloc(lab->model_size) : NULL;
    if (st == SUNMC_OK)
        st = model ? lab_params_load(lab, pf, model, warn, sizeof warn, err, sizeof err)
                   : sunmc_fail(err, sizeof err, SUNMC_ENOMEM, "out of memory");
    if (warn[0])
        fprintf(stderr, "sunmc compensate: WARNING: %s\n", warn);
    lab_comp_stats cs;
    lab_onboard ob;
    lab_onboard_spec spec = {LAB_ONBOARD_DOUBLE, 0};
    if (o->onboard && st == SUNMC_OK)
        st = lab_onboard_parse(o->onboard, "--onboard", &spec, err, sizeof err);
    lab_onboard_init(&ob, lab, &spec);
    lab_onboard_wrap wrap;
    if (st == SUNMC_OK && spec.form != LAB_ONBOARD_DOUBLE &&
        (st = lab_onboard_prepare(&ob, model, err, sizeof err)) != SUNMC_OK)
        onboard_refused(err, sizeof err, o->onboard);
    lab_onboard_wrap_init(&wrap, &ob);
    int through = spec.form != LAB_ONBOARD_DOUBLE; /* double: the family's compensate itself */
    if (st == SUNMC_OK)
        st = lab_compensate_csv(through ? &wrap.lab : lab, through ? (void *)&wrap : model,
                                raw_path, stdout, &cs, &acc, err, sizeof err);
    lab_onboard_free(&ob);
    free(model);
    if (st == SUNMC_OK && acc.found)
        st = lab_accuracy_finish(&acc) == SUNMC_OK
                 ? SUNMC_OK
                 : sunmc_fail(err, sizeof err, SUNMC_ENOMEM, "out of memory for the accuracy");
    if (st == SUNMC_OK && began)
        st = lab_accuracy_save(&acc, &os, err, sizeof err);
    else if (began)
        out_abort(&os);
    if (st != SUNMC_OK) {
        lab_accuracy_free(&acc);
        fprintf(stderr, "sunmc compensate: %s\n", err);
        return cli_exit_code(st);
    }
    if (cs.failed) {
        char why[LAB_HELP_MAX];
        lab_comp_summary(&cs, why, sizeof why);
        fprintf(stderr, "sunmc compensate: %s:%d: %s (written '-': readings the calibrated "
                        "sensor cannot produce%s%s)\n",
                raw_path, cs.first_failed_line, why,
                cs.by_cause[LAB_NO_INVERSE] && lab->comp_fail_note ? "; no inverse: " : "",
                cs.by_cause[LAB_NO_INVERSE] && lab->comp_fail_note ? lab->comp_fail_note : "");
    }
    if (acc.found)
        accuracy_print(&acc, fam, o->config);
    lab_accuracy_free(&acc);
    return fflush(stdout) == 0 && !ferror(stdout) ? 0 : 1;
}

/* The optional --config (bands and spec of the accuracy summary) must be
 * the params.ini's family. */
static int compensate_with_config(const sensor_family *fam, const params_file *pf,
                                  const cli_options *o)
{
    if (!o->config) {
        if (o->n_sets) {
            fprintf(stderr, "sunmc compensate: --set needs --config CONFIG\n");
            return EXIT_BAD_INPUT;
        }
        return compensate(fam->lab, fam, pf, o->positional[1], o, NULL);
    }
    config_state st;
    int rc = cli_config(o, &st);
    if (rc)
        return rc;
    if (st.cfg.family != fam) {
        fprintf(stderr, "sunmc compensate: %s is a %s config, but %s was calibrated for the %s\n",
                o->config, st.cfg.family->name, o->positional[0], fam->name);
        config_state_free(&st);
        return EXIT_BAD_INPUT;
    }
    rc = compensate(fam->lab, fam, pf, o->positional[1], o, &st.cfg);
    config_state_free(&st);
    return rc;
}

int cmd_compensate(int argc, char **argv)
{
    char help[LAB_HELP_MAX];
    lab_help(0, help, sizeof help);
    if (cli_wants_help(argc, argv, help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "compensate", "config set out quiet onboard FILES2",
                        &o);
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
    const sensor_family *fam = sensor_family_find(sensor);
    if (fam && fam->lab)
        rc = compensate_with_config(fam, pf, &o);
    else {
        const params_entry *e = params_find(pf, "calibration", "sensor");
        fprintf(stderr, "sunmc compensate: %s:%d: sensor '%s' is not available\n",
                o.positional[0], e->line, sensor);
        rc = EXIT_BAD_INPUT;
    }
    free(pf);
    return rc;
}
