/* cmd_budget.c - `sunmc budget`: the tolerance budget and inverse limits. */
#include "budget.h"
#include "verdict.h"
#include "cli.h"
#include "table.h"
#include "output.h"
#include "report.h"
#include "status.h"
#include "tsvnum.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char budget_help[] =
    "usage: sunmc budget CONFIG [--units N] [--seed S] [--threads T]\n"
    "                    [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet]\n"
    "Error budget (mean squares) in the widest band of the last measured angle; yields and\n"
    "inverse limits by the spec's verdict (report.spec_statistic in every band of\n"
    "report.spec_bands, report.min_coverage of its points read).  Sources: every tolerance\n"
    "key > 0 and every noise key > 0 of the family (ESS noise.row_current_pct,\n"
    "noise.encoder_arcsec, calibration.roll_sigma_arcsec; DSS noise.centroid_px,\n"
    "noise.encoder_arcsec).  Monte Carlos on the same seed and units: all sources; the floor\n"
    "(every source 0: the nominal design without noise); each source alone on the floor.\n"
    "Share, of the mean square MS (mean over units of RMS^2), all over MS_all:\n"
    "  floor = MS_floor / MS_all;  source = (MS_alone - MS_floor) / MS_all;\n"
    "  interaction = 100 % - floor - sum of the sources (what they do together).\n"
    "They add up to 100 %, before and after calibration.  Each share has a confidence\n"
    "interval (report.confidence) from the paired per-unit values (common random numbers);\n"
    "one whose interval includes 0 is inside the Monte Carlo noise (marked ~, significant\n"
    "= no).  Inverse limit: the largest value of each source (others at theirs) whose yield\n"
    "against report.spec_arcsec is still at least report.yield_target, by bisection on\n"
    "Monte Carlos of report.budget_units units (report.budget_steps steps); its interval\n"
    "from the yield intervals (report.yield_interval) of the values tried (- where none is clear).\n"
    "--out DIR writes budget.tsv and config.ini (all or nothing).\n";

static const char *const limit_names[] = {"ok", "at_key_max", "unmet"};
static const char *const kind_names[] = {"tolerance", "noise"};

/* The budget's progress: its Monte Carlos of `units` units (all, floor,
 * each source alone, no tolerance), then per source an inverse limit of
 * about report.budget_steps + 2 Monte Carlos of report.budget_units (the
 * bisection's count varies: an estimate).  The core calls back at the
 * start of each; the first call gives the count of the first phase. */
typedef struct {
    cli_meter m;
    int quiet, n_runs, last_i, limits;
    long units, per_limit;
} budget_meter;

static void progress(const char *what, int i, int n, void *ctx)
{
    budget_meter *bm = ctx;
    if (bm->n_runs == 0) {
        bm->n_runs = n;
        cli_meter_start(&bm->m, "budget", "units", n * bm->units + (n - 3) * bm->per_limit,
                        bm->quiet);
    }
    if (!bm->limits && bm->last_i == bm->n_runs && i == 1)
        bm->limits = 1;
    bm->last_i = i;
    long base = bm->limits ? bm->n_runs * bm->units + (i - 1) * bm->per_limit
                           : (i - 1) * bm->units;
    char stage[METER_STAGE_MAX];
    snprintf(stage, sizeof stage, "%s (%d/%d)", what, i, n);
    cli_meter_stage(&bm->m, stage, base);
}

static void dist_name(const sunmc_config *c, const budget_source *s, char *buf, size_t len)
{
    char dname[2 * CONFIG_STR_MAX];
    snprintf(dname, sizeof dname, "%s_dist", s->name);
    const config_key *dk =
        s->kind == BUDGET_TOLERANCE ? config_find_in(c->family, "tolerance", dname) : NULL;
    if (dk)
        config_format_value(dk, c, buf, len);
    else
        snprintf(buf, len, s->kind == BUDGET_NOISE ? "normal" : "-");
}

