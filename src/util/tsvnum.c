/* tsvnum.c - numbers in output files (tsvnum.h). */
#include "tsvnum.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* A printed number with no non-zero digit in its mantissa is a zero. */
static int printed_zero(const char *s)
{
    for (; *s && *s != 'e' && *s != 'E'; s++)
        if (*s >= '1' && *s <= '9')
            return 0;
    return 1;
}

int tsv_num_fmt(char *buf, size_t len, const char *fmt, double v)
{
    if (isnan(v))
        return snprintf(buf, len, "-");
    int n = snprintf(buf, len, fmt, v);
    if (n > 1 && (size_t)n < len && buf[0] == '-' && !isinf(v) && printed_zero(buf + 1)) {
        memmove(buf, buf + 1, (size_t)n);
        n--;
    }
    return n;
}

void tsv_num_put(FILE *f, const char *fmt, double v)
{
    char buf[64];
    tsv_num_fmt(buf, sizeof buf, fmt, v);
    fputs(buf, f);
}

/* Is s[0..n) a printed NaN or negative zero (a number with a sign, no
 * non-zero digit before an exponent, digits only)? */
static int field_nan(const char *s, size_t n)
{
    return (n == 3 && strncmp(s, "nan", 3) == 0) || (n == 4 && strncmp(s, "-nan", 4) == 0);
}

static int field_minus_zero(const char *s, size_t n)
{
    if (n < 2 || s[0] != '-' || s[1] < '0' || s[1] > '9')
        return 0;
    int exp = 0;
    for (size_t i = 1; i < n; i++) {
        char ch = s[i];
        if (ch == 'e' || ch == 'E')
            exp = 1;
        else if (!exp && ch >= '1' && ch <= '9')
            return 0;
        else if (!(ch >= '0' && ch <= '9') && ch != '.' && !(exp && (ch == '+' || ch == '-')))
            return 0;
    }
    return 1;
}

#define TSV_LINE_BUF 4096

int tsv_printf(FILE *f, const char *fmt, ...)
{
    char stack[TSV_LINE_BUF], *buf = stack;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(buf, sizeof stack, fmt, ap);
    va_end(ap);
    if (n < 0)
        return n;
    if ((size_t)n >= sizeof stack) {
        buf = malloc((size_t)n + 1);
        if (!buf)
            return -1;
        va_start(ap, fmt);
        vsnprintf(buf, (size_t)n + 1, fmt, ap);
        va_end(ap);
    }
    int out = 0;
    for (size_t i = 0; i <= (size_t)n;) {
        size_t j = i;
        while (j < (size_t)n && buf[j] != '\t' && buf[j] != '\n')
            j++;
        size_t len = j - i;
        if (field_nan(buf + i, len))
            out += fprintf(f, "-");
        else if (field_minus_zero(buf + i, len))
            out += (int)fwrite(buf + i + 1, 1, len - 1, f);
        else
            out += (int)fwrite(buf + i, 1, len, f);
        if (j < (size_t)n) {
            fputc(buf[j], f);
            out++;
        }
        i = j + 1;
    }
    if (buf != stack)
        free(buf);
    return ferror(f) ? -1 : out;
}
