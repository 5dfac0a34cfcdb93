/* cli.c - option parsing, config building, progress and exit codes
 * shared by the commands. */
#include "cli.h"
#include "h5out.h"
#include "output.h"
#include "ranks.h"
#include "status.h"

#include <errno.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

/* Seconds between progress-line refreshes. */
#define PROGRESS_INTERVAL_S 0.25
/* Off a terminal: a line each time the run moves this many percent, or
 * after this many seconds (as the meters of progress.c). */
#define PROGRESS_LOG_STEP_PCT 10.0
#define PROGRESS_LOG_INTERVAL_S 30.0

void cli_print_keys(FILE *f, const sensor_family *fam)
{
    const config_key *keys[CONFIG_KEYS_MAX];
    const sensor_family *owners[CONFIG_KEYS_MAX];
    size_t n = config_list_keys(fam, keys, owners, CONFIG_KEYS_MAX);
    char choices[128];
    config_family_choices(choices, sizeof choices);
    fprintf(f,
            "config keys of the %s family, section by section (default, unit; --family %s\n"
            "for another family's; `sunmc config --reference` explains each):\n",
            fam->name, choices);
    const char *section = "";
    for (size_t i = 0; i < n; i++) {
        const config_key *k = keys[i];
        if (strcmp(k->section, section) != 0)
            fprintf(f, "  [%s]\n", section = k->section);
        fprintf(f, "    %s.%s = %s%s%s\n", k->section, k->name, config_key_default(k, fam),
                k->unit[0] ? "  " : "", k->unit);
    }
}

/* The family whose keys a help text lists: --family NAME, else the family
 * of a config file among the arguments, else the registry's first. */
static const sensor_family *help_family(int argc, char **argv)
{
    for (int i = 1; i + 1 < argc; i++)
        if (strcmp(argv[i], "--family") == 0)
            return sensor_family_find(argv[i + 1]);
    for (int i = 2; i < argc; i++) {
        if (argv[i][0] == '-' || access(argv[i], R_OK) != 0)
            continue;
        config_state st = {0};
        char err[SUNMC_ERRLEN];
        const sensor_family *fam = NULL;
        if (config_build(&st, argv[i], NULL, 0, err, sizeof err) == SUNMC_OK)
            fam = st.cfg.family;
        config_state_free(&st);
        if (fam)
            return fam;
    }
    return sensor_family_at(0);
}

int cli_help_keys(FILE *f, int argc, char **argv)
{
    const sensor_family *fam = help_family(argc, argv);
    if (!fam) {
        char choices[128];
        config_family_choices(choices, sizeof choices);
        fprintf(stderr, "sunmc: --family takes one of %s\n", choices);
        return EXIT_BAD_INPUT;
    }
    cli_print_keys(f, fam);
    return 0;
}

int cli_wants_help(int argc, char **argv, const char *text)
{
    for (int i = 2; i < argc; i++)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            fputs(text, stdout);
            for (int j = 2; j < argc; j++)
                if (strcmp(argv[j], "--family") == 0 ||
                    (argv[j][0] != '-' && access(argv[j], R_OK) == 0)) {
                    fputc('\n', stdout);
                    cli_help_keys(stdout, argc, argv);
                    break;
                }
            return 1;
        }
    return 0;
}

int cli_exit_code(int status)
{
    return status == SUNMC_OK ? 0 : status == SUNMC_EINPUT ? EXIT_BAD_INPUT : 1;
}

int cli_config(const cli_options *o, config_state *st)
{
    char err[SUNMC_ERRLEN];
    int s = config_build(st, o->config, o->sets, o->n_sets, err, sizeof err);
    if (s != SUNMC_OK) {
        fprintf(stderr, "sunmc: %s\n", err);
        return cli_exit_code(s);
    }
    return 0;
}

static double now_s(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (double)tv.tv_sec + 1e-6 * (double)tv.tv_usec;
}

void cli_progress_start(cli_progress *p, int quiet)
{
    p->t0 = now_s();
    p->last = 0;
    p->logged_pct = 0;
    p->logged_t = p->t0;
    p->tty = isatty(STDERR_FILENO);
    p->quiet = quiet;
}

void cli_progress_update(long done, long total, void *ctx)
{
    cli_progress *p = ctx;
    if (p->quiet)
        return;
    double t = now_s();
    if (t - p->last < PROGRESS_INTERVAL_S && done < total)
        return;
    /* Off a terminal (a batch log): a line per 10 % or 30 s. */
    double pct = total > 0 ? 100.0 * (double)done / (double)total : 0.0;
    if (!p->tty && pct - p->logged_pct < PROGRESS_LOG_STEP_PCT &&
        t - p->logged_t < PROGRESS_LOG_INTERVAL_S)
        return;
    p->last = t;
    char line[METER_STAGE_MAX + 128];
    cli_meter_line(line, sizeof line, "run", "units", done, total, t - p->t0, "");
    if (p->tty) {
        fprintf(stderr, "\r%s, %.0f units/s   ", line, done / fmax(t - p->t0, 1e-9));
    } else {
        fprintf(stderr, "%s, %.0f units/s\n", line, done / fmax(t - p->t0, 1e-9));
        p->logged_pct = floor(pct / PROGRESS_LOG_STEP_PCT) * PROGRESS_LOG_STEP_PCT;
        p->logged_t = t;
    }
    fflush(stderr);
}

