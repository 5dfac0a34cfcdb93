/* cmd_curve.c - `sunmc curve`: one unit's (--unit U) or one error source's
 * (--only KEY=VALUE) error before and after compensation at every point of
 * the validation grid (ESS: alpha curves, one per beta; DSS: (b1, b2) maps). */
#include "cli.h"
#include "family.h"
#include "output.h"
#include "report.h"
#include "status.h"
#include "tsvnum.h"
#include "thermal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char curve_help[] =
    "usage: sunmc curve CONFIG (--unit U | --only KEY=VALUE [--unit U]) [--seed S]\n"
    "                   [--set SECTION.KEY=VALUE]... [--out DIR] [--quiet]\n"
    "Error vs table angle, before and after the unit's own calibration, on the validation\n"
    "grid (ESS: validation.alpha_* for each validation.beta_deg; DSS: validation.b_* in both\n"
    "axes), noiseless readings of the unit (its campaign keeps the config's noise).\n"
    "  --unit U          unit U of the Monte Carlo (same draws as in `sunmc run`)\n"
    "  --only KEY=VALUE  one error source alone: tolerance KEY (e.g. dH_um) fixed at VALUE\n"
    "                    (negative: the mirror deviation), every other tolerance 0\n"
    "Columns error_source_* are the error the unit's deviations add to the nominal design\n"
    "(the same reading of a unit with every tolerance 0): the paper's 'error caused by'.\n"
    "--out DIR writes curve.tsv (one block per series, blank line between blocks) and\n"
    "config.ini.  Change the grid with e.g. --set validation.alpha_step_deg=0.5.\n";

/* Every tolerance of st's family to 0 (nominal), through config_set_value. */
static int set_nominal(config_state *st, char *err, size_t errlen)
{
    const sensor_family *fam = st->cfg.family;
    for (const config_key *k = fam->keys; k && k->section; k++)
        if (config_is_tolerance(k, fam)) {
            int s = config_set_value(st, "tolerance", k->name, "0", "--only", err, errlen);
            if (s)
                return s;
        }
    return SUNMC_OK;
}

/* Apply --only KEY=VALUE: nominal elsewhere, KEY fixed at |VALUE|; *sign is
 * the sign of VALUE. */
static int apply_only(config_state *st, const char *spec, double *sign, char *err, size_t errlen)
{
    const char *eq = strchr(spec, '=');
    char name[CONFIG_STR_MAX];
    if (!eq || eq == spec || (size_t)(eq - spec) >= sizeof name)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--only %s: expected KEY=VALUE, e.g. dH_um=2",
                          spec);
    const char *key = spec;
    if (strncmp(key, "tolerance.", strlen("tolerance.")) == 0)
        key += strlen("tolerance.");
    memcpy(name, key, (size_t)(eq - key));
    name[eq - key] = '\0';
    const config_key *k = config_find_in(st->cfg.family, "tolerance", name);
    if (!k || !config_is_tolerance(k, st->cfg.family)) {
        char hint[2 * CONFIG_STR_MAX + 32];
        config_suggest(st->cfg.family, "tolerance", name, hint, sizeof hint);
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--only %s: '%s' is not a tolerance key of this sensor family%s", spec,
                          name, hint);
    }
    const char *val = eq + 1;
    while (*val == ' ')
        val++;
    *sign = 1.0;
    if (*val == '-') {
        *sign = -1.0;
        val++;
    }
    int s = set_nominal(st, err, errlen);
    if (s == SUNMC_OK)
        s = config_set_value(st, "tolerance", name, val, "--only", err, errlen);
    char dist[2 * CONFIG_STR_MAX];
    snprintf(dist, sizeof dist, "%s_dist", name);
    if (s == SUNMC_OK)
        s = config_set_value(st, "tolerance", dist, "fixed", "--only", err, errlen);
    return s;
}

#define CURVE_BISECTIONS 12 /* the boundary of the readings to 2.4e-4 of the value */

