/* csv.c - reading the lab's comma-separated data files (see csv.h). */
#include "csv.h"
#include "numtext.h"
#include "status.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CSV_SEPARATOR ','
#define CSV_COMMENT '#'
#define CSV_QUOTE '"'
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

/* Errors of scan_fields. */
#define CSV_EQUOTE (-1) /* a quote not closed on its line */
#define CSV_EAFTER (-2) /* text after a closing quote */

/* Fields of line s (trimmed, not empty).  A field is unquoted text (blanks
 * around it dropped) or "quoted text" in which "" stands for one quote and
 * the separator is plain text.  With out == NULL only counts, leaving s as it
 * is; else splits s in place into out[].  Returns the count, or CSV_EQUOTE /
 * CSV_EAFTER with *bad = the field (from 1). */
static int scan_fields(char *s, char **out, int *bad)
{
    int n = 0;
    char *p = s;
    for (;;) {
        while (*p && isspace((unsigned char)*p))
            p++;
        n++;
        if (*p != CSV_QUOTE) {
            char *sep = strchr(p, CSV_SEPARATOR);
            if (out) {
                if (sep)
                    *sep = '\0';
                out[n - 1] = trim(p);
            }
            if (!sep)
                return n;
            p = sep + 1;
            continue;
        }
        char *w = p, *start = p;
        for (p++;; p++) {
            if (*p == '\0') {
                *bad = n;
                return CSV_EQUOTE;
            }
            if (*p == CSV_QUOTE && p[1] != CSV_QUOTE)
                break;
            p += *p == CSV_QUOTE; /* "" is one quote */
            if (out)
                *w++ = *p;
        }
        for (p++; *p && isspace((unsigned char)*p);)
            p++;
        if (*p != '\0' && *p != CSV_SEPARATOR) {
            *bad = n;
            return CSV_EAFTER;
        }
        int last = *p == '\0';
        if (out) {
            *w = '\0'; /* w < p: the opening quote is not copied */
            out[n - 1] = start;
        }
        if (last)
            return n;
        p++;
    }
}

/* What text looks separated by, when it is not commas. */
static const char *other_separator(const char *name)
{
    return strchr(name, ';') ? "';'" : strchr(name, '\t') ? "tabs" : NULL;
}

#define SEPARATOR_HINT                                                                            \
    " (the line looks separated by ';' or tabs: sunmc reads ',' as the separator)"

/* scan_fields, turning its errors into FILE:LINE messages. */
static int fields_of(const csv_table *t, int lineno, char *s, char **out, int *n, char *err,
                     size_t errlen)
{
    int bad = 0;
    *n = scan_fields(s, out, &bad);
    if (*n == CSV_EQUOTE)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: field %d: quote not closed (a quoted field must end on its "
                          "line)",
                          t->path, lineno, bad);
    if (*n == CSV_EAFTER)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: field %d: text after the closing quote%s", t->path, lineno, bad,
                          other_separator(s) ? SEPARATOR_HINT : "");
    return SUNMC_OK;
}

/* Check the len new bytes at p of the text read so far: no NUL, no line
 * longer than max_line.  *line and *col are where p starts (from 1, 0). */
static int check_chunk(const char *path, const char *p, size_t len, size_t max_line, int *line,
                       size_t *col, char *err, size_t errlen)
{
    for (size_t i = 0; i < len; i++) {
        if (p[i] == '\0')
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s:%d: binary data (NUL byte) in a text file", path, *line);
        if (p[i] == '\n') {
            (*line)++;
            *col = 0;
        } else if (++*col > max_line) {
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s:%d: line longer than %zu bytes (the most a line may hold): "
                              "not a CSV of readings?", path, *line, max_line);
        }
    }
    return SUNMC_OK;
}

int csv_read_text(const char *path, size_t max_bytes, size_t max_line, char **buf_out,
                  char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot read: %s", path, strerror(errno));
    size_t cap = 1 << 16, len = 0, col = 0;
    int line = 1, st = SUNMC_OK;
    char *buf = malloc(cap);
    if (!buf)
        st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
    while (st == SUNMC_OK) {
        if (len + 1 >= cap) {
            char *nb = realloc(buf, cap *= 2);
            if (!nb) {
                st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
                break;
            }
            buf = nb;
        }
        size_t want = cap - 1 - len;
        if (want > max_bytes + 1 - len)
            want = max_bytes + 1 - len; /* one byte past the limit tells it is passed */
        size_t got = fread(buf + len, 1, want, f);
        st = check_chunk(path, buf + len, got, max_line, &line, &col, err, errlen);
        len += got;
        if (st == SUNMC_OK && len > max_bytes)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: larger than %zu bytes (the most "
                            "sunmc reads from one data file): split it", path,
                            buf[len - 1] == '\n' ? line - 1 : line, max_bytes);
        if (got == 0)
            break;
    }
    if (st == SUNMC_OK && ferror(f))
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: read error", path);
    fclose(f);
    if (st != SUNMC_OK) {
        free(buf);
        return st;
    }
    buf[len] = '\0';
    *buf_out = buf;
    return SUNMC_OK;
}

