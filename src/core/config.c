/* config.c - building a config: finding keys across the shared and family
 * tables, reading the INI file, defaults, --set overrides and validation. */
#include "config.h"
#include "lab_onboard.h"
#include "thermal.h"
#include "verdict.h"
#include "ini.h"
#include "memory.h"
#include "registry.h"
#include "status.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>


/* Rows of a family's key table (it ends with a NULL section). */
static size_t table_len(const config_key *t)
{
    size_t n = 0;
    while (t && t[n].section)
        n++;
    return n;
}

static const config_key *find_in(const config_key *t, size_t n, const char *section,
                                 const char *name)
{
    for (size_t i = 0; i < n; i++)
        if (strcmp(t[i].section, section) == 0 && strcmp(t[i].name, name) == 0)
            return &t[i];
    return NULL;
}

int config_family_omits(const sensor_family *fam, const config_key *k)
{
    if (!fam || !fam->shared_keys_unused || !config_key_is_shared(k))
        return 0;
    size_t ls = strlen(k->section);
    for (const char *const *u = fam->shared_keys_unused; *u; u++)
        if (strncmp(*u, k->section, ls) == 0 && (*u)[ls] == '.' && strcmp(*u + ls + 1, k->name) == 0)
            return 1;
    return 0;
}

const config_key *config_find_in(const sensor_family *fam, const char *section, const char *name)
{
    const config_key *k = find_in(config_keys, config_key_count, section, name);
    if (k && config_family_omits(fam, k))
        return NULL;
    if (!k && fam)
        k = find_in(fam->keys, table_len(fam->keys), section, name);
    return k;
}

const config_key *config_find(const char *section, const char *name)
{
    const config_key *k = config_find_in(NULL, section, name);
    for (int i = 0; !k && i < sensor_family_count(); i++)
        k = config_find_in(sensor_family_at(i), section, name);
    return k;
}

static int section_known(const char *section)
{
    for (size_t i = 0; i < config_section_count; i++)
        if (strcmp(config_sections[i], section) == 0)
            return 1;
    return 0;
}

int config_key_is_shared(const config_key *k)
{
    return k >= config_keys && k < config_keys + config_key_count;
}

int config_key_applies(const config_key *k, const sensor_family *fam)
{
    if (config_key_is_shared(k))
        return !config_family_omits(fam, k);
    return fam && k >= fam->keys && k < fam->keys + table_len(fam->keys);
}

int config_is_tolerance(const config_key *k, const sensor_family *fam)
{
    char dist[2 * CONFIG_STR_MAX];
    if (strcmp(k->section, "tolerance") != 0 || k->type != KEY_DOUBLE ||
        config_key_is_shared(k) || !config_key_applies(k, fam))
        return 0;
    snprintf(dist, sizeof dist, "%s_dist", k->name);
    return find_in(fam->keys, table_len(fam->keys), "tolerance", dist) != NULL;
}

void *config_value_ptr(const config_key *k, sunmc_config *c)
{
    return config_key_is_shared(k) ? (void *)((char *)c + k->offset)
                                   : (void *)(c->fam.bytes + k->offset);
}

const void *config_value_cptr(const config_key *k, const sunmc_config *c)
{
    return config_key_is_shared(k) ? (const void *)((const char *)c + k->offset)
                                   : (const void *)(c->fam.bytes + k->offset);
}

/* Names of the families that have section.name, "a, b". */
static void families_with(const char *section, const char *name, char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < sensor_family_count() && used < len; i++) {
        const sensor_family *f = sensor_family_at(i);
        if (config_find_in(f, section, name))
            used += (size_t)snprintf(buf + used, len - used, "%s%s", used ? ", " : "", f->name);
    }
}

static long view_index(const config_state *st, const config_key *k)
{
    for (size_t i = 0; i < st->n_keys; i++)
        if (st->keys[i] == k)
            return (long)i;
    return -1;
}

const char *config_origin_of(const config_state *st, const config_key *k)
{
    long i = view_index(st, k);
    return i < 0 || !st->origins ? NULL : st->origins[i].origin;
}

static void set_origin(config_state *st, const config_key *k, const char *where)
{
    long i = view_index(st, k);
    if (i >= 0 && st->origins)
        snprintf(st->origins[i].origin, CONFIG_ORIGIN_MAX, "%s", where);
}

