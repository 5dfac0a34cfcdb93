/* csv.h - the comma-separated data files a lab records (turntable campaigns,
 * raw readings to compensate).
 *
 * Format: one header line of column names, then one row per line; fields
 * separated by commas, surrounding blanks ignored; lines whose first
 * non-blank character is '#' and blank lines are skipped anywhere.  A field
 * may be quoted as spreadsheets write it: "alpha_deg", with "" for a quote
 * and commas inside taken as text (a quoted field ends on its line).  A UTF-8
 * byte-order mark at the start is skipped; CRLF line ends are accepted.
 * Columns are found by name in any order; columns nobody asks for are kept
 * (their text is available for pass-through) and otherwise ignored.
 *
 * Every error message starts with "FILE:LINE: " (the line in the file, from
 * 1) and names the column concerned:
 *   - duplicate header names (the first repeated column and its first
 *     occurrence), an unnamed column, a header that is one column separated
 *     by ';' or tabs (said so), a quote not closed or followed by text, a
 *     row with a different number of fields, a NUL byte, a line over
 *     CSV_LINE_MAX bytes, a file over CSV_MAX_BYTES (csv_read);
 *   - a missing column (csv_column, at the header line);
 *   - a field that is not a number, or is NaN or infinite (csv_doubles);
 *   - too few data rows (csv_require_rows, at the last line).
 * All of these return SUNMC_EINPUT; an unreadable file SUNMC_EIO.
 */
#ifndef SUNMC_CSV_H
#define SUNMC_CSV_H

#include <stddef.h>
#include <stdio.h>

typedef struct {
    char *path;          /* as given to csv_read */
    int n_cols;          /* columns in the header */
    char **names;        /* n_cols header names */
    int header_line;     /* line number (from 1) of the header */
    int last_line;       /* number of the file's last line */
    size_t n_rows;       /* data rows */
    int *line;           /* n_rows: line number of each data row */
    char **field;        /* n_rows * n_cols: field[r * n_cols + c], trimmed text */
    char *buf;           /* storage of all the text */
} csv_table;

/* The most csv_read reads: a data file's bytes, and one line's. */
#define CSV_MAX_BYTES ((size_t)1 << 28)
#define CSV_LINE_MAX ((size_t)1 << 22) /* 4 MiB: a 200000-column header fits */

/* The text of path into a new NUL-terminated *buf (free it), checked while
 * it streams in: a NUL byte, a line of more than max_line bytes or a file of
 * more than max_bytes is SUNMC_EINPUT "FILE:LINE: ..." as soon as it is
 * read (never the whole of /dev/zero in memory). */
int csv_read_text(const char *path, size_t max_bytes, size_t max_line, char **buf_out,
                  char *err, size_t errlen);

/* Read and split the whole file.  On success *out is a new table (free it
 * with csv_free).  Checks: a header exists, header names are non-empty and
 * distinct, every row has the header's number of fields. */
int csv_read(const char *path, csv_table **out, char *err, size_t errlen);
void csv_free(csv_table *t);

/* Index of column `name` in *col.  When the column is absent: required != 0
 * gives SUNMC_EINPUT "FILE:LINE: missing column 'name' (columns: ...)"
 * naming the header line; required == 0 sets *col = -1 and returns SUNMC_OK. */
int csv_column(const csv_table *t, const char *name, int required, int *col, char *err,
               size_t errlen);

/* Parse column col of every row as a finite double into out[n_rows].
 * "FILE:LINE: column 'name': 'text' is not a number" (or "is not finite"). */
int csv_doubles(const csv_table *t, int col, double *out, char *err, size_t errlen);

/* At least min_rows data rows, else "FILE:LINE: only N data rows; WHY" at
 * the last line, where `why` says what needs them. */
int csv_require_rows(const csv_table *t, size_t min_rows, const char *why, char *err,
                     size_t errlen);

#endif
