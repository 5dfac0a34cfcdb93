/* sweep.c - parsing --vary axes and applying grid points to a config. */
#include "sweep.h"
#include "numtext.h"
#include "shortest.h"
#include "status.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Slack on the range end so that STOP is kept when it is hit in decimal. */
#define SWEEP_RANGE_EPS 1e-9

static int parse_number(const char *s, const char *end, double *out)
{
    char buf[SWEEP_VALUE_TEXT];
    while (s < end && (*s == ' ' || *s == '\t'))
        s++;
    while (end > s && (end[-1] == ' ' || end[-1] == '\t'))
        end--;
    size_t n = (size_t)(end - s);
    if (n == 0 || n >= sizeof buf)
        return -1;
    memcpy(buf, s, n);
    buf[n] = '\0';
    return num_parse_double(buf, out) == 0 ? 0 : -1;
}

static int key_is_numeric(const config_key *k)
{
    return k->type == KEY_DOUBLE || k->type == KEY_INT || k->type == KEY_LONG;
}

/* Section, name and key of "section.key=..."; *vals after the '='. */
static int parse_key(const char *spec, const sensor_family *family, sweep_axis *ax,
                     const config_key **key, const char **vals, char *err, size_t errlen)
{
    const char *eq = strchr(spec, '=');
    const char *dot = strchr(spec, '.');
    if (!eq || !dot || dot > eq)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--vary %s: expected SECTION.KEY=LIST, SECTION.KEY=START:STOP:STEP or "
                          "SECTION.KEY=ALT|ALT|...",
                          spec);
    size_t ls = (size_t)(dot - spec), ln = (size_t)(eq - dot - 1);
    if (ls == 0 || ln == 0 || ls >= sizeof ax->section || ln >= sizeof ax->name)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--vary %s: malformed SECTION.KEY", spec);
    memcpy(ax->section, spec, ls);
    memcpy(ax->name, dot + 1, ln);
    snprintf(ax->dotted, sizeof ax->dotted, "%s.%s", ax->section, ax->name);
    const config_key *k = config_find_in(family, ax->section, ax->name);
    if (!k)
        k = config_find(ax->section, ax->name);
    if (!k) {
        char hint[2 * CONFIG_STR_MAX + 32];
        config_suggest(family, ax->section, ax->name, hint, sizeof hint);
        if (!hint[0])
            config_suggest_section(ax->section, hint, sizeof hint);
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--vary %s: unknown key '%s'%s", spec,
                          ax->dotted, hint);
    }
    if (k->type == KEY_FAMILY || k->type == KEY_BANDS)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--vary %s: %s cannot be varied (it changes what the report's rows are)",
                          spec, ax->dotted);
    if (!config_key_applies(k, family))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--vary %s: %s does not apply to this sensor family", spec, ax->dotted);
    *key = k;
    *vals = eq + 1;
    return SUNMC_OK;
}

/* START:STOP:STEP of a number key. */
static int parse_range(const char *spec, const char *vals, const char *c1, sweep_axis *ax,
                       char *err, size_t errlen)
{
    const char *c2 = strchr(c1 + 1, ':');
    double start, stop, step;
    if (!c2 || strchr(c2 + 1, ':') || parse_number(vals, c1, &start) != 0 ||
        parse_number(c1 + 1, c2, &stop) != 0 ||
        parse_number(c2 + 1, vals + strlen(vals), &step) != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--vary %s: a range is START:STOP:STEP, three numbers", spec);
    if (step == 0 || (stop - start) * step < 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--vary %s: STEP must be non-zero and lead from START to STOP", spec);
    double count = floor((stop - start) / step + SWEEP_RANGE_EPS) + 1;
    if (count > SWEEP_MAX_VALUES)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--vary %s: more than %d values", spec,
                          SWEEP_MAX_VALUES);
    ax->n = (int)count;
    for (int i = 0; i < ax->n; i++) {
        /* 3:8:0.1 gives 3.3, not 3.3000000000000003: the sum's rounding
         * error cut at 15 significant digits */
        char t[32];
        snprintf(t, sizeof t, "%.15g", start + (double)i * step);
        ax->v[i] = strtod(t, NULL);
    }
    return SUNMC_OK;
}

/* Values separated by sep: numbers into v[] (number key, ',') or texts
 * (alternatives, '|'). */
static int parse_list(const char *spec, const char *vals, char sep, sweep_axis *ax, char *err,
                      size_t errlen)
{
    for (const char *p = vals;;) {
        const char *cut = strchr(p, sep);
        const char *end = cut ? cut : p + strlen(p);
        if (ax->n >= SWEEP_MAX_VALUES)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "--vary %s: more than %d values", spec,
                              SWEEP_MAX_VALUES);
        const char *s = p, *e = end;
        while (s < e && (*s == ' ' || *s == '\t'))
            s++;
        while (e > s && (e[-1] == ' ' || e[-1] == '\t'))
            e--;
        if (sep == ',' || ax->numeric) {
            if (parse_number(p, end, &ax->v[ax->n]) != 0)
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "--vary %s: '%.*s' is not a number (LIST is %s-separated)",
                                  spec, (int)(end - p), p, sep == ',' ? "comma" : "'|'");
        } else {
            if (e == s || (size_t)(e - s) >= SWEEP_VALUE_TEXT)
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "--vary %s: alternative %d is empty or longer than %d "
                                  "characters",
                                  spec, ax->n + 1, SWEEP_VALUE_TEXT - 1);
            ax->v[ax->n] = NAN;
            memcpy(ax->text[ax->n], s, (size_t)(e - s));
            ax->text[ax->n][e - s] = '\0';
        }
        ax->n++;
        if (!cut)
            return SUNMC_OK;
        p = cut + 1;
    }
}

