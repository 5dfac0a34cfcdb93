/* cmd_sensitivity.c - `sunmc sensitivity`: Sobol indices of the per-unit RMS. */
#include "cli.h"
#include "output.h"
#include "report.h"
#include "sensitivity.h"
#include "status.h"
#include "tsvnum.h"
#include "suggest.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char sensitivity_help[] =
    "usage: sunmc sensitivity CONFIG [--units N] [--seed S] [--threads T]\n"
    "                         [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet]\n"
    "                         [--until STAT:HALFWIDTH]\n"
    "Variance-based sensitivity: first-order (S1) and total (ST) Sobol indices of each\n"
    "unit's RMS before and after calibration (widest band of the last measured angle) for\n"
    "every random input: each tolerance > 0 that is not fixed, and each noise stream of the\n"
    "family (ESS campaign_noise = encoder + row currents of the calibration readings,\n"
    "validation_noise = row currents of the validation readings, roll_measurement,\n"
    "sun_y_measurement when calibration.sun_y = measured; DSS campaign_noise,\n"
    "validation_noise, sun_measurement when calibration.sun = measured).  S1 = the share of the unit-to-unit variance the\n"
    "input explains alone, ST = with all its interactions; ST - S1 is what it does only\n"
    "together with others.  Pick-freeze (Saltelli 2010 first order, Jansen 1999 total):\n"
    "sample A is units 0..N-1 under the seed, B the same units under seed XOR 0x5DEECE66D,\n"
    "and A_B^(i) is A with input i's random stream from B, so N units cost (inputs + 2) N\n"
    "unit runs and the result does not depend on --threads.  Intervals (report.confidence):\n"
    "bootstrap percentile over the units, 1000 resamples, fixed seed.\n"
    "--until STAT:HALFWIDTH runs blocks of run.block_units units (every run) until the\n"
    "widest interval of STAT over the inputs has at most that half-width, or --units N /\n"
    "run.units is reached; the result is that of a fixed run of the units it took.  STAT:\n"
    "st, s1 (after calibration), st_before, s1_before; e.g. --until st:0.02.\n"
    "--out DIR writes sensitivity.tsv and config.ini (all or nothing).\n";

static const char *const kind_names[] = {"tolerance", "noise"};

/* Each of the core's stages (sample A, sample B, A with each input from
 * B; or, with --until, each block of every run) runs `per_stage` units;
 * the first call gives their count. */
typedef struct {
    cli_meter m;
    int quiet, started;
    long per_stage;
} sens_meter;

static void progress(const char *what, int i, int n, void *ctx)
{
    sens_meter *sm = ctx;
    if (!sm->started) {
        sm->started = 1;
        cli_meter_start(&sm->m, "sensitivity", "units", n * sm->per_stage, sm->quiet);
    }
    char stage[METER_STAGE_MAX];
    snprintf(stage, sizeof stage, "%s (%d/%d)", what, i, n);
    cli_meter_stage(&sm->m, stage, (i - 1) * sm->per_stage);
}

/* --until STAT:HALFWIDTH into u (u->block from the config); prints the
 * error and returns an exit code. */
static int parse_until(const char *arg, const sunmc_config *c, sens_until *u)
{
    char name[64];
    double h;
    if (!cli_split_until(arg, name, sizeof name, &h)) {
        fprintf(stderr, "sunmc sensitivity: --until %s: needs STAT:HALFWIDTH with HALFWIDTH a "
                        "decimal number > 0, e.g. st:0.02 (STAT one of st, s1, st_before, s1_before)\n", arg);
        return EXIT_BAD_INPUT;
    }
    memset(u, 0, sizeof *u);
    u->stat = -1;
    for (int k = 0; k < SENS_UNTIL_STATS; k++)
        if (strcmp(name, sens_until_names[k]) == 0)
            u->stat = k;
    if (u->stat < 0) {
        char hint[SUGGEST_NAME_MAX + 32];
        suggest_hint(name, "st s1 st_before s1_before", hint, sizeof hint);
        fprintf(stderr, "sunmc sensitivity: --until %s: unknown statistic '%s'%s (one of st, s1, "
                        "st_before, s1_before)\n", arg, name, hint);
        return EXIT_BAD_INPUT;
    }
    u->halfwidth = h;
    u->block = c->block_units;
    return 0;
}

/* Whether --until met its target and after how many units (also the note
 * in config.ini). */
static void until_line(char *buf, size_t len, const char *arg, const sens_until *u, long done)
{
    if (u->met)
        snprintf(buf, len, "--until %s: met after %ld units (widest half-width %.3g)", arg, done,
                 u->reached);
    else
        snprintf(buf, len, "--until %s: NOT met: widest half-width %.3g after all %ld units "
                 "(--units N or run.units); run more units", arg, u->reached, done);
}

