/* test_table_print.c - the one printer of the tables people read
 * (table.h), against layouts written out here by hand: each column as
 * wide as its widest header or cell, labels left and numbers right, "  "
 * between columns and " | " before a column group, the second header line
 * only when a column has one, no trailing blanks, rows past the first
 * allocation, and calls outside the table ignored. */
#include "test_util.h"

#include "table.h"

#include <stdio.h>
#include <string.h>

static void print_to(const table *t, char *buf, size_t len)
{
    FILE *f = tmpfile();
    assert_non_null(f);
    table_print(f, t);
    rewind(f);
    size_t n = fread(buf, 1, len - 1, f);
    buf[n] = '\0';
    fclose(f);
}

static void layout_by_hand(void **state)
{
    table *t = table_new(3);
    assert_non_null(t);
    table_head(t, 0, "angle", "", TABLE_LEFT);
    table_head(t, 1, "RMS", "[arcsec]", TABLE_BAR);
    table_head(t, 2, "note", "", TABLE_LEFT);
    int r = table_row(t);
    table_set(t, r, 0, "%s", "alpha");
    table_set(t, r, 1, "%.2f", 12.5);
    table_set(t, r, 2, "%s", "");
    r = table_row(t);
    table_set(t, r, 0, "%s", "b");
    table_set(t, r, 1, "%.2f", 1234.5);
    table_set(t, r, 2, "%s", "wide note");
    char out[1024];
    print_to(t, out, sizeof out);
    assert_string_equal(out, "angle |      RMS  note\n"
                             "      | [arcsec]\n"
                             "alpha |    12.50\n"
                             "b     |  1234.50  wide note\n");
    table_free(t);
}

static void one_header_line(void **state)
{
    table *t = table_new(2);
    table_head(t, 0, "a", "", 0);
    table_head(t, 1, "bb", "", TABLE_LEFT);
    int r = table_row(t);
    table_set(t, r, 0, "%d", 123);
    table_set(t, r, 1, "%s", "x");
    char out[256];
    print_to(t, out, sizeof out);
    assert_string_equal(out, "  a  bb\n123  x\n");
    table_free(t);
}

static void many_rows_and_limits(void **state)
{
    assert_null(table_new(0));
    assert_null(table_new(TABLE_MAX_COLS + 1));
    table *t = table_new(TABLE_MAX_COLS);
    assert_non_null(t);
    table_free(t);
    t = table_new(1);
    table_head(t, 0, "n", "", 0);
    table_head(t, 5, "ignored", "", 0);
    for (int i = 0; i < 100; i++)
        table_set(t, table_row(t), 0, "%d", i);
    table_set(t, 100, 0, "%s", "out");
    table_set(t, 0, 1, "%s", "out");
    assert_null(table_cell(t, 100, 0));
    assert_null(table_cell(t, 0, 1));
    assert_int_equal(table_rows(t), 100);
    static char out[4096];
    print_to(t, out, sizeof out);
    assert_int_equal(strncmp(out, " n\n 0\n 1\n", 9), 0);
    assert_non_null(strstr(out, "\n99\n"));
    assert_null(strstr(out, "out"));
    /* a cell longer than TABLE_CELL is cut, not overflowed */
    char big[2 * TABLE_CELL];
    memset(big, 'x', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    table_set(t, 0, 0, "%s", big);
    assert_int_equal(strlen(table_cell(t, 0, 0)), TABLE_CELL - 1);
    table_free(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(layout_by_hand),
        cmocka_unit_test(one_header_line),
        cmocka_unit_test(many_rows_and_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
