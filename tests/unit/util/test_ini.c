/* test_ini.c - the one INI dialect (ini.h) of config files and params.ini:
 * comments, sections, values, and every syntax error with its FILE:LINE. */
#include "test_util.h"

#include "ini.h"
#include "status.h"

#include <unistd.h>

static char dir[] = "/tmp/sunmc_test_ini_XXXXXX";
static char path[256];

static int setup(void **state)
{
    if (!mkdtemp(dir))
        return -1;
    snprintf(path, sizeof path, "%s/t.ini", dir);
    return 0;
}

static int teardown(void **state)
{
    unlink(path);
    return rmdir(dir);
}

/* Read text to the end or the first error; entries into e[max], their
 * kinds into kind[]; returns the status, *n the items read. */
static int lex(const char *text, ini_entry *e, int *kind, int max, int *n, char *err)
{
    assert_int_equal(test_write_file(path, text), 0);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    ini_reader r;
    ini_begin(&r, f, path);
    int st, item;
    *n = 0;
    ini_entry tmp;
    while ((st = ini_next(&r, &item, *n < max ? &e[*n] : &tmp, err, SUNMC_ERRLEN)) == SUNMC_OK &&
           item != INI_END) {
        if (*n < max)
            kind[*n] = item;
        (*n)++;
    }
    ini_end(&r);
    fclose(f);
    return st;
}

static void test_dialect(void **state)
{
    ini_entry e[8];
    int kind[8], n;
    char err[SUNMC_ERRLEN];
    const char *text = "# comment\n; also a comment\n\n  [ design ]  # trailing comment\n"
                       "H_mm = 4.124  # type A\nlabel = ESS#3 kept\nempty =\n"
                       "[other]\nH_mm=\t5\t\n";
    assert_int_equal(lex(text, e, kind, 8, &n, err), SUNMC_OK);
    assert_int_equal(n, 6);
    assert_int_equal(kind[0], INI_SECTION);
    assert_string_equal(e[0].section, "design");
    assert_int_equal(e[0].line, 4);
    assert_int_equal(kind[1], INI_KEY);
    assert_string_equal(e[1].section, "design");
    assert_string_equal(e[1].key, "H_mm");
    assert_string_equal(e[1].value, "4.124");
    assert_string_equal(e[1].comment, "type A");
    assert_int_equal(e[1].line, 5);
    assert_string_equal(e[2].value, "ESS#3 kept"); /* '#' inside a word is text */
    assert_string_equal(e[2].comment, "");
    assert_string_equal(e[3].key, "empty");
    assert_string_equal(e[3].value, "");
    /* the same key in another section is not a duplicate */
    assert_int_equal(kind[4], INI_SECTION);
    assert_string_equal(e[5].section, "other");
    assert_string_equal(e[5].value, "5");
    assert_int_equal(e[5].line, 9);
}

static void expect(const char *text, int line, const char *needle)
{
    ini_entry e[8];
    int kind[8], n;
    char err[SUNMC_ERRLEN] = "", where[300];
    assert_int_equal(lex(text, e, kind, 8, &n, err), SUNMC_EINPUT);
    snprintf(where, sizeof where, "%s:%d: ", path, line);
    if (strstr(err, where) != err || !strstr(err, needle))
        fail_msg("message '%s': want '%s' ... '%s'", err, where, needle);
}

static void test_errors(void **state)
{
    expect("k = 1\n", 1, "key 'k' before any [section]");
    expect("[s\n", 1, "malformed section header '[s'");
    expect("[s] x\n", 1, "malformed section header");
    expect("[ ]\n", 1, "malformed section header");
    expect("[s]\n# c\nk 1\n", 3, "expected 'key = value' or '[section]', got 'k 1'");
    expect("[s]\n = 1\n", 2, "empty key");
    expect("[s]\nk = 1\n\nk = 2\n", 4, "duplicate key s.k (first set on line 2)");
    static char text[1200];
    snprintf(text, sizeof text, "[s]\nk = %01100d\n", 0);
    expect(text, 2, "longer than 1024 characters");
    snprintf(text, sizeof text, "[s]\n%070d = 1\n", 0);
    expect(text, 2, "longer than 63 characters");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dialect),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests_name("ini", tests, setup, teardown);
}