int config_set_value(config_state *st, const char *section, const char *name, const char *value,
                     const char *where, char *err, size_t errlen)
{
    const config_key *k = config_find_in(st->cfg.family, section, name);
    if (!k) {
        char fams[128];
        families_with(section, name, fams, sizeof fams);
        char hint[2 * CONFIG_STR_MAX];
        config_suggest(st->cfg.family, section, name, hint, sizeof hint);
        if (fams[0])
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s: %s.%s applies to %s sensors, but sensor.family is %s%s", where,
                              section, name, fams, st->cfg.family->name, hint);
        if (!section_known(section)) {
            config_suggest_section(section, hint, sizeof hint);
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: unknown section [%s]%s", where,
                              section, hint);
        }
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: unknown key '%s' in section [%s]%s",
                          where, name, section, hint);
    }
    if (k->type == KEY_FAMILY) {
        const sensor_family *f = NULL;
        int s = config_parse_value(k, (void *)&f, value, where, err, errlen);
        if (s != SUNMC_OK)
            return s;
        if (f != st->cfg.family)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s: sensor.family = %s, but this config was built for %s", where,
                              f->name, st->cfg.family->name);
        set_origin(st, k, where);
        return SUNMC_OK;
    }
    int s = config_parse_value(k, config_value_ptr(k, &st->cfg), value, where, err, errlen);
    if (s == SUNMC_OK)
        set_origin(st, k, where);
    return s;
}

/* The "key = value" lines of a config file, in file order. */
typedef struct {
    ini_entry *v;
    int n, cap;
} ini_entries;

static int add_entry(ini_entries *out, const ini_entry *e, const char *path, char *err,
                     size_t errlen)
{
    if (out->n == out->cap) {
        int cap = out->cap ? 2 * out->cap : 64;
        ini_entry *nv = realloc(out->v, (size_t)cap * sizeof *nv);
        if (!nv)
            return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
        out->v = nv;
        out->cap = cap;
    }
    out->v[out->n++] = *e;
    return SUNMC_OK;
}


/* FILE:LINE: unknown key, with the nearest known key offered. */
static int unknown_key(const char *path, int line, const char *section, const char *name,
                       char *err, size_t errlen)
{
    char hint[2 * CONFIG_STR_MAX];
    config_suggest(NULL, section, name, hint, sizeof hint);
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: unknown key '%s' in section [%s]%s", path,
                      line, name, section, hint);
}

/* FILE:LINE: unknown section, with the nearest known section offered. */
static int unknown_section(const char *path, int line, const char *section, char *err,
                           size_t errlen)
{
    char hint[2 * CONFIG_STR_MAX];
    config_suggest_section(section, hint, sizeof hint);
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: unknown section [%s]%s", path, line,
                      section, hint);
}

/* Read path's entries; every section and key must be known to some family
 * (whether it applies to this config's family is checked when it is set). */
static int read_ini(const char *path, ini_entries *out, char *err, size_t errlen)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: cannot open config file: %s", path,
                          strerror(errno));
    ini_reader r;
    ini_entry e;
    int item, st;
    ini_begin(&r, f, path);
    while ((st = ini_next(&r, &item, &e, err, errlen)) == SUNMC_OK && item != INI_END) {
        if (item == INI_SECTION && !section_known(e.section))
            st = unknown_section(path, e.line, e.section, err, errlen);
        else if (item == INI_KEY && !config_find(e.section, e.key))
            st = unknown_key(path, e.line, e.section, e.key, err, errlen);
        else if (item == INI_KEY)
            st = add_entry(out, &e, path, err, errlen);
        if (st != SUNMC_OK)
            break;
    }
    ini_end(&r);
    fclose(f);
    return st;
}

/* Narrow [*a, *b) past blanks at either end. */
static void trim_span(const char **a, const char **b)
{
    while (*a < *b && (**a == ' ' || **a == '\t'))
        (*a)++;
    while (*b > *a && ((*b)[-1] == ' ' || (*b)[-1] == '\t'))
        (*b)--;
}

/* Split "section.key=value" into its parts, blanks around each trimmed
 * (as in a config file's "key = value"); SUNMC_EINPUT when malformed. */
