/* config_value.c - one key's value: parsing text into the config (with the
 * key's type and range checks) and formatting it back. */
#include "config.h"
#include "ini.h"
#include "numtext.h"
#include "registry.h"
#include "shortest.h"
#include "status.h"
#include "suggest.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Longest number text read (a long's digits or a double's, with room). */
#define NUMBER_TEXT_MAX 128

/* s without its trailing blanks into buf; -1 when it does not fit. */
static int untrail(const char *s, char *buf, size_t len)
{
    size_t n = strlen(s);
    while (n > 0 && isspace((unsigned char)s[n - 1]))
        n--;
    if (n >= len)
        return -1;
    memcpy(buf, s, n);
    buf[n] = '\0';
    return 0;
}

/* A whole-string decimal double (numtext.h; trailing blanks allowed); 0 on
 * success. */
static int parse_double(const char *s, double *out)
{
    char buf[NUMBER_TEXT_MAX];
    return untrail(s, buf, sizeof buf) != 0 || num_parse_double(buf, out) != 0 ? -1 : 0;
}

/* A whole-string decimal long (numtext.h); 0 on success, -1 when not a
 * whole number, -2 when one too large for a long (a 200-digit seed). */
static int parse_long(const char *s, long *out)
{
    char buf[NUMBER_TEXT_MAX];
    if (untrail(s, buf, sizeof buf) != 0) /* hundreds of digits */
        return strspn(s, "-0123456789") >= sizeof buf ? -2 : -1;
    return num_parse_long(buf, out);
}

void config_family_choices(char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < sensor_family_count() && used < len; i++)
        used += (size_t)snprintf(buf + used, len - used, "%s%s", i ? "|" : "",
                                 sensor_family_at(i)->name);
}

void config_range_text(const config_key *k, char *buf, size_t len)
{
    char fams[128];
    if (k->type == KEY_ENUM)
        snprintf(buf, len, "one of %s", k->choices);
    else if (k->type == KEY_FAMILY) {
        config_family_choices(fams, sizeof fams);
        snprintf(buf, len, "one of %s", fams);
    } else if (k->type == KEY_STRING)
        snprintf(buf, len, "text of at most %d characters", CONFIG_STR_MAX - 1);
    else
        snprintf(buf, len, "%.10g to %.10g%s%s", k->min, k->max, k->unit[0] ? " " : "", k->unit);
}

static int check_range(const config_key *k, double v, const char *where, const char *what,
                       char *err, size_t errlen)
{
    if (v < k->min || v > k->max) {
        char r[128];
        config_range_text(k, r, sizeof r);
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

static int set_number(const config_key *k, void *dst, const char *v, const char *where, char *err,
                      size_t errlen)
{
    double d;
    long l;
    int st;
    if (k->type == KEY_DOUBLE) {
        if (parse_double(v, &d) != 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s = '%s' is not a number", where,
                              k->section, k->name, v);
        if ((st = check_range(k, d, where, v, err, errlen)) != SUNMC_OK)
            return st;
        *(double *)dst = d;
        return SUNMC_OK;
    }
    int pl = parse_long(v, &l);
    if (pl == -2) {
        char r[128];
        config_range_text(k, r, sizeof r);
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: %s.%s = '%.24s...' (%zu digits) is out of range: allowed %s", where,
                          k->section, k->name, v, strlen(v), r);
    }
    if (pl != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s = '%s' is not a whole number",
                          where, k->section, k->name, v);
    if ((st = check_range(k, (double)l, where, v, err, errlen)) != SUNMC_OK)
        return st;
    if (k->type == KEY_INT)
        *(int *)dst = (int)l;
    else
        *(long *)dst = l;
    return SUNMC_OK;
}

static int set_choice(const config_key *k, void *dst, const char *v, const char *where, char *err,
                      size_t errlen)
{
    if (k->type == KEY_FAMILY) {
        const sensor_family *f = sensor_family_find(v);
        char fams[128];
        config_family_choices(fams, sizeof fams);
        char hint[SUGGEST_NAME_MAX + 32];
        suggest_hint(v, fams, hint, sizeof hint);
        if (!f)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s: %s.%s = '%s' is not allowed: one of %s%s", where, k->section,
                              k->name, v, fams, hint);
        *(const sensor_family **)dst = f;
        return SUNMC_OK;
    }
    int idx = enum_index(k->choices, v);
    char hint[SUGGEST_NAME_MAX + 32];
    if (idx < 0)
        suggest_hint(v, k->choices, hint, sizeof hint);
    if (idx < 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: %s.%s = '%s' is not allowed: one of %s%s", where, k->section,
                          k->name, v, k->choices, hint);
    *(int *)dst = idx + (int)k->min;
    return SUNMC_OK;
}

/* Bytes of the UTF-8 sequence starting at p (2 to 4), 0 when it is not
 * one: no overlong forms, surrogates or code points past U+10FFFF. */
