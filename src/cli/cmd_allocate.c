/* cmd_allocate.c - `sunmc allocate`: the cheapest joint set of tolerances
 * whose confirmed yield meets report.yield_target (allocate.h). */
#include "allocate.h"
#include "cli.h"
#include "verdict.h"
#include "output.h"
#include "progress.h"
#include "report.h"
#include "status.h"
#include "tsvnum.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const char allocate_help[] =
    "usage: sunmc allocate CONFIG [--units N] [--seed S] [--threads T]\n"
    "                      [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet]\n"
    "The cheapest joint set of tolerances whose yield (units meeting the spec's verdict:\n"
    "report.spec_statistic within report.spec_arcsec in every band of report.spec_bands,\n"
    "report.min_coverage of their points read; last measured angle) has its lower\n"
    "confidence bound (report.confidence, report.yield_interval) at report.yield_target.\n"
    "Cost: a tolerance at value v costs tolerance.NAME_cost * (today / v)^report.cost_exponent;\n"
    "every tolerance above 0 and not fixed is allocated, within today / 16 .. today * 4 (and\n"
    "its key's maximum); noise keys stay.  A per-unit surrogate of the RMS^2, additive in the\n"
    "sources (the budget's decomposition, each source alone at today's value and at 4x it,\n"
    "N units on run.seed), finds the set; a Monte Carlo on seed + 1 refines it and one on\n"
    "seed + 2, independent of both, confirms it (N units each, --units, default run.units).\n"
    "--out DIR writes allocate.tsv (today against allocated, cost, the confirmed yield with its\n"
    "interval), allocated.ini (the config with the allocated tolerances; `sunmc run` takes it\n"
    "as it is) and config.ini, all or nothing.\n"
    "Exit status 1 when no set is confirmed (allocated.ini is then not written).\n";

static const char *const status_names[] = {"confirmed", "unconfirmed", "none"};

static void progress(const char *what, int i, int n, void *ctx)
{
    cli_meter *m = ctx;
    if (i == 1)
        cli_meter_start(m, "allocate", "runs", n, m->quiet);
    char stage[METER_STAGE_MAX];
    snprintf(stage, sizeof stage, "%s (%d/%d)", what, i, n);
    m->total = n;
    cli_meter_stage(m, stage, i - 1);
}

static void write_tsv(FILE *f, const sunmc_config *c, const allocate_result *a)
{
    fprintf(f, "source\ttoday\tallocated\tratio\tpower\tms_share\tcost_today\tcost_allocated\t"
               "yield\tyield_ci_lo\tyield_ci_hi\tyield_target\tconfidence\tyield_interval\t"
               "units\tconfirm_seed\tstatus\n");
    for (int i = 0; i < a->n; i++) {
        const allocate_source *s = &a->src[i];
        tsv_printf(f, "%s\t%.6g\t%.6g\t%.6g\t%.4g\t%.6g\t%.6g\t%.6g\t", s->name, s->today,
                s->allocated, s->allocated / s->today, s->power, s->ms_share, s->cost_today,
                s->cost_allocated);
        tsv_printf(f, "%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%s\t%ld\t%ld\t%s\n", a->yield, a->yield_ci.lo,
                a->yield_ci.hi, c->yield_target, c->confidence, report_yield_interval_name(c),
                a->units, a->confirm_seed, status_names[a->status]);
    }
    tsv_printf(f, "TOTAL\tnan\tnan\tnan\tnan\tnan\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%s\t%ld\t"
               "%ld\t%s\n",
            a->cost_today, a->cost_allocated, a->yield, a->yield_ci.lo, a->yield_ci.hi,
            c->yield_target, c->confidence, report_yield_interval_name(c), a->units,
            a->confirm_seed, status_names[a->status]);
}