/* Sources in order of ST after calibration (largest first), stable. */
static void order_by_st(const sens_result *s, int *order)
{
    for (int i = 0; i < s->n; i++)
        order[i] = i;
    for (int i = 1; i < s->n; i++) {
        int x = order[i], j = i;
        double vx = isnan(s->src[x].after.st) ? -INFINITY : s->src[x].after.st;
        while (j > 0 && vx > (isnan(s->src[order[j - 1]].after.st)
                                  ? -INFINITY
                                  : s->src[order[j - 1]].after.st)) {
            order[j] = order[j - 1];
            j--;
        }
        order[j] = x;
    }
}

static void write_tsv(FILE *f, const sunmc_config *c, const sensor_family *fam,
                      const sens_result *s, const int *order)
{
    char band[32];
    report_band_label(c, s->band, band, sizeof band);
    fprintf(f, "rms\tsource\tkind\tkeys\tS1\tS1_ci_lo\tS1_ci_hi\tST\tST_ci_lo\tST_ci_hi\t"
               "variance\tmean\trms_unit\tangle\tband\tunits\tpaired_units\tseed\tseed_b\t"
               "confidence\tbootstrap\n");
    for (int w = 0; w < 2; w++)
        for (int i = 0; i < s->n; i++) {
            const sens_source *src = &s->src[order[i]];
            const stats_sobol_index *x = w ? &src->after : &src->before;
            tsv_printf(f, "%s\t%s\t%s\t%s\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%s\t%s\t"
                       "%s\t%ld\t%ld\t%ld\t%ld\t%g\t%d\n",
                    w ? "after" : "before", src->name, kind_names[src->kind], src->keys, x->s1,
                    x->s1_lo, x->s1_hi, x->st, x->st_lo, x->st_hi,
                    w ? s->var_after : s->var_before, w ? s->mean_after : s->mean_before,
                    fam->rms_unit, fam->angle_names[s->angle], band, s->units, s->paired_units,
                    s->seed, s->seed_b, c->confidence, SENS_BOOTSTRAP);
        }
}

/* "0.123 [0.101, 0.140]" */
/* Half the last printed digit of an index: a value that prints as 0.000
 * or 1.000 is inside 0..1. */
#define SENS_INDEX_PRINT_TOL 5e-4

/* Whether index v lies outside 0..1 as printed: no share of a variance. */
static int index_outside(double v)
{
    return v < -SENS_INDEX_PRINT_TOL || v > 1 + SENS_INDEX_PRINT_TOL || isnan(v);
}

/* "0.123 [0.100, 0.150]", a trailing "!" when the index lies outside 0..1,
 * "-" when it could not be formed. */
static void fmt_index(char *buf, size_t len, double v, double lo, double hi, int *outside)
{
    if (isnan(v)) {
        snprintf(buf, len, "-");
        return;
    }
    int out = index_outside(v);
    *outside += out;
    snprintf(buf, len, "%6.3f [%6.3f, %6.3f]%s", v, lo, hi, out ? "!" : "");
}