static int utf8_sequence(const unsigned char *p)
{
    int n = p[0] >= 0xC2 && p[0] <= 0xDF ? 2 : p[0] >= 0xE0 && p[0] <= 0xEF ? 3
            : p[0] >= 0xF0 && p[0] <= 0xF4 ? 4 : 0;
    for (int i = 1; i < n; i++)
        if ((p[i] & 0xC0) != 0x80)
            return 0;
    if ((p[0] == 0xE0 && p[1] < 0xA0) || (p[0] == 0xED && p[1] > 0x9F) ||
        (p[0] == 0xF0 && p[1] < 0x90) || (p[0] == 0xF4 && p[1] > 0x8F))
        return 0;
    return n;
}

/* Printable text: ASCII without control characters and tabs, or UTF-8
 * ("Sonnensensor Typ Ä"); a product label goes to reports and TSV files. */
static int set_string(const config_key *k, void *dst, const char *v, const char *where, char *err,
                      size_t errlen)
{
    if (strlen(v) >= CONFIG_STR_MAX || strlen(v) == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: %s.%s must be text of 1 to %d bytes", where, k->section, k->name,
                          CONFIG_STR_MAX - 1);
    for (const unsigned char *p = (const unsigned char *)v; *p; p++) {
        if (*p >= 0x80) {
            int n = utf8_sequence(p);
            if (!n)
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "%s: %s.%s is not valid UTF-8 (byte %ld)", where, k->section,
                                  k->name, (long)(p - (const unsigned char *)v) + 1);
            p += n - 1;
        } else if (*p == '#' && (p == (const unsigned char *)v || p[-1] == ' ')) {
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s: %s.%s holds '#' at its start or after a blank, which starts "
                              "a comment in a config file (config.ini would not read it back); "
                              "write it without the blank, e.g. 'Typ#2'",
                              where, k->section, k->name);
        } else if (*p == '\t' || !isprint(*p)) {
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s: %s.%s holds a tab or control character", where, k->section,
                              k->name);
        }
    }
    snprintf((char *)dst, CONFIG_STR_MAX, "%s", v);
    return SUNMC_OK;
}

/* The comma-separated items of v in turn (v on the first call, NULL after;
 * *save keeps the place): unlike strtok, "1,,2" has an empty second item. */
static char *strsep_items(char **save, char *v)
{
    if (v)
        *save = v;
    return strsep(save, ",");
}

/* An empty item ("1,,2", a comma at either end) is an error, not skipped:
 * it is a typo for a missing value. */
static int nonempty_item(const config_key *k, const char *t, int item, const char *where,
                         char *err, size_t errlen)
{
    if (*t)
        return SUNMC_OK;
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "%s: %s.%s: item %d of the list is empty (two commas in a row, or a comma "
                      "at an end)", where, k->section, k->name, item);
}

/* Guard against the rounding of (stop - start) / step: 0:60:30 has 3 values. */
#define LIST_RANGE_EPS 1e-9

/* Append d to l, within the key's range and the list's size. */
static int list_push(const config_key *k, double_list *l, double d, const char *t,
                     const char *where, char *err, size_t errlen)
{
    int st = check_range(k, d, where, t, err, errlen);
    if (st != SUNMC_OK)
        return st;
    if (l->n >= CONFIG_LIST_MAX)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s has more than %d values", where,
                          k->section, k->name, CONFIG_LIST_MAX);
    l->v[l->n++] = d;
    return SUNMC_OK;
}

/* An item START:STOP:STEP: START, START + STEP, ... up to STOP (the
 * values cut at 15 significant digits, as sweep's ranges). */
static int list_range(const config_key *k, double_list *l, char *t, const char *where, char *err,
                      size_t errlen)
{
    char *c1 = strchr(t, ':'), *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    double start, stop, step;
    if (!c2 || strchr(c2 + 1, ':'))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: %s.%s: '%s' is not a number or a range START:STOP:STEP", where,
                          k->section, k->name, t);
    *c1 = *c2 = '\0';
    if (parse_double(ini_trim(t), &start) != 0 || parse_double(ini_trim(c1 + 1), &stop) != 0 ||
        parse_double(ini_trim(c2 + 1), &step) != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: %s.%s: a range is START:STOP:STEP, three numbers", where,
                          k->section, k->name);
    if (step == 0 || (stop - start) * step < 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: %s.%s: range %g:%g:%g: STEP must be non-zero and lead from START "
                          "to STOP",
                          where, k->section, k->name, start, stop, step);
    double count = floor((stop - start) / step + LIST_RANGE_EPS) + 1;
    if (count > CONFIG_LIST_MAX)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s has more than %d values", where,
                          k->section, k->name, CONFIG_LIST_MAX);
    for (int i = 0; i < (int)count; i++) {
        char v[32];
        snprintf(v, sizeof v, "%.15g", start + (double)i * step);
        int st = list_push(k, l, strtod(v, NULL), v, where, err, errlen);
        if (st != SUNMC_OK)
            return st;
    }
    return SUNMC_OK;
}

/* A comma-separated list of numbers and ranges START:STOP:STEP, each value
 * within the key's range. */