static int split_set(const char *arg, char *section, char *name, char *value, char *err,
                     size_t errlen)
{
    const char *eq = strchr(arg, '=');
    const char *dot = strchr(arg, '.');
    if (!eq || !dot || dot > eq || dot == arg || dot + 1 == eq)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--set %s: expected section.key=value (e.g. tolerance.dH_um=3)", arg);
    const char *s0 = arg, *s1 = dot, *n0 = dot + 1, *n1 = eq, *v0 = eq + 1;
    trim_span(&s0, &s1);
    trim_span(&n0, &n1);
    while (*v0 == ' ' || *v0 == '\t')
        v0++;
    if (s0 == s1 || n0 == n1)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--set %s: expected section.key=value (e.g. tolerance.dH_um=3)", arg);
    size_t ls = (size_t)(s1 - s0), ln = (size_t)(n1 - n0);
    if (ls >= CONFIG_STR_MAX || ln >= CONFIG_STR_MAX || strlen(eq + 1) >= INI_LINE_MAX)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--set %s: too long", arg);
    memcpy(section, s0, ls);
    section[ls] = '\0';
    memcpy(name, n0, ln);
    name[ln] = '\0';
    strcpy(value, v0);
    size_t lv = strlen(value);
    while (lv > 0 && (value[lv - 1] == ' ' || value[lv - 1] == '\t'))
        value[--lv] = '\0';
    return SUNMC_OK;
}

/* 1 when fam lists its keys of `section` after the shared ones. */
static int after_shared(const sensor_family *fam, const char *section)
{
    for (const char *const *s = fam->sections_after_shared; s && *s; s++)
        if (strcmp(*s, section) == 0)
            return 1;
    return 0;
}

/* Append to keys[] (up to max) the keys of `section` of each family in
 * fams[nf] that lists them before (after = 0) or after the shared ones. */
static size_t add_family_keys(const sensor_family *const *fams, int nf, const char *section,
                              int after, const config_key **keys, const sensor_family **owners,
                              size_t n, size_t max)
{
    for (int f = 0; f < nf; f++) {
        if (after_shared(fams[f], section) != after)
            continue;
        for (const config_key *k = fams[f]->keys; k && k->section; k++)
            if (strcmp(k->section, section) == 0 && n < max) {
                owners[n] = fams[f];
                keys[n++] = k;
            }
    }
    return n;
}

size_t config_list_keys(const sensor_family *fam, const config_key **keys,
                        const sensor_family **owners, size_t max)
{
    const sensor_family *fams[CONFIG_FAMILIES_MAX];
    int nf = 0;
    if (fam)
        fams[nf++] = fam;
    else
        for (; nf < sensor_family_count() && nf < CONFIG_FAMILIES_MAX; nf++)
            fams[nf] = sensor_family_at(nf);
    size_t n = 0;
    for (size_t s = 0; s < config_section_count; s++) {
        const char *sec = config_sections[s];
        n = add_family_keys(fams, nf, sec, 0, keys, owners, n, max);
        for (size_t i = 0; i < config_key_count; i++)
            if (strcmp(config_keys[i].section, sec) == 0 && n < max &&
                !config_family_omits(fam, &config_keys[i])) {
                owners[n] = NULL;
                keys[n++] = &config_keys[i];
            }
        n = add_family_keys(fams, nf, sec, 1, keys, owners, n, max);
    }
    return n;
}

const char *config_key_default(const config_key *k, const sensor_family *fam)
{
    if (!fam)
        fam = sensor_family_at(0);
    if (k->type == KEY_FAMILY)
        return fam->name;
    if (config_key_is_shared(k))
        for (size_t i = 0; fam->defaults && fam->defaults[i].section; i++)
            if (strcmp(fam->defaults[i].section, k->section) == 0 &&
                strcmp(fam->defaults[i].name, k->name) == 0)
                return fam->defaults[i].value;
    return k->def;
}

