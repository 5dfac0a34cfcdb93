/* cmd_run.c - `sunmc run` (the Monte Carlo and Table 1) and `sunmc config`. */
#include "cli.h"
#include "montecarlo.h"
#include "output.h"
#include "report.h"
#include "runner.h"
#include "status.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

static const char run_help[] =
    "usage: sunmc run CONFIG [--units N|FIRST:END] [--seed S] [--threads T]\n"
    "                 [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet] [--profile]\n"
    "                 [--until STAT:HALFWIDTH] [--shard K/N]\n"
    "Simulates each unit's tolerances, its turntable calibration campaign and fit, validates\n"
    "it on a grid it was not calibrated on, and prints Table 1 (ESS paper) per band.\n"
    "--out DIR writes summary.tsv, units.tsv, config.ini, manifest.ini and units.bin (the\n"
    "per-unit results at full precision, for `sunmc merge`), all or nothing.\n"
    "--shard K/N runs the K-th (0..N-1) of N near-equal parts of the units, for merge.\n"
    "--until STAT:HALFWIDTH runs blocks of run.block_units units until the half-width of\n"
    "STAT's interval in the widest band is at most HALFWIDTH (STAT's unit; yield as a\n"
    "fraction) or --units N / run.units is reached; the result is that of a fixed run of\n"
    "the units it took.  STAT: yield, rms_after_mean, rms_before_mean, rms_after_sys_mean,\n"
    "rms_after_p95, improvement_mean.\n"
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

/* Stream units [first, end) of c through r with progress and timing on
 * stderr; prints an error and returns an exit code. */
static int stream_units(run_sink *r, long first, long end, int threads, int quiet, long *done)
{
    cli_progress prog;
    cli_progress_start(&prog, quiet);
    char err[SUNMC_ERRLEN];
    int st = run_stream(r, first, end, threads, cli_progress_update, &prog, done, err,
                        sizeof err);
    cli_progress_end(&prog, *done, threads);
    if (st != SUNMC_OK)
        fprintf(stderr, "sunmc: %s\n", err);
    return cli_exit_code(st);
}

int cli_monte_carlo(const sunmc_config *c, long first, long end, int threads, int quiet,
                    summary_row *rows)
{
    run_sink r;
    char err[SUNMC_ERRLEN];
    if (run_sink_init(&r, c, c->family, NULL, NULL, err, sizeof err) != SUNMC_OK) {
        fprintf(stderr, "sunmc: %s\n", err);
        return 1;
    }
    long done = 0;
    int rc = stream_units(&r, first, end, threads, quiet, &done);
    if (rc == 0)
        report_acc_rows(r.acc, rows);
    run_sink_free(&r);
    return rc;
}