static int set_list(const config_key *k, void *dst, char *v, const char *where, char *err,
                    size_t errlen)
{
    double_list tmp = {0};
    char *save = NULL;
    double d;
    int st;
    int item = 0;
    for (char *tok = *v ? strsep_items(&save, v) : NULL; tok; tok = strsep_items(&save, NULL)) {
        char *t = ini_trim(tok);
        if ((st = nonempty_item(k, t, ++item, where, err, errlen)) != SUNMC_OK)
            return st;
        if (strchr(t, ':'))
            st = list_range(k, &tmp, t, where, err, errlen);
        else if (parse_double(t, &d) != 0)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                            "%s: %s.%s: '%s' is not a number (a comma-separated list)", where,
                            k->section, k->name, t);
        else
            st = list_push(k, &tmp, d, t, where, err, errlen);
        if (st != SUNMC_OK)
            return st;
    }
    if (tmp.n == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s is an empty list", where,
                          k->section, k->name);
    *(double_list *)dst = tmp;
    return SUNMC_OK;
}

/* One band "LO:HI" of a band list into b->lo/hi[b->n]. */
static int add_band(const config_key *k, band_list *b, char *t, const char *where, char *err,
                    size_t errlen)
{
    char *colon = strchr(t, ':');
    double lo, hi;
    int st;
    if (b->n >= CONFIG_BANDS_MAX)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s has more than %d bands", where,
                          k->section, k->name, CONFIG_BANDS_MAX);
    if (!colon)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: %s.%s: band '%s' is not LO:HI (e.g. 0:30, 30:60)", where,
                          k->section, k->name, t);
    *colon = '\0';
    if (parse_double(ini_trim(t), &lo) != 0 || parse_double(ini_trim(colon + 1), &hi) != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s: band bounds must be numbers",
                          where, k->section, k->name);
    if ((st = check_range(k, lo, where, "band low", err, errlen)) != SUNMC_OK ||
        (st = check_range(k, hi, where, "band high", err, errlen)) != SUNMC_OK)
        return st;
    if (!(hi > lo))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s: band %g:%g must have LO < HI",
                          where, k->section, k->name, lo, hi);
    b->lo[b->n] = lo;
    b->hi[b->n] = hi;
    b->n++;
    return SUNMC_OK;
}

static int set_bands(const config_key *k, void *dst, char *v, const char *where, char *err,
                     size_t errlen)
{
    band_list tmp = {0};
    char *save = NULL;
    int item = 0;
    for (char *tok = *v ? strsep_items(&save, v) : NULL; tok; tok = strsep_items(&save, NULL)) {
        char *t = ini_trim(tok);
        int st = nonempty_item(k, t, ++item, where, err, errlen);
        if (st == SUNMC_OK)
            st = add_band(k, &tmp, t, where, err, errlen);
        if (st != SUNMC_OK)
            return st;
    }
    if (tmp.n == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s.%s has no band", where, k->section,
                          k->name);
    *(band_list *)dst = tmp;
    return SUNMC_OK;
}

int config_parse_value(const config_key *k, void *dst, const char *value, const char *where,
                       char *err, size_t errlen)
{
    char buf[INI_LINE_MAX];
    snprintf(buf, sizeof buf, "%s", value);
    char *v = ini_trim(buf);
    switch (k->type) {
    case KEY_DOUBLE:
    case KEY_INT:
    case KEY_LONG:
        return set_number(k, dst, v, where, err, errlen);
    case KEY_ENUM:
    case KEY_FAMILY:
        return set_choice(k, dst, v, where, err, errlen);
    case KEY_STRING:
        return set_string(k, dst, v, where, err, errlen);
    case KEY_LIST:
        return set_list(k, dst, v, where, err, errlen);
    case KEY_BANDS:
        return set_bands(k, dst, v, where, err, errlen);
    }
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: internal: bad key type", where);
}

static void format_list(const double_list *l, char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < l->n && used < len; i++) {
        char t[SHORTEST_TEXT_MAX];
        shortest_double(l->v[i], t, sizeof t);
        used += (size_t)snprintf(buf + used, len - used, "%s%s", i ? ", " : "", t);
    }
}

static void format_bands(const band_list *b, char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < b->n && used < len; i++) {
        char lo[SHORTEST_TEXT_MAX], hi[SHORTEST_TEXT_MAX];
        shortest_double(b->lo[i], lo, sizeof lo);
        shortest_double(b->hi[i], hi, sizeof hi);
        used += (size_t)snprintf(buf + used, len - used, "%s%s:%s", i ? ", " : "", lo, hi);
    }
}

void config_format_value(const config_key *k, const sunmc_config *c, char *buf, size_t len)
{
    const void *base = config_value_cptr(k, c);
    switch (k->type) {
    case KEY_DOUBLE:
        shortest_double(*(const double *)base, buf, len);
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
    case KEY_FAMILY:
        snprintf(buf, len, "%s", (*(const sensor_family *const *)base)->name);
        break;
    case KEY_STRING:
        snprintf(buf, len, "%s", (const char *)base);
        break;
    case KEY_LIST:
        format_list(base, buf, len);
        break;
    case KEY_BANDS:
        format_bands(base, buf, len);
        break;
    default:
        snprintf(buf, len, "?");
    }
}
