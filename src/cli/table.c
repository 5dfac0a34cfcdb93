/* table.c - the one printer of the tables people read (table.h). */
#include "table.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

struct table {
    int ncols, nrows, cap;
    char head[TABLE_MAX_COLS][2][TABLE_CELL];
    int flags[TABLE_MAX_COLS];
    char (*cell)[TABLE_MAX_COLS][TABLE_CELL]; /* cap rows */
};

table *table_new(int ncols)
{
    if (ncols < 1 || ncols > TABLE_MAX_COLS)
        return NULL;
    table *t = calloc(1, sizeof *t);
    if (t)
        t->ncols = ncols;
    return t;
}

void table_free(table *t)
{
    if (t)
        free(t->cell);
    free(t);
}

void table_head(table *t, int col, const char *h0, const char *h1, int flags)
{
    if (col < 0 || col >= t->ncols)
        return;
    snprintf(t->head[col][0], TABLE_CELL, "%s", h0);
    snprintf(t->head[col][1], TABLE_CELL, "%s", h1 ? h1 : "");
    t->flags[col] = flags;
}

int table_row(table *t)
{
    if (t->nrows == t->cap) {
        int cap = t->cap ? 2 * t->cap : 16;
        void *p = realloc(t->cell, (size_t)cap * sizeof *t->cell);
        if (!p)
            return -1;
        t->cell = p;
        t->cap = cap;
    }
    memset(t->cell[t->nrows], 0, sizeof *t->cell);
    return t->nrows++;
}

void table_set(table *t, int row, int col, const char *fmt, ...)
{
    if (row < 0 || row >= t->nrows || col < 0 || col >= t->ncols)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(t->cell[row][col], TABLE_CELL, fmt, ap);
    va_end(ap);
}

char *table_cell(table *t, int row, int col)
{
    if (row < 0 || row >= t->nrows || col < 0 || col >= t->ncols)
        return NULL;
    return t->cell[row][col];
}

int table_rows(const table *t)
{
    return t->nrows;
}

static int max_int(int a, int b)
{
    return a > b ? a : b;
}

void table_print(FILE *f, const table *t)
{
    int w[TABLE_MAX_COLS], two = 0;
    size_t len = 1;
    for (int j = 0; j < t->ncols; j++) {
        w[j] = max_int((int)strlen(t->head[j][0]), (int)strlen(t->head[j][1]));
        two |= t->head[j][1][0] != '\0';
        for (int i = 0; i < t->nrows; i++)
            w[j] = max_int(w[j], (int)strlen(t->cell[i][j]));
        len += (size_t)w[j] + 3;
    }
    char *line = malloc(len);
    if (!line)
        return;
    for (int l = two ? -2 : -1; l < t->nrows; l++) {
        size_t used = 0;
        for (int j = 0; j < t->ncols; j++) {
            const char *s = l >= 0 ? t->cell[l][j] : t->head[j][two ? l + 2 : 0];
            used += (size_t)snprintf(line + used, len - used, "%s%*s",
                                     j == 0                       ? ""
                                     : t->flags[j] & TABLE_BAR ? " | "
                                                               : "  ",
                                     t->flags[j] & TABLE_LEFT ? -w[j] : w[j], s);
        }
        while (used > 0 && line[used - 1] == ' ') /* no trailing blanks */
            used--;
        fprintf(f, "%.*s\n", (int)used, line);
    }
    free(line);
}
