/* sweep.c - parsing --vary axes and applying grid points to a config. */
#include "sweep.h"
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
    char *e;
    errno = 0;
    double v = strtod(buf, &e);
    if (*e != '\0' || errno == ERANGE || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

int sweep_axis_parse(const char *spec, const sensor_family *family, sweep_axis *ax, char *err,
                     size_t errlen)
{
    memset(ax, 0, sizeof *ax);
    const char *eq = strchr(spec, '=');
    const char *dot = strchr(spec, '.');
    if (!eq || !dot || dot > eq)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--vary %s: expected SECTION.KEY=LIST or SECTION.KEY=START:STOP:STEP",
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
    if (!k)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--vary %s: unknown key '%s'", spec,
                          ax->dotted);
    if (k->type != KEY_DOUBLE && k->type != KEY_INT && k->type != KEY_LONG)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--vary %s: %s is not a single number and cannot be varied", spec,
                          ax->dotted);
    if (!config_key_applies(k, family))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--vary %s: %s does not apply to this sensor family", spec, ax->dotted);

    const char *vals = eq + 1;
    const char *c1 = strchr(vals, ':');
    if (c1) {
        const char *c2 = strchr(c1 + 1, ':');
        double start, stop, step;
        if (!c2 || strchr(c2 + 1, ':') || parse_number(vals, c1, &start) != 0 ||
            parse_number(c1 + 1, c2, &stop) != 0 ||
            parse_number(c2 + 1, vals + strlen(vals), &step) != 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "--vary %s: a range is START:STOP:STEP, three numbers", spec);
        if (step == 0 || (stop - start) * step < 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "--vary %s: STEP must be non-zero and lead from START to STOP",
                              spec);
        double count = floor((stop - start) / step + SWEEP_RANGE_EPS) + 1;
        if (count > SWEEP_MAX_VALUES)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "--vary %s: more than %d values", spec,
                              SWEEP_MAX_VALUES);
        ax->n = (int)count;
        for (int i = 0; i < ax->n; i++)
            ax->v[i] = start + (double)i * step;
        return SUNMC_OK;
    }
    const char *p = vals;
    for (;;) {
        const char *comma = strchr(p, ',');
        const char *end = comma ? comma : p + strlen(p);
        if (ax->n >= SWEEP_MAX_VALUES)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "--vary %s: more than %d values", spec,
                              SWEEP_MAX_VALUES);
        if (parse_number(p, end, &ax->v[ax->n]) != 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "--vary %s: '%.*s' is not a number (LIST is comma-separated)", spec,
                              (int)(end - p), p);
        ax->n++;
        if (!comma)
            break;
        p = comma + 1;
    }
    return SUNMC_OK;
}

long sweep_n_points(const sweep_axis *axes, int n_axes)
{
    long n = 1;
    for (int i = 0; i < n_axes; i++)
        n *= axes[i].n;
    return n;
}

void sweep_point_values(const sweep_axis *axes, int n_axes, long p, double *values)
{
    for (int i = n_axes - 1; i >= 0; i--) {
        values[i] = axes[i].v[p % axes[i].n];
        p /= axes[i].n;
    }
}

int sweep_apply(config_state *st, const sweep_axis *axes, int n_axes, long p, char *err,
                size_t errlen)
{
    double values[SWEEP_MAX_AXES];
    sweep_point_values(axes, n_axes, p, values);
    for (int i = 0; i < n_axes; i++) {
        char text[SWEEP_VALUE_TEXT], where[sizeof axes[i].dotted + 16];
        snprintf(text, sizeof text, "%.10g", values[i]);
        snprintf(where, sizeof where, "--vary %s", axes[i].dotted);
        int s = config_set_value(st, axes[i].section, axes[i].name, text, where, err, errlen);
        if (s != SUNMC_OK)
            return s;
    }
    char verr[SUNMC_ERRLEN];
    int s = config_validate(&st->cfg, verr, sizeof verr);
    if (s != SUNMC_OK) {
        char pt[2 * SWEEP_VALUE_TEXT + 2 * sizeof axes[0].dotted + 8] = "";
        size_t used = 0;
        for (int i = 0; i < n_axes && used < sizeof pt; i++)
            used += (size_t)snprintf(pt + used, sizeof pt - used, "%s%s=%.10g", i ? ", " : "",
                                     axes[i].dotted, values[i]);
        return sunmc_fail(err, errlen, s, "--vary point %s: %s", pt, verr);
    }
    return SUNMC_OK;
}
