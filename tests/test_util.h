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

/* Remove the private directory at exit. */
static char test_tmp_dir_[64];
static inline void test_tmp_cleanup_(void)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", test_tmp_dir_);
    if (system(cmd) != 0)
        fprintf(stderr, "cannot remove %s\n", test_tmp_dir_);
}

/* "DIR/name" in this test binary's private temporary directory (mkdtemp on
 * the first call, removed at exit); one of 8 rotating buffers, so a few
 * paths can be used at once. */
static inline const char *test_tmp(const char *name)
{
    static char buf[8][512];
    static int next;
    if (!test_tmp_dir_[0]) {
        snprintf(test_tmp_dir_, sizeof test_tmp_dir_, "/tmp/sunmc_test_XXXXXX");
        if (!mkdtemp(test_tmp_dir_)) {
            perror("mkdtemp");
            exit(1);
        }
        atexit(test_tmp_cleanup_);
    }
    char *b = buf[next++ % 8];
    snprintf(b, sizeof buf[0], "%s/%s", test_tmp_dir_, name);
    return b;
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
