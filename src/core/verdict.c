/* verdict.c - whether a unit meets the spec (verdict.h). */
#include "verdict.h"
#include "bands.h"
#include "status.h"
#include "thermal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A read share this close to the required one meets it (n of n). */
#define VERDICT_COVERAGE_EPS 1e-12

static const char *const statistic_names[] = {"rms", "p99.7", "max"};
static const char *const why_names[] = {"pass", "no_fit", "coverage", "over_spec"};

const char *verdict_statistic_name(const sunmc_config *c)
{
    int s = c->spec_statistic;
    return s >= 0 && s <= VERDICT_MAX ? statistic_names[s] : "?";
}

const char *verdict_why_name(int why)
{
    return why >= 0 && why <= VERDICT_OVER_SPEC ? why_names[why] : "?";
}

int verdict_angle(const sunmc_config *c)
{
    return c->family->n_angles(c) - 1;
}

int verdict_tail_keep(const sunmc_config *c)
{
    return c->spec_statistic == VERDICT_RMS ? 0 : c->spec_statistic == VERDICT_MAX ? 1
                                                                                   : BAND_TAIL_MAX;
}

double verdict_level(const sunmc_config *c)
{
    return c->spec_statistic == VERDICT_P997 ? VERDICT_P997_LEVEL : 1.0;
}

/* The band of c's list written as "lo:hi" in [a, b) (blanks trimmed), or
 * -1. */
static int band_named(const sunmc_config *c, const char *a, const char *b)
{
    while (a < b && (*a == ' ' || *a == '\t'))
        a++;
    while (b > a && (b[-1] == ' ' || b[-1] == '\t'))
        b--;
    char text[CONFIG_STR_MAX];
    size_t n = (size_t)(b - a);
    if (n == 0 || n >= sizeof text)
        return -1;
    memcpy(text, a, n);
    text[n] = '\0';
    char *end;
    double lo = strtod(text, &end);
    if (end == text || *end != ':')
        return -1;
    char *hi_at = end + 1;
    double hi = strtod(hi_at, &end);
    if (end == hi_at || *end != '\0')
        return -1;
    for (int i = 0; i < c->bands_deg.n; i++)
        if (fabs(c->bands_deg.lo[i] - lo) <= BAND_EPS && fabs(c->bands_deg.hi[i] - hi) <= BAND_EPS)
            return i;
    return -1;
}

/* The bits of spec_bands, or a message naming the item that is not a band. */
static int parse_bands(const sunmc_config *c, unsigned *mask, char *err, size_t errlen)
{
    const char *s = c->spec_bands;
    *mask = 0;
    if (strcmp(s, "all") == 0 || s[0] == '\0') {
        *mask = c->bands_deg.n >= 32 ? ~0u : (1u << c->bands_deg.n) - 1u;
        return SUNMC_OK;
    }
    for (const char *a = s;;) {
        const char *b = strchr(a, ',');
        if (!b)
            b = a + strlen(a);
        int i = band_named(c, a, b);
        if (i < 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "report.spec_bands: '%.*s' is not one of report.bands_deg's bands "
                              "(write them as there, lo:hi in deg, or all)",
                              (int)(b - a), a);
        *mask |= 1u << i;
        if (*b == '\0')
            break;
        a = b + 1;
    }
    return SUNMC_OK;
}

unsigned verdict_band_mask(const sunmc_config *c)
{
    unsigned m;
    char err[SUNMC_ERRLEN];
    return parse_bands(c, &m, err, sizeof err) == SUNMC_OK ? m : 0;
}

int verdict_check(const sunmc_config *c, char *err, size_t errlen)
{
    unsigned m;
    return parse_bands(c, &m, err, errlen);
}

/* Statistic and read points of angle a, band b at set (a temperature t or
 * the lab's). */
static void cell_of(const unit_result *r, int a, int b, int set, double *stat, int *read)
{
    if (set >= 0) {
        *stat = r->stat_after_t[set][a][b];
        *read = r->read_after_t[set][a][b];
    } else {
        *stat = r->stat_after[a][b];
        *read = r->read_after[a][b];
    }
}

