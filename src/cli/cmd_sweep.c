/* cmd_sweep.c - `sunmc sweep`: the Monte Carlo at every point of one or two
 * varied config keys, same seed everywhere (common random numbers). */
#include "cli.h"
#include "verdict.h"
#include "montecarlo.h"
#include "output.h"
#include "report.h"
#include "status.h"
#include "sweep.h"
#include "table.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char sweep_help[] =
    "usage: sunmc sweep CONFIG --vary SECTION.KEY=VALUES [--vary ...]\n"
    "                   [--units N|FIRST:END] [--seed S] [--threads T]\n"
    "                   [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet]\n"
    "Runs the Monte Carlo at every point of one axis, or of the full grid of two, with the\n"
    "same seed at every point (common random numbers: tolerance draws do not change with\n"
    "campaign keys), and prints one row per point and band.  VALUES is\n"
    "  --vary campaign.alpha_step_deg=1,0.5,0.3,0.25,0.2    a list (number keys)\n"
    "  --vary design.H_mm=3:8:0.5                           a range, STOP included\n"
    "  --vary 'campaign.beta_deg=-20,0,20|-30,0,30|-30,-10,10,30'\n"
    "                                                       alternatives separated by '|',\n"
    "        each written as in a config file: any key (lists, choices, numbers) but\n"
    "        sensor.family and report.bands_deg; quote the argument for the shell\n"
    "--out DIR writes sweep.tsv and config.ini (the base config), all or nothing.  sweep.tsv:\n"
    "the varied values (one column per key), `label` (the point's values joined by \"; \",\n"
    "for plot labels), `aliased` (1 when the point's campaign could not resolve the\n"
    "family's aliasing term, e.g. the ESS fine-code term), then the summary.tsv columns.\n";

/* Build point p's config: file + --set, then the point's values. */
static int point_config(const cli_options *o, const sweep_axis *axes, int n_axes, long p,
                        config_state *st)
{
    char err[SUNMC_ERRLEN];
    int s = config_build(st, o->config, o->sets, o->n_sets, err, sizeof err);
    if (s == SUNMC_OK) {
        s = sweep_apply(st, axes, n_axes, p, err, sizeof err);
        if (s != SUNMC_OK)
            config_state_free(st);
    }
    if (s != SUNMC_OK)
        fprintf(stderr, "sunmc sweep: %s\n", err);
    return cli_exit_code(s);
}

static void print_table(const sunmc_config *c, const sensor_family *fam, const sweep_axis *axes,
                        int n_axes, long n_points, const summary_row *rows, int n_rows)
{
    const char *u = fam->rms_unit;
    int prec = report_decimals(fam);
    /* run.units / run.seed on an axis: the header says so, not the base's */
    int vary_units = 0, vary_seed = 0;
    for (int i = 0; i < n_axes; i++) {
        vary_units |= strcmp(axes[i].dotted, "run.units") == 0;
        vary_seed |= strcmp(axes[i].dotted, "run.seed") == 0;
    }
    char units[48], seed[48];
    if (vary_units)
        snprintf(units, sizeof units, "run.units per point");
    else
        snprintf(units, sizeof units, "%ld units each", rows[0].units);
    if (vary_seed)
        snprintf(seed, sizeof seed, "run.seed per point");
    else
        snprintf(seed, sizeof seed, "seed %ld", c->seed);
    printf("\n%s (%s): sweep of %ld points, %s, %s, spec %g arcsec\n", c->product, fam->name,
           n_points, units, seed, c->spec_arcsec);
    static const char *const heads[] = {"angle",   "band",       "before",     "after",
                                        "p95 after", "improve",  "band yield", "spec yield",
                                        "alias",   "failed",     "points",     "hours",
                                        ""};
    enum { N_HEADS = sizeof heads / sizeof *heads };
    table *t = table_new(n_axes + N_HEADS);
    if (!t)
        return;
    for (int i = 0; i < n_axes; i++)
        table_head(t, i, axes[i].dotted, "", TABLE_LEFT);
    for (int k = 0; k < N_HEADS; k++)
        table_head(t, n_axes + k, heads[k], "", k < 2 || k == N_HEADS - 1 ? TABLE_LEFT : 0);
    int extrapolated = 0, missing = 0;
    for (long p = 0; p < n_points; p++) {
        const char *v[SWEEP_MAX_AXES];
        sweep_point_text(axes, n_axes, p, v);
        for (int r = 0; r < n_rows; r++) {
            const summary_row *s = &rows[p * n_rows + r];
            int row = table_row(t);
            if (row < 0)
                break;
            for (int i = 0; i < n_axes; i++)
                table_set(t, row, i, "%s", v[i]);
            char *cell = table_cell(t, row, n_axes);
            snprintf(cell, TABLE_CELL, "%s", fam->angle_names[s->angle]);
            report_band_label(c, s->band, table_cell(t, row, n_axes + 1), TABLE_CELL);
            const double x[4] = {s->rms_before_mean, s->rms_after_mean, s->rms_after_p95,
                                 s->improvement_mean};
            for (int k = 0; k < 4; k++) {
                report_format_number(table_cell(t, row, n_axes + 2 + k), TABLE_CELL, x[k],
                                     k == 3 ? 2 : prec);
                missing |= !isfinite(x[k]);
            }
            table_set(t, row, n_axes + 6, "%.*f%%", report_percent_decimals(s->yield, 1),
                      100.0 * s->yield);
            table_set(t, row, n_axes + 7, "%.*f%%", report_percent_decimals(s->spec_yield, 1),
                      100.0 * s->spec_yield);
            table_set(t, row, n_axes + 8, "%ld", s->alias_units);
            table_set(t, row, n_axes + 9, "%ld", s->fit_failures);
            table_set(t, row, n_axes + 10, "%ld", s->campaign_points);
            table_set(t, row, n_axes + 11, "%.2f", s->campaign_hours);
            table_set(t, row, n_axes + 12, "%s", s->extrapolation_deg > 0 ? "*" : "");
            extrapolated |= s->extrapolation_deg > 0;
        }
    }
    table_print(stdout, t);
    table_free(t);
    char rule[256];
    verdict_rule_text(c, rule, sizeof rule);
    printf("band yield: the spec in the row's band alone; spec yield: %s (per angle)\n", rule);
    printf("mean RMS in %s", u);
    if (fam->alias_term)
        printf("; alias = units whose campaign could not resolve %s", fam->alias_term);
    printf("; points and turntable hours of the campaign\n");
    if (missing)
        printf("WARNING: - = no statistic: no unit of that point has a fit and a reading in "
               "the band (failed counts the units whose fit failed)\n");
    if (extrapolated)
        printf("WARNING: * = validation angles beyond the campaign's span: the calibration is "
               "extrapolated there (sweep.tsv: extrapolation_deg)\n");
}

