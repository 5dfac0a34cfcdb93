/* progress.c - the overall progress line of long commands (progress.h). */
#include "progress.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

/* Seconds between refreshes of the terminal line. */
#define PROGRESS_REFRESH_S 0.25
/* Off a terminal: a stage's line once the total has moved this many
 * percent, or this many seconds have passed, since the last line. */
#define PROGRESS_LOG_STEP_PCT 10.0
#define PROGRESS_LOG_S 30.0
#define SECONDS_PER_MINUTE 60.0
#define SECONDS_PER_HOUR 3600.0

static double meter_now_s(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (double)tv.tv_sec + 1e-6 * (double)tv.tv_usec;
}

double cli_eta_s(long done, long total, double elapsed_s)
{
    if (done <= 0 || total <= 0)
        return NAN;
    if (done >= total)
        return 0.0;
    return elapsed_s / (double)done * (double)(total - done);
}

static void format_eta(char *buf, size_t len, double s)
{
    if (!isfinite(s))
        snprintf(buf, len, "-");
    else if (s < SECONDS_PER_MINUTE)
        snprintf(buf, len, "%.0f s", s);
    else if (s < SECONDS_PER_HOUR)
        snprintf(buf, len, "%.0f min %02.0f s", floor(s / SECONDS_PER_MINUTE),
                 floor(fmod(s, SECONDS_PER_MINUTE)));
    else
        snprintf(buf, len, "%.0f h %02.0f min", floor(s / SECONDS_PER_HOUR),
                 floor(fmod(s, SECONDS_PER_HOUR) / SECONDS_PER_MINUTE));
}

void cli_meter_line(char *buf, size_t len, const char *cmd, const char *what, long done,
                    long total, double elapsed_s, const char *stage)
{
    char eta[32];
    format_eta(eta, sizeof eta, cli_eta_s(done, total, elapsed_s));
    double pct = total > 0 ? 100.0 * (double)done / (double)total : 0.0;
    snprintf(buf, len, "sunmc %s: %ld/%ld %s (%.0f%%), ETA %s%s%s", cmd, done, total, what, pct,
             eta, stage && stage[0] ? ": " : "", stage ? stage : "");
}

void cli_meter_start(cli_meter *m, const char *cmd, const char *what, long total, int quiet)
{
    memset(m, 0, sizeof *m);
    m->cmd = cmd;
    m->what = what;
    m->total = total;
    m->quiet = quiet;
    m->tty = isatty(STDERR_FILENO);
    m->t0 = meter_now_s();
}

static void meter_show(cli_meter *m, int force)
{
    double t = meter_now_s();
    if (m->quiet || (!force && t - m->last < PROGRESS_REFRESH_S))
        return;
    m->last = t;
    char line[METER_STAGE_MAX + 128];
    cli_meter_line(line, sizeof line, m->cmd, m->what, m->done, m->total, t - m->t0, m->stage);
    if (m->tty)
        fprintf(stderr, "\r%-*s", m->shown > (int)strlen(line) ? m->shown : 0, line);
    else
        fprintf(stderr, "%s\n", line);
    m->shown = (int)strlen(line);
    fflush(stderr);
}

void cli_meter_stage(cli_meter *m, const char *stage, long base)
{
    snprintf(m->stage, sizeof m->stage, "%s", stage);
    m->base = m->done = base;
    if (!m->tty) {
        double pct = m->total > 0 ? 100.0 * (double)base / (double)m->total : 0.0;
        if (m->shown && pct - m->logged_pct < PROGRESS_LOG_STEP_PCT &&
            meter_now_s() - m->last < PROGRESS_LOG_S)
            return;
        m->logged_pct = pct;
    }
    meter_show(m, 1);
}

void cli_meter_units(long done, long total, void *ctx)
{
    cli_meter *m = ctx;
    (void)total;
    m->done = m->base + done;
    if (m->tty)
        meter_show(m, 0);
}

void cli_meter_end(cli_meter *m)
{
    if (!m->quiet && m->tty && m->shown)
        fprintf(stderr, "\r%*s\r", m->shown, "");
}
