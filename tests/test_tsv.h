/* test_tsv.h - a tab-separated file with a header line, in memory, for the
 * suites that recompute sunmc's output columns; and the comparison of a
 * value written with %.6g. */
#ifndef SUNMC_TEST_TSV_H
#define SUNMC_TEST_TSV_H

#include "test_util.h"

#define TSV_MAX_COLS 160
#define TSV_MAX_ROWS 4096

typedef struct {
    int nc, nr;
    char *names[TSV_MAX_COLS];
    char *cell[TSV_MAX_ROWS][TSV_MAX_COLS];
    char *buf;
} tsv;

static inline tsv *tsv_load(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        fail_msg("%s: cannot read", path);
    tsv *t = calloc(1, sizeof *t);
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    rewind(f);
    t->buf = malloc((size_t)len + 1);
    assert_int_equal(fread(t->buf, 1, (size_t)len, f), (size_t)len);
    t->buf[len] = '\0';
    fclose(f);
    char *save = NULL;
    int r = -1;
    for (char *line = strtok_r(t->buf, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        char **dst = r < 0 ? t->names : t->cell[r];
        int n = 0;
        for (char *p = line;; p++) {
            char *tab = strchr(p, '\t');
            assert_true(n < TSV_MAX_COLS);
            dst[n++] = p;
            if (!tab)
                break;
            *tab = '\0';
            p = tab;
        }
        if (r < 0)
            t->nc = n;
        else if (n != t->nc)
            fail_msg("%s: row %d has %d fields, the header %d", path, r + 1, n, t->nc);
        r++;
        assert_true(r < TSV_MAX_ROWS);
    }
    t->nr = r;
    return t;
}

static inline void tsv_free(tsv *t)
{
    free(t->buf);
    free(t);
}

static inline int tsv_col(const tsv *t, const char *name)
{
    for (int i = 0; i < t->nc; i++)
        if (strcmp(t->names[i], name) == 0)
            return i;
    fail_msg("no column '%s'", name);
    return -1;
}

/* A number; "-" (a number sunmc could not form) is NaN. */
static inline double tsv_num(const tsv *t, int r, const char *name)
{
    const char *v = t->cell[r][tsv_col(t, name)];
    return strcmp(v, "-") == 0 ? NAN : strtod(v, NULL);
}

static inline const char *tsv_str(const tsv *t, int r, const char *name)
{
    return t->cell[r][tsv_col(t, name)];
}

/* Written with %.6g: equal to the printed digits (and NaN to NaN). */
static inline void expect_g6(double got, double want, const char *what)
{
    if (isnan(want) && isnan(got))
        return;
    if (!(fabs(got - want) <= 2e-5 * fabs(want) + 1e-300))
        fail_msg("%s: %.8g, recomputed %.8g", what, got, want);
}

#endif
