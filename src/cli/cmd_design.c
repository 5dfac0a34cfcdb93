/* cmd_design.c - `sunmc design`: the cheapest calibration campaign whose
 * yield meets report.yield_target against report.spec_arcsec (design.h). */
#include "cli.h"
#include "verdict.h"
#include "design.h"
#include "output.h"
#include "status.h"
#include "tsvnum.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

static const char design_help[] =
    "usage: sunmc design CONFIG [--space KEY=VALUE]... [--units N] [--seed S] [--threads T]\n"
    "                    [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet]\n"
    "--units N: at most N units a candidate (campaign.search_max_units; the screen too).\n"
    "Searches calibration campaigns -- fast-axis step (ESS alpha), symmetric slow-axis line\n"
    "sets (ESS beta: 1 line at 0, or 2..7 evenly spaced over +-B), readings per point -- for\n"
    "the cheapest in turntable hours whose yield (the spec's verdict: report.spec_statistic\n"
    "within report.spec_arcsec in every band of report.spec_bands) has its\n"
    "lower confidence bound (report.confidence, report.yield_interval) at report.yield_target or above.\n"
    "Every candidate runs the same units and seed (common random numbers); a screen on\n"
    "campaign.search_screen_units units drops hopeless ones and marks aliasing steps (never\n"
    "chosen); survivors, cheapest first, run on in blocks of run.block_units until the bound\n"
    "settles (at most campaign.search_max_units), until campaign.search_shortlist pass.\n"
    "The input config's own campaign is always settled, for comparison.\n"
    "  --space steps_deg=0.2,0.3,0.4   the same as --set campaign.search_steps_deg=...; also\n"
    "        max_lines, beta_max_deg, beta_step_deg, repeats, screen_units, max_units, shortlist\n"
    "--out DIR writes design.tsv (every candidate: points, hours, yield with its interval,\n"
    "mean RMS after with its interval, verdict, pareto), best.ini (the input config with\n"
    "the chosen campaign; `sunmc run` takes it as it is) and config.ini, all or nothing.\n"
    "Exit status 1 when no candidate meets the target (design.tsv is written, best.ini not).\n";

static double now_s(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (double)tv.tv_sec + 1e-6 * (double)tv.tv_usec;
}

/* The design's two passes over its n candidates (screen each, settle
 * the shortlist; a candidate's units vary): the meter counts candidate
 * steps, 2 n in all, a settled step skipping those that are not settled. */
typedef struct {
    cli_meter m;
    int quiet, started;
} design_meter;

static void progress(const char *stage, int i, int n, void *ctx)
{
    design_meter *dm = ctx;
    if (!dm->started) {
        dm->started = 1;
        cli_meter_start(&dm->m, "design", "candidate steps", 2L * n, dm->quiet);
    }
    int settle = strcmp(stage, "settle") == 0;
    char text[METER_STAGE_MAX];
    snprintf(text, sizeof text, "%s candidate %d/%d", stage, i, n);
    cli_meter_stage(&dm->m, text, (settle ? n : 0) + i - 1);
}

/* "step 0.3, lines -30, 0, 30, 1 reading" */
static void label(const design_candidate *k, char *buf, size_t len)
{
    snprintf(buf, len, "%s%s%s x%d", k->step, k->lines[0] ? " | " : "", k->lines, k->repeats);
}

