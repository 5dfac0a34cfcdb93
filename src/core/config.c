/* config.c - INI parsing, --set overrides, validation and dumps, all driven
 * by the key table in config_keys.c. */
#include "config.h"
#include "status.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LINE_MAX_LEN 1024

static const char *const family_names[] = {"", "ess", "dss", "ess, dss"};

static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    char *e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = '\0';
    return s;
}

const config_key *config_find(const char *section, const char *name)
{
    for (size_t i = 0; i < config_key_count; i++)
        if (strcmp(config_keys[i].section, section) == 0 && strcmp(config_keys[i].name, name) == 0)
            return &config_keys[i];
    return NULL;
}

static int section_known(const char *section)
{
    for (size_t i = 0; i < config_key_count; i++)
        if (strcmp(config_keys[i].section, section) == 0)
            return 1;
    return 0;
}

/* Parse a whole-string double; 0 on success. */
static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno == ERANGE || !isfinite(v))
        return -1;
    while (isspace((unsigned char)*end))
        end++;
    if (*end != '\0')
        return -1;
    *out = v;
    return 0;
}

static int parse_long(const char *s, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || errno == ERANGE)
        return -1;
    while (isspace((unsigned char)*end))
        end++;
    if (*end != '\0')
        return -1;
    *out = v;
    return 0;
}

static void range_text(const config_key *k, char *buf, size_t len)
{
    if (k->type == KEY_ENUM)
        snprintf(buf, len, "one of %s", k->choices);
    else if (k->type == KEY_STRING)
        snprintf(buf, len, "text of at most %d characters", CONFIG_STR_MAX - 1);
    else
        snprintf(buf, len, "%g to %g%s%s", k->min, k->max, k->unit[0] ? " " : "", k->unit);
}

static int check_range(const config_key *k, double v, const char *where, const char *what,
                       char *err, size_t errlen)
{
    if (v < k->min || v > k->max) {
        char r[128];
        range_text(k, r, sizeof r);
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s = %s is out of range: allowed %s",
                          where, k->section, k->name, what, r);
    }
    return SUNMC_OK;
}

static int enum_index(const char *choices, const char *value)
{
    size_t vlen = strlen(value);
    int idx = 0;
    const char *p = choices;
    while (*p) {
        const char *bar = strchr(p, '|');
        size_t len = bar ? (size_t)(bar - p) : strlen(p);
        if (len == vlen && strncmp(p, value, len) == 0)
            return idx;
        if (!bar)
            break;
        p = bar + 1;
        idx++;
    }
    return -1;
}

static void enum_name(const char *choices, int idx, char *buf, size_t len)
{
    const char *p = choices;
    for (int i = 0; i < idx && p; i++) {
        p = strchr(p, '|');
        if (p)
            p++;
    }
    if (!p) {
        snprintf(buf, len, "?");
        return;
    }
    const char *bar = strchr(p, '|');
    size_t n = bar ? (size_t)(bar - p) : strlen(p);
    if (n >= len)
        n = len - 1;
    memcpy(buf, p, n);
    buf[n] = '\0';
}

