/* status.c - the one helper that fills an error message and returns a code. */
#include "status.h"

#include <stdarg.h>
#include <stdio.h>

int sunmc_fail(char *err, size_t errlen, int status, const char *fmt, ...)
{
    if (err != NULL && errlen > 0) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, errlen, fmt, ap);
        va_end(ap);
    }
    return status;
}