double cli_progress_end(cli_progress *p, long units, int threads)
{
    double dt = now_s() - p->t0;
    if (!p->quiet) {
        if (p->tty)
            fprintf(stderr, "\r%100s\r", "");
        fprintf(stderr, "sunmc: %ld units in %.2f s (%.0f units/s, %d threads", units, dt,
                units / fmax(dt, 1e-9), threads);
        if (ranks_size() > 1)
            fprintf(stderr, " on each of %d MPI ranks", ranks_size());
        fprintf(stderr, ")\n");
    }
    return dt;
}

int cli_run_files_begin(cli_run_files *rf, const char *out, char *err, size_t errlen)
{
    static const char *const names[RUN_FILES] = {"summary.tsv", "units.tsv", "config.ini",
                                                 MANIFEST_NAME, UNITFILE_NAME};
    memset(rf, 0, sizeof *rf);
    if (!out)
        return SUNMC_OK;
    int status = out_begin(&rf->os, out, err, errlen);
    if (status == SUNMC_OK && (status = out_open_all(&rf->os, names, rf->f, RUN_FILES, err, errlen)))
        out_abort(&rf->os);
    rf->open = status == SUNMC_OK;
    return status;
}

/* --format hdf5: results.h5 in the set, from the tables just written (the
 * set lists it, so the marker names it; its stream stays unwritten). */
static int run_files_h5(cli_run_files *rf, const sunmc_config *c, const run_manifest *m,
                        char *err, size_t errlen)
{
    for (int k = 0; k < RUN_FILES; k++)
        if (fflush(rf->f[k]) != 0)
            return sunmc_fail(err, errlen, SUNMC_EIO, "%s: write error (%s)", rf->os.dir,
                              strerror(errno));
    FILE *hf;
    int st = out_open(&rf->os, H5OUT_NAME, &hf, err, errlen);
    if (st != SUNMC_OK)
        return st;
    char p[4][OUT_PATH_MAX + 32];
    static const char *const names[4] = {H5OUT_NAME, "units.tsv", "summary.tsv", "config.ini"};
    for (int k = 0; k < 4; k++)
        snprintf(p[k], sizeof p[k], "%s/%s", rf->os.tmpdir, names[k]);
    h5out_meta meta = {m->family, c->product, m->seed, c->units, m->first, m->end};
    st = h5out_write(p[0], p[1], p[2], p[3], &meta, err, errlen);
    if (st != SUNMC_OK) {
        char e2[SUNMC_ERRLEN];
        snprintf(e2, sizeof e2, "%s", err);
        return sunmc_fail(err, errlen, st, "%s/%s: %s", rf->os.dir, H5OUT_NAME, e2);
    }
    return SUNMC_OK;
}

int cli_run_files_commit(cli_run_files *rf, const sunmc_config *c, const summary_row *rows,
                         const run_manifest *m, char *err, size_t errlen)
{
    report_write_summary_header_of(rf->f[RUN_FILE_SUMMARY], c, 0, NULL);
    report_write_summary_rows(rf->f[RUN_FILE_SUMMARY], c, rows, 0, NULL);
    int st = manifest_write(rf->f[RUN_FILE_MANIFEST], m, err, errlen);
    if (st == SUNMC_OK && rf->hdf5)
        st = run_files_h5(rf, c, m, err, errlen);
    rf->open = 0;
    if (st != SUNMC_OK) {
        out_abort(&rf->os);
        return st;
    }
    return out_commit(&rf->os, err, errlen);
}

void cli_run_files_abort(cli_run_files *rf)
{
    if (rf->open)
        out_abort(&rf->os);
    rf->open = 0;
}

/* 1 when s needs quoting for a POSIX shell. */
static int needs_quotes(const char *s)
{
    if (!*s)
        return 1;
    for (; *s; s++)
        if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=./:,@%",
                     *s))
            return 1;
    return 0;
}

void cli_resume_command(int argc, char **argv, char *buf, size_t len)
{
    size_t used = (size_t)snprintf(buf, len, "sunmc");
    int has_resume = 0;
    for (int i = 1; i < argc && used < len; i++) {
        const char *a = argv[i];
        has_resume |= strcmp(a, "--resume") == 0;
        if (!needs_quotes(a)) {
            used += (size_t)snprintf(buf + used, len - used, " %s", a);
            continue;
        }
        used += (size_t)snprintf(buf + used, len - used, " '");
        for (; *a && used < len; a++)
            used += (size_t)(*a == '\'' ? snprintf(buf + used, len - used, "'\\''")
                                        : snprintf(buf + used, len - used, "%c", *a));
        if (used < len)
            used += (size_t)snprintf(buf + used, len - used, "'");
    }
    if (!has_resume && used < len)
        snprintf(buf + used, len - used, " --resume");
}
