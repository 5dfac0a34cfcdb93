/* csv.c - reading the lab's comma-separated data files (see csv.h). */
#include "csv.h"
#include "status.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CSV_SEPARATOR ','
#define CSV_COMMENT '#'
#define CSV_ROWS_INITIAL 256

static char *trim(char *s)
{
    while (*s && isspace((unsigned char)*s))
        s++;
    char *e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = '\0';
    return s;
}

/* Count the fields of a line (separators + 1). */
static int count_fields(const char *s)
{
    int n = 1;
    for (; *s; s++)
        n += *s == CSV_SEPARATOR;
    return n;
}

/* Split line s in place into n trimmed fields. */
static void split_fields(char *s, char **out, int n)
{
    for (int i = 0; i < n; i++) {
        char *sep = strchr(s, CSV_SEPARATOR);
        if (sep)
            *sep = '\0';
        out[i] = trim(s);
        s = sep ? sep + 1 : s + strlen(s);
    }
}

static int read_all(const char *path, char **buf_out, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot read: %s", path, strerror(errno));
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap);
    if (!buf) {
        fclose(f);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
    }
    for (;;) {
        if (len + 1 >= cap) {
            char *nb = realloc(buf, cap *= 2);
            if (!nb) {
                free(buf);
                fclose(f);
                return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
            }
            buf = nb;
        }
        size_t got = fread(buf + len, 1, cap - 1 - len, f);
        len += got;
        if (got == 0)
            break;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        free(buf);
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: read error", path);
    }
    if (memchr(buf, '\0', len)) {
        free(buf);
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: binary data (NUL byte) in a text file",
                          path);
    }
    buf[len] = '\0';
    *buf_out = buf;
    return SUNMC_OK;
}

void csv_free(csv_table *t)
{
    if (!t)
        return;
    free(t->path);
    free(t->names);
    free(t->line);
    free(t->field);
    free(t->buf);
    free(t);
}

int csv_read(const char *path, csv_table **out, char *err, size_t errlen)
{
    *out = NULL;
    csv_table *t = calloc(1, sizeof *t);
    if (!t)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
    t->path = strdup(path);
    int st = t->path ? read_all(path, &t->buf, err, errlen)
                     : sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
    if (st != SUNMC_OK) {
        csv_free(t);
        return st;
    }
    size_t cap = 0;
    int lineno = 0;
    char *p = t->buf;
    while (*p) {
        char *nl = strchr(p, '\n');
        if (nl)
            *nl = '\0';
        char *next = nl ? nl + 1 : p + strlen(p);
        lineno++;
        char *s = trim(p);
        p = next;
        if (*s == '\0' || *s == CSV_COMMENT)
            continue;
        int nf = count_fields(s);
        if (!t->names) {
            t->header_line = lineno;
            t->n_cols = nf;
            t->names = malloc((size_t)nf * sizeof *t->names);
            if (!t->names) {
                csv_free(t);
                return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
            }
            split_fields(s, t->names, nf);
            for (int i = 0; i < nf; i++) {
                if (t->names[i][0] == '\0') {
                    st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                                    "%s:%d: header column %d has no name", path, lineno, i + 1);
                    csv_free(t);
                    return st;
                }
                for (int j = 0; j < i; j++)
                    if (strcmp(t->names[i], t->names[j]) == 0) {
                        st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                                        "%s:%d: duplicate column '%s' in the header (columns %d "
                                        "and %d)",
                                        path, lineno, t->names[i], j + 1, i + 1);
                        csv_free(t);
                        return st;
                    }
            }
            continue;
        }
        if (nf != t->n_cols) {
            st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                            "%s:%d: %d fields, but the header (line %d) has %d columns", path,
                            lineno, nf, t->header_line, t->n_cols);
            csv_free(t);
            return st;
        }
        if (t->n_rows == cap) {
            cap = cap ? 2 * cap : CSV_ROWS_INITIAL;
            int *nl2 = realloc(t->line, cap * sizeof *nl2);
            if (nl2)
                t->line = nl2;
            char **nf2 = nl2 ? realloc(t->field, cap * (size_t)t->n_cols * sizeof *nf2) : NULL;
            if (!nf2) {
                csv_free(t);
                return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
            }
            t->field = nf2;
        }
        t->line[t->n_rows] = lineno;
        split_fields(s, t->field + t->n_rows * (size_t)t->n_cols, t->n_cols);
        t->n_rows++;
    }
    t->last_line = lineno;
    if (!t->names) {
        st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                        "%s:%d: no header line (expected column names separated by commas)", path,
                        lineno > 0 ? lineno : 1);
        csv_free(t);
        return st;
    }
    *out = t;
    return SUNMC_OK;
}

int csv_column(const csv_table *t, const char *name, int required, int *col, char *err,
               size_t errlen)
{
    for (int i = 0; i < t->n_cols; i++)
        if (strcmp(t->names[i], name) == 0) {
            *col = i;
            return SUNMC_OK;
        }
    *col = -1;
    if (!required)
        return SUNMC_OK;
    char have[SUNMC_ERRLEN / 2];
    size_t used = 0;
    have[0] = '\0';
    for (int i = 0; i < t->n_cols && used < sizeof have; i++)
        used += (size_t)snprintf(have + used, sizeof have - used, "%s%s", i ? "," : "",
                                 t->names[i]);
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: missing column '%s' (the header has: %s)",
                      t->path, t->header_line, name, have);
}

int csv_doubles(const csv_table *t, int col, double *out, char *err, size_t errlen)
{
    for (size_t r = 0; r < t->n_rows; r++) {
        const char *s = t->field[r * (size_t)t->n_cols + (size_t)col];
        char *end;
        errno = 0;
        double v = strtod(s, &end);
        if (*s == '\0' || end == s || *end != '\0')
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: column '%s': '%s' is not a number",
                              t->path, t->line[r], t->names[col], s);
        if (!isfinite(v))
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s:%d: column '%s': '%s' is not a finite number", t->path,
                              t->line[r], t->names[col], s);
        out[r] = v;
    }
    return SUNMC_OK;
}

int csv_require_rows(const csv_table *t, size_t min_rows, const char *why, char *err,
                     size_t errlen)
{
    if (t->n_rows >= min_rows)
        return SUNMC_OK;
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: only %zu data rows; %s", t->path,
                      t->last_line > 0 ? t->last_line : 1, t->n_rows, why);
}
