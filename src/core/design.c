/* design.c - candidate campaigns, screened and settled against the yield
 * target with common random numbers (design.h). */
#include "design.h"
#include "campaign.h"
#include "family.h"
#include "montecarlo.h"
#include "report.h"
#include "shortest.h"
#include "status.h"
#include "unit_store.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DESIGN_MAX_CANDIDATES 4096

const char *const design_verdict_names[DESIGN_VERDICTS] = {
    "pass", "fail", "screened out", "aliased", "undecided", "not settled"};

/* Set "section.key" of cfg from text, as a file value would be. */
static int set_key(sunmc_config *cfg, const char *dotted, const char *text, char *err,
                   size_t errlen)
{
    char sec[CONFIG_STR_MAX];
    const char *dot = strchr(dotted, '.');
    size_t ls = dot ? (size_t)(dot - dotted) : 0;
    if (!dot || ls >= sizeof sec)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "design: malformed key %s", dotted);
    memcpy(sec, dotted, ls);
    sec[ls] = '\0';
    const config_key *k = config_find_in(cfg->family, sec, dot + 1);
    if (!k)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "design: the family has no key %s", dotted);
    return config_parse_value(k, config_value_ptr(k, cfg), text, "sunmc design", err, errlen);
}

/* Table positions a lab sets: line angles rounded to 0.01 deg. */
#define DESIGN_LINE_RES_DEG 0.01

/* Line set of n lines evenly spaced over +-extent, each rounded to
 * DESIGN_LINE_RES_DEG (-40, -13.33, 13.33, 40, not 13.33333333), as
 * config text. */
static void line_set(int n, double extent, char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < n && used < len; i++) {
        double v = n == 1 ? 0.0 : -extent + 2.0 * extent * i / (n - 1);
        v = round(v / DESIGN_LINE_RES_DEG) * DESIGN_LINE_RES_DEG;
        used += (size_t)snprintf(buf + used, len - used, "%s%.10g", i ? ", " : "",
                                 fabs(v) < 1e-12 ? 0.0 : v);
    }
}

/* Add a candidate (skipped when its config does not validate, e.g. too few
 * points for the fit); a copy of the input campaign marks the input. */
static int add_candidate(design_result *d, const sunmc_config *base, const char *step,
                         const char *lines, int repeats)
{
    const sensor_family *fam = base->family;
    for (int i = 0; i < d->n; i++)
        if (strcmp(d->cand[i].step, step) == 0 && strcmp(d->cand[i].lines, lines) == 0 &&
            d->cand[i].repeats == repeats)
            return SUNMC_OK;
    if (d->n >= DESIGN_MAX_CANDIDATES)
        return SUNMC_OK;
    design_candidate *k = &d->cand[d->n];
    memset(k, 0, sizeof *k);
    k->cfg = *base;
    char err[SUNMC_ERRLEN], rep[16];
    snprintf(rep, sizeof rep, "%d", repeats);
    if (set_key(&k->cfg, fam->grid->design_step_key, step, err, sizeof err) != SUNMC_OK ||
        (lines[0] && set_key(&k->cfg, fam->grid->design_lines_key, lines, err, sizeof err) != SUNMC_OK) ||
        set_key(&k->cfg, "campaign.repeats", rep, err, sizeof err) != SUNMC_OK ||
        config_validate(&k->cfg, err, sizeof err) != SUNMC_OK)
        return SUNMC_OK;
    snprintf(k->step, sizeof k->step, "%s", step);
    snprintf(k->lines, sizeof k->lines, "%s", lines);
    k->repeats = repeats;
    k->is_input = d->n == 0;
    campaign_info ci;
    if (campaign_describe(&k->cfg, &ci, err, sizeof err) != SUNMC_OK)
        return SUNMC_ENOMEM;
    if (d->n > 0 && ci.known && ci.extrapolation_deg > base->search_max_extrapolation_deg) {
        d->n_extrapolating++;
        return SUNMC_OK;
    }
    k->points = ci.points;
    k->hours = ci.known ? ci.hours : NAN;
    k->extrapolation_deg = ci.known ? ci.extrapolation_deg : NAN;
    k->cfg.no_systematic = 1; /* the design reads no systematic part */
    k->yield = k->after_mean = NAN;
    k->yield_ci = k->after_ci = (stats_interval){NAN, NAN};
    d->n++;
    return SUNMC_OK;
}