static void print_table(const sunmc_config *c, const allocate_result *a)
{
    char band[32];
    report_band_label(c, a->band, band, sizeof band);
    printf("\n%s (%s): tolerance allocation, yield target %g%% (lower bound, %s, %g%%), "
           "spec %g arcsec, band %s deg, %ld units per run, cost exponent %g\n",
           c->product, c->family->name, 100 * c->yield_target, report_yield_interval_name(c),
           100 * c->confidence, c->spec_arcsec, band, a->units, c->cost_exponent);
    char rule[256];
    verdict_rule_text(c, rule, sizeof rule);
    printf("yield: %s (the search's surrogate is the RMS^2 in band %s; every\nyield printed is a "
           "Monte Carlo's under the spec)\n", rule, band);
    printf("today's tolerances: yield %.2f%% [%.2f, %.2f] (seed %ld)\n", 100 * a->yield_today,
           100 * a->yield_today_ci.lo, 100 * a->yield_today_ci.hi, c->seed);
    if (a->status == ALLOCATE_NONE) {
        printf("NO SET: every tolerance at today / %g still gives a surrogate yield of %.2f%%, "
               "below the %.2f%% the lower bound needs at %ld units: the rest (design, noise, "
               "calibration) fails the spec; relax report.spec_arcsec or the noise.\n",
               ALLOCATE_RANGE, 100 * a->surrogate_yield, 100 * a->yield_needed, a->units);
        return;
    }
    printf("%-28s %10s %10s %7s %6s %10s %10s\n", "source", "today", "allocated", "ratio", "p",
           "cost today", "allocated");
    for (int i = 0; i < a->n; i++) {
        const allocate_source *s = &a->src[i];
        printf("%-28s %10.4g %10.4g %6.2fx %6.2f %10.4g %10.4g\n", s->name, s->today,
               s->allocated, s->allocated / s->today, s->power, s->cost_today, s->cost_allocated);
    }
    printf("%-28s %10s %10s %7s %6s %10.4g %10.4g (%+.1f%%)\n", "total cost", "", "", "", "",
           a->cost_today, a->cost_allocated, 100 * (a->cost_allocated / a->cost_today - 1));
    printf("surrogate yield %.2f%% (asked %.2f%%), refinement (seed %ld) %.2f%%, %d "
           "refinement%s\n",
           100 * a->surrogate_yield, 100 * a->yield_needed, c->seed + 1, 100 * a->yield_refine,
           a->refinements, a->refinements == 1 ? "" : "s");
    printf("confirmed yield (seed %ld, independent): %.2f%% [%.2f, %.2f]: %s\n", a->confirm_seed,
           100 * a->yield, 100 * a->yield_ci.lo, 100 * a->yield_ci.hi,
           a->status == ALLOCATE_CONFIRMED ? "lower bound meets the target"
                                           : "WARNING: lower bound below the target; more "
                                             "--units, or a stricter report.yield_target");
}

static int write_out(const char *dir, config_state *st, const allocate_result *a, char *err,
                     size_t errlen)
{
    out_set os;
    FILE *ft, *fa = NULL, *fc;
    int status = out_begin(&os, dir, err, errlen);
    if (status == SUNMC_OK)
        status = out_open(&os, "allocate.tsv", &ft, err, errlen);
    if (status == SUNMC_OK)
        status = out_open(&os, "config.ini", &fc, err, errlen);
    if (status == SUNMC_OK && a->status == ALLOCATE_CONFIRMED)
        status = out_open(&os, "allocated.ini", &fa, err, errlen);
    if (status != SUNMC_OK) {
        out_abort(&os);
        return status;
    }
    write_tsv(ft, &st->cfg, a);
    fprintf(fc, "# config of a tolerance allocation, %ld units per run\n", a->units);
    config_write(fc, st);
    if (fa) {
        sunmc_config today = st->cfg;
        allocate_apply(a, &st->cfg);
        fprintf(fa, "# allocated tolerances (sunmc allocate): confirmed yield %.4g [%.4g, %.4g] "
                    "on seed %ld\n", a->yield, a->yield_ci.lo, a->yield_ci.hi, a->confirm_seed);
        config_write(fa, st);
        st->cfg = today;
    }
    return out_commit(&os, err, errlen);
}

int cmd_allocate(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, allocate_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "allocate", "CONFIG units seed threads set out quiet", &o);
    if (rc)
        return rc;
    if (o.end >= 0 && o.first != 0) {
        fprintf(stderr, "sunmc allocate: --units takes a count N here, not FIRST:END\n");
        return EXIT_BAD_INPUT;
    }
    config_state st;
    if ((rc = cli_config(&o, &st)))
        return rc;
    long units = o.end >= 0 ? o.end : st.cfg.units;
    allocate_result *a = calloc(1, sizeof *a);
    char err[SUNMC_ERRLEN] = "out of memory";
    cli_meter m = {.quiet = o.quiet};
    int status = a ? allocate_run(&st.cfg, units, cli_threads(&o, &st.cfg), progress, &m, a, err,
                                  sizeof err)
                   : SUNMC_ENOMEM;
    if (a && m.total > 0)
        cli_meter_end(&m);
    if (status == SUNMC_OK) {
        print_table(&st.cfg, a);
        fflush(stdout);
        if (o.out)
            status = write_out(o.out, &st, a, err, sizeof err);
    }
    if (status != SUNMC_OK)
        fprintf(stderr, "sunmc allocate: %s\n", err);
    int code = status != SUNMC_OK ? cli_exit_code(status) : a->status == ALLOCATE_CONFIRMED ? 0 : 1;
    free(a);
    config_state_free(&st);
    return code;
}
