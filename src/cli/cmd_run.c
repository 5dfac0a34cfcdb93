/* cmd_run.c - `sunmc run` (the Monte Carlo and Table 1) and `sunmc config`. */
#include "cli.h"
#include "h5out.h"
#include "summary_print.h"
#include "memory.h"
#include "montecarlo.h"
#include "output.h"
#include "ranks.h"
#include "report.h"
#include "checkpoint.h"
#include "runner.h"
#include "status.h"
#include "suggest.h"
#include "vmath.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char run_help[] =
    "usage: sunmc run CONFIG [--units N|FIRST:END] [--seed S] [--threads T]\n"
    "                 [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet] [--profile]\n"
    "                 [--until STAT:HALFWIDTH] [--shard K/N] [--resume] [--isa baseline|avx2]\n"
    "                 [--format tsv|hdf5]\n"
    "Simulates each unit's tolerances, its turntable calibration campaign and fit, validates\n"
    "it on a grid it was not calibrated on, and prints Table 1 (ESS paper) per band.\n"
    "--out DIR writes summary.tsv, units.tsv, config.ini, manifest.ini and units.bin (the\n"
    "per-unit results at full precision, for `sunmc merge`), all or nothing; with\n"
    "--format hdf5 also results.h5 (the units and summary tables as datasets, the config as\n"
    "attributes; docs/outputs.md).  Not with --shard (merge writes TSV only).\n"
    "--shard K/N runs the K-th (0..N-1) of N near-equal parts of the units, for merge.\n"
    "With --out, completed blocks are checkpointed beside DIR (.NAME.resume/); after an\n"
    "interruption (Ctrl-C, SIGTERM, kill -9, power cut) the same command with --resume\n"
    "runs the missing blocks only and ends with the files of an uninterrupted run; on a\n"
    "finished --until run it runs nothing and prints the result again (files untouched).\n"
    "While a run writes DIR, another command into DIR is refused (exit 2, its PID named).\n"
    "--until STAT:HALFWIDTH runs blocks of run.block_units units until the half-width of\n"
    "STAT's interval in the widest band is at most HALFWIDTH (STAT's unit; yield as a\n"
    "fraction) or --units N / run.units is reached; the result is that of a fixed run of\n"
    "the units it took.  STAT: yield, rms_after_mean, rms_before_mean, rms_after_sys_mean,\n"
    "rms_after_p95, improvement_mean.\n"
    "--profile prints on stderr the time per unit and its split (campaign, fit, validation).\n"
    "--isa baseline|avx2 (or SUNMC_ISA) runs only if the kernels take that path; manifest.ini\n"
    "records the path and the build, and merge and --resume refuse a mix of them.\n";

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

int cli_monte_carlo(const sunmc_config *c, long first, long end, int threads, cli_meter *m,
                    summary_row *rows)
{
    run_sink r;
    char err[SUNMC_ERRLEN];
    int st = memory_check_run(c, first, end, threads, 0, 0, err, sizeof err);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc: %s\n", err);
        return cli_exit_code(st);
    }
    if (run_sink_init(&r, c, NULL, NULL, err, sizeof err) != SUNMC_OK) {
        fprintf(stderr, "sunmc: %s\n", err);
        return 1;
    }
    long done = 0;
    st = run_stream(&r, first, end, threads, cli_meter_units, m, &done, err, sizeof err);
    if (st != SUNMC_OK)
        fprintf(stderr, "sunmc: %s\n", err);
    int rc = cli_exit_code(st);
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

void cli_shard_units(long k, long n, long units, long *first, long *end)
{
    *first = k * units / n;
    *end = (k + 1) * units / n;
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
    cli_shard_units(o->shard_k, o->shard_n, c->units, first, end);
    return 0;
}

