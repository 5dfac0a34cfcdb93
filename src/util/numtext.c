/* numtext.c - plain decimal numbers from text (numtext.h). */
#include "numtext.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int num_parse_long(const char *s, long *out)
{
    const char *d = s[0] == '-' ? s + 1 : s;
    if (*d == '\0' || strspn(d, "0123456789") != strlen(d))
        return -1;
    errno = 0;
    long v = strtol(s, NULL, 10);
    if (errno == ERANGE)
        return -2;
    *out = v;
    return 0;
}

int num_parse_double(const char *s, double *out)
{
    const char *m = *s == '-' || *s == '+' ? s + 1 : s;
    if (strncasecmp(m, "inf", 3) == 0 || strncasecmp(m, "nan", 3) == 0)
        return -2;
    /* strtod's other forms (hex, leading blanks) hold a character outside
     * these */
    if (*s == '\0' || strspn(s, "0123456789+-.eE") != strlen(s))
        return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0')
        return -1;
    /* a subnormal (ERANGE too) is read exactly as written: params.ini's
     * 5e-324 round-trips; too large, or a non-zero text read as 0, is not */
    if (!isfinite(v) || (errno == ERANGE && v == 0))
        return -2;
    *out = v;
    return 0;
}
