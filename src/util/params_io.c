/* params_io.c - params.ini writing and reading, FNV-1a checksums. */
#include "ini.h"
#include "numtext.h"
#include "params_io.h"
#include "status.h"
#include "suggest.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FNV1A64_PRIME 0x100000001b3ULL
#define HASH_CHUNK 65536

unsigned long long params_fnv1a64(unsigned long long h, const void *data, size_t n)
{
    const unsigned char *b = data;
    for (size_t i = 0; i < n; i++) {
        h ^= b[i];
        h *= FNV1A64_PRIME;
    }
    return h;
}

int params_file_fnv1a64(const char *path, unsigned long long *hash, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot read: %s", path, strerror(errno));
    unsigned char buf[HASH_CHUNK];
    unsigned long long h = PARAMS_FNV1A64_INIT;
    size_t got;
    while ((got = fread(buf, 1, sizeof buf, f)) > 0)
        h = params_fnv1a64(h, buf, got);
    int bad = ferror(f);
    fclose(f);
    if (bad)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: read error", path);
    *hash = h;
    return SUNMC_OK;
}

void params_init(params_file *p)
{
    memset(p, 0, sizeof *p);
}

const params_entry *params_find(const params_file *p, const char *section, const char *key)
{
    for (int i = 0; i < p->n; i++)
        if (strcmp(p->e[i].section, section) == 0 && strcmp(p->e[i].key, key) == 0)
            return &p->e[i];
    return NULL;
}

int params_rename(params_file *p, const char *section, const char *from, const char *to)
{
    params_entry *e = (params_entry *)params_find(p, section, from);
    if (!e || params_find(p, section, to) || strlen(to) >= sizeof e->key)
        return 0;
    memcpy(e->key, to, strlen(to) + 1);
    return 1;
}

static int copy_str(char *dst, size_t cap, const char *src)
{
    size_t n = strlen(src);
    if (n >= cap)
        return -1;
    memcpy(dst, src, n + 1);
    return 0;
}

int params_set_text(params_file *p, const char *section, const char *key, const char *text,
                    const char *comment)
{
    if (p->n >= PARAMS_MAX_ENTRIES)
        return SUNMC_EINPUT;
    if (params_find(p, section, key))
        return SUNMC_EINPUT;
    params_entry *e = &p->e[p->n];
    memset(e, 0, sizeof *e);
    if (copy_str(e->section, sizeof e->section, section) ||
        copy_str(e->key, sizeof e->key, key) || copy_str(e->value, sizeof e->value, text) ||
        copy_str(e->comment, sizeof e->comment, comment ? comment : ""))
        return SUNMC_EINPUT;
    if (strchr(text, '\n') || strchr(text, '#'))
        return SUNMC_EINPUT;
    p->n++;
    return SUNMC_OK;
}

int params_set_double(params_file *p, const char *section, const char *key, double v,
                      const char *comment)
{
    char buf[64];
    snprintf(buf, sizeof buf, "%.17g", v);
    return params_set_text(p, section, key, buf, comment);
}

int params_write(FILE *f, const params_file *p, const char *title)
{
    const char *t = title;
    while (t && *t) {
        const char *nl = strchr(t, '\n');
        int len = nl ? (int)(nl - t) : (int)strlen(t);
        fprintf(f, "# %.*s\n", len, t);
        t = nl ? nl + 1 : t + len;
    }
    int done[PARAMS_MAX_ENTRIES] = {0};
    for (int i = 0; i < p->n; i++) {
        if (done[i])
            continue;
        fprintf(f, "\n[%s]\n", p->e[i].section);
        for (int j = i; j < p->n; j++) {
            if (done[j] || strcmp(p->e[j].section, p->e[i].section) != 0)
                continue;
            done[j] = 1;
            if (p->e[j].comment[0])
                fprintf(f, "%-24s = %-24s  # %s\n", p->e[j].key, p->e[j].value, p->e[j].comment);
            else
                fprintf(f, "%s = %s\n", p->e[j].key, p->e[j].value);
        }
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

int params_read(const char *path, params_file *p, char *err, size_t errlen)
{
    params_init(p);
    if (copy_str(p->path, sizeof p->path, path))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: path too long", path);
    FILE *f = fopen(path, "r");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot read: %s", path, strerror(errno));
    ini_reader r;
    ini_entry e;
    int item, st;
    ini_begin(&r, f, path);
    while ((st = ini_next(&r, &item, &e, err, errlen)) == SUNMC_OK && item != INI_END) {
        if (item != INI_KEY)
            continue;
        if (params_set_text(p, e.section, e.key, e.value, e.comment) != SUNMC_OK) {
            st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: key %s.%s: too long or too many keys",
                            path, e.line, e.section, e.key);
            break;
        }
        p->e[p->n - 1].line = e.line;
    }
    ini_end(&r);
    fclose(f);
    return st;
}

int params_get_text(const params_file *p, const char *section, const char *key,
                    const char **out, char *err, size_t errlen)
{
    const params_entry *e = params_find(p, section, key);
    if (!e)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: missing key %s.%s",
                          p->path[0] ? p->path : "params", section, key);
    *out = e->value;
    return SUNMC_OK;
}