int design_space(const sunmc_config *c, design_result *d, char *err, size_t errlen)
{
    memset(d, 0, sizeof *d);
    d->best = -1;
    const sensor_family *fam = c->family;
    if (!fam->grid || !fam->grid->design_step_key)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "design: the %s family names no campaign keys to search", fam->name);
    d->cand = calloc(DESIGN_MAX_CANDIDATES, sizeof *d->cand);
    if (!d->cand)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "design: out of memory");
    d->angle = fam->n_angles(c) - 1;
    d->band = report_widest_band(c);
    char step[DESIGN_TEXT], lines[DESIGN_TEXT] = "";
    const config_key *ks = NULL, *kl = NULL;
    for (const config_key *k = fam->keys; k && k->section; k++) {
        char dotted[2 * CONFIG_STR_MAX + 2];
        snprintf(dotted, sizeof dotted, "%s.%s", k->section, k->name);
        ks = strcmp(dotted, fam->grid->design_step_key) == 0 ? k : ks;
        kl = fam->grid->design_lines_key && strcmp(dotted, fam->grid->design_lines_key) == 0 ? k : kl;
    }
    if (!ks || (fam->grid->design_lines_key && !kl))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "design: %s's design keys are not its keys",
                          fam->name);
    config_format_value(ks, c, step, sizeof step);
    if (kl)
        config_format_value(kl, c, lines, sizeof lines);
    int s = add_candidate(d, c, step, lines, c->cal_repeats);
    if (s == SUNMC_OK && d->n == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "design: the input campaign is not valid");
    for (int i = 0; s == SUNMC_OK && i < c->search_steps_deg.n; i++) {
        shortest_double(c->search_steps_deg.v[i], step, sizeof step);
        for (int r = 0; s == SUNMC_OK && r < c->search_repeats.n; r++) {
            int rep = (int)c->search_repeats.v[r];
            if (!kl) {
                s = add_candidate(d, c, step, lines, rep);
                continue;
            }
            line_set(1, 0, lines, sizeof lines);
            s = add_candidate(d, c, step, lines, rep);
            for (int n = 2; s == SUNMC_OK && n <= c->search_max_lines; n++)
                for (double b = c->search_beta_step_deg;
                     s == SUNMC_OK && b <= c->search_beta_max_deg + 1e-9;
                     b += c->search_beta_step_deg) {
                    line_set(n, b, lines, sizeof lines);
                    s = add_candidate(d, c, step, lines, rep);
                }
        }
    }
    if (s != SUNMC_OK)
        return sunmc_fail(err, errlen, s, "design: out of memory");
    return SUNMC_OK;
}

/* What the runs of a design share: the block's results, the rows, and
 * the units' validation readings (every candidate reads the same). */
typedef struct {
    unit_result *buf;
    summary_row *rows;
    unit_store *store;
    int threads;
} design_work;

/* Candidate k has run n more units, added to acc: its statistics. */
static void took(design_result *d, design_candidate *k, report_acc *acc, long n,
                 summary_row *rows)
{
    k->units += n;
    d->units_run += n;
    report_acc_rows(acc, rows);
    const summary_row *r = &rows[report_primary_row(&k->cfg, d->angle, d->band)];
    k->yield = r->spec_yield; /* the spec's verdict (verdict.h), every band it names */
    k->yield_ci = r->spec_yield_ci;
    k->after_mean = r->rms_after_mean;
    k->after_ci = r->rms_after_mean_ci;
    k->alias_units = r->alias_units;
    k->fit_failures = r->fit_failures;
}