/* st's key view and origins for family fam, every key at its default. */
static int init_state(config_state *st, const sensor_family *fam, char *err, size_t errlen)
{
    const config_key *keys[CONFIG_KEYS_MAX];
    const sensor_family *owners[CONFIG_KEYS_MAX];
    size_t n = config_list_keys(fam, keys, owners, CONFIG_KEYS_MAX);
    size_t omitted = 0;
    for (size_t i = 0; i < config_key_count; i++)
        omitted += (size_t)config_family_omits(fam, &config_keys[i]);
    if (n != config_key_count - omitted + table_len(fam->keys))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "internal: family %s has a key outside the known sections", fam->name);
    st->keys = malloc(n * sizeof *st->keys);
    st->origins = calloc(n, sizeof *st->origins);
    if (!st->keys || !st->origins)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    memcpy(st->keys, keys, n * sizeof *keys);
    st->n_keys = n;
    st->cfg.family = fam;
    for (size_t i = 0; i < n; i++) {
        const config_key *k = keys[i];
        snprintf(st->origins[i].origin, CONFIG_ORIGIN_MAX, "default");
        if (k->type == KEY_FAMILY)
            continue;
        int s = config_parse_value(k, config_value_ptr(k, &st->cfg), config_key_default(k, fam),
                                   "default", err, errlen);
        if (s != SUNMC_OK)
            return s;
    }
    return SUNMC_OK;
}

/* The family decides which keys and defaults apply: the file's
 * sensor.family, then the overrides', else the registry's first.  where
 * receives the origin of the deciding value ("" for the default). */
static int resolve_family(const ini_entries *ents, const char *path, const char *const *sets,
                          int n_sets, const sensor_family **fam, char *where, char *err,
                          size_t errlen)
{
    const config_key *fk = config_find("sensor", "family");
    char section[CONFIG_STR_MAX], name[CONFIG_STR_MAX], value[INI_LINE_MAX];
    int s;
    *fam = sensor_family_at(0);
    where[0] = '\0';
    for (int i = 0; i < ents->n; i++)
        if (strcmp(ents->v[i].section, "sensor") == 0 && strcmp(ents->v[i].key, "family") == 0) {
            snprintf(where, CONFIG_ORIGIN_MAX, "%s:%d", path, ents->v[i].line);
            if ((s = config_parse_value(fk, (void *)fam, ents->v[i].value, where, err, errlen)))
                return s;
        }
    for (int i = 0; i < n_sets; i++) {
        if ((s = split_set(sets[i], section, name, value, err, errlen)) != SUNMC_OK)
            return s;
        if (strcmp(section, "sensor") == 0 && strcmp(name, "family") == 0) {
            snprintf(where, CONFIG_ORIGIN_MAX, "--set %s.%s", section, name);
            if ((s = config_parse_value(fk, (void *)fam, value, "--set", err, errlen)))
                return s;
        }
    }
    return SUNMC_OK;
}

/* The file's entries, then the overrides (sensor.family is already set). */
static int apply_values(config_state *st, const ini_entries *ents, const char *path,
                        const char *const *sets, int n_sets, char *err, size_t errlen)
{
    char where[CONFIG_ORIGIN_MAX];
    char section[CONFIG_STR_MAX], name[CONFIG_STR_MAX], value[INI_LINE_MAX];
    int s;
    for (int i = 0; i < ents->n; i++) {
        if (strcmp(ents->v[i].section, "sensor") == 0 && strcmp(ents->v[i].key, "family") == 0)
            continue;
        snprintf(where, sizeof where, "%s:%d", path, ents->v[i].line);
        s = config_set_value(st, ents->v[i].section, ents->v[i].key, ents->v[i].value, where, err,
                             errlen);
        if (s != SUNMC_OK)
            return s;
    }
    for (int i = 0; i < n_sets; i++) {
        split_set(sets[i], section, name, value, err, errlen);
        if (strcmp(section, "sensor") == 0 && strcmp(name, "family") == 0)
            continue;
        snprintf(where, sizeof where, "--set %s.%s", section, name);
        if ((s = config_set_value(st, section, name, value, where, err, errlen)) != SUNMC_OK)
            return s;
    }
    return SUNMC_OK;
}

/* 1 when "section.name" of k appears in msg as a whole key name. */
static long key_position(const config_key *k, const char *msg)
{
    char dotted[2 * CONFIG_STR_MAX + 2];
    snprintf(dotted, sizeof dotted, "%s.%s", k->section, k->name);
    size_t len = strlen(dotted);
    for (const char *p = strstr(msg, dotted); p; p = strstr(p + 1, dotted)) {
        char before = p > msg ? p[-1] : ' ', after = p[len];
        if (!isalnum((unsigned char)before) && before != '_' && before != '.' &&
            !isalnum((unsigned char)after) && after != '_')
            return p - msg;
    }
    return -1;
}

/* The origins of the keys a cross-key message names, in the order it names
 * them ("--set tolerance.dH_um, ess.ini:11"); defaults are left out, and
 * when no named key has another origin, the file (or "config"). */