/* --until STAT:HALFWIDTH into u; prints the error and returns an exit code. */
static int parse_until(const char *arg, const sunmc_config *c, long first, run_until *u)
{
    char name[64], list[256];
    double h;
    report_stat_list(list, sizeof list);
    if (!cli_split_until(arg, name, sizeof name, &h)) {
        fprintf(stderr, "sunmc run: --until %s: needs STAT:HALFWIDTH with HALFWIDTH a decimal "
                        "number > 0, e.g. yield:0.005 (STAT one of %s)\n", arg, list);
        return EXIT_BAD_INPUT;
    }
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
        char hint[SUGGEST_NAME_MAX + 32];
        suggest_hint(name, list, hint, sizeof hint);
        fprintf(stderr, "sunmc run: --until %s: unknown statistic '%s'%s (one of %s)\n", arg,
                name, hint, list);
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

/* One `sunmc run`: its options, config, unit range, files and checkpoint. */
typedef struct {
    cli_options o;
    config_state st;
    long first, end;
    int threads;
    run_until until;
    summary_row *rows;
    cli_run_files rf;
    run_sink r;
    checkpoint ckpt;
    int has_ckpt;
    long replayed;          /* units taken from the checkpoint */
    char resume_cmd[1536];  /* the command that finishes this run */
} run_job;

/* --isa (else $SUNMC_ISA): the kernel path this run must take.  baseline
 * was forced before main (main.c runs sunmc-baseline); a path this binary
 * cannot run here (avx2 on a CPU or build without it) is refused, never
 * run silently. */
static int check_isa(const char *want)
{
    const char *env = getenv("SUNMC_ISA");
    const char *how = want ? "--isa" : "SUNMC_ISA";
    if (!want)
        want = env && env[0] ? env : NULL;
    if (!want)
        return 0;
    if (strcmp(want, "baseline") != 0 && strcmp(want, "avx2") != 0) {
        char hint[SUGGEST_NAME_MAX + 32];
        suggest_hint(want, "baseline avx2", hint, sizeof hint);
        fprintf(stderr, "sunmc run: %s %s: one of baseline, avx2%s\n", how, want, hint);
        return EXIT_BAD_INPUT;
    }
    if (strcmp(want, vm_isa()) == 0)
        return 0;
    fprintf(stderr,
            "sunmc run: %s %s: this binary on this CPU runs the %s kernels (chosen when it "
            "loaded); %s\n",
            how, want, vm_isa(),
            strcmp(want, "baseline") == 0
                ? "run sunmc-baseline (built and installed beside sunmc)"
                : "this CPU or build has no AVX2 path: run on an x86-64-v3 node with sunmc "
                  "(not sunmc-baseline)");
    return EXIT_BAD_INPUT;
}

/* --format tsv|hdf5.  hdf5 writes DIR/results.h5 beside the TSV files, so
 * it needs --out and the HDF5 library (h5out_load); a shard is refused: shards are joined by `sunmc merge`,
 * which reads units.bin and writes TSV only (run the whole, or convert
 * nothing half-way). */
static int check_format(const cli_options *o)
{
    const char *f = o->format;
    if (!f || strcmp(f, "tsv") == 0)
        return 0;
    if (strcmp(f, "hdf5") != 0) {
        char hint[SUGGEST_NAME_MAX + 32];
        suggest_hint(f, "tsv hdf5", hint, sizeof hint);
        fprintf(stderr, "sunmc run: --format %s: one of tsv, hdf5%s\n", f, hint);
        return EXIT_BAD_INPUT;
    }
    if (!o->out) {
        fprintf(stderr, "sunmc run: --format hdf5 writes DIR/results.h5: it needs --out DIR\n");
        return EXIT_BAD_INPUT;
    }
    if (o->shard_n > 0) {
        fprintf(stderr, "sunmc run: --format hdf5 with --shard: shards are joined by `sunmc "
                        "merge`, which writes TSV only; run the shards without --format hdf5\n");
        return EXIT_BAD_INPUT;
    }
    /* the library is loaded now, so a machine without it refuses the run
     * before any unit (exit 2, nothing written) */
    char err[SUNMC_ERRLEN];
    if (h5out_load(err, sizeof err) != SUNMC_OK) {
        fprintf(stderr, "sunmc run: %s\n", err);
        return EXIT_BAD_INPUT;
    }
    return 0;
}

/* Options, config, unit range and --until; prints errors, returns an exit code. */
static int job_setup(run_job *j, int argc, char **argv)
{
    int rc = cli_parse(argc, argv, 2, "run",
                       "CONFIG units seed threads set out quiet profile until shard resume isa "
                       "format",
                       &j->o);
    if (rc)
        return rc;
    cli_resume_command(argc, argv, j->resume_cmd, sizeof j->resume_cmd);
    if ((rc = check_isa(j->o.isa)) || (rc = check_format(&j->o)))
        return rc;
    if (j->o.resume && !j->o.out) {
        fprintf(stderr, "sunmc run: --resume needs the --out DIR of the interrupted run\n");
        return EXIT_BAD_INPUT;
    }
    if ((rc = cli_config(&j->o, &j->st)))
        return rc;
    const sunmc_config *c = &j->st.cfg;
    j->first = j->o.end >= 0 ? j->o.first : 0;
    j->end = j->o.end >= 0 ? j->o.end : c->units;
    j->threads = cli_threads(&j->o, c);
    if (ranks_rank() != 0) { /* under mpirun: rank 0 alone prints and writes */
        j->o.out = NULL;
        j->o.quiet = 1;
        j->o.profile = 0;
    }
    if (j->o.until && (rc = parse_until(j->o.until, c, j->first, &j->until)))
        return rc;
    if (j->o.shard_n > 0 && (rc = shard_range(&j->o, c, &j->first, &j->end)))
        return rc;
    /* Before any work: what the run would need must fit in memory. */
    char err[SUNMC_ERRLEN];
    int st = memory_check_run(c, j->first, j->end, j->threads, 0, 0, err, sizeof err);
    if (st != SUNMC_OK) {
        fprintf(stderr, "sunmc run: %s\n", err);
        return cli_exit_code(st);
    }
    return 0;
}

/* --resume without a checkpoint: a finished run in out must be of this
 * run (same config, seed, build), else it would be replaced by another
 * one without a word. */
static int finished_same_run(const char *out, const run_manifest *m, char *err, size_t errlen)
{
    char path[PATH_MAX], e2[SUNMC_ERRLEN];
    run_manifest old;
    if (snprintf(path, sizeof path, "%s/%s", out, MANIFEST_NAME) >= (int)sizeof path ||
        access(path, F_OK) != 0 || manifest_read(path, &old, e2, sizeof e2) != SUNMC_OK)
        return SUNMC_OK;
    int st = manifest_compatible(&old, path, m, "this run", e2, sizeof e2);
    if (st == SUNMC_OK && (old.first != m->first || old.end != m->end)) {
        snprintf(e2, sizeof e2, "%.300s holds units %ld:%ld, this run %ld:%ld", path, old.first,
                 old.end, m->first, m->end);
        st = SUNMC_EINPUT;
    }
    if (st == SUNMC_OK)
        return SUNMC_OK;
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "--resume: %s holds a finished run, not this one (%s); drop --resume to "
                      "replace it, or give the options of that run",
                      out, e2);
}