static void write_tsv(FILE *f, const design_result *d)
{
    const sensor_family *fam = d->cand[0].cfg.family;
    fprintf(f, "rank\tcandidate\t%s\t%s\trepeats\tinput\tpoints\thours\textrapolation_deg\tunits\t"
               "yield\tyield_ci_lo\tyield_ci_hi\trms_after_mean_%s\trms_after_mean_ci_lo\t"
               "rms_after_mean_ci_hi\talias_units\tfit_failures\tverdict\tpareto\tbest\n",
            fam->grid->design_step_key, fam->grid->design_lines_key ? fam->grid->design_lines_key : "lines",
            fam->rms_unit);
    for (int j = 0; j < d->n; j++) {
        const design_candidate *k = &d->cand[d->order[j]];
        char lab[3 * DESIGN_TEXT];
        label(k, lab, sizeof lab);
        tsv_printf(f, "%d\t%s\t%s\t%s\t%d\t%d\t%ld\t%.6g\t%.6g\t%ld\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t"
                   "%ld\t%ld\t%s\t%d\t%d\n",
                j + 1, lab, k->step, k->lines[0] ? k->lines : "-", k->repeats, k->is_input,
                k->points, k->hours, k->extrapolation_deg, k->units, k->yield, k->yield_ci.lo,
                k->yield_ci.hi, k->after_mean, k->after_ci.lo, k->after_ci.hi, k->alias_units,
                k->fit_failures, design_verdict_names[k->verdict], k->pareto,
                d->order[j] == d->best);
    }
}

static void print_row(const design_candidate *k, const char *mark)
{
    char lab[3 * DESIGN_TEXT];
    label(k, lab, sizeof lab);
    printf("%-2s %-40s %6ld %6.2f %6ld  %5.1f%% [%5.1f, %5.1f]  %-12s%s\n", mark, lab, k->points,
           k->hours, k->units, 100 * k->yield, 100 * k->yield_ci.lo, 100 * k->yield_ci.hi,
           design_verdict_names[k->verdict], k->extrapolation_deg > 0 ? " (extrapolates)" : "");
}

static void print_shortlist(const design_result *d, double secs)
{
    const sunmc_config *c = &d->cand[0].cfg;
    const sensor_family *fam = c->family;
    printf("\n%s (%s): campaign design, spec %g arcsec, yield target %g%% at %g%% confidence\n",
           c->product, fam->name, c->spec_arcsec, 100 * c->yield_target, 100 * c->confidence);
    char rule[256];
    verdict_rule_text(c, rule, sizeof rule);
    printf("candidate = %s | %s x repeats; yield: %s; seed %ld\n",
           fam->grid->design_step_key, fam->grid->design_lines_key ? fam->grid->design_lines_key : "-",
           rule, c->seed);
    printf("   %-40s %6s %6s %6s  %-21s  %s\n", "candidate", "points", "hours", "units",
           "yield [CI]", "verdict");
    int shown = 0;
    for (int j = 0; j < d->n; j++) {
        const design_candidate *k = &d->cand[d->order[j]];
        if (k->verdict == DESIGN_PASS && shown < c->search_shortlist) {
            print_row(k, d->order[j] == d->best ? "*" : "");
            shown++;
        }
    }
    for (int j = 0; j < d->n; j++)
        if (d->cand[d->order[j]].is_input)
            print_row(&d->cand[d->order[j]], "in");
    int count[DESIGN_VERDICTS] = {0};
    for (int i = 0; i < d->n; i++)
        count[d->cand[i].verdict]++;
    printf("* = chosen (best.ini), in = the input config's campaign.  %d candidates:", d->n);
    for (int v = 0; v < DESIGN_VERDICTS; v++)
        printf("%s %d %s", v ? "," : "", count[v], design_verdict_names[v]);
    printf(".\n%d more not tried: they validate beyond campaign.search_max_extrapolation_deg = "
           "%g deg outside their span.\n%ld unit runs (%ld of them on validation readings read "
           "for another candidate) in %.1f s.\n",
           d->n_extrapolating, c->search_max_extrapolation_deg, d->units_run, d->units_reused,
           secs);
    if (d->best < 0)
        printf("WARNING: no candidate met the target; widen the space (--space) or relax "
               "the spec\n");
}

