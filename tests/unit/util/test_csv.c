/* test_csv.c - the CSV reader (every error with FILE:LINE and the column),
 * params.ini round trips and errors, FNV-1a known answers. */
#include "test_util.h"

#include "csv.h"
#include "params_io.h"
#include "status.h"

#include <time.h>
#include <unistd.h>

static char dir[] = "/tmp/sunmc_test_csv_XXXXXX";

static int setup(void **state)
{
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* Write text to dir/name; path receives the full name. */
static void put(const char *name, const char *text, char *path, size_t len)
{
    snprintf(path, len, "%s/%s", dir, name);
    assert_int_equal(test_write_file(path, text), 0);
}

/* Read a file that must fail; the message must contain want. */
static void expect_read_error(const char *name, const char *text, const char *want)
{
    char path[512], err[SUNMC_ERRLEN], full[600];
    put(name, text, path, sizeof path);
    csv_table *t;
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_EINPUT);
    assert_null(t);
    snprintf(full, sizeof full, "%s%s", path, want);
    if (!strstr(err, full))
        fail_msg("message '%s' lacks '%s'", err, full);
}

static void test_read_good(void **state)
{
    char path[512], err[SUNMC_ERRLEN];
    put("good.csv",
        "# a comment\n"
        "\n"
        " beta_deg , note,alpha_deg,output_deg\r\n"
        "20, first ,-62,-61.9\r\n"
        "  # an indented comment\n"
        "-20,x,1.5e1,  15.25\n"
        "0,,0,0", /* no final newline */
        path, sizeof path);
    csv_table *t;
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_OK);
    assert_int_equal(t->n_cols, 4);
    assert_int_equal(t->header_line, 3);
    assert_int_equal((int)t->n_rows, 3);
    assert_int_equal(t->line[0], 4);
    assert_int_equal(t->line[1], 6);
    assert_int_equal(t->line[2], 7);
    int ca, cb, co, cw;
    assert_int_equal(csv_column(t, "alpha_deg", 1, &ca, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_column(t, "beta_deg", 1, &cb, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_column(t, "output_deg", 1, &co, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_column(t, "weight", 0, &cw, err, sizeof err), SUNMC_OK);
    assert_int_equal(ca, 2);
    assert_int_equal(cb, 0);
    assert_int_equal(co, 3);
    assert_int_equal(cw, -1);
    double a[3], b[3], o[3];
    assert_int_equal(csv_doubles(t, ca, a, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_doubles(t, cb, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_doubles(t, co, o, err, sizeof err), SUNMC_OK);
    assert_true(a[0] == -62 && a[1] == 15 && a[2] == 0);
    assert_true(b[0] == 20 && b[1] == -20 && b[2] == 0);
    assert_true(o[0] == -61.9 && o[1] == 15.25 && o[2] == 0);
    /* The extra column is kept as text, trimmed. */
    assert_string_equal(t->field[0 * 4 + 1], "first");
    assert_string_equal(t->field[2 * 4 + 1], "");
    assert_int_equal(csv_require_rows(t, 3, "need 3", err, sizeof err), SUNMC_OK);
    csv_free(t);
}

static void test_missing_column(void **state)
{
    char path[512], err[SUNMC_ERRLEN], want[600];
    put("missing.csv", "# c\n# c\nalpha_deg,output_deg\n1,2\n", path, sizeof path);
    csv_table *t;
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_OK);
    int c;
    assert_int_equal(csv_column(t, "beta_deg", 1, &c, err, sizeof err), SUNMC_EINPUT);
    snprintf(want, sizeof want, "%s:3: missing column 'beta_deg'", path);
    assert_non_null(strstr(err, want));
    csv_free(t);
}

static void check_bad_value(const char *text, const char *want_fmt)
{
    char path[512], err[SUNMC_ERRLEN], want[600];
    put("bad.csv", text, path, sizeof path);
    csv_table *t;
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_OK);
    double v[8];
    int c;
    assert_int_equal(csv_column(t, "output_deg", 1, &c, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_doubles(t, c, v, err, sizeof err), SUNMC_EINPUT);
    snprintf(want, sizeof want, want_fmt, path);
    if (!strstr(err, want))
        fail_msg("message '%s' lacks '%s'", err, want);
    csv_free(t);
}

static void test_bad_values(void **state)
{
    check_bad_value("alpha_deg,output_deg\n1,2\n2,abc\n",
                    "%s:3: column 'output_deg': 'abc' is not a number");
    check_bad_value("alpha_deg,output_deg\n1,2\n\n2,2x\n",
                    "%s:4: column 'output_deg': '2x' is not a number");
    check_bad_value("alpha_deg,output_deg\n1,\n", "%s:2: column 'output_deg': '' is not a number");
    check_bad_value("alpha_deg,output_deg\n1,nan\n", "%s:2: column 'output_deg': 'nan' is not a finite");
    check_bad_value("alpha_deg,output_deg\n1,1\n1,-inf\n",
                    "%s:3: column 'output_deg': '-inf' is not a finite");
    check_bad_value("alpha_deg,output_deg\n1,1e400\n",
                    "%s:2: column 'output_deg': '1e400' is not a finite");
    /* issue 36: strtod read 0x10 as 16; hex is refused as in every input */
    check_bad_value("alpha_deg,output_deg\n1,0x10\n",
                    "%s:2: column 'output_deg': '0x10' is not a number");
    check_bad_value("alpha_deg,output_deg\n1,0X1p3\n",
                    "%s:2: column 'output_deg': '0X1p3' is not a number");
    check_bad_value("alpha_deg,output_deg\n1,Infinity\n",
                    "%s:2: column 'output_deg': 'Infinity' is not a finite");
}

static void test_structure_errors(void **state)
{
    expect_read_error("dup.csv", "# x\nalpha_deg,beta_deg,alpha_deg\n1,2,3\n",
                      ":2: duplicate column 'alpha_deg' in the header (columns 1 and 3)");
    expect_read_error("fields.csv", "a,b,c\n1,2,3\n1,2\n", ":3: 2 fields, but the header (line 1) has 3");
    expect_read_error("more.csv", "a,b\n1,2\n1,2,3\n", ":3: 3 fields, but the header (line 1) has 2");
    expect_read_error("noname.csv", "a,,c\n", ":1: header column 2 has no name");
    expect_read_error("empty.csv", "", ":1: no header line");
    expect_read_error("comments.csv", "# only\n# comments\n", ":2: no header line");
}

static void test_too_few_rows(void **state)
{
    char path[512], err[SUNMC_ERRLEN], want[600];
    put("few.csv", "a\n1\n2\n# trailing comment\n", path, sizeof path);
    csv_table *t;
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_require_rows(t, 9, "the model has 8 parameters", err, sizeof err),
                     SUNMC_EINPUT);
    snprintf(want, sizeof want, "%s:4: only 2 data rows; the model has 8 parameters", path);
    assert_string_equal(err, want);
    /* the limit on both sides */
    assert_int_equal(csv_require_rows(t, 2, "two", err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_require_rows(t, 3, "three", err, sizeof err), SUNMC_EINPUT);
    csv_free(t);
}

static void test_unreadable(void **state)
{
    char err[SUNMC_ERRLEN];
    csv_table *t;
    assert_int_equal(csv_read("/nonexistent/x.csv", &t, err, sizeof err), SUNMC_EIO);
    assert_non_null(strstr(err, "/nonexistent/x.csv"));
}

/* What a spreadsheet exports: a byte-order mark, CRLF, quoted names and
 * quoted fields (with "" and a comma inside). */
static void test_spreadsheet_export(void **state)
{
    char path[512], err[SUNMC_ERRLEN];
    put("excel.csv",
        "\xEF\xBB\xBF\"alpha_deg\",\"note\", \"output_deg\" \r\n"
        "\"1.5\",\"say \"\"hi\"\", twice\",2\r\n"
        "-3,\"\",\"-4.25\"\r\n",
        path, sizeof path);
    csv_table *t;
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_OK);
    assert_int_equal(t->n_cols, 3);
    assert_string_equal(t->names[0], "alpha_deg");
    assert_string_equal(t->names[2], "output_deg");
    assert_int_equal((int)t->n_rows, 2);
    int ca, co;
    assert_int_equal(csv_column(t, "alpha_deg", 1, &ca, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_column(t, "output_deg", 1, &co, err, sizeof err), SUNMC_OK);
    double a[2], o[2];
    assert_int_equal(csv_doubles(t, ca, a, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_doubles(t, co, o, err, sizeof err), SUNMC_OK);
    assert_true(a[0] == 1.5 && a[1] == -3 && o[0] == 2 && o[1] == -4.25);
    assert_string_equal(t->field[1], "say \"hi\", twice");
    assert_string_equal(t->field[3 + 1], "");
    csv_free(t);
}

static void test_quotes_and_separators(void **state)
{
    expect_read_error("open.csv", "a,b\n1,\"2\n", ":2: field 2: quote not closed");
    expect_read_error("open2.csv", "\"a,b\n", ":1: field 1: quote not closed");
    expect_read_error("after.csv", "a,\"b\"x,c\n", ":1: field 2: text after the closing quote");
    expect_read_error("semi.csv", "# export\nalpha_deg;beta_deg;output_deg\n1;2;3\n",
                      ":2: the header 'alpha_deg;beta_deg;output_deg' is one column: its fields "
                      "are separated by ';', but sunmc reads comma-separated files");
    expect_read_error("semi_bom.csv", "\xEF\xBB\xBF\"alpha_deg\";\"beta_deg\"\n",
                      ":1: field 1: text after the closing quote (the line looks separated by ';' "
                      "or tabs");
    expect_read_error("tabs.csv", "alpha_deg\tbeta_deg\n1\t2\n",
                      ":1: the header 'alpha_deg\tbeta_deg' is one column: its fields are "
                      "separated by tabs");
    expect_read_error("semirow.csv", "a,b\n1,2\n1;2\n",
                      ":3: 1 fields, but the header (line 1) has 2 columns (the line looks "
                      "separated by ';'");
    char path[512], err[SUNMC_ERRLEN];
    snprintf(path, sizeof path, "%s/nul.csv", dir);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite("a,b\n1,2\n3,\0\n", 1, 12, f), 12);
    assert_int_equal(fclose(f), 0);
    csv_table *t;
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "nul.csv:3: binary data (NUL byte)"));
}

/* Issue 22: the limits of csv_read_text, each on both sides, checked while
 * the file streams in. */
static void write_bytes(const char *path, const char *text, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}

static void test_read_text_limits(void **state)
{
    char path[512], err[SUNMC_ERRLEN], *buf = NULL;
    snprintf(path, sizeof path, "%s/lim.csv", dir);
    write_bytes(path, "a,b\n1,2\n", 8);
    assert_int_equal(csv_read_text(path, 8, 3, &buf, err, sizeof err), SUNMC_OK);
    assert_string_equal(buf, "a,b\n1,2\n");
    free(buf);
    assert_int_equal(csv_read_text(path, 7, 3, &buf, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "lim.csv:2: larger than 7 bytes"));
    assert_int_equal(csv_read_text(path, 8, 2, &buf, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "lim.csv:1: line longer than 2 bytes"));
    /* the last line without its newline counts too */
    write_bytes(path, "a,b\n1,22", 8);
    assert_int_equal(csv_read_text(path, 100, 3, &buf, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "lim.csv:2: line longer than 3 bytes"));
    /* a NUL far into a long file is found with its line */
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    for (int i = 0; i < 100000; i++)
        fputs("1,2\n", f);
    fputc('\0', f);
    assert_int_equal(fclose(f), 0);
    assert_int_equal(csv_read_text(path, CSV_MAX_BYTES, CSV_LINE_MAX, &buf, err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "lim.csv:100001: binary data (NUL byte)"));
}

/* The reproducer: `calibrate /dev/zero` read until memory ran out (the
 * size limit itself is tested above on both sides with small limits). */
static void test_calibrate_endless_input(void **state)
{
    char out[4096], cmd[1024];
    const char *cal = "calibrate --sensor dss --config configs/dss.ini";
    snprintf(cmd, sizeof cmd, "%s %s /dev/zero", test_sunmc(), cal);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "/dev/zero:1: binary data (NUL byte) in a text file"));
    snprintf(cmd, sizeof cmd, "head -c 4194305 /dev/zero | tr '\\0' 1 | %s %s /dev/stdin",
             test_sunmc(), cal);
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "/dev/stdin:1: line longer than 4194304 bytes"));
}