/* Parse `value` for key k into cfg (no family check). */
static int set_parsed(const config_key *k, sunmc_config *cfg, const char *value, const char *where,
                      char *err, size_t errlen)
{
    char *base = (char *)cfg + k->offset;
    char buf[LINE_MAX_LEN];
    snprintf(buf, sizeof buf, "%s", value);
    char *v = trim(buf);
    double d;
    long l;
    int st;

    switch (k->type) {
    case KEY_DOUBLE:
        if (parse_double(v, &d) != 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s = '%s' is not a number", where,
                              k->section, k->name, v);
        if ((st = check_range(k, d, where, v, err, errlen)) != SUNMC_OK)
            return st;
        *(double *)base = d;
        return SUNMC_OK;
    case KEY_INT:
    case KEY_LONG:
        if (parse_long(v, &l) != 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s = '%s' is not a whole number",
                              where, k->section, k->name, v);
        if ((st = check_range(k, (double)l, where, v, err, errlen)) != SUNMC_OK)
            return st;
        if (k->type == KEY_INT)
            *(int *)base = (int)l;
        else
            *(long *)base = l;
        return SUNMC_OK;
    case KEY_ENUM: {
        int idx = enum_index(k->choices, v);
        if (idx < 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s = '%s' is not allowed: one of %s",
                              where, k->section, k->name, v, k->choices);
        *(int *)base = idx + (int)k->min;
        return SUNMC_OK;
    }
    case KEY_STRING:
        if (strlen(v) >= CONFIG_STR_MAX || strlen(v) == 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s: %s.%s must be text of 1 to %d characters", where, k->section,
                              k->name, CONFIG_STR_MAX - 1);
        for (const char *p = v; *p; p++)
            if (*p == '\t' || !isprint((unsigned char)*p))
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "%s: %s.%s holds a tab or control character", where,
                                  k->section, k->name);
        snprintf((char *)base, CONFIG_STR_MAX, "%s", v);
        return SUNMC_OK;
    case KEY_LIST: {
        double_list tmp = {0};
        char *save = NULL;
        for (char *tok = strtok_r(v, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
            char *t = trim(tok);
            if (tmp.n >= CONFIG_LIST_MAX)
                return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s has more than %d values",
                                  where, k->section, k->name, CONFIG_LIST_MAX);
            if (parse_double(t, &d) != 0)
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "%s: %s.%s: '%s' is not a number (a comma-separated list)",
                                  where, k->section, k->name, t);
            if ((st = check_range(k, d, where, t, err, errlen)) != SUNMC_OK)
                return st;
            tmp.v[tmp.n++] = d;
        }
        if (tmp.n == 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s is an empty list", where,
                              k->section, k->name);
        *(double_list *)base = tmp;
        return SUNMC_OK;
    }
    case KEY_BANDS: {
        band_list tmp = {0};
        char *save = NULL;
        for (char *tok = strtok_r(v, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
            char *t = trim(tok);
            char *colon = strchr(t, ':');
            double lo, hi;
            if (tmp.n >= CONFIG_BANDS_MAX)
                return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s has more than %d bands",
                                  where, k->section, k->name, CONFIG_BANDS_MAX);
            if (!colon)
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "%s: %s.%s: band '%s' is not LO:HI (e.g. 0:30, 30:60)", where,
                                  k->section, k->name, t);
            *colon = '\0';
            if (parse_double(trim(t), &lo) != 0 || parse_double(trim(colon + 1), &hi) != 0)
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "%s: %s.%s: band bounds must be numbers", where, k->section,
                                  k->name);
            if ((st = check_range(k, lo, where, "band low", err, errlen)) != SUNMC_OK ||
                (st = check_range(k, hi, where, "band high", err, errlen)) != SUNMC_OK)
                return st;
            if (!(hi > lo))
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "%s: %s.%s: band %g:%g must have LO < HI", where, k->section,
                                  k->name, lo, hi);
            tmp.lo[tmp.n] = lo;
            tmp.hi[tmp.n] = hi;
            tmp.n++;
        }
        if (tmp.n == 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s has no band", where,
                              k->section, k->name);
        *(band_list *)base = tmp;
        return SUNMC_OK;
    }
    }
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: internal: bad key type", where);
}

int config_set_value(config_state *st, const char *section, const char *name, const char *value,
                     const char *where, char *err, size_t errlen)
{
    const config_key *k = config_find(section, name);
    if (!k) {
        if (!section_known(section))
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: unknown section [%s]", where, section);
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: unknown key '%s' in section [%s]", where,
                          name, section);
    }
    if (!(k->families & st->cfg.family))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: %s.%s applies to %s sensors, but sensor.family is %s", where,
                          section, name, family_names[k->families], family_names[st->cfg.family]);
    int s = set_parsed(k, &st->cfg, value, where, err, errlen);
    if (s == SUNMC_OK && st->origins)
        snprintf(st->origins[k - config_keys].origin, CONFIG_ORIGIN_MAX, "%s", where);
    return s;
}