/* `run --profile`: wall time per unit per thread and the phases' shares. */
static void print_profile(const double phase_s[UNIT_PHASES], long n, double wall_s, int threads)
{
    static const char *const names[UNIT_PHASES] = {"campaign", "fit", "validation"};
    double per_unit_ms = 1e3 * wall_s * threads / (double)(n > 0 ? n : 1);
    double phase_ms[UNIT_PHASES] = {0}, sum_ms = 0;
    for (int k = 0; k < UNIT_PHASES; k++)
        phase_ms[k] = 1e3 * phase_s[k] / (double)(n > 0 ? n : 1);
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

/* --shard K/N: the K-th of N near-equal parts of units 0..run.units-1
 * (--units N sets run.units); prints the error and returns an exit code. */
static int shard_range(const cli_options *o, const sunmc_config *c, long *first, long *end)
{
    if (o->end >= 0 || o->until) {
        fprintf(stderr, "sunmc run: --shard K/N splits run.units (--units N); it takes no "
                        "--units FIRST:END or --until\n");
        return EXIT_BAD_INPUT;
    }
    if (o->shard_n > c->units) {
        fprintf(stderr, "sunmc run: --shard %ld/%ld: more shards than the %ld units\n", o->shard_k,
                o->shard_n, c->units);
        return EXIT_BAD_INPUT;
    }
    *first = o->shard_k * c->units / o->shard_n;
    *end = (o->shard_k + 1) * c->units / o->shard_n;
    return 0;
}

/* --until STAT:HALFWIDTH into u; prints the error and returns an exit code. */
static int parse_until(const char *arg, const sunmc_config *c, long first, run_until *u)
{
    char name[64], list[256];
    const char *colon = strrchr(arg, ':');
    size_t n = colon ? (size_t)(colon - arg) : 0;
    char *end = NULL;
    double h = colon ? strtod(colon + 1, &end) : NAN;
    report_stat_list(list, sizeof list);
    if (!colon || n >= sizeof name || end == colon + 1 || *end != '\0' || !(h > 0) || !isfinite(h)) {
        fprintf(stderr, "sunmc run: --until %s: needs STAT:HALFWIDTH with HALFWIDTH > 0, e.g. "
                        "yield:0.005 (STAT one of %s)\n", arg, list);
        return EXIT_BAD_INPUT;
    }
    memcpy(name, arg, n);
    name[n] = '\0';
    if (first != 0) {
        fprintf(stderr, "sunmc run: --until runs units from 0: give its most units as --units N, "
                        "not FIRST:END\n");
        return EXIT_BAD_INPUT;
    }
    memset(u, 0, sizeof *u);
    u->stat = report_stat_find(name);
    u->halfwidth = h;
    u->band = report_widest_band(c);
    u->reached = NAN;
    if (u->stat < 0) {
        fprintf(stderr, "sunmc run: --until %s: unknown statistic '%s' (one of %s)\n", arg, name,
                list);
        return EXIT_BAD_INPUT;
    }
    return 0;
}

/* The line saying whether --until met its target and after how many units;
 * also the note in config.ini. */
static void until_line(char *buf, size_t len, const char *arg, const run_until *u,
                       const sunmc_config *c, long done)
{
    char band[32];
    report_band_label(c, u->band, band, sizeof band);
    if (u->met)
        snprintf(buf, len, "--until %s: met after %ld units (half-width %.3g in band %s)", arg,
                 done, u->reached, band);
    else
        snprintf(buf, len, "--until %s: NOT met: half-width %.3g in band %s after all %ld units "
                 "(--units N or run.units); run more units", arg, u->reached, band, done);
}

int cmd_run(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, run_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "run", "CONFIG units seed threads set out quiet profile until shard", &o);
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
    run_until until;
    if (o.until && (rc = parse_until(o.until, c, first, &until))) {
        config_state_free(&st);
        return rc;
    }
    if (o.shard_n > 0 && (rc = shard_range(&o, c, &first, &end))) {
        config_state_free(&st);
        return rc;
    }
    char err[SUNMC_ERRLEN];
    summary_row *rows = calloc((size_t)report_n_rows(c, fam), sizeof *rows);
    cli_run_files rf;
    run_sink r;
    int status = rows ? SUNMC_OK : sunmc_fail(err, sizeof err, SUNMC_ENOMEM, "out of memory");
    if (status == SUNMC_OK)
        status = cli_run_files_begin(&rf, o.out, err, sizeof err);
    if (status == SUNMC_OK && (status = run_sink_init(&r, c, fam, rf.f[RUN_FILE_UNITS],
                                                      rf.f[RUN_FILE_BIN], err, sizeof err)))
        cli_run_files_abort(&rf);
    if (status != SUNMC_OK) {
        fprintf(stderr, "sunmc run: %s\n", err);
        free(rows);
        config_state_free(&st);
        return cli_exit_code(status);
    }
    r.until = o.until ? &until : NULL;
    unit_profile_enable(o.profile);
    double t0 = unit_clock();
    long done = 0;
    rc = stream_units(&r, first, end, threads, o.quiet, &done);
    if (rc == 0) {
        char note[512] = "";
        report_acc_rows(r.acc, rows);
        if (o.profile)
            print_profile(r.phase_s, done, unit_clock() - t0, threads);
        /* Table 1 first: a failed write must not cost the result. */
        report_print_table(stdout, c, fam, rows);
        if (o.until) {
            note[0] = ';';
            note[1] = ' ';
            until_line(note + 2, sizeof note - 2, o.until, &until, c, done);
            printf("%s\n", note + 2);
        }
        fflush(stdout);
        if (rf.open) {
            run_manifest m;
            manifest_of(&st, first, first + done, &m);
            fprintf(rf.f[RUN_FILE_CONFIG], "# units %ld:%ld of this config%s\n", first,
                    first + done, note);
            config_write(rf.f[RUN_FILE_CONFIG], &st);
            if ((status = cli_run_files_commit(&rf, c, rows, &m, err, sizeof err)))
                fprintf(stderr, "sunmc run: %s: results not saved (Table 1 above)\n", err);
        }
        rc = cli_exit_code(status);
    } else {
        cli_run_files_abort(&rf);
    }
    run_sink_free(&r);
    free(rows);
    config_state_free(&st);
    return rc;
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