/* sweep.tsv: the axes' values, label, aliased, then the summary columns. */
static void write_sweep_tsv(FILE *fs, const sunmc_config *c, const sensor_family *fam,
                            const sweep_axis *axes, int n_axes, long n_points,
                            const summary_row *rows, int n_rows)
{
    const char *lead[SWEEP_MAX_AXES + 2];
    for (int i = 0; i < n_axes; i++)
        lead[i] = axes[i].dotted;
    lead[n_axes] = "label";
    lead[n_axes + 1] = "aliased";
    report_write_summary_header(fs, n_axes + 2, lead);
    for (long p = 0; p < n_points; p++) {
        char label[SWEEP_LABEL_MAX];
        sweep_point_text(axes, n_axes, p, lead);
        sweep_point_label(axes, n_axes, p, label, sizeof label);
        lead[n_axes] = label;
        lead[n_axes + 1] = rows[p * n_rows].alias_units > 0 ? "1" : "0";
        report_write_summary_rows(fs, c, &rows[p * n_rows], n_axes + 2, lead);
    }
}

/* Parse the --vary axes against the base config; a message and non-zero
 * exit status for a bad one. */
static int parse_axes(const cli_options *o, const config_state *base, sweep_axis *axes)
{
    char err[SUNMC_ERRLEN];
    for (int i = 0; i < o->n_vary; i++) {
        int s = sweep_axis_parse(o->vary[i], base->cfg.family, &axes[i], err, sizeof err);
        if (s == SUNMC_OK && i == 1 && strcmp(axes[0].dotted, axes[1].dotted) == 0)
            s = sunmc_fail(err, sizeof err, SUNMC_EINPUT, "--vary %s: the same key twice",
                           o->vary[i]);
        if (s != SUNMC_OK) {
            fprintf(stderr, "sunmc sweep: %s\n", err);
            return cli_exit_code(s);
        }
    }
    return 0;
}

/* One point's Monte Carlo into its lab-shaped rows: the lab's, or with
 * operating temperatures the worst over them (report_primary_row). */
static int point_rows(const sunmc_config *c, long first, long end, int threads, cli_meter *m,
                      summary_row *rows)
{
    int n = report_n_rows(c), nb = c->bands_deg.n;
    summary_row *all = calloc((size_t)n, sizeof *all);
    if (!all) {
        fprintf(stderr, "sunmc sweep: out of memory\n");
        return 1;
    }
    int rc = cli_monte_carlo(c, first, end, threads, m, all);
    for (int i = 0; rc == 0 && i < report_n_lab_rows(c); i++)
        rows[i] = all[report_primary_row(c, i / nb, i % nb)];
    free(all);
    return rc;
}

/* Run every point's Monte Carlo into its rows (n_rows per point); the
 * command's exit status. */
