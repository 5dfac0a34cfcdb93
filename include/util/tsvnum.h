/* tsvnum.h - the one writer of numbers into sunmc's output files (TSV).
 *
 * A number the tool could not form (NaN) is written "-" (docs/outputs.md);
 * a zero is written without a sign ("-0" from a tiny negative value or a
 * negated zero reads as a different number to people and to diff). */
#ifndef SUNMC_TSVNUM_H
#define SUNMC_TSVNUM_H

#include <stddef.h>
#include <stdio.h>

/* v formatted with fmt (a printf format with exactly one double
 * conversion, e.g. "%.6g") into buf: "-" for NaN, the sign dropped from a
 * printed zero ("-0", "-0.00", "-0e+00" become "0", "0.00", "0e+00").
 * Returns what snprintf returns. */
int tsv_num_fmt(char *buf, size_t len, const char *fmt, double v);

/* The same, written to f. */
void tsv_num_put(FILE *f, const char *fmt, double v);

/* fprintf for TSV text: formats, then writes every tab- or
 * newline-delimited field that is a NaN ("nan", "-nan") as "-" and every
 * printed negative zero without its sign (tsv_num_fmt's rules), so the
 * writers of tables with many columns keep their one format string.  A
 * call must hold whole fields.  Returns what fprintf returns. */
int tsv_printf(FILE *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