/* best.ini: the input config with the chosen candidate's campaign. */
static int write_best(FILE *f, config_state *st, const design_result *d, const char *config,
                      char *err, size_t errlen)
{
    const design_candidate *k = &d->cand[d->best];
    const sensor_family *fam = st->cfg.family;
    char rep[16];
    snprintf(rep, sizeof rep, "%d", k->repeats);
    const char *keys[3] = {fam->grid->design_step_key, fam->grid->design_lines_key, "campaign.repeats"};
    const char *vals[3] = {k->step, k->lines, rep};
    for (int i = 0; i < 3; i++) {
        if (!keys[i])
            continue;
        char sec[CONFIG_STR_MAX];
        const char *dot = strchr(keys[i], '.');
        snprintf(sec, sizeof sec, "%.*s", (int)(dot - keys[i]), keys[i]);
        int s = config_set_value(st, sec, dot + 1, vals[i], "sunmc design", err, errlen);
        if (s != SUNMC_OK)
            return s;
    }
    fprintf(f, "# %s with the campaign chosen by sunmc design: %ld points, %.2f turntable hours,\n"
               "# yield %.1f%% [%.1f, %.1f] on %ld units (seed %ld); confirm with another seed\n",
            config, k->points, k->hours, 100 * k->yield, 100 * k->yield_ci.lo,
            100 * k->yield_ci.hi, k->units, st->cfg.seed);
    return config_write(f, st);
}

static int write_outputs(const cli_options *o, config_state *st, const design_result *d,
                         char *err, size_t errlen)
{
    out_set os;
    FILE *ft, *fb = NULL, *fc;
    int s = out_begin(&os, o->out, err, errlen);
    if (s == SUNMC_OK)
        s = out_open(&os, "design.tsv", &ft, err, errlen);
    if (s == SUNMC_OK)
        s = out_open(&os, "config.ini", &fc, err, errlen);
    if (s == SUNMC_OK && d->best >= 0)
        s = out_open(&os, "best.ini", &fb, err, errlen);
    if (s != SUNMC_OK) {
        out_abort(&os);
        return s;
    }
    write_tsv(ft, d);
    config_write(fc, st);
    if (fb && (s = write_best(fb, st, d, o->config, err, errlen)) != SUNMC_OK) {
        out_abort(&os);
        return s;
    }
    return out_commit(&os, err, errlen);
}

int cmd_design(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, design_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "design", "CONFIG units seed threads set space out quiet",
                       &o);
    if (rc)
        return rc;
    if (o.end >= 0) {
        fprintf(stderr, "sunmc design: --units takes N, the most units a candidate runs\n");
        return EXIT_BAD_INPUT;
    }
    config_state st;
    if ((rc = cli_config(&o, &st)))
        return rc;
    for (int i = 0; i < o.n_sets; i++) /* --units N: the most units a candidate runs */
        if (o.sets[i] == o.set_buf[i] && strncmp(o.sets[i], "run.units=", 10) == 0) {
            st.cfg.search_max_units = st.cfg.units;
            if (st.cfg.search_screen_units > st.cfg.units)
                st.cfg.search_screen_units = st.cfg.units;
        }
    char err[SUNMC_ERRLEN];
    design_result d;
    double t0 = now_s();
    int s = design_space(&st.cfg, &d, err, sizeof err);
    design_meter dm = {.quiet = o.quiet};
    if (s == SUNMC_OK)
        s = design_run(&d, cli_threads(&o, &st.cfg), progress, &dm, err, sizeof err);
    if (dm.started)
        cli_meter_end(&dm.m);
    if (s == SUNMC_OK) {
        print_shortlist(&d, now_s() - t0);
        fflush(stdout);
        if (o.out)
            s = write_outputs(&o, &st, &d, err, sizeof err);
    }
    if (s != SUNMC_OK)
        fprintf(stderr, "sunmc design: %s\n", err);
    rc = s != SUNMC_OK ? cli_exit_code(s) : d.best < 0 ? 1 : 0;
    design_free(&d);
    config_state_free(&st);
    return rc;
}
