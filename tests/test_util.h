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
#include <sys/stat.h>

#include "config.h"
#include "family.h"
#include "status.h"

/* assert |a - b| <= tol, printing both on failure. */
#define assert_near(a, b, tol)                                                                    \
    do {                                                                                          \
        double a_ = (a), b_ = (b), t_ = (tol);                                                    \
        if (!(fabs(a_ - b_) <= t_))                                                               \
            fail_msg("%s = %.15g, expected %s = %.15g within %g (off by %.3g)", #a, a_, #b, b_,  \
                     t_, fabs(a_ - b_));                                                          \
    } while (0)

/* Hand-made unit results as a family's scorer would leave them for the
 * spec's verdict (verdict.h): the statistic is the RMS after, and each band
 * has one validation point, read where the RMS after has a value. */
static inline void test_read_all(unit_result *r, long n)
{
    for (long u = 0; u < n; u++)
        for (int b = 0; b < CONFIG_BANDS_MAX; b++) {
            r[u].points[b] = 1;
            for (int a = 0; a < UNIT_MAX_ANGLES; a++) {
                r[u].stat_after[a][b] = r[u].rms_after[a][b];
                r[u].read_after[a][b] = isfinite(r[u].rms_after[a][b]) ? 1 : 0;
                for (int t = 0; t < UNIT_MAX_TEMPS; t++) {
                    r[u].stat_after_t[t][a][b] = r[u].rms_after_t[t][a][b];
                    r[u].read_after_t[t][a][b] = isfinite(r[u].rms_after_t[t][a][b]) ? 1 : 0;
                }
            }
        }
}

/* The spec's verdict worked out by hand for an RMS spec that must hold in
 * every one of nb bands with every point read (the defaults): r's fit
 * converged and, in each band, every validation point was read and the
 * RMS after is at most spec (rms unit). */
static inline int test_rms_spec_pass(const unit_result *r, int angle, int nb, double spec)
{
    if (r->fit_status != UNIT_FIT_OK)
        return 0;
    for (int b = 0; b < nb; b++)
        if (r->points[b] <= 0 || r->read_after[angle][b] != r->points[b] ||
            !(r->rms_after[angle][b] <= spec))
            return 0;
    return 1;
}

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

/* `sunmc COMMAND ARGS --out dir --quiet` for each of the n ARGS in bad: every
 * one must exit 2 and leave dir unmade (nothing written). */
static inline void test_refused(const char *command, const char *const *bad, size_t n,
                                const char *dir)
{
    char out[16384], cmd[4096];
    for (size_t i = 0; i < n; i++) {
        snprintf(cmd, sizeof cmd, "%s %s %s --out %s --quiet", test_sunmc(), command, bad[i], dir);
        int rc = test_run(cmd, out, sizeof out);
        if (rc != 2)
            fail_msg("%s '%s' exited %d: %s", command, bad[i], rc, out);
    }
    snprintf(cmd, sizeof cmd, "test -e %s", dir);
    assert_int_not_equal(system(cmd), 0);
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

/* A new directory `name` in the private temporary directory, its path in
 * buf; 0 on success (for a group setup). */
static inline int test_private_dir(char *buf, size_t len, const char *name)
{
    snprintf(buf, len, "%s", test_tmp(name));
    return mkdir(buf, 0700);
}

/* Run `sunmc ARGS` (the binary under test) with $D in ARGS standing for
 * directory d; the exit status, stdout+stderr in out. */
static inline int test_sunmc_in(const char *d, const char *args, char *out, size_t len)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "D=%s; %s %s", d, test_sunmc(), args);
    return test_run(cmd, out, len);
}

/* Run each of n `sunmc` steps in directory d (test_sunmc_in); on the first
 * that fails, print it and its output and return -1 (a group setup's
 * failure), else 0. */
static inline int test_sunmc_steps(const char *d, const char *const *steps, int n)
{
    static char out[16384];
    for (int i = 0; i < n; i++)
        if (test_sunmc_in(d, steps[i], out, sizeof out) != 0) {
            fprintf(stderr, "%s: %s\n", steps[i], out);
            return -1;
        }
    return 0;
}

/* Fail the test unless out holds what (and say what out held). */
static inline void test_must_have(const char *out, const char *what)
{
    if (!strstr(out, what))
        fail_msg("no '%s' in: %s", what, out);
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

/* Build st from the config file at path (NULL: defaults) and sets[n]
 * ("section.key=value", as --set), failing the test with the message if it
 * is refused.  Free with config_state_free. */
static inline void test_build(config_state *st, const char *path, const char *const *sets, int n)
{
    char err[SUNMC_ERRLEN];
    if (config_build(st, path, sets, n, err, sizeof err) != SUNMC_OK)
        fail_msg("config: %s", err);
}

/* The default config of a family ("ess", "dss"), as the command line builds
 * it (sensor.family set, nothing else). */
static inline sunmc_config test_family_config(const char *family)
{
    char set[64], err[SUNMC_ERRLEN];
    snprintf(set, sizeof set, "sensor.family=%s", family);
    const char *sets[] = {set};
    config_state st;
    if (config_build(&st, NULL, sets, 1, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    sunmc_config c = st.cfg;
    config_state_free(&st);
    return c;
}

/* Brute-force centroid of a uniform disc of diameter D pixels centred at x0,
 * integrated over unit pixels centred at the integers: each pixel's weight
 * is the integral of the chord length 2 sqrt(R^2 - x^2) over it, from its
 * antiderivative x sqrt(R^2 - x^2) + R^2 asin(x / R). */
static inline double test_disc_centroid(double D, double x0)
{
    double R = D / 2, sw = 0, sx = 0;
    for (long n = (long)floor(x0 - R) - 1; n <= (long)ceil(x0 + R) + 1; n++) {
        double a = fmax(-R, fmin(R, n - 0.5 - x0)), b = fmax(-R, fmin(R, n + 0.5 - x0));
        double w = (b * sqrt(R * R - b * b) + R * R * asin(b / R)) -
                   (a * sqrt(R * R - a * a) + R * R * asin(a / R));
        sw += w;
        sx += w * (double)n;
    }
    return sx / sw;
}

/* 1 when the first 64 KiB of file path hold needle. */
static inline int test_file_has(const char *path, const char *needle)
{
    static char buf[65536];
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    return strstr(buf, needle) != NULL;
}

#endif
