/* cmd_run.c - `sunmc run` (the Monte Carlo and Table 1) and `sunmc config`. */
#include "cli.h"
#include "montecarlo.h"
#include "output.h"
#include "report.h"
#include "status.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

static const char run_help[] =
    "usage: sunmc run CONFIG [--units N|FIRST:END] [--seed S] [--threads T]\n"
    "                 [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet] [--profile]\n"
    "Simulates each unit's tolerances, its turntable calibration campaign and fit, validates\n"
    "it on a grid it was not calibrated on, and prints Table 1 (ESS paper) per band.\n"
    "--out DIR writes summary.tsv, units.tsv and config.ini (all or nothing).\n"
    "--profile prints on stderr the time per unit and its split (campaign, fit, validation).\n";

static const char config_help[] =
    "usage: sunmc config [CONFIG] [--set SECTION.KEY=VALUE]... [--reference]\n"
    "Prints the effective config (every key of the family, defaults filled in, origin of each\n"
    "value), or with --reference the commented reference config of every key.\n";

int cli_threads(const cli_options *o, const sunmc_config *c)
{
    if (o->threads > 0)
        return o->threads;
    if (c->threads > 0)
        return c->threads;
    return omp_get_max_threads();
}

int cli_monte_carlo(const sunmc_config *c, long first, long end, int threads, int quiet,
                    void **results_out, void **rows_out)
{
    const sensor_family *fam = c->family;
    long n = end - first;
    unit_result *results = calloc((size_t)n, sizeof *results);
    summary_row *rows = calloc((size_t)report_n_rows(c, fam), sizeof *rows);
    if (!results || !rows) {
        free(results);
        free(rows);
        fprintf(stderr, "sunmc: out of memory for %ld units\n", n);
        return 1;
    }
    cli_progress prog;
    cli_progress_start(&prog, quiet);
    char err[SUNMC_ERRLEN];
    int st = mc_run(c, fam, first, end, threads, results, cli_progress_update, &prog, err,
                    sizeof err);
    if (st == SUNMC_OK)
        st = report_summarize(c, fam, results, n, rows);
    cli_progress_end(&prog, n, threads);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc: %s\n", st == SUNMC_ENOMEM ? "out of memory" : err);
        free(results);
        free(rows);
        return cli_exit_code(st);
    }
    *results_out = results;
    *rows_out = rows;
    return 0;
}

/* `run --profile`: wall time per unit per thread and the phases' shares. */
static void print_profile(const unit_result *results, long n, double wall_s, int threads)
{
    static const char *const names[UNIT_PHASES] = {"campaign", "fit", "validation"};
    double per_unit_ms = 1e3 * wall_s * threads / (double)(n > 0 ? n : 1);
    double phase_ms[UNIT_PHASES] = {0}, sum_ms = 0;
    for (long u = 0; u < n; u++)
        for (int k = 0; k < UNIT_PHASES; k++)
            phase_ms[k] += 1e3 * results[u].phase_s[k] / (double)n;
    fprintf(stderr, "profile: %ld units, %d threads, %.3f s: %.3f ms per unit per thread\n"
                    "profile:", n, threads, wall_s, per_unit_ms);
    for (int k = 0; k < UNIT_PHASES; k++) {
        sum_ms += phase_ms[k];
        fprintf(stderr, " %s %.3f ms (%.0f%%)", names[k], phase_ms[k],
                100.0 * phase_ms[k] / per_unit_ms);
    }
    fprintf(stderr, " other %.3f ms (%.0f%%)\n", per_unit_ms - sum_ms,
            100.0 * (per_unit_ms - sum_ms) / per_unit_ms);
}

int cmd_run(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, run_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "run", "CONFIG units seed threads set out quiet profile", &o);
    if (rc)
        return rc;
    config_state st;
    if ((rc = cli_config(&o, &st)))
        return rc;
    const sunmc_config *c = &st.cfg;
    const sensor_family *fam = c->family;
    long first = o.end >= 0 ? o.first : 0;
    long end = o.end >= 0 ? o.end : c->units;
    int threads = cli_threads(&o, c);

    unit_result *results;
    summary_row *rows;
    unit_profile_enable(o.profile);
    double t0 = unit_clock();
    if ((rc = cli_monte_carlo(c, first, end, threads, o.quiet, (void **)&results, (void **)&rows))) {
        config_state_free(&st);
        return rc;
    }
    if (o.profile)
        print_profile(results, end - first, unit_clock() - t0, threads);

    /* Table 1 first: a failed write must not cost the result. */
    report_print_table(stdout, c, fam, rows);
    fflush(stdout);
    int status = SUNMC_OK;
    char err[SUNMC_ERRLEN];
    if (o.out) {
        out_set os;
        static const char *const names[3] = {"summary.tsv", "units.tsv", "config.ini"};
        FILE *f[3] = {NULL};
        status = out_begin(&os, o.out, err, sizeof err);
        if (status == SUNMC_OK)
            status = out_open_all(&os, names, f, 3, err, sizeof err);
        if (status == SUNMC_OK) {
            FILE *fs = f[0], *fu = f[1], *fc = f[2];
            report_write_summary_header(fs, 0, NULL);
            report_write_summary_rows(fs, c, fam, rows, 0, NULL);
            report_write_units(fu, c, fam, results, end - first);
            fprintf(fc, "# units %ld:%ld of this config\n", first, end);
            config_write(fc, &st);
            status = out_commit(&os, err, sizeof err);
        } else {
            out_abort(&os);
        }
    }
    if (status != SUNMC_OK)
        fprintf(stderr, "sunmc run: %s: results not saved (Table 1 above)\n", err);
    free(results);
    free(rows);
    config_state_free(&st);
    return cli_exit_code(status);
}

int cmd_config(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, config_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "config", "CONFIG? set reference", &o);
    if (rc)
        return rc;
    if (o.reference)
        return config_write_reference(stdout) == SUNMC_OK ? 0 : 1;
    config_state st;
    if ((rc = cli_config(&o, &st)))
        return rc;
    int s = config_write(stdout, &st);
    config_state_free(&st);
    return s == SUNMC_OK ? 0 : 1;
}