/* Run candidate k on its next n units (common random numbers: units
 * [k->units, k->units + n) of the same seed) and refresh its statistics. */
static int run_more(design_result *d, design_candidate *k, report_acc *acc, long n,
                    design_work *w, char *err, size_t errlen)
{
    int s = mc_run_store(&k->cfg, w->store, k->units, k->units + n, w->threads, w->buf, NULL,
                         NULL, err, errlen);
    if (s == SUNMC_OK && report_acc_add(acc, w->buf, n) != SUNMC_OK)
        s = sunmc_fail(err, errlen, SUNMC_ENOMEM, "design: out of memory");
    if (s == SUNMC_OK)
        took(d, k, acc, n, w->rows);
    return s;
}

/* The screen: every candidate on the same first units, a candidate to a
 * thread (mc_run_each), each one's results into its accumulator. */
typedef struct {
    report_acc **acc;
    design_progress_fn progress;
    void *ctx;
} screen_ctx;

static int screen_sink(int i, const unit_result *res, long n, void *ctx, char *err, size_t errlen)
{
    screen_ctx *sc = ctx;
    if (report_acc_add(sc->acc[i], res, n) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "design: out of memory");
    return SUNMC_OK;
}

static void screen_progress(long done, long total, void *ctx)
{
    const screen_ctx *sc = ctx;
    sc->progress("screen", (int)done, (int)total, sc->ctx);
}

static int screen(design_result *d, report_acc **acc, design_work *w, design_progress_fn progress,
                  void *ctx, char *err, size_t errlen)
{
    long n = d->cand[0].cfg.search_screen_units;
    const sunmc_config **cfg = calloc((size_t)d->n, sizeof *cfg);
    int s = cfg ? SUNMC_OK : SUNMC_ENOMEM;
    for (int i = 0; s == SUNMC_OK && i < d->n; i++) {
        cfg[i] = &d->cand[i].cfg;
        if (!(acc[i] = report_acc_new(cfg[i])))
            s = SUNMC_ENOMEM;
    }
    screen_ctx sc = {acc, progress, ctx};
    if (s == SUNMC_OK)
        s = mc_run_each(cfg, d->n, w->store, 0, n, w->threads, screen_sink, &sc,
                        progress ? screen_progress : NULL, &sc, err, errlen);
    free(cfg);
    for (int i = 0; s == SUNMC_OK && i < d->n; i++) {
        design_candidate *k = &d->cand[i];
        took(d, k, acc[i], n, w->rows);
        k->verdict = k->alias_units > 0                         ? DESIGN_ALIASED
                     : k->yield_ci.hi < k->cfg.yield_target     ? DESIGN_SCREENED_OUT
                                                                : DESIGN_NOT_SETTLED;
        if (k->verdict != DESIGN_NOT_SETTLED && !k->is_input) {
            report_acc_free(acc[i]);
            acc[i] = NULL;
        }
    }
    return s;
}

static const design_result *sort_ctx;

static int by_cost(const void *a, const void *b)
{
    const design_candidate *x = &sort_ctx->cand[*(const int *)a];
    const design_candidate *y = &sort_ctx->cand[*(const int *)b];
    if (x->hours != y->hours)
        return x->hours < y->hours ? -1 : 1;
    if (x->yield != y->yield)
        return x->yield > y->yield ? -1 : 1;
    return *(const int *)a - *(const int *)b;
}

/* Pareto front of yield against hours over the candidates with a yield
 * that did not alias: none cheaper-or-equal with a higher yield. */
static void mark_pareto(design_result *d)
{
    double best_yield = -1;
    for (int j = 0; j < d->n; j++) {
        design_candidate *k = &d->cand[d->order[j]];
        if (k->verdict == DESIGN_ALIASED || !isfinite(k->yield))
            continue;
        k->pareto = k->yield > best_yield;
        best_yield = fmax(best_yield, k->yield);
    }
}

