/* cmd_budget.c - `sunmc budget`: the tolerance budget and inverse limits. */
#include "budget.h"
#include "cli.h"
#include "output.h"
#include "report.h"
#include "status.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char budget_help[] =
    "usage: sunmc budget CONFIG [--units N] [--seed S] [--threads T]\n"
    "                    [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet]\n"
    "Tolerance budget: for each error source (tolerance key > 0) the Monte Carlo with that\n"
    "source alone (others 0) and with it removed (others on), same seed, in the widest band\n"
    "of the last measured angle; sources ranked by the share of the after-calibration mean\n"
    "square that goes away without them.  Inverse limit: the largest tolerance of each\n"
    "source (others at theirs) whose yield against report.spec_arcsec is still at least\n"
    "report.yield_target, by bisection on Monte Carlos of report.budget_units units\n"
    "(report.budget_steps steps; --set report.budget_steps=1 for a rough, fast answer).\n"
    "--out DIR writes budget.tsv and config.ini (all or nothing).\n";

static const char *const limit_names[] = {"ok", "at_key_max", "unmet"};

static void progress(const char *what, int i, int n, void *ctx)
{
    if (!*(const int *)ctx)
        fprintf(stderr, "sunmc budget: %d/%d %s\n", i, n, what);
}

static void dist_name(const sunmc_config *c, const budget_source *s, char *buf, size_t len)
{
    char dname[2 * CONFIG_STR_MAX];
    snprintf(dname, sizeof dname, "%s_dist", s->name);
    const config_key *dk = config_find_in(c->family, "tolerance", dname);
    if (dk)
        config_format_value(dk, c, buf, len);
    else
        snprintf(buf, len, "?");
}

static void write_tsv(FILE *f, const sunmc_config *c, const sensor_family *fam,
                      const budget_result *b)
{
    char band[32];
    report_band_label(c, b->band, band, sizeof band);
    fprintf(f, "rank\tsource\tunit\ttolerance\tdist\tbefore_alone\tafter_alone\tbefore_removed\t"
               "after_removed\tshare_alone_before\tshare_alone_after\tshare_removed_before\t"
               "share_removed_after\tyield_today\tlimit\tlimit_status\tyield_target\t"
               "spec_arcsec\trms_unit\tangle\tband\tunits\tlimit_units\n");
    const budget_stats *tot[2] = {&b->all, &b->none};
    const char *tname[2] = {"ALL", "NONE"};
    for (int t = 0; t < 2; t++)
        fprintf(f, "0\t%s\t-\tnan\t-\t%.6g\t%.6g\tnan\tnan\tnan\tnan\tnan\tnan\t%.6g\tnan\t-\t%g\t"
                   "%g\t%s\t%s\t%s\t%ld\t%ld\n",
                tname[t], tot[t]->before_mean, tot[t]->after_mean, tot[t]->yield,
                c->yield_target, c->spec_arcsec, fam->rms_unit, fam->angle_names[b->angle], band,
                b->units, c->budget_units);
    for (int i = 0; i < b->n; i++) {
        const budget_source *s = &b->src[b->order[i]];
        char dist[CONFIG_STR_MAX];
        dist_name(c, s, dist, sizeof dist);
        fprintf(f, "%d\t%s\t%s\t%.10g\t%s\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t"
                   "%.6g\t%s\t%g\t%g\t%s\t%s\t%s\t%ld\t%ld\n",
                s->rank, s->name, s->key->unit[0] ? s->key->unit : "-", s->tolerance, dist,
                s->alone.before_mean, s->alone.after_mean, s->removed.before_mean,
                s->removed.after_mean, s->share_alone_before, s->share_alone_after,
                s->share_removed_before, s->share_removed_after, s->yield_today, s->limit,
                limit_names[s->limit_status], c->yield_target, c->spec_arcsec, fam->rms_unit,
                fam->angle_names[b->angle], band, b->units, c->budget_units);
    }
}