static void print_table(const sunmc_config *c, const sensor_family *fam, const sens_result *s,
                        const int *order)
{
    char band[32];
    report_band_label(c, s->band, band, sizeof band);
    int prec = report_decimals(fam);
    printf("\n%s (%s): Sobol indices of the unit RMS, %s in band %s deg; N = %ld units (%ld with "
           "a fit in every run), seeds %ld / %ld\n",
           c->product, fam->name, fam->angle_names[s->angle], band, s->units, s->paired_units,
           s->seed, s->seed_b);
    printf("RMS before: mean %.*f, sd %.*f %s;  after: mean %.*f, sd %.*f %s\n", prec,
           s->mean_before, prec, sqrt(s->var_before), fam->rms_unit, prec, s->mean_after, prec,
           sqrt(s->var_after), fam->rms_unit);
    char h[64];
    report_ci_label(c, h, sizeof h);
    printf("%-20s %-9s | %-22s %-22s | %-22s %-22s\n", "source", "kind", "S1 before", "ST before",
           "S1 after", "ST after");
    printf("%-20s %-9s | %-22s %-22s | %-22s %-22s\n", "", "", h, h, h, h);
    double sum[2] = {0, 0};
    int outside = 0;
    for (int i = 0; i < s->n; i++) {
        const sens_source *x = &s->src[order[i]];
        char a[48], b[48], cc[48], d[48];
        fmt_index(a, sizeof a, x->before.s1, x->before.s1_lo, x->before.s1_hi, &outside);
        fmt_index(b, sizeof b, x->before.st, x->before.st_lo, x->before.st_hi, &outside);
        fmt_index(cc, sizeof cc, x->after.s1, x->after.s1_lo, x->after.s1_hi, &outside);
        fmt_index(d, sizeof d, x->after.st, x->after.st_lo, x->after.st_hi, &outside);
        printf("%-20s %-9s | %-22s %-22s | %-22s %-22s\n", x->name, kind_names[x->kind], a, b,
               cc, d);
        sum[0] += x->before.s1;
        sum[1] += x->after.s1;
    }
    printf("sum of S1: before %.3f, after %.3f (1 - sum = the variance only interactions "
           "explain)\n",
           sum[0], sum[1]);
    printf("Sorted by ST after calibration.  S1: the share of the unit-to-unit variance of the "
           "RMS the input\nexplains alone; ST: with its interactions.  Intervals: bootstrap over "
           "the units (%d resamples).\n%ld unit runs: (%d inputs + 2) x %ld; %ld of them finished "
           "from sample A's validation\nreadings (the inputs only the campaign draws from).\n",
           SENS_BOOTSTRAP, (long)(s->n + 2) * s->units, s->n, s->units, s->reused_units);
    if (outside || index_outside(sum[0]) || index_outside(sum[1]))
        printf("WARNING: %d ind%s outside 0..1 (marked !)%s: no share of a variance is; the "
               "estimators' noise at %ld units (more --units narrow it)\n",
               outside, outside == 1 ? "ex" : "ices",
               index_outside(sum[0]) || index_outside(sum[1]) ? ", and a sum of S1 outside 0..1"
                                                              : "",
               s->paired_units);
}

static int write_out(const cli_options *o, const config_state *st, const sens_result *s,
                     const int *order, const char *note, char *err, size_t errlen)
{
    out_set os;
    FILE *fs, *fc;
    int status = out_begin(&os, o->out, err, errlen);
    if (status == SUNMC_OK)
        status = out_open(&os, "sensitivity.tsv", &fs, err, errlen);
    if (status == SUNMC_OK)
        status = out_open(&os, "config.ini", &fc, err, errlen);
    if (status != SUNMC_OK) {
        out_abort(&os);
        return status;
    }
    write_tsv(fs, &st->cfg, st->cfg.family, s, order);
    fprintf(fc, "# config of a sensitivity analysis, %ld units per sample\n", s->units);
    if (note)
        fprintf(fc, "# %s\n", note);
    config_write(fc, st);
    return out_commit(&os, err, errlen);
}

int cmd_sensitivity(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, sensitivity_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "sensitivity", "CONFIG units seed threads set out quiet until",
                       &o);
    if (rc)
        return rc;
    if (o.end >= 0 && o.first != 0) {
        fprintf(stderr, "sunmc sensitivity: --units takes a count N here, not FIRST:END\n");
        return EXIT_BAD_INPUT;
    }
    config_state st;
    if ((rc = cli_config(&o, &st)))
        return rc;
    const sunmc_config *c = &st.cfg;
    long units = o.end >= 0 ? o.end : c->units;
    sens_until until;
    if (o.until && (rc = parse_until(o.until, c, &until))) {
        config_state_free(&st);
        return rc;
    }
    int threads = cli_threads(&o, c);
    sens_result *s = calloc(1, sizeof *s);
    char err[SUNMC_ERRLEN];
    int order[SENS_MAX_SOURCES];
    int status = s ? SUNMC_OK : SUNMC_ENOMEM;
    if (!s)
        snprintf(err, sizeof err, "out of memory");
    if (status == SUNMC_OK) {
        sens_meter sm = {.quiet = o.quiet, .per_stage = units};
        if (o.until) {
            sm.per_stage = (until.block < units ? until.block : units) *
                           (long)(sens_random_inputs(c) + 2);
            status = sens_run_until(c, units, &until, threads, progress, &sm, s, err, sizeof err);
        } else {
            status = sens_run(c, units, threads, progress, &sm, s, err, sizeof err);
        }
        if (sm.started)
            cli_meter_end(&sm.m);
    }
    if (status == SUNMC_OK) {
        order_by_st(s, order);
        print_table(c, c->family, s, order); /* before writing: a failed write must not cost it */
        char note[256] = "";
        if (o.until) {
            until_line(note, sizeof note, o.until, &until, s->units);
            printf("%s\n", note);
        }
        fflush(stdout);
        if (o.out)
            status = write_out(&o, &st, s, order, o.until ? note : NULL, err, sizeof err);
    }
    if (status != SUNMC_OK)
        fprintf(stderr, "sunmc sensitivity: %s\n", err);
    free(s);
    config_state_free(&st);
    return cli_exit_code(status);
}
