/* cli.h - the command-line front end: the only code that prints to the
 * user and decides exit codes.  One file per command (src/cli/cmd_*.c). */
#ifndef SUNMC_CLI_H
#define SUNMC_CLI_H

#include "progress.h"
#include "output.h"
#include "registry.h"
#include "report.h"
#include "unitfile.h"

#include <stdio.h>

#define CLI_MAX_SETS 128
#define CLI_MAX_VARY 2
#define CLI_MAX_GIVEN 32

/* Exit codes. */
#define EXIT_BAD_INPUT 2

/* Options shared by the commands. */
typedef struct {
    const char *config;               /* positional CONFIG */
    const char *positional[4];        /* further positionals (data files) */
    int n_positional;
    const char *sets[CLI_MAX_SETS];   /* "section.key=value", in order */
    int n_sets;
    char set_buf[CLI_MAX_SETS][1024]; /* storage for sets made from options */
    long first, end;                  /* unit range; end < 0: from run.units */
    int threads;                      /* -1: from run.threads */
    const char *out;                  /* --out DIR */
    int quiet;
    int profile;                      /* run --profile: time split on stderr */
    int reference;                    /* config --reference */
    const char *vary[CLI_MAX_VARY];   /* sweep --vary */
    int n_vary;
    long unit;                        /* curve/simulate --unit */
    const char *only;                 /* curve --only KEY=VALUE */
    const char *sensor;               /* calibrate --sensor */
    const char *until;                /* run --until STAT:HALFWIDTH */
    long shard_k, shard_n;            /* run --shard K/N; shard_n = 0: none */
    int resume;                       /* run --resume */
    const char *isa;                  /* run --isa baseline|avx2 (else SUNMC_ISA) */
    const char *format;               /* run --format tsv|hdf5 (NULL: tsv) */
    const char *duplicates;           /* calibrate --duplicates average|refuse|keep */
    const char *onboard;              /* compensate --onboard double|float|table:STEP */
    const char *given[CLI_MAX_GIVEN]; /* options seen (their words in the allowed list) */
    int n_given;
    int units_given, seed_given;      /* --units N (not FIRST:END), --seed S */
} cli_options;

/* Parse argv[first..] for a command; allowed is a string of the options the
 * command takes ("units seed threads set out ..."), with CONFIG for a
 * required positional config file or CONFIG? for an optional one.  Prints
 * the error and returns EXIT_BAD_INPUT on bad usage, 0 otherwise. */
int cli_parse(int argc, char **argv, int first, const char *command, const char *allowed,
              cli_options *o);

/* Build the effective config from o (file + sets); prints and returns
 * EXIT_BAD_INPUT (or 1) on error. */
int cli_config(const cli_options *o, config_state *st);

/* Run the Monte Carlo of st over o's unit range and report; used by run. */
/* --shard K/N of `units` units: units [*first, *end), floor(K units / N)
 * to floor((K + 1) units / N); the N parts tile 0..units-1, their sizes
 * differ by at most one (0 <= K < N). */
void cli_shard_units(long k, long n, long units, long *first, long *end);

int cmd_run(int argc, char **argv);
int cmd_config(int argc, char **argv);
int cmd_sweep(int argc, char **argv);
int cmd_design(int argc, char **argv);
int cmd_budget(int argc, char **argv);
int cmd_allocate(int argc, char **argv);
int cmd_sensitivity(int argc, char **argv);
int cmd_curve(int argc, char **argv);
int cmd_simulate(int argc, char **argv);
int cmd_calibrate(int argc, char **argv);
int cmd_compensate(int argc, char **argv);
int cmd_export(int argc, char **argv);
int cmd_merge(int argc, char **argv);

/* Progress on stderr: a refreshed line on a terminal, else (a log) a line
 * per 10 % of the units or 30 s. */
typedef struct {
    double t0;
    double last; /* time of the last refresh */
    double logged_pct, logged_t; /* off a terminal: the last line's step and time */
    int tty;
    int quiet;
} cli_progress;
void cli_progress_start(cli_progress *p, int quiet);
void cli_progress_update(long done, long total, void *ctx);
double cli_progress_end(cli_progress *p, long units, int threads);

/* Run units [first, end) of c, its progress into meter m (progress.h), in
 * blocks (nothing held per unit but the statistics); fills rows
 * (report_n_rows of them).  Prints errors and returns an exit code. */
int cli_monte_carlo(const sunmc_config *c, long first, long end, int threads, cli_meter *m,
                    summary_row *rows);

/* The files of a run or a merge in --out DIR: units.tsv and units.bin are
 * written as the units stream by (run_sink), config.ini by the caller,
 * summary.tsv and manifest.ini at the commit.  Without --out nothing is
 * opened (every f NULL). */
enum { RUN_FILE_SUMMARY, RUN_FILE_UNITS, RUN_FILE_CONFIG, RUN_FILE_MANIFEST, RUN_FILE_BIN,
       RUN_FILES };
typedef struct {
    out_set os;
    FILE *f[RUN_FILES];
    int open;
    int hdf5; /* run --format hdf5: results.h5 as well, from the tables (h5out.h) */
} cli_run_files;
int cli_run_files_begin(cli_run_files *rf, const char *out, char *err, size_t errlen);
int cli_run_files_commit(cli_run_files *rf, const sunmc_config *c, const summary_row *rows,
                         const run_manifest *m, char *err, size_t errlen);
void cli_run_files_abort(cli_run_files *rf);

/* Threads to use: o->threads, else run.threads, else OpenMP's default. */
int cli_threads(const cli_options *o, const sunmc_config *c);

/* --until STAT:HALFWIDTH split at its last colon: STAT into name[len],
 * HALFWIDTH (finite, > 0) into *halfwidth.  1 when arg has that form, 0
 * otherwise (nothing written). */
int cli_split_until(const char *arg, char *name, size_t len, double *halfwidth);

/* Print fam's config keys section by section: key = default  unit. */
void cli_print_keys(FILE *f, const sensor_family *fam);

/* Print the keys of the family argv asks for (--family NAME, else a config
 * file's family, else the first registered); EXIT_BAD_INPUT for an unknown
 * family name, else 0. */
int cli_help_keys(FILE *f, int argc, char **argv);

/* Print text and return 1 when argv[2..] holds --help or -h; with
 * --family NAME or a config file also that family's config keys. */
int cli_wants_help(int argc, char **argv, const char *text);

/* The command line argv as a shell command ("sunmc run ... --resume"),
 * arguments quoted where needed, --resume added when missing: what a user
 * types to finish an interrupted run. */
void cli_resume_command(int argc, char **argv, char *buf, size_t len);

/* Exit status for a module status. */
int cli_exit_code(int status);

#endif