/* The checkpoint beside --out: resumed (--resume, same run) or new.  A
 * checkpoint of another run is refused on --resume; without --resume an
 * earlier one is discarded, saying so. */
static int job_checkpoint(run_job *j, char *err, size_t errlen)
{
    const sunmc_config *c = &j->st.cfg;
    run_manifest m;
    manifest_of(&j->st, j->first, j->end, &m);
    int found = 0, st = SUNMC_OK;
    if (j->o.resume) {
        st = checkpoint_open(&j->ckpt, j->o.out, &m, c->block_units, &j->r.layout, &found, err,
                             errlen);
        if (st != SUNMC_OK)
            return st;
        if (!found && (st = finished_same_run(j->o.out, &m, err, errlen)) != SUNMC_OK)
            return st;
        if (!found && !j->o.quiet)
            fprintf(stderr, "sunmc run: --resume: no checkpoint of %s; running every unit\n",
                    j->o.out);
        else if (!j->o.quiet)
            fprintf(stderr, "sunmc run: resuming %s: %ld of units %ld:%ld done\n", j->o.out,
                    j->ckpt.done, j->first, j->end);
    }
    if (!found) {
        long old;
        checkpoint_remove(j->o.out, &old);
        if (old >= 0)
            fprintf(stderr, "sunmc run: discarded the checkpoint of an interrupted run into %s "
                            "(%ld units; --resume continues one)\n", j->o.out, old);
        st = checkpoint_create(&j->ckpt, j->o.out, &m, c->block_units, &j->r.layout, err, errlen);
    }
    j->has_ckpt = st == SUNMC_OK;
    if (j->has_ckpt) {
        char note[OUT_NOTE_MAX];
        snprintf(note, sizeof note,
                 "\nsunmc run: interrupted: %s is as it was; kept: every completed block of "
                 "units, checkpointed in %s; this finishes the run without running them "
                 "again:\n  %s\n",
                 j->o.out, j->ckpt.dir, j->resume_cmd);
        out_signal_note(note);
    }
    return st;
}

/* Rows, files, the streaming sink and the checkpoint. */
static int job_open(run_job *j, char *err, size_t errlen)
{
    const sunmc_config *c = &j->st.cfg;
    j->rows = calloc((size_t)report_n_rows(c), sizeof *j->rows);
    if (!j->rows)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    int st = cli_run_files_begin(&j->rf, j->o.out, err, errlen);
    if (st != SUNMC_OK)
        return st;
    j->rf.hdf5 = j->o.format && strcmp(j->o.format, "hdf5") == 0;
    st = run_sink_init(&j->r, c, j->rf.f[RUN_FILE_UNITS], j->rf.f[RUN_FILE_BIN], err,
                       errlen);
    if (st == SUNMC_OK && j->o.out && (st = job_checkpoint(j, err, errlen)) != SUNMC_OK)
        run_sink_free(&j->r);
    if (st != SUNMC_OK)
        cli_run_files_abort(&j->rf);
    j->r.until = j->o.until ? &j->until : NULL;
    return st;
}