typedef struct {
    double sum2[3];       /* before, after, source */
    double maxabs[3];
    long n[3];
} series_stats;

static void stats_add(series_stats *s, int i, double e)
{
    if (!isfinite(e))
        return;
    s->sum2[i] += e * e;
    s->maxabs[i] = fmax(s->maxabs[i], fabs(e));
    s->n[i]++;
}

/* One curve command's state: the unit (c) and the nominal design (nom),
 * their prepared curve workspaces, the grid and the statistics per series
 * (axis-1 value) and angle. */
typedef struct {
    const sensor_family *fam;
    const sunmc_config *c, *nom;
    long n0, n1;
    int na;
    double *ax0, *ax1;
    series_stats *ss;
    void *cv, *cn;
    int fit_ok, nom_ok;
    long unseen;
    long uncompensated;   /* points seen whose after error is not a number */
} curve_run;

static void curve_free(curve_run *r)
{
    if (r->cv)
        r->fam->curve->free(r->cv);
    if (r->cn)
        r->fam->curve->free(r->cn);
    free(r->ax0);
    free(r->ax1);
    free(r->ss);
}

/* Allocate the grid and workspaces, and prepare unit `unit` (its
 * deviations times sign) and the nominal unit. */
static int curve_setup(curve_run *r, const sunmc_config *c, const sunmc_config *nom, long unit,
                       double sign, char *err, size_t errlen)
{
    const sensor_family *fam = c->family;
    memset(r, 0, sizeof *r);
    r->fam = fam;
    r->c = c;
    r->nom = nom;
    r->n0 = fam->curve->axis(c, 0, NULL, 0);
    r->n1 = fam->curve->axis(c, 1, NULL, 0);
    r->na = fam->n_angles(c);
    r->ax0 = malloc((size_t)(r->n0 > 0 ? r->n0 : 1) * sizeof *r->ax0);
    r->ax1 = malloc((size_t)(r->n1 > 0 ? r->n1 : 1) * sizeof *r->ax1);
    r->ss = calloc((size_t)(r->n1 > 0 ? r->n1 : 1) * (size_t)r->na, sizeof *r->ss);
    r->cv = fam->curve->alloc(c, err, errlen);
    r->cn = r->cv ? fam->curve->alloc(nom, err, errlen) : NULL;
    if (!r->cv || !r->cn)
        return SUNMC_ENOMEM;
    if (!r->ax0 || !r->ax1 || !r->ss)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the curve grid");
    fam->curve->axis(c, 0, r->ax0, r->n0);
    fam->curve->axis(c, 1, r->ax1, r->n1);
    int status = fam->curve->prepare(c, unit, sign, r->cv, &r->fit_ok);
    if (status == SUNMC_OK)
        status = fam->curve->prepare(nom, unit, 1.0, r->cn, &r->nom_ok);
    return status;
}

static void curve_header(const curve_run *r, FILE *fo)
{
    const sensor_family *fam = r->fam;
    const char *u = fam->rms_unit;
    fprintf(fo, "%s\t%s", fam->curve->axis_names[0], fam->curve->axis_names[1]);
    for (int a = 0; a < r->na; a++)
        fprintf(fo, "\terror_before_%s_%s\terror_after_%s_%s\terror_source_%s_%s",
                fam->angle_names[a], u, fam->angle_names[a], u, fam->angle_names[a], u);
    fputc('\n', fo);
}

static int all_finite(const double *v, int n)
{
    for (int a = 0; a < n; a++)
        if (!isfinite(v[a]))
            return 0;
    return 1;
}

/* Evaluate every grid point (before, after, the source alone = before
 * minus the nominal unit's before), into the statistics and, when fo is
 * open, one row of curve.tsv each; a blank line between series. */