/* Settle candidate k in blocks: pass, fail or undecided. */
static int settle(design_result *d, design_candidate *k, report_acc *acc, design_work *w,
                  char *err, size_t errlen)
{
    const sunmc_config *c = &k->cfg;
    for (;;) {
        if (k->yield_ci.lo >= c->yield_target) {
            k->verdict = DESIGN_PASS;
            return SUNMC_OK;
        }
        if (k->yield_ci.hi < c->yield_target) {
            k->verdict = DESIGN_FAIL;
            return SUNMC_OK;
        }
        if (k->units >= c->search_max_units) {
            k->verdict = DESIGN_UNDECIDED;
            return SUNMC_OK;
        }
        long n = c->block_units;
        n = k->units + n > c->search_max_units ? c->search_max_units - k->units : n;
        int s = run_more(d, k, acc, n, w, err, errlen);
        if (s != SUNMC_OK)
            return s;
    }
}

/* Units of readings the design keeps: a block, or the screen's units
 * when a block's would take more than DESIGN_STORE_MAX_BYTES (many
 * operating temperatures), or none. */
#define DESIGN_STORE_MAX_BYTES 256e6
static long store_units(const sunmc_config *c, long block)
{
    if (unit_store_bytes(c, block) <= DESIGN_STORE_MAX_BYTES)
        return block;
    if (unit_store_bytes(c, c->search_screen_units) <= DESIGN_STORE_MAX_BYTES)
        return c->search_screen_units;
    return 0;
}

int design_run(design_result *d, int threads, design_progress_fn progress, void *ctx, char *err,
               size_t errlen)
{
    const sunmc_config *c0 = &d->cand[0].cfg;
    long block = c0->block_units > c0->search_screen_units ? c0->block_units
                                                           : c0->search_screen_units;
    design_work w = {calloc((size_t)block, sizeof *w.buf),
                     calloc((size_t)report_n_rows(c0), sizeof *w.rows), NULL, threads};
    report_acc **acc = calloc((size_t)d->n, sizeof *acc);
    d->order = calloc((size_t)d->n, sizeof *d->order);
    int s = w.buf && w.rows && acc && d->order ? SUNMC_OK : SUNMC_ENOMEM;
    if (s == SUNMC_OK && !d->no_reuse)
        s = unit_store_alloc(c0, store_units(c0, block), &w.store, err, errlen);
    if (s == SUNMC_OK)
        s = screen(d, acc, &w, progress, ctx, err, errlen);
    for (int i = 0; i < d->n; i++)
        d->order[i] = i;
    sort_ctx = d;
    if (s == SUNMC_OK)
        qsort(d->order, (size_t)d->n, sizeof *d->order, by_cost);
    int passed = 0;
    for (int j = 0; s == SUNMC_OK && j < d->n; j++) {
        design_candidate *k = &d->cand[d->order[j]];
        int input = k->is_input && k->verdict != DESIGN_ALIASED;
        if ((k->verdict != DESIGN_NOT_SETTLED && !input) || (passed >= c0->search_shortlist && !input))
            continue;
        if (progress)
            progress("settle", j + 1, d->n, ctx);
        s = settle(d, k, acc[d->order[j]], &w, err, errlen);
        passed += s == SUNMC_OK && k->verdict == DESIGN_PASS;
    }
    if (s == SUNMC_OK) {
        qsort(d->order, (size_t)d->n, sizeof *d->order, by_cost);
        mark_pareto(d);
        for (int j = 0; j < d->n && d->best < 0; j++)
            if (d->cand[d->order[j]].verdict == DESIGN_PASS)
                d->best = d->order[j];
    }
    if (s == SUNMC_ENOMEM)
        sunmc_fail(err, errlen, s, "design: out of memory");
    d->units_reused = w.store ? d->units_run - unit_store_reads(w.store) : 0;
    unit_store_free(w.store);
    for (int i = 0; acc && i < d->n; i++)
        report_acc_free(acc[i]);
    free(acc);
    free(w.buf);
    free(w.rows);
    return s;
}

void design_free(design_result *d)
{
    free(d->cand);
    free(d->order);
    memset(d, 0, sizeof *d);
}