static void test_duplicates(void **state)
{
    /* the first column from the left that repeats one, and its first place */
    expect_read_error("dup2.csv", "b,a,c,a,b\n", ":1: duplicate column 'a' in the header "
                                                 "(columns 2 and 4)");
    expect_read_error("dup3.csv", "x,x,x\n", ":1: duplicate column 'x' in the header "
                                             "(columns 1 and 2)");
    expect_read_error("dupq.csv", "\"a\",a\n", ":1: duplicate column 'a' in the header "
                                               "(columns 1 and 2)");
}

/* A 200,000-column header is read in well under a second (the duplicate
 * check was quadratic: 49 s), with or without a duplicate at its end. */
static void test_wide_header(void **state)
{
    enum { N = 200000 };
    char path[512], err[SUNMC_ERRLEN], want[600];
    snprintf(path, sizeof path, "%s/wide.csv", dir);
    for (int dup = 0; dup < 2; dup++) {
        FILE *f = fopen(path, "w");
        assert_non_null(f);
        for (int i = 0; i < N; i++)
            fprintf(f, "%sc%d", i ? "," : "", i);
        fputs(dup ? ",c7\n" : "\n", f);
        for (int i = 0; i < N + dup; i++)
            fputs(i ? ",1" : "1", f);
        fputc('\n', f);
        assert_int_equal(fclose(f), 0);
        clock_t t0 = clock();
        csv_table *t;
        int st = csv_read(path, &t, err, sizeof err);
        double cpu_s = (double)(clock() - t0) / CLOCKS_PER_SEC;
        if (cpu_s > 1.0)
            fail_msg("a %d-column header took %.2f s of CPU", N, cpu_s);
        if (!dup) {
            assert_int_equal(st, SUNMC_OK);
            assert_int_equal(t->n_cols, N);
            assert_int_equal((int)t->n_rows, 1);
            csv_free(t);
            continue;
        }
        assert_int_equal(st, SUNMC_EINPUT);
        snprintf(want, sizeof want, "%s:1: duplicate column 'c7' in the header (columns 8 and %d)",
                 path, N + 1);
        assert_string_equal(err, want);
    }
}