static int read_all(const char *path, char **buf_out, char *err, size_t errlen)
{
    return csv_read_text(path, CSV_MAX_BYTES, CSV_LINE_MAX, buf_out, err, errlen);
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

typedef struct {
    const char *name;
    int col;
} name_ref;

static int cmp_name_ref(const void *a, const void *b)
{
    const name_ref *x = a, *y = b;
    int c = strcmp(x->name, y->name);
    return c ? c : (x->col > y->col) - (x->col < y->col);
}

/* Header names must be distinct: sorted, equal names are neighbours (n log n,
 * not n^2: a spreadsheet export can have 100k columns).  Reports the first
 * column (from the left) that repeats an earlier one, and that earlier one. */
static int check_duplicates(const csv_table *t, char *err, size_t errlen)
{
    int n = t->n_cols;
    name_ref *r = malloc((size_t)n * sizeof *r);
    if (!r)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", t->path);
    for (int i = 0; i < n; i++)
        r[i] = (name_ref){t->names[i], i};
    qsort(r, (size_t)n, sizeof *r, cmp_name_ref);
    int first = -1, again = n;
    for (int k = 1; k < n; k++)
        if (strcmp(r[k].name, r[k - 1].name) == 0 &&
            (k < 2 || strcmp(r[k - 1].name, r[k - 2].name) != 0) && r[k].col < again) {
            again = r[k].col;
            first = r[k - 1].col;
        }
    free(r);
    if (first < 0)
        return SUNMC_OK;
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "%s:%d: duplicate column '%s' in the header (columns %d and %d)", t->path,
                      t->header_line, t->names[again], first + 1, again + 1);
}

static int read_header(csv_table *t, int lineno, char *s, char *err, size_t errlen)
{
    int nf;
    int st = fields_of(t, lineno, s, NULL, &nf, err, errlen);
    if (st != SUNMC_OK)
        return st;
    t->header_line = lineno;
    t->n_cols = nf;
    t->names = malloc((size_t)nf * sizeof *t->names);
    if (!t->names)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", t->path);
    fields_of(t, lineno, s, t->names, &nf, err, errlen);
    const char *sep = nf == 1 ? other_separator(t->names[0]) : NULL;
    if (sep)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: the header '%.60s' is one column: its fields are separated by "
                          "%s, but sunmc reads comma-separated files (export with ',' as the "
                          "separator and '.' as the decimal point)",
                          t->path, lineno, t->names[0], sep);
    for (int i = 0; i < nf; i++)
        if (t->names[i][0] == '\0')
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: header column %d has no name",
                              t->path, lineno, i + 1);
    return check_duplicates(t, err, errlen);
}

static int read_row(csv_table *t, int lineno, char *s, size_t *cap, char *err, size_t errlen)
{
    int nf;
    int st = fields_of(t, lineno, s, NULL, &nf, err, errlen);
    if (st != SUNMC_OK)
        return st;
    if (nf != t->n_cols)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: %d fields, but the header (line %d) has %d columns%s", t->path,
                          lineno, nf, t->header_line, t->n_cols,
                          nf == 1 && other_separator(s) ? SEPARATOR_HINT : "");
    if (t->n_rows == *cap) {
        size_t c = *cap ? 2 * *cap : CSV_ROWS_INITIAL;
        int *nl = realloc(t->line, c * sizeof *nl);
        if (nl)
            t->line = nl;
        char **nf2 = nl ? realloc(t->field, c * (size_t)t->n_cols * sizeof *nf2) : NULL;
        if (!nf2)
            return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", t->path);
        t->field = nf2;
        *cap = c;
    }
    t->line[t->n_rows] = lineno;
    fields_of(t, lineno, s, t->field + t->n_rows * (size_t)t->n_cols, &nf, err, errlen);
    t->n_rows++;
    return SUNMC_OK;
}

/* A UTF-8 byte-order mark, as spreadsheet exports write. */
#define CSV_BOM "\xEF\xBB\xBF"

int csv_read(const char *path, csv_table **out, char *err, size_t errlen)
{
    *out = NULL;
    csv_table *t = calloc(1, sizeof *t);
    if (!t)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
    t->path = strdup(path);
    int st = t->path ? read_all(path, &t->buf, err, errlen)
                     : sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
    size_t cap = 0;
    int lineno = 0;
    char *p = t->buf;
    if (st == SUNMC_OK && strncmp(p, CSV_BOM, 3) == 0)
        p += 3;
    while (st == SUNMC_OK && *p) {
        char *nl = strchr(p, '\n');
        if (nl)
            *nl = '\0';
        char *next = nl ? nl + 1 : p + strlen(p);
        lineno++;
        char *s = trim(p);
        p = next;
        if (*s == '\0' || *s == CSV_COMMENT)
            continue;
        st = t->names ? read_row(t, lineno, s, &cap, err, errlen)
                      : read_header(t, lineno, s, err, errlen);
    }
    t->last_line = lineno;
    if (st == SUNMC_OK && !t->names)
        st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                        "%s:%d: no header line (expected column names separated by commas)", path,
                        lineno > 0 ? lineno : 1);
    if (st != SUNMC_OK) {
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
        double v = 0;
        int pst = num_parse_double(s, &v);
        if (pst == -1)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s:%d: column '%s': '%s' is not a number", t->path,
                              t->line[r], t->names[col], s);
        if (pst != 0)
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