/* The checkpoint's units replayed, then the rest run (each block
 * checkpointed); *done = all units handed to the sink. */
static int job_execute(run_job *j, long *done)
{
    char err[SUNMC_ERRLEN];
    long streamed = 0;
    int stop = 0;
    if (j->has_ckpt && j->ckpt.done > 0) {
        char path[PATH_MAX + 16];
        checkpoint_units_path(&j->ckpt, path, sizeof path);
        int st = run_replay(&j->r, path, j->first, j->first + j->ckpt.done, &j->replayed, err,
                            sizeof err);
        if (st != SUNMC_OK) {
            fprintf(stderr, "sunmc run: --resume: %s\n", err);
            return cli_exit_code(st);
        }
        stop = j->r.until && j->r.until->met;
    }
    /* Under mpirun every rank starts where rank 0's checkpoint ends. */
    long start = j->first + j->replayed, go = !stop;
    if (ranks_bcast_long(&start) != SUNMC_OK || ranks_bcast_long(&go) != SUNMC_OK)
        return 1;
    j->r.ckpt = j->has_ckpt ? &j->ckpt : NULL;
    j->r.distribute = 1;
    int rc = go ? stream_units(&j->r, start, j->end, j->threads, j->o.quiet, &streamed) : 0;
    *done = j->replayed + streamed;
    if (j->r.ckpt_status != SUNMC_OK)
        fprintf(stderr, "sunmc run: checkpointing stopped (the run went on): %s\n",
                j->r.ckpt_err);
    return rc;
}

/* Table 1 of the j->r's units (done of them), the units line and the
 * --until line (also into note, "; ..." for config.ini, when given). */
static void job_print(run_job *j, long done, char *note, size_t len)
{
    const sunmc_config *c = &j->st.cfg;
    report_acc_rows(j->r.acc, j->rows);
    summary_print(stdout, c, j->rows);
    if (j->first != 0 || j->end != c->units)
        printf("units %ld:%ld of the run of %ld units (run.units): `sunmc merge` joins the "
               "shards of a run\n",
               j->first, j->first + done, c->units);
    if (j->o.until && len > 2) {
        note[0] = ';';
        note[1] = ' ';
        until_line(note + 2, len - 2, j->o.until, &j->until, c, done);
        printf("%s\n", note + 2);
    }
    fflush(stdout);
}

/* Table 1 and the --until line, then the files; the checkpoint is
 * removed once they are complete. */
static int job_finish(run_job *j, long done, double wall_s)
{
    const sunmc_config *c = &j->st.cfg;
    char note[512] = "", err[SUNMC_ERRLEN];
    if (j->o.profile)
        print_profile(j->r.phase_s, done, wall_s, j->threads);
    /* Table 1 first: a failed write must not cost the result. */
    job_print(j, done, note, sizeof note);
    if (!j->rf.open)
        return 0;
    run_manifest m;
    manifest_of(&j->st, j->first, j->first + done, &m);
    run_sink_sums(&j->r, &m);
    fprintf(j->rf.f[RUN_FILE_CONFIG], "# units %ld:%ld of this config%s\n", j->first,
            j->first + done, note);
    config_write(j->rf.f[RUN_FILE_CONFIG], &j->st);
    int status = cli_run_files_commit(&j->rf, c, j->rows, &m, err, sizeof err);
    if (status != SUNMC_OK) {
        fprintf(stderr, "sunmc run: %s: results not saved (Table 1 above)\n", err);
        if (j->has_ckpt && j->ckpt.done > 0) {
            fprintf(stderr, "sunmc run: kept: %ld units checkpointed in %s; once there is room, "
                            "this writes them without running them again:\n  %s\n",
                    j->ckpt.done, j->ckpt.dir, j->resume_cmd);
        } else if (j->has_ckpt) { /* its first block was not written either */
            checkpoint_close(&j->ckpt);
            checkpoint_remove(j->o.out, NULL);
            j->has_ckpt = 0;
            fprintf(stderr, "sunmc run: nothing kept (no unit was checkpointed); once there is "
                            "room, run the command again\n");
        }
        return cli_exit_code(status);
    }
    checkpoint_close(&j->ckpt);
    checkpoint_remove(j->o.out, NULL);
    j->has_ckpt = 0;
    return 0;
}