int sweep_axis_parse(const char *spec, const sensor_family *family, sweep_axis *ax, char *err,
                     size_t errlen)
{
    memset(ax, 0, sizeof *ax);
    const config_key *k = NULL;
    const char *vals = NULL;
    int s = parse_key(spec, family, ax, &k, &vals, err, errlen);
    if (s != SUNMC_OK)
        return s;
    ax->numeric = key_is_numeric(k);
    const char *colon = strchr(vals, ':');
    if (strchr(vals, '|'))
        s = parse_list(spec, vals, '|', ax, err, errlen);
    else if (!ax->numeric)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--vary %s: %s is not a single number: give its alternatives separated "
                          "by '|', each as written in a file (e.g. %s=-20,0,20|-30,0,30)",
                          spec, ax->dotted, ax->dotted);
    else if (colon)
        s = parse_range(spec, vals, colon, ax, err, errlen);
    else
        s = parse_list(spec, vals, ',', ax, err, errlen);
    if (s == SUNMC_OK && ax->numeric)
        for (int i = 0; i < ax->n; i++)
            shortest_double(ax->v[i], ax->text[i], sizeof ax->text[i]);
    return s;
}

long sweep_n_points(const sweep_axis *axes, int n_axes)
{
    long n = 1;
    for (int i = 0; i < n_axes; i++)
        n *= axes[i].n;
    return n;
}

/* Index of point p's value on each axis. */
static void point_index(const sweep_axis *axes, int n_axes, long p, int *idx)
{
    for (int i = n_axes - 1; i >= 0; i--) {
        idx[i] = (int)(p % axes[i].n);
        p /= axes[i].n;
    }
}

void sweep_point_values(const sweep_axis *axes, int n_axes, long p, double *values)
{
    int idx[SWEEP_MAX_AXES];
    point_index(axes, n_axes, p, idx);
    for (int i = 0; i < n_axes; i++)
        values[i] = axes[i].v[idx[i]];
}

void sweep_point_text(const sweep_axis *axes, int n_axes, long p, const char **texts)
{
    int idx[SWEEP_MAX_AXES];
    point_index(axes, n_axes, p, idx);
    for (int i = 0; i < n_axes; i++)
        texts[i] = axes[i].text[idx[i]];
}

void sweep_point_label(const sweep_axis *axes, int n_axes, long p, char *buf, size_t len)
{
    const char *t[SWEEP_MAX_AXES];
    sweep_point_text(axes, n_axes, p, t);
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < n_axes && used < len; i++)
        used += (size_t)snprintf(buf + used, len - used, "%s%s", i ? "; " : "", t[i]);
}

int sweep_apply(config_state *st, const sweep_axis *axes, int n_axes, long p, char *err,
                size_t errlen)
{
    const char *text[SWEEP_MAX_AXES];
    sweep_point_text(axes, n_axes, p, text);
    for (int i = 0; i < n_axes; i++) {
        char where[sizeof axes[i].dotted + 16];
        snprintf(where, sizeof where, "--vary %s", axes[i].dotted);
        int s = config_set_value(st, axes[i].section, axes[i].name, text[i], where, err, errlen);
        if (s != SUNMC_OK)
            return s;
    }
    char verr[SUNMC_ERRLEN];
    int s = config_validate(&st->cfg, verr, sizeof verr);
    if (s != SUNMC_OK) {
        char pt[SWEEP_MAX_AXES * (SWEEP_VALUE_TEXT + sizeof axes[0].dotted + 4)] = "";
        size_t used = 0;
        for (int i = 0; i < n_axes && used < sizeof pt; i++)
            used += (size_t)snprintf(pt + used, sizeof pt - used, "%s%s=%s", i ? ", " : "",
                                     axes[i].dotted, text[i]);
        return sunmc_fail(err, errlen, s, "--vary point %s: %s", pt, verr);
    }
    return SUNMC_OK;
}
