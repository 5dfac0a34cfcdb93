/* test_util.h - shared helpers for the cmocka suites. */
#ifndef SUNMC_TEST_UTIL_H
#define SUNMC_TEST_UTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* assert |a - b| <= tol, printing both on failure. */
#define assert_near(a, b, tol)                                                                    \
    do {                                                                                          \
        double a_ = (a), b_ = (b), t_ = (tol);                                                    \
        if (!(fabs(a_ - b_) <= t_))                                                               \
            fail_msg("%s = %.15g, expected %s = %.15g within %g (off by %.3g)", #a, a_, #b, b_,  \
                     t_, fabs(a_ - b_));                                                          \
    } while (0)

/* Path of the sunmc binary under test (set by tests/run-suite.sh). */
static inline const char *test_sunmc(void)
{
    const char *p = getenv("SUNMC");
    return p ? p : "build/sunmc";
}

/* Run a shell command, capture stdout+stderr into out (truncated), return
 * the exit status (or -1). */
static inline int test_run(const char *cmd, char *out, size_t outlen)
{
    char full[8192];
    snprintf(full, sizeof full, "%s 2>&1", cmd);
    FILE *p = popen(full, "r");
    if (!p)
        return -1;
    size_t n = fread(out, 1, outlen - 1, p);
    out[n] = '\0';
    while (fgetc(p) != EOF) {
    }
    int st = pclose(p);
    return (st >= 0 && (st & 0x7f) == 0) ? (st >> 8) & 0xff : -1;
}

/* Write text to a file; returns 0 on success. */
static inline int test_write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fputs(text, f);
    return fclose(f);
}

#endif
