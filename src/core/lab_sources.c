/* lab_sources.c - the campaigns of a lab data file: the rows after each
 * "# source: NAME" comment line (lab.h, lab_columns). */
#include "lab.h"
#include "status.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

#define SOURCE_TAG "# source:"
#define SOURCE_LINE_MAX 512
#define SOURCE_HEAD_NAME "(head)"

static int add_name(lab_columns *d, const char *name, int **lines, int line)
{
    char **nn = realloc(d->source_name, (size_t)(d->n_sources + 1) * sizeof *nn);
    int *nl = realloc(*lines, (size_t)(d->n_sources + 1) * sizeof *nl);
    if (nn)
        d->source_name = nn;
    if (nl)
        *lines = nl;
    if (!nn || !nl)
        return SUNMC_ENOMEM;
    size_t len = strlen(name);
    while (len > 0 && isspace((unsigned char)name[len - 1]))
        len--;
    d->source_name[d->n_sources] = malloc(len + 1);
    if (!d->source_name[d->n_sources])
        return SUNMC_ENOMEM;
    memcpy(d->source_name[d->n_sources], name, len);
    d->source_name[d->n_sources][len] = '\0';
    (*lines)[d->n_sources++] = line;
    return SUNMC_OK;
}

/* The "# source:" lines of the file: their names and line numbers. */
static int scan(lab_columns *d, int **lines, char *err, size_t errlen)
{
    FILE *f = fopen(d->path, "r");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot open it again", d->path);
    char buf[SOURCE_LINE_MAX];
    int line = 1, at_start = 1, st = SUNMC_OK;
    while (st == SUNMC_OK && fgets(buf, sizeof buf, f)) {
        size_t len = strlen(buf);
        const char *s = buf;
        while (at_start && (*s == ' ' || *s == '\t'))
            s++;
        if (at_start && strncmp(s, SOURCE_TAG, strlen(SOURCE_TAG)) == 0) {
            s += strlen(SOURCE_TAG);
            while (*s == ' ' || *s == '\t')
                s++;
            st = add_name(d, s, lines, line);
        }
        at_start = len > 0 && buf[len - 1] == '\n';
        line += at_start;
    }
    fclose(f);
    return st == SUNMC_OK ? SUNMC_OK
                          : sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", d->path);
}

int lab_columns_sources(lab_columns *d, char *err, size_t errlen)
{
    int *lines = NULL;
    int st = scan(d, &lines, err, errlen);
    if (st != SUNMC_OK || d->n_sources == 0) {
        free(lines);
        return st;
    }
    /* rows before the first source line form a campaign of their own */
    if (d->n > 0 && d->line[0] < lines[0]) {
        st = add_name(d, SOURCE_HEAD_NAME, &lines, 0);
        if (st != SUNMC_OK) {
            free(lines);
            return sunmc_fail(err, errlen, st, "%s: out of memory", d->path);
        }
        /* move it first */
        char *hn = d->source_name[d->n_sources - 1];
        int hl = lines[d->n_sources - 1];
        memmove(d->source_name + 1, d->source_name, (size_t)(d->n_sources - 1) * sizeof hn);
        memmove(lines + 1, lines, (size_t)(d->n_sources - 1) * sizeof hl);
        d->source_name[0] = hn;
        lines[0] = hl;
    }
    d->source = malloc((d->n + 1) * sizeof *d->source);
    if (!d->source) {
        free(lines);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", d->path);
    }
    int s = 0;
    for (size_t i = 0; i < d->n; i++) {
        while (s + 1 < d->n_sources && lines[s + 1] < d->line[i])
            s++;
        d->source[i] = s;
    }
    free(lines);
    return SUNMC_OK;
}