static void message_origins(const config_state *st, const char *msg, const char *path, char *buf,
                            size_t len)
{
    enum { MAX_NAMED = 8 };
    long pos[MAX_NAMED];
    const char *org[MAX_NAMED];
    int n = 0;
    for (size_t i = 0; i < st->n_keys && n < MAX_NAMED; i++) {
        long p = key_position(st->keys[i], msg);
        const char *o = st->origins[i].origin;
        if (p < 0 || strcmp(o, "default") == 0)
            continue;
        int j = n++;
        for (; j > 0 && pos[j - 1] > p; j--) {
            pos[j] = pos[j - 1];
            org[j] = org[j - 1];
        }
        pos[j] = p;
        org[j] = o;
    }
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < n && used < len; i++)
        used += (size_t)snprintf(buf + used, len - used, "%s%s", i ? ", " : "", org[i]);
    if (n == 0)
        snprintf(buf, len, "%s", path ? path : "config");
}

int config_check(config_state *st, const char *path, char *err, size_t errlen)
{
    char verr[SUNMC_ERRLEN];
    int status = config_validate(&st->cfg, verr, sizeof verr);
    if (status != SUNMC_OK) {
        char where[2 * CONFIG_ORIGIN_MAX];
        message_origins(st, verr, path, where, sizeof where);
        sunmc_fail(err, errlen, status, "%s: %s", where, verr);
    }
    return status;
}

int config_build(config_state *st, const char *path, const char *const *sets, int n_sets,
                 char *err, size_t errlen)
{
    int status = config_build_unchecked(st, path, sets, n_sets, err, errlen);
    if (status == SUNMC_OK && (status = config_check(st, path, err, errlen)) != SUNMC_OK)
        config_state_free(st);
    return status;
}

int config_build_unchecked(config_state *st, const char *path, const char *const *sets,
                           int n_sets, char *err, size_t errlen)
{
    memset(st, 0, sizeof *st);
    ini_entries ents = {0};
    const sensor_family *fam;
    char fam_where[CONFIG_ORIGIN_MAX];
    int status = SUNMC_OK;
    if (path && (status = read_ini(path, &ents, err, errlen)) != SUNMC_OK)
        goto done;
    status = resolve_family(&ents, path, sets, n_sets, &fam, fam_where, err, errlen);
    if (status == SUNMC_OK)
        status = init_state(st, fam, err, errlen);
    if (status != SUNMC_OK)
        goto done;
    if (fam_where[0])
        set_origin(st, config_find("sensor", "family"), fam_where);
    status = apply_values(st, &ents, path, sets, n_sets, err, errlen);
done:
    free(ents.v);
    if (status != SUNMC_OK)
        config_state_free(st);
    return status;
}

void config_state_free(config_state *st)
{
    free(st->keys);
    free(st->origins);
    st->keys = NULL;
    st->origins = NULL;
    st->n_keys = 0;
}

int config_validate(const sunmc_config *c, char *err, size_t errlen)
{
    if (!c->family)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "sensor.family is not set");
    int s = thermal_check(c, err, errlen);
    if (s == SUNMC_OK)
        s = verdict_check(c, err, errlen);
    lab_onboard_spec ob;
    if (s == SUNMC_OK)
        s = lab_onboard_config(c, &ob, err, errlen);
    if (s == SUNMC_OK && c->family->validate)
        s = c->family->validate(c, err, errlen);
    return s == SUNMC_OK ? memory_check_workspace(c, err, errlen) : s;
}

const config_key *config_find_dotted(const struct sensor_family *fam, const char *dotted)
{
    char section[CONFIG_STR_MAX];
    const char *dot = strchr(dotted, '.');
    if (!dot || (size_t)(dot - dotted) >= sizeof section)
        return NULL;
    memcpy(section, dotted, (size_t)(dot - dotted));
    section[dot - dotted] = '\0';
    return config_find_in(fam, section, dot + 1);
}

int config_get_number(const sunmc_config *c, const char *dotted, double *out, char *err,
                      size_t errlen)
{
    if (!strchr(dotted, '.'))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "'%s' is not section.key", dotted);
    const config_key *k = config_find_dotted(c->family, dotted);
    if (!k)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "unknown key '%s'", dotted);
    const void *base = config_value_cptr(k, c);
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