/* End to end: the campaign `simulate` writes, saved by a spreadsheet (BOM,
 * CRLF, quoted header and numbers), calibrates to the same residuals. */
static void test_calibrate_spreadsheet_export(void **state)
{
    char cmd[2048], out[8192];
    snprintf(cmd, sizeof cmd,
             "set -e; S=%s; D=%s; "
             "$S simulate configs/ess_type_a.ini --unit 1 --out $D/sim >/dev/null; "
             "{ printf '\\357\\273\\277'; awk -F, 'BEGIN{OFS=\",\"} /^#/ {print; next} "
             "{for (i = 1; i <= NF; i++) $i = \"\\\"\" $i \"\\\"\"; printf \"%%s\\r\\n\", $0}' "
             "$D/sim/campaign.csv; } > $D/excel.csv; "
             "for c in sim/campaign excel; do $S calibrate --sensor ess --config "
             "configs/ess_type_a.ini $D/$c.csv --out $D/cal_${c%%%%/*} >/dev/null; done; "
             "cmp $D/cal_sim/residuals.tsv $D/cal_excel/residuals.tsv; "
             "cmp $D/cal_sim/bands.tsv $D/cal_excel/bands.tsv; "
             "grep -q '^\"alpha_deg\",\"beta_deg\"' $D/excel.csv; head -c 3 $D/excel.csv | od -c",
             test_sunmc(), dir);
    int st = test_run(cmd, out, sizeof out);
    if (st != 0)
        fail_msg("exit %d: %s", st, out);
    assert_non_null(strstr(out, "357 273 277"));
}

