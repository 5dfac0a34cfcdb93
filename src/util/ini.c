/* ini.c - the INI lexer shared by the config reader and params.ini. */
#include "ini.h"
#include "status.h"

#include <ctype.h>

/* A UTF-8 byte-order mark, as spreadsheet and Windows editors write it. */
#define UTF8_BOM "\xEF\xBB\xBF"
#include <stdlib.h>
#include <string.h>

char *ini_trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    char *e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = '\0';
    return s;
}

void ini_begin(ini_reader *r, FILE *f, const char *path)
{
    memset(r, 0, sizeof *r);
    r->f = f;
    r->path = path;
}

void ini_end(ini_reader *r)
{
    free(r->seen);
    r->seen = NULL;
    r->n_seen = r->cap_seen = 0;
}

/* Cut the comment off line s into comment (trimmed): a '#' at the start or
 * after white space.  A line whose first character is ';' is all comment. */
static void cut_comment(char *s, char *comment, size_t len)
{
    comment[0] = '\0';
    if (*s == ';') {
        snprintf(comment, len, "%s", ini_trim(s + 1));
        *s = '\0';
        return;
    }
    for (char *p = s; *p; p++)
        if (*p == '#' && (p == s || isspace((unsigned char)p[-1]))) {
            snprintf(comment, len, "%s", ini_trim(p + 1));
            *p = '\0';
            return;
        }
}

static int copy_name(char *dst, const char *src, const ini_reader *r, char *err, size_t errlen)
{
    if (strlen(src) >= INI_NAME_MAX)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: name '%.20s...' longer than %d "
                          "characters", r->path, r->line, src, INI_NAME_MAX - 1);
    strcpy(dst, src);
    return SUNMC_OK;
}

static int section_header(ini_reader *r, char *s, ini_entry *e, char *err, size_t errlen)
{
    char *close = strchr(s, ']');
    if (!close || *ini_trim(close + 1) != '\0' || (*close = '\0', *ini_trim(s + 1) == '\0')) {
        if (close)
            *close = ']';
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: malformed section header '%s'",
                          r->path, r->line, s);
    }
    int st = copy_name(r->section, ini_trim(s + 1), r, err, errlen);
    if (st == SUNMC_OK)
        strcpy(e->section, r->section);
    return st;
}

/* Record section.key at this line; a key given twice is an error. */
static int remember_key(ini_reader *r, const ini_entry *e, char *err, size_t errlen)
{
    for (int i = 0; i < r->n_seen; i++)
        if (strcmp(r->seen[i].section, e->section) == 0 && strcmp(r->seen[i].key, e->key) == 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s:%d: duplicate key %s.%s (first set on line %d)", r->path,
                              r->line, e->section, e->key, r->seen[i].line);
    if (r->n_seen == r->cap_seen) {
        int cap = r->cap_seen ? 2 * r->cap_seen : 64;
        ini_seen *nv = realloc(r->seen, (size_t)cap * sizeof *nv);
        if (!nv)
            return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", r->path);
        r->seen = nv;
        r->cap_seen = cap;
    }
    ini_seen *k = &r->seen[r->n_seen++];
    strcpy(k->section, e->section);
    strcpy(k->key, e->key);
    k->line = r->line;
    return SUNMC_OK;
}

static int key_line(ini_reader *r, char *s, ini_entry *e, char *err, size_t errlen)
{
    char *eq = strchr(s, '=');
    if (!eq)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: expected 'key = value' or '[section]', got '%s'", r->path,
                          r->line, s);
    *eq = '\0';
    char *key = ini_trim(s);
    if (r->section[0] == '\0')
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: key '%s' before any [section]",
                          r->path, r->line, key);
    if (*key == '\0')
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: empty key", r->path, r->line);
    int st = copy_name(e->key, key, r, err, errlen);
    if (st != SUNMC_OK)
        return st;
    strcpy(e->section, r->section);
    snprintf(e->value, sizeof e->value, "%s", ini_trim(eq + 1));
    return remember_key(r, e, err, errlen);
}

/* The next line of f, its end included as fgets keeps it, into
 * buf[INI_LINE_MAX + 1]: INI_READ_LINE, INI_READ_END at the end of the file,
 * INI_READ_LONG for a line longer than INI_LINE_MAX (reading stops there, so
 * an endless line such as /dev/zero's ends too), INI_READ_NUL for a NUL
 * byte (a binary file: fgets would cut the line there and read on). */
enum { INI_READ_END, INI_READ_LINE, INI_READ_LONG, INI_READ_NUL };

static int read_line(FILE *f, char *buf)
{
    size_t n = 0;
    int c;
    while ((c = getc(f)) != EOF) {
        if (c == '\0')
            return INI_READ_NUL;
        if (n >= INI_LINE_MAX)
            return INI_READ_LONG;
        buf[n++] = (char)c;
        if (c == '\n')
            break;
    }
    buf[n] = '\0';
    return n ? INI_READ_LINE : INI_READ_END;
}

int ini_next(ini_reader *r, int *item, ini_entry *e, char *err, size_t errlen)
{
    char buf[INI_LINE_MAX + 1];
    int got;
    *item = INI_END;
    while ((got = read_line(r->f, buf)) != INI_READ_END) {
        r->line++;
        if (got == INI_READ_NUL)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s:%d: a NUL byte: this is not a text file", r->path, r->line);
        if (got == INI_READ_LONG)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: line longer than %d characters",
                              r->path, r->line, INI_LINE_MAX);
        if (r->line == 1 && strncmp(buf, UTF8_BOM, strlen(UTF8_BOM)) == 0)
            memmove(buf, buf + strlen(UTF8_BOM), strlen(buf) - strlen(UTF8_BOM) + 1);
        memset(e, 0, sizeof *e);
        e->line = r->line;
        char *s = ini_trim(buf);
        cut_comment(s, e->comment, sizeof e->comment);
        s = ini_trim(s);
        if (*s == '\0')
            continue;
        int is_section = *s == '[';
        int st = is_section ? section_header(r, s, e, err, errlen) : key_line(r, s, e, err, errlen);
        if (st == SUNMC_OK)
            *item = is_section ? INI_SECTION : INI_KEY;
        return st;
    }
    if (ferror(r->f))
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: read error", r->path);
    return SUNMC_OK;
}