/* 1 when out holds the run j would make with --until, finished: the same
 * config, seed and build, units from j->first, and the target met after
 * exactly those units (or not met after all of --units N).  Replays its
 * units.bin (checksums checked) into j->r, files untouched. */
static int finished_until_run(run_job *j, const char *man, long *done)
{
    char bin[PATH_MAX], err[SUNMC_ERRLEN];
    run_manifest old, m;
    manifest_of(&j->st, j->first, j->end, &m);
    if (manifest_read(man, &old, err, sizeof err) != SUNMC_OK ||
        manifest_compatible(&old, man, &m, "this run", err, sizeof err) != SUNMC_OK ||
        old.first != j->first || old.end > j->end ||
        snprintf(bin, sizeof bin, "%s/%s", j->o.out, UNITFILE_NAME) >= (int)sizeof bin ||
        run_sink_init(&j->r, &j->st.cfg, NULL, NULL, err, sizeof err) != SUNMC_OK)
        return 0;
    j->r.until = &j->until;
    long n = old.end - old.first;
    int same = unitsum_verify(bin, &j->r.layout, old.first, old.end, UNITSUM_LEAF_UNITS,
                              old.sum_units, old.sum, old.nsum, man, err, sizeof err) == SUNMC_OK &&
               run_replay(&j->r, bin, old.first, old.end, done, err, sizeof err) == SUNMC_OK &&
               *done == n && (j->until.met || old.end == j->end);
    if (!same)
        run_sink_free(&j->r);
    return same;
}

/* `run --until ... --resume` once its run has finished (a requeued cluster
 * task): nothing to run, its result is printed again from --out's files,
 * which stay as they are, byte for byte.  *finished = 1 then.  Any other
 * case (a checkpoint, another run) is left to job_checkpoint. */
static int job_finished_until(run_job *j, int *finished)
{
    char man[PATH_MAX], ck[PATH_MAX];
    long done = 0;
    *finished = 0;
    if (!j->o.resume || !j->o.until || !j->o.out ||
        checkpoint_path(j->o.out, ck, sizeof ck) != SUNMC_OK || access(ck, F_OK) == 0 ||
        snprintf(man, sizeof man, "%s/%s", j->o.out, MANIFEST_NAME) >= (int)sizeof man ||
        access(man, F_OK) != 0 || !finished_until_run(j, man, &done))
        return 0;
    *finished = 1;
    j->rows = calloc((size_t)report_n_rows(&j->st.cfg), sizeof *j->rows);
    if (!j->rows) {
        run_sink_free(&j->r);
        fprintf(stderr, "sunmc run: out of memory\n");
        return 1;
    }
    if (!j->o.quiet)
        fprintf(stderr, "sunmc run: --resume: %s holds this run, finished (units %ld:%ld); "
                        "nothing to run, its files are as they were\n",
                j->o.out, j->first, j->first + done);
    char note[512];
    job_print(j, done, note, sizeof note);
    run_sink_free(&j->r);
    return 0;
}

int cmd_run(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, run_help))
        return 0;
    run_job *j = calloc(1, sizeof *j);
    if (!j)
        return 1;
    char err[SUNMC_ERRLEN];
    int rc = job_setup(j, argc, argv), opened = 0, setup_ok = rc == 0, finished = 0;
    if (setup_ok)
        rc = job_finished_until(j, &finished);
    /* under mpirun rank 0 alone reads --out: the others follow its word */
    long all_finished = finished;
    if (setup_ok && ranks_bcast_long(&all_finished) == SUNMC_OK && all_finished)
        setup_ok = 0;
    if (setup_ok) {
        int st = job_open(j, err, sizeof err);
        if (st != SUNMC_OK)
            fprintf(stderr, "sunmc run: %s\n", err);
        rc = cli_exit_code(st);
        opened = st == SUNMC_OK;
    }
    /* Every rank reads the same input, so a bad one stops them all; rank 0
     * alone opens the files, and its failure must stop the others. */
    long all_open = opened;
    if (setup_ok && ranks_bcast_long(&all_open) == SUNMC_OK && !all_open && opened) {
        rc = 1;
        cli_run_files_abort(&j->rf);
        run_sink_free(&j->r);
        opened = 0;
    }
    if (opened) {
        unit_profile_enable(j->o.profile);
        double t0 = unit_clock();
        long done = 0;
        rc = job_execute(j, &done);
        if (rc == 0 && ranks_rank() == 0)
            rc = job_finish(j, done, unit_clock() - t0);
        else
            cli_run_files_abort(&j->rf);
        checkpoint_close(&j->ckpt);
        run_sink_free(&j->r);
    }
    free(j->rows);
    if (j->st.keys)
        config_state_free(&j->st);
    free(j);
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