/* n numbers with fmt, each followed by a tab ("-" for NaN: tsvnum.h). */
static void put_nums(FILE *f, const char *fmt, int n, const double *v)
{
    for (int i = 0; i < n; i++) {
        tsv_num_put(f, fmt, v[i]);
        fputc('\t', f);
    }
}

/* "S\tS_ci_lo\tS_ci_hi\tsignificant\t" */
static void write_share(FILE *f, const budget_share *s)
{
    put_nums(f, "%.6g", 3, (double[]){s->v, s->ci.lo, s->ci.hi});
    fprintf(f, "%s\t", s->significant ? "yes" : "no");
}

/* The columns every row ends with. */
static void write_tail(FILE *f, const sunmc_config *c, const sensor_family *fam,
                       const budget_result *b)
{
    char band[32];
    report_band_label(c, b->band, band, sizeof band);
    put_nums(f, "%g", 3, (double[]){c->yield_target, c->spec_arcsec, c->confidence});
    fprintf(f, "%s\t%s\t%s\t%ld\t%ld\t%ld\t", fam->rms_unit, fam->angle_names[b->angle], band,
            b->units, b->paired_units, c->budget_units);
    put_nums(f, "%.6g", 6,
             (double[]){b->all.before_mean, b->all.after_mean, b->all.yield, b->all.yield_ci.lo,
                        b->all.yield_ci.hi, b->no_tolerance.before_mean});
    tsv_num_put(f, "%.6g", b->no_tolerance.after_mean);
    fputc('\n', f);
}

/* What ended a limit (budget.h), as printed and in budget.tsv. */
static const char *const end_names[] = {"spec", "coverage", "fit", "range"};

static const char *const part_names[BUDGET_PARTS] = {"NOISE_OF_READING", "ESTIMATION",
                                                      "MODEL_FORM"};

static void fmt_share(char *buf, size_t len, const budget_share *s);

static void write_tsv(FILE *f, const sunmc_config *c, const sensor_family *fam,
                      const budget_result *b)
{
    fprintf(f, "rank\tkind\tsource\tunit\ttolerance\tdist\tbefore_alone\tafter_alone\t"
               "share_before\tshare_before_ci_lo\tshare_before_ci_hi\tsignificant_before\t"
               "share_after\tshare_after_ci_lo\tshare_after_ci_hi\tsignificant_after\t"
               "yield_today\tyield_today_ci_lo\tyield_today_ci_hi\tlimit\tlimit_ci_lo\t"
               "limit_ci_hi\tlimit_status\tlimit_end\tin_noise\tyield_target\tspec_arcsec\tconfidence\trms_unit\t"
               "angle\tband\tunits\tpaired_units\tlimit_units\tall_before\tall_after\t"
               "all_yield\tall_yield_ci_lo\tall_yield_ci_hi\tno_tolerance_before\t"
               "no_tolerance_after\n");
    fprintf(f, "0\tfloor\tFLOOR\t-\t-\t-\t");
    put_nums(f, "%.6g", 2, (double[]){b->floor.before_mean, b->floor.after_mean});
    write_share(f, &b->floor_before);
    write_share(f, &b->floor_after);
    put_nums(f, "%.6g", 3, (double[]){b->floor.yield, b->floor.yield_ci.lo, b->floor.yield_ci.hi});
    fprintf(f, "-\t-\t-\t-\t-\t-\t");
    write_tail(f, c, fam, b);
    for (int i = 0; i < b->n; i++) {
        const budget_source *s = &b->src[b->order[i]];
        char dist[CONFIG_STR_MAX];
        dist_name(c, s, dist, sizeof dist);
        fprintf(f, "%d\t%s\t%s\t%s\t", s->rank, kind_names[s->kind], s->name,
                s->key->unit[0] ? s->key->unit : "-");
        tsv_num_put(f, "%.10g", s->tolerance);
        fprintf(f, "\t%s\t", dist);
        put_nums(f, "%.6g", 2, (double[]){s->alone.before_mean, s->alone.after_mean});
        write_share(f, &s->share_before);
        write_share(f, &s->share_after);
        put_nums(f, "%.6g", 6,
                 (double[]){s->yield_today, s->yield_today_ci.lo, s->yield_today_ci.hi, s->limit,
                            s->limit_ci.lo, s->limit_ci.hi});
        fprintf(f, "%s\t%s\t%s\t", limit_names[s->limit_status],
                s->limit_runs ? end_names[s->limit_end] : "-", s->in_noise ? "yes" : "no");
        write_tail(f, c, fam, b);
    }
    fprintf(f, "0\tinteraction\tINTERACTION\t-\t-\t-\t-\t-\t");
    write_share(f, &b->interaction_before);
    write_share(f, &b->interaction_after);
    fprintf(f, "-\t-\t-\t-\t-\t-\t-\t-\t-\t");
    write_tail(f, c, fam, b);
    for (int k = 0; k < BUDGET_PARTS + (b->onboard_name[0] != '\0'); k++) {
        fprintf(f, "0\tafter_part\t%s\t-\t-\t-\t-\t-\t-\t-\t-\t-\t",
                k < BUDGET_PARTS ? part_names[k] : b->onboard_name);
        write_share(f, k < BUDGET_PARTS ? &b->part_after[k] : &b->part_onboard);
        fprintf(f, "-\t-\t-\t-\t-\t-\t-\t-\t-\t");
        write_tail(f, c, fam, b);
    }
}