static void curve_walk(curve_run *r, FILE *fo)
{
    const sensor_family *fam = r->fam;
    int na = r->na;
    for (long j = 0; j < r->n1; j++) {
        if (fo && j > 0)
            fputc('\n', fo);
        for (long i = 0; i < r->n0; i++) {
            double bef[UNIT_MAX_ANGLES], aft[UNIT_MAX_ANGLES], nb[UNIT_MAX_ANGLES],
                na_[UNIT_MAX_ANGLES];
            int s1 = fam->curve->eval(r->c, r->cv, r->ax0[i], r->ax1[j], bef, aft);
            int s2 = fam->curve->eval(r->nom, r->cn, r->ax0[i], r->ax1[j], nb, na_);
            if (s1 != SUNMC_OK) {
                r->unseen++;
                for (int a = 0; a < na; a++)
                    bef[a] = aft[a] = NAN;
            }
            if (fo)
                tsv_printf(fo, "%.10g\t%.10g", r->ax0[i], r->ax1[j]);
            r->uncompensated += s1 == SUNMC_OK && !all_finite(aft, na);
            for (int a = 0; a < na; a++) {
                double src = (s1 == SUNMC_OK && s2 == SUNMC_OK) ? bef[a] - nb[a] : NAN;
                series_stats *s = &r->ss[j * na + a];
                stats_add(s, 0, bef[a]);
                stats_add(s, 1, aft[a]);
                stats_add(s, 2, src);
                if (fo)
                    tsv_printf(fo, "\t%.8g\t%.8g\t%.8g", bef[a], aft[a], src);
            }
            if (fo)
                fputc('\n', fo);
        }
    }
}

/* One number of the table, or "-" where there is none (no point). */
static void print_cell(double v, int prec)
{
    char text[64];
    report_format_number(text, sizeof text, v, prec);
    printf(" %9s", text);
}

/* The table on stdout: RMS and max |error| per series and angle. */
static void curve_print(const curve_run *r, const char *only, long unit)
{
    const sensor_family *fam = r->fam;
    const char *u = fam->rms_unit;
    int prec = report_decimals(fam), na = r->na;
    printf("\n%s (%s): ", r->c->product, fam->name);
    if (only)
        printf("%s alone, every other tolerance 0 (unit %ld's noise in the campaign)", only, unit);
    else
        printf("unit %ld, seed %ld", unit, r->c->seed);
    if (thermal_n_temps(r->c) > 0)
        printf("; calibrated at %g C, validated at %g C (the first operating temperature)",
               r->c->cal_temp_c, thermal_temp_c(r->c, 0));
    printf("%s\n", r->fit_ok ? "" : "  -- its fit FAILED: no after-compensation curve");
    printf("%-10s %-6s | %9s %9s %9s | %9s %9s %9s | %s\n", fam->curve->axis_names[1], "angle",
           "RMS", "", "", "max |err|", "", "", "points");
    printf("%-10s %-6s | %9s %9s %9s | %9s %9s %9s |\n", "", "", "before", "after", "source",
           "before", "after", "source");
    for (long j = 0; j < r->n1; j++)
        for (int a = 0; a < na; a++) {
            const series_stats *s = &r->ss[j * na + a];
            printf("%-10.4g %-6s |", r->ax1[j], fam->angle_names[a]);
            for (int k = 0; k < 3; k++)
                print_cell(s->n[k] ? sqrt(s->sum2[k] / (double)s->n[k]) : NAN, prec);
            printf(" |");
            for (int k = 0; k < 3; k++)
                print_cell(s->n[k] ? s->maxabs[k] : NAN, prec);
            printf(" | %ld\n", s->n[0]);
        }
    printf("errors in %s; %ld grid points not seen or gross (left out)\n", u, r->unseen);
}

/* On stderr, whatever --quiet says: the grid points whose after error is
 * nan in curve.tsv and left out of the table's after columns. */
