/* progress.h - one overall progress line for a long command (sweep,
 * budget, sensitivity, design): done/total units, percent and ETA.
 *
 * On a terminal (isatty(stderr)) the line is rewritten in place, at most
 * every PROGRESS_REFRESH_S; otherwise (a log, a pipe) one line per stage
 * is printed, never a carriage return -- but when stages are many (design
 * has hundreds) only the first, then one each PROGRESS_LOG_STEP_PCT of the
 * total or PROGRESS_LOG_S seconds, so a log stays short.  --quiet prints nothing.  The core
 * reports its stages and units through the callbacks it is given; only
 * this file prints them. */
#ifndef SUNMC_CLI_PROGRESS_H
#define SUNMC_CLI_PROGRESS_H

#include <stddef.h>

#define METER_STAGE_MAX 160

typedef struct {
    const char *cmd;          /* "sweep" */
    const char *what;         /* what total counts: "units" */
    double t0, last;          /* start, last refresh (s) */
    int tty, quiet, shown;    /* shown: length of the last line printed (0: none yet) */
    double logged_pct;        /* off a terminal: the last line's percent (its time: last) */
    long total, base, done;   /* all, done by finished stages, done now */
    char stage[METER_STAGE_MAX];
} cli_meter;

/* Seconds left at done of total after elapsed_s, at the rate so far; NaN
 * before the first unit is done or when total is not known (<= 0). */
double cli_eta_s(long done, long total, double elapsed_s);

/* "sunmc CMD: DONE/TOTAL WHAT (P%), ETA T: STAGE" into buf; the ETA as
 * "12 s", "3 min 05 s" or "1 h 02 min", "ETA -" before it is known. */
void cli_meter_line(char *buf, size_t len, const char *cmd, const char *what, long done,
                    long total, double elapsed_s, const char *stage);

/* Start a meter of total units (what they are: "units", "runs"). */
void cli_meter_start(cli_meter *m, const char *cmd, const char *what, long total, int quiet);
/* A stage begins with base of the total done: one line off a terminal. */
void cli_meter_stage(cli_meter *m, const char *stage, long base);
/* mc_progress_fn: done of the current stage's units (ctx: the meter). */
void cli_meter_units(long done, long total, void *ctx);
/* Clear the terminal line. */
void cli_meter_end(cli_meter *m);

#endif