/* The parts of the mean square after calibration (budget.h), as the
 * print and budget.tsv name them. */
static void print_parts(const budget_result *b)
{
    static const char *const words[BUDGET_PARTS] = {
        "noise of the validation reading", "the calibration's estimation error (campaign noise)",
        "model form (what the calibration model cannot represent)"};
    printf("After calibration, all sources, by kind (%ld units run again with a noise-free "
           "reading and a\nnoise-free campaign; docs/statistics.md), share of MS_all:\n",
           b->part_units);
    for (int k = 0; k < BUDGET_PARTS; k++) {
        char sh[96];
        fmt_share(sh, sizeof sh, &b->part_after[k]);
        printf("  %-58s %s\n", words[k], sh);
    }
    if (b->onboard_name[0]) {
        char sh[96], what[96];
        fmt_share(sh, sizeof sh, &b->part_onboard);
        snprintf(what, sizeof what, "on-board arithmetic (%s: MS - MS in double)", b->onboard_name);
        printf("  %-58s %s\n", what, sh);
    }
}

/* Shares named in the outside-0..100 % warning. */
#define BUDGET_OUTSIDE_SHOWN 4

static int shown_significant(const budget_share *s);

/* "12.34% [11.90, 12.80]~" (~: the interval includes 0); "-" for a share
 * that cannot be formed (too few units with a fit), never "nan%"; a share
 * without an interval is marked neither way. */
static void fmt_share(char *buf, size_t len, const budget_share *s)
{
    if (isnan(s->v)) {
        snprintf(buf, len, "-");
        return;
    }
    if (!isfinite(s->ci.lo) || !isfinite(s->ci.hi)) { /* no interval: neither ~ nor significant */
        snprintf(buf, len, "%6.2f%% [     -,      -] ", 100 * s->v);
        return;
    }
    snprintf(buf, len, "%6.2f%% [%6.2f, %6.2f]%s", 100 * s->v, 100 * s->ci.lo, 100 * s->ci.hi,
             shown_significant(s) ? " " : "~");
}

/* A share in percent as printed (two decimals). */
static double shown_pct(double v)
{
    return round(100 * 100 * v) / 100;
}

/* The mark follows the interval as printed: one that shows 0 at either end
 * ("-0.00% [-0.00, -0.00]") is not marked significant. */
static int shown_significant(const budget_share *s)
{
    return s->significant && (shown_pct(s->ci.lo) > 0 || shown_pct(s->ci.hi) < 0);
}

/* Shares outside 0..100 % (as printed) are named in a warning: sources
 * that interact (calibration couples them), or too few units. */
