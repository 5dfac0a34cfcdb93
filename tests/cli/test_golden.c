/* test_golden.c - the recorded outputs of a fixed set of commands (both
 * families: run, sweep, budget, curve, simulate, calibrate, compensate; small
 * unit counts, fixed seeds) are reproduced.  A guard for refactoring: a
 * change that moves a number must re-record them on purpose (`make golden`)
 * and say why in its commit.
 *
 * Text must match exactly; a number may differ only in its last bits
 * (relative 1e-9, or 1e-12 absolute for values near zero): the libm and
 * vector-math variants glibc picks for a processor round a few results
 * differently, so a recording made on one machine differs from another's
 * in the 16th digit.  Byte-identity across threads, shards and ranks on one
 * machine is tested by the determinism suites, not here. */
#include "test_util.h"

#include <ctype.h>
#include <unistd.h>

#define GOLDEN_REL_TOL 1e-9
#define GOLDEN_ABS_TOL 1e-12

/* The next token of *p: a run of characters that are not separators. */
static size_t golden_token(const char **p, const char **start)
{
    const char *s = *p;
    while (*s && strchr("\t\n ,=[]()", *s))
        s++;
    *start = s;
    while (*s && !strchr("\t\n ,=[]()", *s))
        s++;
    *p = s;
    return (size_t)(s - *start);
}

/* A token that is a number as a whole: its value in *v. */
static int golden_number(const char *t, size_t n, double *v)
{
    char buf[64];
    if (n == 0 || n >= sizeof buf)
        return 0;
    memcpy(buf, t, n);
    buf[n] = '\0';
    char *end;
    *v = strtod(buf, &end);
    return *end == '\0' && isfinite(*v);
}

/* Whether texts a and b agree: the same separators and text, numbers within
 * the tolerance.  On a difference, a description in why. */
static int golden_same(const char *a, const char *b, char *why, size_t len)
{
    const char *pa = a, *pb = b;
    for (;;) {
        const char *ta, *tb;
        const char *sep_a = pa, *sep_b = pb;
        size_t na = golden_token(&pa, &ta), nb = golden_token(&pb, &tb);
        if (ta - sep_a != tb - sep_b || memcmp(sep_a, sep_b, (size_t)(ta - sep_a)) != 0) {
            snprintf(why, len, "separators differ before '%.40s' / '%.40s'", ta, tb);
            return 0;
        }
        if (na == 0 && nb == 0)
            return 1;
        if (na == nb && memcmp(ta, tb, na) == 0)
            continue;
        double va, vb;
        if (golden_number(ta, na, &va) && golden_number(tb, nb, &vb) &&
            fabs(va - vb) <= GOLDEN_REL_TOL * fmax(fabs(va), fabs(vb)) + GOLDEN_ABS_TOL)
            continue;
        snprintf(why, len, "'%.*s' recorded, '%.*s' now", (int)(na < 60 ? na : 60), ta,
                 (int)(nb < 60 ? nb : 60), tb);
        return 0;
    }
}

static char *golden_slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    size_t got = s ? fread(s, 1, (size_t)n, f) : 0;
    fclose(f);
    if (!s)
        return NULL;
    s[got] = '\0';
    return s;
}

/* Compare the files `diff -rq` lists as differing; a missing file fails. */
static void golden_compare(const char *dir)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "diff -rq tests/golden %s/g 2>&1", dir);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    char line[2048];
    int bad = 0;
    while (fgets(line, sizeof line, p)) {
        char fa[1024], fb[1024];
        if (sscanf(line, "Files %1023s and %1023s differ", fa, fb) != 2) {
            fprintf(stderr, "golden: %s", line);
            bad = 1;
            continue;
        }
        char *a = golden_slurp(fa), *b = golden_slurp(fb), why[256] = "";
        if (!a || !b || !golden_same(a, b, why, sizeof why)) {
            fprintf(stderr, "golden: %s differs: %s\n", fa, a && b ? why : "unreadable");
            bad = 1;
        }
        free(a);
        free(b);
    }
    pclose(p);
    if (bad)
        fail_msg("golden outputs differ (see above); `make golden` re-records them");
}

static void golden_outputs_identical(void **state)
{
    (void)state;
    char dir[] = "/tmp/sunmc_golden_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char cmd[1024], out[16384];
    snprintf(cmd, sizeof cmd, "bash tests/golden.sh %s %s/g", test_sunmc(), dir);
    int st = test_run(cmd, out, sizeof out);
    if (st != 0)
        fail_msg("golden commands failed (exit %d):\n%.4000s", st, out);
    golden_compare(dir);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    assert_int_equal(system(cmd), 0);
}

/* The comparison itself: last-bit differences pass, anything else fails. */
static void golden_tolerance_both_sides(void **state)
{
    (void)state;
    char why[256];
    assert_true(golden_same("a\t0.00038841079053869961\n", "a\t0.00038841079053869956\n", why,
                            sizeof why));
    assert_true(golden_same("x=4.36053e-10,1", "x=4.36055e-10,1", why, sizeof why));
    assert_false(golden_same("a\t1.000000\n", "a\t1.000001\n", why, sizeof why));
    assert_false(golden_same("a\t1\n", "b\t1\n", why, sizeof why));
    assert_false(golden_same("a\t1\n", "a,1\n", why, sizeof why));
    assert_false(golden_same("a\t1\n", "a\t1\t2\n", why, sizeof why));
    assert_false(golden_same("a\tnan\n", "a\t0\n", why, sizeof why));
    assert_true(golden_same("a\tnan\n", "a\tnan\n", why, sizeof why));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(golden_tolerance_both_sides),
        cmocka_unit_test(golden_outputs_identical),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