static void print_table(const sunmc_config *c, const sensor_family *fam, const budget_result *b)
{
    char band[32];
    report_band_label(c, b->band, band, sizeof band);
    const char *u = fam->rms_unit;
    int prec = strcmp(u, "deg") == 0 ? 4 : 2;
    printf("\n%s (%s): tolerance budget, %ld units per run, seed %ld; %s in band %s deg\n",
           c->product, fam->name, b->units, c->seed, fam->angle_names[b->angle], band);
    printf("all sources: RMS before %.*f, after %.*f %s, yield %.1f%%;  no source (design + "
           "noise): before %.*f, after %.*f\n",
           prec, b->all.before_mean, prec, b->all.after_mean, u, 100 * b->all.yield, prec,
           b->none.before_mean, prec, b->none.after_mean);
    printf("%-4s %-20s %10s %-8s | %9s %9s | %9s %9s | %7s %7s | %7s %7s | %-24s\n", "rank",
           "source", "tolerance", "unit", "alone", "", "removed", "", "share", "removed",
           "share", "alone", "inverse limit");
    printf("%-4s %-20s %10s %-8s | %9s %9s | %9s %9s | %7s %7s | %7s %7s | yield %.0f%%, spec "
           "%g\"\n",
           "", "", "today", "", "before", "after", "before", "after", "before", "after",
           "before", "after", 100 * c->yield_target, c->spec_arcsec);
    for (int i = 0; i < b->n; i++) {
        const budget_source *s = &b->src[b->order[i]];
        char lim[64];
        if (b->src[0].limit_runs == 0)
            snprintf(lim, sizeof lim, "-");
        else if (s->limit_status == BUDGET_LIMIT_UNMET)
            snprintf(lim, sizeof lim, "unmet even at 0");
        else if (s->limit_status == BUDGET_LIMIT_AT_MAX)
            snprintf(lim, sizeof lim, ">= %g (key max)", s->limit);
        else
            snprintf(lim, sizeof lim, "%.4g (%.1fx today)", s->limit, s->limit / s->tolerance);
        printf("%-4d %-20s %10.4g %-8s | %9.*f %9.*f | %9.*f %9.*f | %6.1f%% %6.1f%% | %6.1f%% "
               "%6.1f%% | %s\n",
               s->rank, s->name, s->tolerance, s->key->unit[0] ? s->key->unit : "-", prec,
               s->alone.before_mean, prec, s->alone.after_mean, prec, s->removed.before_mean,
               prec, s->removed.after_mean, 100 * s->share_removed_before,
               100 * s->share_removed_after, 100 * s->share_alone_before,
               100 * s->share_alone_after, lim);
    }
    printf("RMS in %s.  share removed = part of the mean square that goes away without the "
           "source;\nshare alone = part of the tolerance-caused mean square the source makes "
           "alone.\n",
           u);
}

int cmd_budget(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, budget_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "budget", "CONFIG units seed threads set out quiet", &o);
    if (rc)
        return rc;
    if (o.end >= 0 && o.first != 0) {
        fprintf(stderr, "sunmc budget: --units takes a count N here, not FIRST:END\n");
        return EXIT_BAD_INPUT;
    }
    config_state st;
    if ((rc = cli_config(&o, &st)))
        return rc;
    const sunmc_config *c = &st.cfg;
    const sensor_family *fam = c->family;
    long units = o.end >= 0 ? o.end : c->units;
    int threads = cli_threads(&o, c);

    budget_result *b = calloc(1, sizeof *b);
    char err[SUNMC_ERRLEN];
    int status = b ? SUNMC_OK : SUNMC_ENOMEM;
    if (!b)
        snprintf(err, sizeof err, "out of memory");
    if (status == SUNMC_OK)
        status = budget_run(c, units, threads, 1, progress, &o.quiet, b, err, sizeof err);
    if (status == SUNMC_OK) {
        print_table(c, fam, b); /* before writing: a failed write must not cost it */
        fflush(stdout);
    }
    if (status == SUNMC_OK && o.out) {
        out_set os;
        FILE *fb, *fc;
        status = out_begin(&os, o.out, err, sizeof err);
        if (status == SUNMC_OK)
            status = out_open(&os, "budget.tsv", &fb, err, sizeof err);
        if (status == SUNMC_OK)
            status = out_open(&os, "config.ini", &fc, err, sizeof err);
        if (status == SUNMC_OK) {
            write_tsv(fb, c, fam, b);
            fprintf(fc, "# config of a tolerance budget, %ld units per run\n", units);
            config_write(fc, &st);
            status = out_commit(&os, err, sizeof err);
        } else {
            out_abort(&os);
        }
    }
    if (status != SUNMC_OK)
        fprintf(stderr, "sunmc budget: %s\n", err);
    free(b);
    config_state_free(&st);
    return cli_exit_code(status);
}