static void add_outside(char *buf, size_t len, int *n, const char *name, const char *when,
                        const budget_share *s)
{
    if (isnan(s->v) || (shown_pct(s->v) >= 0 && shown_pct(s->v) <= 100))
        return;
    size_t used = strlen(buf);
    if (*n < BUDGET_OUTSIDE_SHOWN && used < len)
        snprintf(buf + used, len - used, "%s%s %s %.2f%%", *n ? ", " : "", name, when,
                 shown_pct(s->v));
    else if (*n == BUDGET_OUTSIDE_SHOWN && used < len)
        snprintf(buf + used, len - used, ", ...");
    (*n)++;
}

static void warn_outside(const budget_result *b)
{
    char list[512] = "";
    int n = 0;
    add_outside(list, sizeof list, &n, "floor", "before", &b->floor_before);
    add_outside(list, sizeof list, &n, "floor", "after", &b->floor_after);
    for (int i = 0; i < b->n; i++) {
        const budget_source *s = &b->src[b->order[i]];
        add_outside(list, sizeof list, &n, s->name, "before", &s->share_before);
        add_outside(list, sizeof list, &n, s->name, "after", &s->share_after);
    }
    add_outside(list, sizeof list, &n, "interaction", "before", &b->interaction_before);
    add_outside(list, sizeof list, &n, "interaction", "after", &b->interaction_after);
    if (n)
        printf("WARNING: %d share%s outside 0..100 %% (%s): a share is no fraction of the "
               "total there; the sources interact (the interaction row holds what they do "
               "together) or the units are too few (more --units narrow the intervals)\n",
               n, n == 1 ? "" : "s", list);
}

static void fmt_limit(char *buf, size_t len, const budget_source *s)
{
    char lo[32] = "-", hi[32] = "-";
    if (!isnan(s->limit_ci.lo))
        snprintf(lo, sizeof lo, "%.3g", s->limit_ci.lo);
    if (!isnan(s->limit_ci.hi))
        snprintf(hi, sizeof hi, "%.3g", s->limit_ci.hi);
    if (s->limit_runs == 0)
        snprintf(buf, len, "-");
    else if (s->limit_status == BUDGET_LIMIT_UNMET)
        snprintf(buf, len, "unmet even at 0 (%s)", end_names[s->limit_end]);
    else if (s->limit_status == BUDGET_LIMIT_AT_MAX)
        snprintf(buf, len, ">= %g (key max) [%s, -]", s->limit, lo);
    else
        snprintf(buf, len, "%.4g [%s, %s] (%.1fx today; %s)", s->limit, lo, hi,
                 s->limit / s->tolerance, end_names[s->limit_end]);
}

/* One row of the table: rank, source, today, unit | alone before, after |
 * share before, after | inverse limit. */
static void print_row(table *t, const char *rank, const char *name, const char *today,
                      const char *unit, const budget_stats *alone, const budget_share *sb,
                      const budget_share *sa, const char *limit, int prec)
{
    int r = table_row(t);
    if (r < 0)
        return;
    table_set(t, r, 0, "%s", rank);
    table_set(t, r, 1, "%s", name);
    table_set(t, r, 2, "%s", today);
    table_set(t, r, 3, "%s", unit);
    if (alone) {
        table_set(t, r, 4, "%.*f", prec, alone->before_mean);
        table_set(t, r, 5, "%.*f", prec, alone->after_mean);
    }
    fmt_share(table_cell(t, r, 6), TABLE_CELL, sb);
    fmt_share(table_cell(t, r, 7), TABLE_CELL, sa);
    table_set(t, r, 8, "%s", limit);
}