/* One "key = value" line read from a file. */
typedef struct {
    char section[CONFIG_STR_MAX];
    char name[CONFIG_STR_MAX];
    char value[LINE_MAX_LEN];
    int line;
} ini_entry;

typedef struct {
    ini_entry *v;
    int n, cap;
} ini_entries;

static int read_ini(const char *path, ini_entries *out, char *err, size_t errlen)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: cannot open config file: %s", path,
                          strerror(errno));
    char line[LINE_MAX_LEN + 2];
    char section[CONFIG_STR_MAX] = "";
    int lineno = 0;
    int status = SUNMC_OK;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        if (strlen(line) > LINE_MAX_LEN) {
            status = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: line longer than %d characters",
                                path, lineno, LINE_MAX_LEN);
            break;
        }
        char *s = trim(line);
        if (*s == '\0' || *s == '#' || *s == ';')
            continue;
        if (*s == '[') {
            char *close = strchr(s, ']');
            if (!close || *trim(close + 1) != '\0') {
                status = sunmc_fail(err, errlen, SUNMC_EINPUT,
                                    "%s:%d: malformed section header '%s'", path, lineno, s);
                break;
            }
            *close = '\0';
            char *name = trim(s + 1);
            if (!section_known(name)) {
                status = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: unknown section [%s]",
                                    path, lineno, name);
                break;
            }
            snprintf(section, sizeof section, "%s", name);
            continue;
        }
        char *eq = strchr(s, '=');
        if (!eq) {
            status = sunmc_fail(err, errlen, SUNMC_EINPUT,
                                "%s:%d: expected 'key = value' or '[section]', got '%s'", path,
                                lineno, s);
            break;
        }
        *eq = '\0';
        char *key = trim(s);
        char *value = trim(eq + 1);
        /* inline comment: " # ..." */
        char *hash = strstr(value, " #");
        if (hash) {
            *hash = '\0';
            value = trim(value);
        }
        if (section[0] == '\0') {
            status = sunmc_fail(err, errlen, SUNMC_EINPUT,
                                "%s:%d: key '%s' comes before any [section]", path, lineno, key);
            break;
        }
        if (!config_find(section, key)) {
            status = sunmc_fail(err, errlen, SUNMC_EINPUT,
                                "%s:%d: unknown key '%s' in section [%s]", path, lineno, key,
                                section);
            break;
        }
        for (int i = 0; i < out->n; i++)
            if (strcmp(out->v[i].section, section) == 0 && strcmp(out->v[i].name, key) == 0) {
                status = sunmc_fail(err, errlen, SUNMC_EINPUT,
                                    "%s:%d: duplicate key %s.%s (first set on line %d)", path,
                                    lineno, section, key, out->v[i].line);
                break;
            }
        if (status != SUNMC_OK)
            break;
        if (out->n == out->cap) {
            int cap = out->cap ? 2 * out->cap : 64;
            ini_entry *nv = realloc(out->v, (size_t)cap * sizeof *nv);
            if (!nv) {
                status = sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
                break;
            }
            out->v = nv;
            out->cap = cap;
        }
        ini_entry *e = &out->v[out->n++];
        snprintf(e->section, sizeof e->section, "%s", section);
        snprintf(e->name, sizeof e->name, "%s", key);
        snprintf(e->value, sizeof e->value, "%s", value);
        e->line = lineno;
    }
    if (status == SUNMC_OK && ferror(f))
        status = sunmc_fail(err, errlen, SUNMC_EIO, "%s: read error", path);
    fclose(f);
    return status;
}

/* Split "section.key=value" into its parts; SUNMC_EINPUT when malformed. */
static int split_set(const char *arg, char *section, char *name, char *value, char *err,
                     size_t errlen)
{
    const char *eq = strchr(arg, '=');
    const char *dot = strchr(arg, '.');
    if (!eq || !dot || dot > eq || dot == arg || dot + 1 == eq)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--set %s: expected section.key=value (e.g. tolerance.dH_um=3)", arg);
    size_t ls = (size_t)(dot - arg), ln = (size_t)(eq - dot - 1);
    if (ls >= CONFIG_STR_MAX || ln >= CONFIG_STR_MAX || strlen(eq + 1) >= LINE_MAX_LEN)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--set %s: too long", arg);
    memcpy(section, arg, ls);
    section[ls] = '\0';
    memcpy(name, dot + 1, ln);
    name[ln] = '\0';
    strcpy(value, eq + 1);
    return SUNMC_OK;
}

