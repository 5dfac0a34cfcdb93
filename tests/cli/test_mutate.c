/* test_mutate.c - scripts/dev/mutate.sh on a toy tree (one C file, one test):
 * a mutant the test catches, one marked equivalent, one that survives, one
 * whose text is not in the file; the verdicts, the per-module table, the
 * score and the exit status.  Runs in about a second: it builds the toy,
 * not sunmc. */
#include "test_util.h"

#include <sys/stat.h>
#include <unistd.h>

static char root[64];

static void put(const char *rel, const char *text)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", root, rel);
    assert_int_equal(test_write_file(path, text), 0);
}

static int setup(void **state)
{
    (void)state;
    snprintf(root, sizeof root, "/tmp/sunmc_test_mutate_XXXXXX");
    if (!mkdtemp(root))
        return -1;
    char d[128];
    const char *dirs[] = {"src", "src/lib", "tests"};
    for (int i = 0; i < 3; i++) {
        snprintf(d, sizeof d, "%s/%s", root, dirs[i]);
        if (mkdir(d, 0777) != 0)
            return -1;
    }
    put("Makefile",
        "build/tests/test_calc: src/lib/calc.c tests/test_calc.c\n"
        "\t@mkdir -p build/tests\n"
        "\t$(CC) -o $@ src/lib/calc.c tests/test_calc.c\n"
        "mutate-build: build/tests/test_calc\n"
        "mutate-tests:\n"
        "\t@echo build/tests/test_calc\n");
    put("src/lib/calc.c", "int add(int a, int b) { return a + b; }\n"
                          "int twice(int a) { return a * 2; }\n"
                          "int half(int a) { return a / 2; }\n");
    put("tests/test_calc.c", "int add(int, int);\nint twice(int);\n"
                             "int main(void) { return !(add(2, 3) == 5 && twice(4) == 8); }\n");
    put("mutants.txt", "# toy mutants\n"
                       "id: add-sign\nfile: src/lib/calc.c\nfrom: a + b\nto: a - b\n"
                       "why: sign flip\n\n"
                       "id: twice-sum\nfile: src/lib/calc.c\nfrom: a * 2\nto: a + a\n"
                       "why: same value\nequivalent: a + a is 2a for every int\n\n"
                       "id: half-untested\nfile: src/lib/calc.c\nfrom: a / 2\nto: a / 3\n"
                       "why: wrong divisor, no test\n\n"
                       "# a mutant whose text moved away\n"
                       "id: gone\nfile: src/lib/calc.c\nfrom: a % 2\nto: a % 3\nwhy: moved\n");
    put("ok.txt", "id: add-sign\nfile: src/lib/calc.c\nfrom: return a + b;\nto: return b + b;\n"
                  "why: wrong operand\n");
    put("bad.txt", "id: no-to\nfile: src/lib/calc.c\nfrom: a + b\n");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf %s", root);
    return system(cmd) == 0 ? 0 : -1;
}

static int run_mutate(const char *list, const char *extra, char *out, size_t len)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, "bash scripts/dev/mutate.sh --tree %s --list %s/%s %s", root, root, list,
             extra);
    return test_run(cmd, out, len);
}

/* The table row starting with `start`: 4 mutants, 1 of each verdict, 50 %. */
static void expect_row(const char *out, const char *start)
{
    const char *row = strstr(out, start);
    if (!row)
        fail_msg("no row '%s' in:\n%s", start + 1, out);
    char name[64];
    int t, c, s, e, r;
    double score;
    assert_int_equal(sscanf(row, "%63s %d %d %d %d %d %lf %%", name, &t, &c, &s, &e, &r, &score),
                     7);
    assert_int_equal(t, 4);
    assert_int_equal(c, 1);
    assert_int_equal(s, 1);
    assert_int_equal(e, 1);
    assert_int_equal(r, 1);
    assert_near(score, 50.0, 1e-9);
}

static void verdicts_table_and_status(void **state)
{
    (void)state;
    static char out[16384];
    int st = run_mutate("mutants.txt", "", out, sizeof out);
    assert_int_equal(st, 2); /* a mutant could not be applied */
    assert_non_null(strstr(out, "caught    add-sign by test_calc"));
    assert_non_null(strstr(out, "equiv     twice-sum: a + a is 2a for every int"));
    assert_non_null(strstr(out, "SURVIVED  half-untested: src/lib/calc.c: wrong divisor, no test"));
    assert_non_null(strstr(out, "ERROR     gone: src/lib/calc.c: the text is found 0 times"));
    /* per folder and per file: total caught survived equivalent error score */
    expect_row(out, "\nsrc/lib ");
    expect_row(out, "\n  calc.c ");
    expect_row(out, "\ntotal ");
    assert_non_null(strstr(out, "score: 1 caught of 2 non-equivalent mutants (50.0 %); 1 marked "
                                "equivalent; 1 not applied"));
    /* the tree itself is left as it was */
    char path[128], text[256] = "";
    snprintf(path, sizeof path, "%s/src/lib/calc.c", root);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    assert_non_null(strstr(text, "return a * 2;"));
    assert_null(strstr(text, "a + a"));

    st = run_mutate("mutants.txt", "--only 'add|twice'", out, sizeof out);
    assert_int_equal(st, 0); /* caught or equivalent */
    assert_non_null(strstr(out, "mutate: 2 of 4 mutants"));
    st = run_mutate("mutants.txt", "--only half", out, sizeof out);
    assert_int_equal(st, 1); /* a survivor */
    st = run_mutate("ok.txt", "", out, sizeof out);
    assert_int_equal(st, 0);
    assert_non_null(strstr(out, "score: 1 caught of 1 non-equivalent mutants (100.0 %)"));
}

static void malformed_list(void **state)
{
    (void)state;
    char out[4096];
    assert_int_equal(run_mutate("bad.txt", "", out, sizeof out), 2);
    assert_non_null(strstr(out, "bad.txt:1: a mutant needs id:, file:, from: and to:"));
    assert_int_equal(run_mutate("missing.txt", "", out, sizeof out), 2);
    assert_non_null(strstr(out, "no such mutant list"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(verdicts_table_and_status),
        cmocka_unit_test(malformed_list),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
