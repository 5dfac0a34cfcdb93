/* numtext.h - the one reading of a number typed by a user (command-line
 * options, config values, CSV cells, params.ini): plain decimal text only.
 * strtod alone would take "0x10" as 16 and "inf"/"nan" as numbers, strtol
 * " 5" and "+5"; these are refused here, so every input reads a number the
 * same way. */
#ifndef SUNMC_NUMTEXT_H
#define SUNMC_NUMTEXT_H

/* A whole number: an optional '-' and decimal digits, nothing else (no
 * '+', blanks, exponent, hex).  0 on success; -1 when s is not one; -2
 * when it is one too large for a long. */
int num_parse_long(const char *s, long *out);

/* A finite decimal number: [-+]digits[.digits][e[-+]digits] (or .digits),
 * nothing else (no blanks, hex).  0 on success; -1 when s is not one; -2
 * when it is not finite ("inf", "nan" in any case) or out of a double's
 * range (too large, or so small it would read as 0). */
int num_parse_double(const char *s, double *out);

#endif