static int apply_defaults(config_state *st, int family, char *err, size_t errlen)
{
    for (size_t i = 0; i < config_key_count; i++) {
        const config_key *k = &config_keys[i];
        const char *def = (family == FAMILY_DSS && k->def_dss) ? k->def_dss : k->def;
        int s = set_parsed(k, &st->cfg, def, "default", err, errlen);
        if (s != SUNMC_OK)
            return s;
        snprintf(st->origins[i].origin, CONFIG_ORIGIN_MAX, "default");
    }
    return SUNMC_OK;
}

int config_build(config_state *st, const char *path, const char *const *sets, int n_sets,
                 char *err, size_t errlen)
{
    memset(st, 0, sizeof *st);
    st->origins = calloc(config_key_count, sizeof *st->origins);
    if (!st->origins)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");

    ini_entries ents = {0};
    int status = SUNMC_OK;
    char where[CONFIG_ORIGIN_MAX];
    char section[CONFIG_STR_MAX], name[CONFIG_STR_MAX], value[LINE_MAX_LEN];

    if (path && (status = read_ini(path, &ents, err, errlen)) != SUNMC_OK)
        goto done;

    /* The family decides which defaults apply: find it first. */
    const config_key *fk = config_find("sensor", "family");
    st->cfg.family = FAMILY_ESS;
    for (int i = 0; i < ents.n; i++)
        if (strcmp(ents.v[i].section, "sensor") == 0 && strcmp(ents.v[i].name, "family") == 0) {
            snprintf(where, sizeof where, "%s:%d", path, ents.v[i].line);
            if ((status = set_parsed(fk, &st->cfg, ents.v[i].value, where, err, errlen)) != SUNMC_OK)
                goto done;
        }
    for (int i = 0; i < n_sets; i++) {
        if ((status = split_set(sets[i], section, name, value, err, errlen)) != SUNMC_OK)
            goto done;
        if (strcmp(section, "sensor") == 0 && strcmp(name, "family") == 0 &&
            (status = set_parsed(fk, &st->cfg, value, "--set", err, errlen)) != SUNMC_OK)
            goto done;
    }
    int family = st->cfg.family;
    if ((status = apply_defaults(st, family, err, errlen)) != SUNMC_OK)
        goto done;
    st->cfg.family = family;

    for (int i = 0; i < ents.n; i++) {
        snprintf(where, sizeof where, "%s:%d", path, ents.v[i].line);
        status = config_set_value(st, ents.v[i].section, ents.v[i].name, ents.v[i].value, where,
                                  err, errlen);
        if (status != SUNMC_OK)
            goto done;
    }
    for (int i = 0; i < n_sets; i++) {
        split_set(sets[i], section, name, value, err, errlen);
        snprintf(where, sizeof where, "--set %s.%s", section, name);
        if ((status = config_set_value(st, section, name, value, where, err, errlen)) != SUNMC_OK)
            goto done;
    }
    {
        char verr[SUNMC_ERRLEN];
        status = config_validate(&st->cfg, verr, sizeof verr);
        if (status != SUNMC_OK)
            sunmc_fail(err, errlen, status, "%s: %s", path ? path : "config", verr);
    }
done:
    free(ents.v);
    if (status != SUNMC_OK)
        config_state_free(st);
    return status;
}

void config_state_free(config_state *st)
{
    free(st->origins);
    st->origins = NULL;
}