static int run_points(const cli_options *o, const sweep_axis *axes, int n_axes, long n_points,
                      long units, summary_row *rows, int n_rows)
{
    cli_meter m;
    cli_meter_start(&m, "sweep", "units", n_points * units, o->quiet);
    int rc = 0;
    long base = 0; /* units of the points done (an axis may vary run.units) */
    for (long p = 0; p < n_points && rc == 0; p++) {
        config_state st;
        if ((rc = point_config(o, axes, n_axes, p, &st)))
            break;
        const sunmc_config *c = &st.cfg;
        long first = o->end >= 0 ? o->first : 0;
        long end = o->end >= 0 ? o->end : c->units;
        const char *v[SWEEP_MAX_AXES];
        char stage[METER_STAGE_MAX];
        sweep_point_text(axes, n_axes, p, v);
        int k = snprintf(stage, sizeof stage, "point %ld/%ld", p + 1, n_points);
        for (int i = 0; i < n_axes && k > 0 && (size_t)k < sizeof stage; i++)
            k += snprintf(stage + k, sizeof stage - (size_t)k, " %s=%s", axes[i].dotted, v[i]);
        cli_meter_stage(&m, stage, base);
        base += end - first;
        rc = point_rows(c, first, end, cli_threads(o, c), &m, &rows[p * n_rows]);
        config_state_free(&st);
    }
    cli_meter_end(&m);
    return rc;
}

/* sweep.tsv and config.ini into o->out, all or nothing. */
static int write_outputs(const cli_options *o, const config_state *base, const sweep_axis *axes,
                         int n_axes, long n_points, const summary_row *rows, int n_rows,
                         char *err, size_t errlen)
{
    const sunmc_config *c = &base->cfg;
    out_set os;
    FILE *fs, *fc;
    int status = out_begin(&os, o->out, err, errlen);
    if (status == SUNMC_OK)
        status = out_open(&os, "sweep.tsv", &fs, err, errlen);
    if (status == SUNMC_OK)
        status = out_open(&os, "config.ini", &fc, err, errlen);
    if (status != SUNMC_OK) {
        out_abort(&os);
        return status;
    }
    write_sweep_tsv(fs, c, c->family, axes, n_axes, n_points, rows, n_rows);
    fprintf(fc, "# base config of a sweep over");
    for (int i = 0; i < n_axes; i++)
        fprintf(fc, " %s", o->vary[i]);
    fputc('\n', fc);
    config_write(fc, base);
    return out_commit(&os, err, errlen);
}

int cmd_sweep(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, sweep_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "sweep", "CONFIG units seed threads set out quiet vary", &o);
    if (rc)
        return rc;
    if (o.n_vary == 0) {
        fprintf(stderr, "sunmc sweep: needs at least one --vary SECTION.KEY=VALUES "
                        "(see sunmc sweep --help)\n");
        return EXIT_BAD_INPUT;
    }
    config_state base;
    if ((rc = cli_config(&o, &base)))
        return rc;
    sweep_axis axes[SWEEP_MAX_AXES];
    if ((rc = parse_axes(&o, &base, axes))) {
        config_state_free(&base);
        return rc;
    }
    int n_axes = o.n_vary;
    long n_points = sweep_n_points(axes, n_axes);

    /* Every point is checked before any runs: a bad value fails at once. */
    for (long p = 0; p < n_points; p++) {
        config_state st;
        if ((rc = point_config(&o, axes, n_axes, p, &st))) {
            config_state_free(&base);
            return rc;
        }
        config_state_free(&st);
    }

    const sensor_family *fam = base.cfg.family;
    int n_rows = report_n_lab_rows(&base.cfg);
    summary_row *rows = calloc((size_t)(n_points * n_rows), sizeof *rows);
    if (!rows) {
        fprintf(stderr, "sunmc sweep: out of memory for %ld points\n", n_points);
        config_state_free(&base);
        return 1;
    }
    /* Per-point configs are kept only for the rows' writer (bands and
     * product come from the config; they cannot be varied). */
    long units = o.end >= 0 ? o.end - o.first : base.cfg.units;
    if ((rc = run_points(&o, axes, n_axes, n_points, units, rows, n_rows))) {
        free(rows);
        config_state_free(&base);
        return rc;
    }
    print_table(&base.cfg, fam, axes, n_axes, n_points, rows, n_rows); /* before writing */
    fflush(stdout);
    char err[SUNMC_ERRLEN];
    int status = o.out ? write_outputs(&o, &base, axes, n_axes, n_points, rows, n_rows, err,
                                       sizeof err)
                       : SUNMC_OK;
    if (status != SUNMC_OK)
        fprintf(stderr, "sunmc sweep: %s\n", err);
    free(rows);
    config_state_free(&base);
    return cli_exit_code(status);
}