static void test_fnv1a64_known_answers(void **state)
{
    /* Reference values of the FNV-1a 64-bit hash (Fowler, Noll, Vo). */
    assert_true(params_fnv1a64(PARAMS_FNV1A64_INIT, "", 0) == 0xcbf29ce484222325ULL);
    assert_true(params_fnv1a64(PARAMS_FNV1A64_INIT, "a", 1) == 0xaf63dc4c8601ec8cULL);
    assert_true(params_fnv1a64(PARAMS_FNV1A64_INIT, "foobar", 6) == 0x85944171f73967e8ULL);
    /* Continuing equals hashing at once; a file hashes as its bytes. */
    assert_true(params_fnv1a64(params_fnv1a64(PARAMS_FNV1A64_INIT, "foo", 3), "bar", 3) ==
                0x85944171f73967e8ULL);
    char path[512], err[SUNMC_ERRLEN];
    put("hash.txt", "foobar", path, sizeof path);
    unsigned long long h;
    assert_int_equal(params_file_fnv1a64(path, &h, err, sizeof err), SUNMC_OK);
    assert_true(h == 0x85944171f73967e8ULL);
}

static void test_params_round_trip(void **state)
{
    params_file *p = malloc(sizeof *p), *q = malloc(sizeof *q);
    params_init(p);
    const double v[] = {1.0004763517400035, -7.8748500632267764e-05, 1.0 / 3.0, -0.1,
                        6.02214076e23, 5e-324};
    const char *names[] = {"a", "c", "third", "neg", "big", "tiny"};
    assert_int_equal(params_set_text(p, "calibration", "sensor", "ess", NULL), SUNMC_OK);
    for (int i = 0; i < 6; i++)
        assert_int_equal(params_set_double(p, "parameters", names[i], v[i], "unit 1"), SUNMC_OK);
    assert_int_equal(params_set_double(p, "design", "theta0_deg", 2, NULL), SUNMC_OK);
    assert_int_equal(params_set_double(p, "parameters", "a", 2, NULL), SUNMC_EINPUT); /* twice */
    assert_int_equal(params_set_text(p, "x", "y", "has # hash", NULL), SUNMC_EINPUT);
    char path[512], err[SUNMC_ERRLEN];
    snprintf(path, sizeof path, "%s/params.ini", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    assert_int_equal(params_write(f, p, "title line 1\ntitle line 2"), SUNMC_OK);
    fclose(f);
    assert_int_equal(params_read(path, q, err, sizeof err), SUNMC_OK);
    for (int i = 0; i < 6; i++) {
        double got;
        assert_int_equal(params_get_double(q, "parameters", names[i], &got, err, sizeof err),
                         SUNMC_OK);
        assert_true(got == v[i]); /* exact */
    }
    const char *s;
    assert_int_equal(params_get_text(q, "calibration", "sensor", &s, err, sizeof err), SUNMC_OK);
    assert_string_equal(s, "ess");
    assert_string_equal(params_find(q, "parameters", "a")->comment, "unit 1");
    assert_int_equal(params_check_keys(q, "parameters", names, 6, err, sizeof err), SUNMC_OK);
    assert_int_equal(params_check_keys(q, "parameters", names, 5, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "unknown key parameters.tiny"));
    double d;
    assert_int_equal(params_get_double(q, "parameters", "zzz", &d, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "missing key parameters.zzz"));
    free(p);
    free(q);
}

static void expect_params_error(const char *text, const char *want)
{
    char path[512], err[SUNMC_ERRLEN], full[700];
    put("bad.ini", text, path, sizeof path);
    params_file *p = malloc(sizeof *p);
    int st = params_read(path, p, err, sizeof err);
    if (st == SUNMC_OK) {
        double v;
        st = params_get_double(p, "s", "k", &v, err, sizeof err);
    }
    assert_int_equal(st, SUNMC_EINPUT);
    snprintf(full, sizeof full, "%s%s", path, want);
    if (!strstr(err, full))
        fail_msg("message '%s' lacks '%s'", err, full);
    free(p);
}

static void test_params_errors(void **state)
{
    expect_params_error("k = 1\n", ":1: key 'k' before any [section]");
    expect_params_error("[s]\n# c\nk 1\n", ":3: expected 'key = value'");
    expect_params_error("[s\nk = 1\n", ":1: malformed section header");
    expect_params_error("[s]\nk = 1\nk = 2\n", ":3: duplicate key s.k (first set on line 2)");
    expect_params_error("[s]\n\nk = one  # unit\n", ":3: key s.k: 'one' is not a number");
    expect_params_error("[s]\nk = inf\n", ":2: key s.k: 'inf' is not finite");
    expect_params_error("[s]\nk = 0x10\n", ":2: key s.k: '0x10' is not a number");
    expect_params_error("[s]\nj = 1\n", ": missing key s.k");
    char err[SUNMC_ERRLEN];
    params_file *p = malloc(sizeof *p);
    assert_int_equal(params_read("/nonexistent/p.ini", p, err, sizeof err), SUNMC_EIO);
    free(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_read_good),          cmocka_unit_test(test_missing_column),
        cmocka_unit_test(test_bad_values),         cmocka_unit_test(test_structure_errors),
        cmocka_unit_test(test_too_few_rows),       cmocka_unit_test(test_unreadable),
        cmocka_unit_test(test_fnv1a64_known_answers), cmocka_unit_test(test_params_round_trip),
        cmocka_unit_test(test_params_errors),
        cmocka_unit_test(test_spreadsheet_export),
        cmocka_unit_test(test_quotes_and_separators),
        cmocka_unit_test(test_read_text_limits),
        cmocka_unit_test(test_calibrate_endless_input),
        cmocka_unit_test(test_duplicates),
        cmocka_unit_test(test_wide_header),
        cmocka_unit_test(test_calibrate_spreadsheet_export),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