static void curve_warn(const curve_run *r)
{
    long seen = r->n0 * r->n1 - r->unseen;
    if (r->uncompensated == 0)
        return;
    if (!r->fit_ok)
        fprintf(stderr,
                "sunmc curve: WARNING: the unit's calibration fit FAILED: error_after is nan at "
                "all %ld grid points seen\n",
                r->uncompensated);
    else
        fprintf(stderr,
                "sunmc curve: WARNING: %ld of %ld grid points seen could not be compensated by the "
                "unit's fitted model (no inverse there): error_after is nan at them and the "
                "after columns leave them out\n",
                r->uncompensated, seen);
}

/* Grid points at which the unit of r gives a reading. */
static long curve_seen(const curve_run *r)
{
    double bef[UNIT_MAX_ANGLES], aft[UNIT_MAX_ANGLES];
    long seen = 0;
    for (long j = 0; j < r->n1; j++)
        for (long i = 0; i < r->n0; i++)
            seen += r->fam->curve->eval(r->c, r->cv, r->ax0[i], r->ax1[j], bef, aft) == SUNMC_OK;
    return seen;
}

/* Grid points seen by the sensor of `--only NAME=value` (-1: the config
 * refuses that value). */
static long seen_at(const cli_options *o, const char *name, double value)
{
    config_state t, nom;
    char spec[2 * CONFIG_STR_MAX], err[SUNMC_ERRLEN];
    double sign = 1.0;
    snprintf(spec, sizeof spec, "%s=%.17g", name, value);
    long seen = -1;
    if (config_build_unchecked(&t, o->config, o->sets, o->n_sets, err, sizeof err) != SUNMC_OK)
        return -1;
    if (config_build_unchecked(&nom, o->config, o->sets, o->n_sets, err, sizeof err) == SUNMC_OK) {
        curve_run r;
        memset(&r, 0, sizeof r);
        if (apply_only(&t, spec, &sign, err, sizeof err) == SUNMC_OK &&
            set_nominal(&nom, err, sizeof err) == SUNMC_OK &&
            config_check(&t, o->config, err, sizeof err) == SUNMC_OK &&
            config_check(&nom, o->config, err, sizeof err) == SUNMC_OK &&
            curve_setup(&r, &t.cfg, &nom.cfg, 0, sign, err, sizeof err) == SUNMC_OK)
            seen = curve_seen(&r);
        if (r.fam)
            curve_free(&r);
        config_state_free(&nom);
    }
    config_state_free(&t);
    return seen;
}

/* --only NAME=VALUE gives a sensor that sees no grid point: refused, with
 * the value (found by bisection between 0 and VALUE) where readings stop. */
static int only_impossible(const cli_options *o, long points, char *err, size_t errlen)
{
    const char *eq = strchr(o->only, '=');
    char name[CONFIG_STR_MAX];
    snprintf(name, sizeof name, "%.*s", (int)(eq - o->only), o->only);
    double bad = strtod(eq + 1, NULL), good = 0.0;
    if (seen_at(o, name, good) <= 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "curve --only %s: the sensor gives no reading "
                          "at any of the %ld grid points, even with %s = 0", o->only, points,
                          name);
    for (int it = 0; it < CURVE_BISECTIONS; it++) {
        double mid = 0.5 * (good + bad);
        *(seen_at(o, name, mid) > 0 ? &good : &bad) = mid;
    }
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "curve --only %s: an impossible sensor: it gives no reading at any of the "
                      "%ld grid points (every cell would be '-'); with every other tolerance 0 it "
                      "reads from %s = 0 to about %.4g (bisection), and nothing from %.4g on",
                      o->only, points, name, good, bad);
}

/* Walk the grid, writing curve.tsv and config.ini to o->out (all or
 * nothing; a failed write is returned in *wstatus, the table still
 * prints). */