int params_get_double(const params_file *p, const char *section, const char *key, double *out,
                      char *err, size_t errlen)
{
    const char *s = NULL;
    int st = params_get_text(p, section, key, &s, err, errlen);
    if (st != SUNMC_OK)
        return st;
    const params_entry *e = params_find(p, section, key);
    double v = 0;
    int pst = num_parse_double(s, &v);
    if (pst == -1)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: key %s.%s: '%s' is not a number", p->path, e->line,
                          section, key, s);
    if (pst != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: key %s.%s: '%s' is not finite",
                          p->path, e->line, section, key, s);
    *out = v;
    return SUNMC_OK;
}

int params_get_int(const params_file *p, const char *section, const char *key, int *out,
                   char *err, size_t errlen)
{
    const char *s = NULL;
    int st = params_get_text(p, section, key, &s, err, errlen);
    if (st != SUNMC_OK)
        return st;
    long v = 0;
    if (num_parse_long(s, &v) != 0 || v < INT_MIN || v > INT_MAX) {
        const params_entry *e = params_find(p, section, key);
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: key %s.%s: '%s' is not a whole number",
                          p->path, e->line, section, key, e->value);
    }
    *out = (int)v;
    return SUNMC_OK;
}

int params_check_ranges(const params_file *p, const params_range *ranges, int n, char *err,
                        size_t errlen)
{
    for (int i = 0; i < n; i++) {
        const params_range *r = &ranges[i];
        double v;
        int st = params_get_double(p, r->section, r->key, &v, err, errlen);
        if (st != SUNMC_OK)
            return st;
        if (v >= r->lo && v <= r->hi)
            continue;
        const params_entry *e = params_find(p, r->section, r->key);
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: %s.%s = %s is out of range: allowed %g to %g%s%s%s%s%s",
                          p->path, e->line, r->section, r->key, e->value, r->lo, r->hi,
                          r->unit[0] ? " " : "", r->unit, r->why ? " (" : "", r->why ? r->why : "",
                          r->why ? ")" : "");
    }
    return SUNMC_OK;
}

int params_require(const params_file *p, const char *section, const char *key, int ok,
                   const char *what, char *err, size_t errlen)
{
    if (ok)
        return SUNMC_OK;
    const params_entry *e = params_find(p, section, key);
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: key %s.%s must be %s", p->path,
                      e ? e->line : 0, section, key, what);
}

const params_entry *params_unknown_key(const params_file *p, const char *section,
                                       const char *const *names, int n)
{
    for (int i = 0; i < p->n; i++) {
        if (strcmp(p->e[i].section, section) != 0)
            continue;
        int known = 0;
        for (int j = 0; j < n && !known; j++)
            known = strcmp(p->e[i].key, names[j]) == 0;
        if (!known)
            return &p->e[i];
    }
    return NULL;
}

int params_check_keys(const params_file *p, const char *section, const char *const *names,
                      int n, char *err, size_t errlen)
{
    const params_entry *e = params_unknown_key(p, section, names, n);
    if (!e)
        return SUNMC_OK;
    const char *near = suggest_nearest(e->key, names, (size_t)n);
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: unknown key %s.%s%s%s%s", p->path,
                      e->line, section, e->key, near ? " (did you mean " : "", near ? near : "",
                      near ? "?)" : "");
}