void config_format_value(const config_key *k, const sunmc_config *c, char *buf, size_t len)
{
    const char *base = (const char *)c + k->offset;
    size_t used = 0;
    switch (k->type) {
    case KEY_DOUBLE:
        snprintf(buf, len, "%.10g", *(const double *)base);
        break;
    case KEY_INT:
        snprintf(buf, len, "%d", *(const int *)base);
        break;
    case KEY_LONG:
        snprintf(buf, len, "%ld", *(const long *)base);
        break;
    case KEY_ENUM:
        enum_name(k->choices, *(const int *)base - (int)k->min, buf, len);
        break;
    case KEY_STRING:
        snprintf(buf, len, "%s", base);
        break;
    case KEY_LIST: {
        const double_list *l = (const double_list *)base;
        buf[0] = '\0';
        for (int i = 0; i < l->n && used < len; i++)
            used += (size_t)snprintf(buf + used, len - used, "%s%.10g", i ? ", " : "", l->v[i]);
        break;
    }
    case KEY_BANDS: {
        const band_list *b = (const band_list *)base;
        buf[0] = '\0';
        for (int i = 0; i < b->n && used < len; i++)
            used += (size_t)snprintf(buf + used, len - used, "%s%.10g:%.10g", i ? ", " : "",
                                     b->lo[i], b->hi[i]);
        break;
    }
    default:
        snprintf(buf, len, "?");
    }
}

int config_write(FILE *f, const config_state *st)
{
    const sunmc_config *c = &st->cfg;
    const char *cur = "";
    char buf[LINE_MAX_LEN];
    fprintf(f, "# sunmc effective configuration (%s); the comment names each value's origin\n",
            family_names[c->family]);
    for (size_t i = 0; i < config_key_count; i++) {
        const config_key *k = &config_keys[i];
        if (!(k->families & c->family))
            continue;
        if (strcmp(cur, k->section) != 0) {
            fprintf(f, "\n[%s]\n", k->section);
            cur = k->section;
        }
        config_format_value(k, c, buf, sizeof buf);
        if (st->origins)
            fprintf(f, "%s = %s  # %s\n", k->name, buf, st->origins[i].origin);
        else
            fprintf(f, "%s = %s\n", k->name, buf);
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

int config_write_reference(FILE *f)
{
    const char *cur = "";
    char r[128];
    fprintf(f, "# sunmc reference configuration: every key, generated from the key table\n"
               "# (`sunmc config --reference`).  Values shown are the ESS defaults; where the\n"
               "# DSS default differs it is given in the comment.  Units are in the key names.\n"
               "# Tolerances: KEY = magnitude and KEY_dist = fixed|uniform|normal|truncnormal\n"
               "# (uniform: +-magnitude; normal, truncnormal: sigma = magnitude).\n");
    for (size_t i = 0; i < config_key_count; i++) {
        const config_key *k = &config_keys[i];
        if (strcmp(cur, k->section) != 0) {
            fprintf(f, "\n[%s]\n", k->section);
            cur = k->section;
        }
        range_text(k, r, sizeof r);
        fprintf(f, "# %s\n#   families: %s; allowed: %s", k->help, family_names[k->families], r);
        if (k->def_dss)
            fprintf(f, "; dss default: %s", k->def_dss);
        fprintf(f, "\n# %s = %s\n", k->name, k->def);
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

int config_get_number(const sunmc_config *c, const char *dotted, double *out, char *err,
                      size_t errlen)
{
    char section[CONFIG_STR_MAX];
    const char *dot = strchr(dotted, '.');
    if (!dot || (size_t)(dot - dotted) >= sizeof section)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "'%s' is not section.key", dotted);
    memcpy(section, dotted, (size_t)(dot - dotted));
    section[dot - dotted] = '\0';
    const config_key *k = config_find(section, dot + 1);
    if (!k)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "unknown key '%s'", dotted);
    const char *base = (const char *)c + k->offset;
    switch (k->type) {
    case KEY_DOUBLE:
        *out = *(const double *)base;
        return SUNMC_OK;
    case KEY_INT:
        *out = *(const int *)base;
        return SUNMC_OK;
    case KEY_LONG:
        *out = (double)*(const long *)base;
        return SUNMC_OK;
    default:
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "key '%s' is not a single number", dotted);
    }
}