static int curve_output(curve_run *r, const cli_options *o, const config_state *st, long unit,
                        int *wstatus, char *err, size_t errlen)
{
    out_set os;
    FILE *fo = NULL, *fc = NULL;
    int status = SUNMC_OK;
    *wstatus = SUNMC_OK;
    if (o->out) {
        status = out_begin(&os, o->out, err, errlen);
        if (status == SUNMC_OK)
            status = out_open(&os, "curve.tsv", &fo, err, errlen);
        if (status == SUNMC_OK)
            status = out_open(&os, "config.ini", &fc, err, errlen);
        if (status != SUNMC_OK) {
            out_abort(&os);
            return status;
        }
        curve_header(r, fo);
    }
    curve_walk(r, fo);
    if (fc) {
        if (o->only)
            fprintf(fc, "# curve --only %s (unit %ld), every other tolerance 0\n", o->only, unit);
        else
            fprintf(fc, "# curve --unit %ld\n", unit);
        config_write(fc, st);
    }
    if (fo)
        *wstatus = out_commit(&os, err, errlen);
    return SUNMC_OK;
}

int cmd_curve(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, curve_help))
        return 0;
    cli_options o;
    int rc = cli_parse(argc, argv, 2, "curve", "CONFIG seed set out quiet unit only", &o);
    if (rc)
        return rc;
    if (o.unit < 0 && !o.only) {
        fprintf(stderr, "sunmc curve: needs --unit U or --only KEY=VALUE (see sunmc curve --help)\n");
        return EXIT_BAD_INPUT;
    }
    /* The cross-key checks come after --only: a tolerance it switches off
     * cannot make the unit impossible. */
    config_state st, nom;
    char err[SUNMC_ERRLEN];
    int status = config_build_unchecked(&st, o.config, o.sets, o.n_sets, err, sizeof err);
    if (status != SUNMC_OK) {
        fprintf(stderr, "sunmc: %s\n", err);
        return cli_exit_code(status);
    }
    if ((status = config_build_unchecked(&nom, o.config, o.sets, o.n_sets, err, sizeof err))) {
        config_state_free(&st);
        fprintf(stderr, "sunmc: %s\n", err);
        return cli_exit_code(status);
    }
    double sign = 1.0;
    int wstatus = SUNMC_OK;
    if (o.only)
        status = apply_only(&st, o.only, &sign, err, sizeof err);
    if (status == SUNMC_OK)
        status = set_nominal(&nom, err, sizeof err);
    if (status == SUNMC_OK)
        status = config_check(&st, o.config, err, sizeof err);
    if (status == SUNMC_OK)
        status = config_check(&nom, o.config, err, sizeof err);
    long unit = o.unit >= 0 ? o.unit : 0;
    if (status == SUNMC_OK && !st.cfg.family->curve)
        status = sunmc_fail(err, sizeof err, SUNMC_EINPUT,
                            "the %s family has no error curves in this version",
                            st.cfg.family->name);
    curve_run r;
    memset(&r, 0, sizeof r);
    if (status == SUNMC_OK)
        status = curve_setup(&r, &st.cfg, &nom.cfg, unit, sign, err, sizeof err);
    if (status == SUNMC_OK && curve_seen(&r) == 0)
        status = o.only ? only_impossible(&o, r.n0 * r.n1, err, sizeof err)
                        : sunmc_fail(err, sizeof err, SUNMC_EINPUT,
                                     "curve --unit %ld: the unit gives no reading at any of the "
                                     "%ld grid points (every cell would be '-')",
                                     unit, r.n0 * r.n1);
    if (status == SUNMC_OK)
        status = curve_output(&r, &o, &st, unit, &wstatus, err, sizeof err);
    if (status == SUNMC_OK) {
        curve_print(&r, o.only, unit);
        curve_warn(&r);
    }
    if (status != SUNMC_OK || wstatus != SUNMC_OK)
        fprintf(stderr, "sunmc curve: %s\n", err);
    if (status == SUNMC_OK)
        status = wstatus;
    if (r.fam)
        curve_free(&r);
    config_state_free(&st);
    config_state_free(&nom);
    return cli_exit_code(status);
}