/* The verdict in one band at one set (not the worst): into v. */
static void judge_band(const sunmc_config *c, const unit_result *r, int a, int b, int set,
                       verdict *v)
{
    double stat;
    int read;
    cell_of(r, a, b, set, &stat, &read);
    int pts = r->points[b];
    v->band = b;
    v->stat = stat;
    v->coverage = pts > 0 ? (double)read / (double)pts : 0.0;
    double spec = c->spec_arcsec / c->family->arcsec_per_rms_unit;
    if (r->fit_status != UNIT_FIT_OK) {
        v->why = VERDICT_NO_FIT;
        v->band = -1;
    } else if (read == 0 || (double)read + VERDICT_COVERAGE_EPS < c->min_coverage * (double)pts) {
        v->why = VERDICT_COVERAGE;
    } else if (!(stat <= spec)) {
        v->why = VERDICT_OVER_SPEC;
    } else {
        v->why = VERDICT_PASS;
    }
    v->pass = v->why == VERDICT_PASS;
}

/* Over the spec's bands at one set: the first failing band, else the
 * passing band closest to the spec (largest statistic). */
static void judge_set(const sunmc_config *c, const unit_result *r, int a, int set, verdict *v)
{
    unsigned m = verdict_band_mask(c);
    int found = 0;
    for (int b = 0; b < c->bands_deg.n; b++) {
        if (!((m >> b) & 1u))
            continue;
        verdict vb;
        judge_band(c, r, a, b, set, &vb);
        if (!vb.pass) {
            *v = vb;
            return;
        }
        if (!found || vb.stat > v->stat)
            *v = vb;
        found = 1;
    }
    if (!found) { /* no band named: nothing the unit could meet */
        v->pass = 0;
        v->why = VERDICT_COVERAGE;
        v->band = -1;
        v->stat = NAN;
        v->coverage = 0;
    }
}

/* Over the operating temperatures (the worst): the first temperature the
 * unit fails at, else the one closest to the spec. */
static void judge_worst(const sunmc_config *c, const unit_result *r, int a, int band, verdict *v)
{
    int nt = thermal_n_temps(c);
    for (int t = 0; t < nt; t++) {
        verdict vt;
        if (band >= 0)
            judge_band(c, r, a, band, t, &vt);
        else
            judge_set(c, r, a, t, &vt);
        if (!vt.pass) {
            *v = vt;
            return;
        }
        if (t == 0 || vt.stat > v->stat)
            *v = vt;
    }
}

void verdict_unit(const sunmc_config *c, const unit_result *r, int angle, int set, verdict *v)
{
    memset(v, 0, sizeof *v);
    if (set == VERDICT_WORST && thermal_n_temps(c) > 0)
        judge_worst(c, r, angle, -1, v);
    else
        judge_set(c, r, angle, set == VERDICT_WORST ? VERDICT_LAB : set, v);
}

void verdict_band(const sunmc_config *c, const unit_result *r, int angle, int band, int set,
                  verdict *v)
{
    memset(v, 0, sizeof *v);
    if (set == VERDICT_WORST && thermal_n_temps(c) > 0)
        judge_worst(c, r, angle, band, v);
    else
        judge_band(c, r, angle, band, set == VERDICT_WORST ? VERDICT_LAB : set, v);
}

int verdict_pass(const sunmc_config *c, const unit_result *r)
{
    verdict v;
    verdict_unit(c, r, verdict_angle(c), VERDICT_WORST, &v);
    return v.pass;
}

void verdict_rule_text(const sunmc_config *c, char *buf, size_t len)
{
    const sensor_family *fam = c->family;
    char bands[CONFIG_STR_MAX * 2] = "";
    size_t used = 0;
    unsigned m = verdict_band_mask(c);
    int all = strcmp(c->spec_bands, "all") == 0;
    for (int b = 0; b < c->bands_deg.n && used < sizeof bands; b++)
        if ((m >> b) & 1u)
            used += (size_t)snprintf(bands + used, sizeof bands - used, "%s%g:%g",
                                     used ? ", " : "", c->bands_deg.lo[b], c->bands_deg.hi[b]);
    char cover[64];
    if (c->min_coverage >= 1)
        snprintf(cover, sizeof cover, "every point read");
    else
        snprintf(cover, sizeof cover, "at least %g %% of the points read",
                 100.0 * c->min_coverage);
    snprintf(buf, len, "%s of |%s| <= %g\" in %s band (%s), %s%s",
             verdict_statistic_name(c), fam->angle_names[verdict_angle(c)], c->spec_arcsec,
             all ? "every" : "each named", bands, cover,
             thermal_n_temps(c) > 0 ? ", at every operating temperature" : "");
}