static void print_table(const sunmc_config *c, const sensor_family *fam, const budget_result *b)
{
    char band[32];
    report_band_label(c, b->band, band, sizeof band);
    const char *u = fam->rms_unit;
    int prec = report_decimals(fam);
    printf("\n%s (%s): error budget, %ld units per run (%ld with a fit in every run), seed %ld;"
           " %s in band %s deg\n",
           c->product, fam->name, b->units, b->paired_units, c->seed, fam->angle_names[b->angle],
           band);
    int dy = report_percent_decimals(b->all.yield, 1);
    printf("all sources: mean RMS before %.*f, after %.*f %s, yield %.*f%% [%.*f, %.*f];  every "
           "tolerance 0 (design + noise): before %.*f, after %.*f\n",
           prec, b->all.before_mean, prec, b->all.after_mean, u, dy, 100 * b->all.yield, dy,
           100 * b->all.yield_ci.lo, dy, 100 * b->all.yield_ci.hi, prec, b->no_tolerance.before_mean,
           prec, b->no_tolerance.after_mean);
    char h[64], ci[32], lim[64];
    report_ci_label(c, ci, sizeof ci);
    snprintf(h, sizeof h, "share of the mean square %s", ci);
    snprintf(lim, sizeof lim, "yield %.0f%%, spec %g\"", 100 * c->yield_target, c->spec_arcsec);
    table *t = table_new(9);
    if (!t)
        return;
    table_head(t, 0, "rank", "", TABLE_LEFT);
    table_head(t, 1, "source", "", TABLE_LEFT);
    table_head(t, 2, "today", "", 0);
    table_head(t, 3, "unit", "", TABLE_LEFT);
    table_head(t, 4, "mean RMS alone", "before", TABLE_BAR);
    table_head(t, 5, "", "after", 0);
    table_head(t, 6, h, "before", TABLE_BAR | TABLE_LEFT);
    table_head(t, 7, "", "after", TABLE_LEFT);
    table_head(t, 8, "inverse limit [CI]", lim, TABLE_BAR | TABLE_LEFT);
    print_row(t, "", "FLOOR (design, no noise)", "", "", &b->floor, &b->floor_before,
              &b->floor_after, "", prec);
    for (int i = 0; i < b->n; i++) {
        const budget_source *s = &b->src[b->order[i]];
        char rank[16], today[32], limit[96];
        snprintf(rank, sizeof rank, "%d%s", s->rank, s->in_noise ? "*" : "");
        snprintf(today, sizeof today, "%.4g", s->tolerance);
        fmt_limit(limit, sizeof limit, s);
        print_row(t, rank, s->name, today, s->key->unit[0] ? s->key->unit : "-", &s->alone,
                  &s->share_before, &s->share_after, limit, prec);
    }
    print_row(t, "", "INTERACTION (rest)", "", "", NULL, &b->interaction_before,
              &b->interaction_after, "", prec);
    table_print(stdout, t);
    table_free(t);
    printf("RMS in %s.  Floor + sources + interaction = 100 %% of the mean square of all sources "
           "(MS_all);\na source's share is (MS of the floor with it alone - MS of the floor) / "
           "MS_all.  ~ = the interval\nincludes 0: inside the Monte Carlo noise (more --units "
           "narrow it).  Ranked by the share after\ncalibration, then before, each counted "
           "only outside the noise; * = every share inside the noise:\nlisted last, their "
           "order means nothing.\n",
           u);
    char rule[256];
    verdict_rule_text(c, rule, sizeof rule);
    printf("Yield and inverse limits judged by the spec: %s (verdict: `sunmc config "
           "--reference`,\nreport.spec_*); the limit's end: spec (units over it), coverage "
           "(units lost their field), fit\n(fits failed), range (the key's maximum).\n",
           rule);
    printf("%ld unit runs (each inverse limit's yield at today's value is the all-sources run's "
           "first %ld units;\nthe floor is one unit, copied); %ld of them finished from another "
           "run's validation readings.\n",
           budget_unit_runs(b), c->budget_units, budget_reused_units(b));
    print_parts(b);
    warn_outside(b);
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
    if (status == SUNMC_OK) {
        budget_meter bm = {.quiet = o.quiet, .units = units,
                           .per_limit = (long)(c->budget_steps + 2) * c->budget_units};
        status = budget_run(c, units, threads, 1, progress, &bm, b, err, sizeof err);
        if (bm.n_runs)
            cli_meter_end(&bm.m);
    }
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
