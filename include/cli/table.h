/* table.h - the one printer of the tables people read (Table 1, sweep,
 * budget, ...): columns with one or two header lines, labels
 * left-aligned, numbers right-aligned under their header, each column as
 * wide as its widest header or cell, " | " between groups.
 *
 *     table *t = table_new(3);
 *     table_head(t, 0, "angle", "", TABLE_LEFT);
 *     table_head(t, 1, "RMS after", "[arcsec]", TABLE_BAR);
 *     ...
 *     int r = table_row(t);
 *     table_set(t, r, 0, "%s", "alpha");
 *     table_print(stdout, t);
 *     table_free(t);
 *
 * Cells are copied (at most TABLE_CELL - 1 bytes each); rows grow as
 * needed.  Only src/cli prints: the table lives there. */
#ifndef SUNMC_TABLE_H
#define SUNMC_TABLE_H

#include <stdio.h>

#define TABLE_CELL 96
#define TABLE_MAX_COLS 24

/* Column flags: left-aligned (labels), a " | " before the column. */
enum { TABLE_LEFT = 1, TABLE_BAR = 2 };

typedef struct table table;

/* A table of ncols (1..TABLE_MAX_COLS) columns and no rows; NULL when out
 * of memory or ncols is out of range. */
table *table_new(int ncols);
void table_free(table *t);

/* Column col's two header lines (h1 may be "") and flags. */
void table_head(table *t, int col, const char *h0, const char *h1, int flags);

/* Append an empty row; its index, or -1 when out of memory. */
int table_row(table *t);

/* Cell (row, col) from a printf format. */
void table_set(table *t, int row, int col, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* The cell itself: TABLE_CELL bytes to write into (snprintf), or NULL
 * outside the table. */
char *table_cell(table *t, int row, int col);

/* Rows so far. */
int table_rows(const table *t);

/* Print the header lines (the second only when a column has one), then
 * the rows, each line without trailing blanks. */
void table_print(FILE *f, const table *t);

#endif
