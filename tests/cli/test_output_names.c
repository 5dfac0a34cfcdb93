/* test_output_names.c - issue 36 rule 1: every column name of every file a
 * command writes is unique in its file and documented in docs/outputs.md
 * ("Every column, by file"; placeholders ANGLE, LO, HI, UNIT, T,
 * SECTION.KEY), for every family: run (every shipped config, also with
 * --format hdf5, and with operating temperatures), sweep, budget,
 * sensitivity, design, allocate, curve, simulate, calibrate (tests/golden.sh
 * for the ESS and DSS, the same commands here for the PSD).  No file holds a
 * field `nan` or a negative zero (`-0`, `-0.000`, `-0e+00`). */
#include "test_util.h"

#include <dirent.h>
#include <regex.h>
#include <sys/stat.h>

#define MAX_DOC_NAMES 1024
#define NAME_MAX_LEN 96

static char dir[512];
static char doc_names[MAX_DOC_NAMES][NAME_MAX_LEN];
static int n_doc_names;

/* The backquoted words of docs/outputs.md's section "Every column, by
 * file". */
static void load_doc_names(void)
{
    FILE *f = fopen("docs/outputs.md", "r");
    assert_non_null(f);
    char line[1024];
    int in = 0;
    n_doc_names = 0;
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, "## ", 3) == 0)
            in = strstr(line, "Every column") != NULL;
        for (char *p = line; in && (p = strchr(p, '`'));) {
            char *q = strchr(p + 1, '`');
            if (!q)
                break;
            size_t n = (size_t)(q - p - 1);
            if (n > 0 && n < NAME_MAX_LEN && n_doc_names < MAX_DOC_NAMES) {
                memcpy(doc_names[n_doc_names], p + 1, n);
                doc_names[n_doc_names++][n] = '\0';
            }
            p = q + 1;
        }
    }
    fclose(f);
    assert_true(n_doc_names > 200);
}

/* A documented word as a regular expression: its placeholders replaced. */
static void pattern_of(const char *doc, char *re, size_t len)
{
    static const char *const ph[][2] = {
        {"SECTION.KEY", "[a-z_]+\\.[a-zA-Z][A-Za-z0-9_]*"}, {"ANGLE", "(alpha|beta|total)"},
        {"UNIT", "(deg|arcsec)"},                   {"LO", "-?[0-9.]+"},
        {"HI", "-?[0-9.]+"},                         {"T", "-?[0-9.]+"}};
    size_t k = 0;
    re[k++] = '^';
    for (const char *p = doc; *p && k + 40 < len;) {
        int hit = 0;
        for (size_t i = 0; i < sizeof ph / sizeof ph[0] && !hit; i++) {
            size_t n = strlen(ph[i][0]);
            if (strncmp(p, ph[i][0], n) == 0) {
                k += (size_t)snprintf(re + k, len - k, "%s", ph[i][1]);
                p += n;
                hit = 1;
            }
        }
        if (!hit) {
            if (*p == '.')
                re[k++] = '\\';
            re[k++] = *p++;
        }
    }
    re[k++] = '$';
    re[k] = '\0';
}

static int documented(const char *name)
{
    for (int i = 0; i < n_doc_names; i++) {
        if (strcmp(doc_names[i], name) == 0)
            return 1;
        char re[512];
        pattern_of(doc_names[i], re, sizeof re);
        if (strcmp(re + 1, doc_names[i]) == 0)
            continue; /* no placeholder: compared above */
        regex_t rx;
        if (regcomp(&rx, re, REG_EXTENDED | REG_NOSUB) != 0)
            continue;
        int ok = regexec(&rx, name, 0, NULL, 0) == 0;
        regfree(&rx);
        if (ok)
            return 1;
    }
    return 0;
}

/* A field that is a NaN or a printed negative zero. */
static int bad_field(const char *s, size_t n)
{
    if ((n == 3 && strncmp(s, "nan", 3) == 0) || (n == 4 && strncmp(s, "-nan", 4) == 0))
        return 1;
    if (n < 2 || s[0] != '-' || s[1] < '0' || s[1] > '9')
        return 0;
    for (size_t i = 1; i < n && s[i] != 'e'; i++)
        if ((s[i] >= '1' && s[i] <= '9') || !(s[i] == '0' || s[i] == '.'))
            return 0;
    return 1;
}

static int checked_tsv, checked_files;

/* One output file: no bad field; a TSV: a unique, documented header. */
static void check_file(const char *path)
{
    size_t len = strlen(path);
    int is_tsv = len > 4 && strcmp(path + len - 4, ".tsv") == 0;
    int is_csv = len > 4 && strcmp(path + len - 4, ".csv") == 0;
    if (!is_tsv && !is_csv)
        return;
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    static char line[1 << 16];
    char names[256][NAME_MAX_LEN];
    int nn = 0, row = 0;
    const char sep = is_tsv ? '\t' : ',';
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        if (line[0] == '#')
            continue;
        for (char *p = line;;) {
            char *e = strchr(p, sep);
            size_t n = e ? (size_t)(e - p) : strlen(p);
            if (bad_field(p, n))
                fail_msg("%s line %d: field '%.*s'", path, row + 1, (int)n, p);
            if (row == 0 && is_tsv) {
                assert_true(nn < 256 && n < NAME_MAX_LEN);
                memcpy(names[nn], p, n);
                names[nn][n] = '\0';
                for (int j = 0; j < nn; j++)
                    if (strcmp(names[j], names[nn]) == 0)
                        fail_msg("%s: column %s twice", path, names[nn]);
                if (!documented(names[nn]))
                    fail_msg("%s: column %s is not in docs/outputs.md", path, names[nn]);
                nn++;
            }
            if (!e)
                break;
            p = e + 1;
        }
        row++;
    }
    fclose(f);
    checked_tsv += is_tsv;
    checked_files++;
}

static void walk(const char *path)
{
    DIR *d = opendir(path);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        char sub[1024];
        snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
        struct stat st;
        assert_int_equal(stat(sub, &st), 0);
        if (S_ISDIR(st.st_mode))
            walk(sub);
        else
            check_file(sub);
    }
    closedir(d);
}

static void ok(const char *args)
{
    char out[1 << 14];
    int st = test_sunmc_in(dir, args, out, sizeof out);
    if (st != 0)
        fail_msg("sunmc %s: exit %d\n%s", args, st, out);
}

#define PSD "configs/psd.ini --quiet "

static void every_column_unique_and_documented(void **state)
{
    (void)state;
    char cmd[2048], out[1 << 14];
    snprintf(cmd, sizeof cmd, "bash tests/golden.sh %s %s/g", test_sunmc(), dir);
    if (test_run(cmd, out, sizeof out) != 0)
        fail_msg("%s\n%s", cmd, out);
    static const char *const configs[] = {"dss",     "ess_type_a",    "ess_type_b", "psd",
                                          "psd_14og", "psd_aeroztark", "psd_kenscl"};
    for (size_t i = 0; i < sizeof configs / sizeof *configs; i++) {
        /* HDF5 writes every column as a dataset of its name: every family
         * and shipped config (the PSD's used to repeat six names) */
        snprintf(cmd, sizeof cmd,
                 "run configs/%s.ini --units 3 --seed 2 --quiet --format hdf5 --out $D/h5_%s",
                 configs[i], configs[i]);
        ok(cmd);
        char h5[700];
        snprintf(h5, sizeof h5, "%s/h5_%s/results.h5", dir, configs[i]);
        struct stat st;
        assert_int_equal(stat(h5, &st), 0);
    }
    ok("run " PSD "--units 4 --set environment.operating_temp_c=-30,60 --out $D/thermal");
    ok("run configs/ess_type_a.ini --units 3 --quiet --set calibration.model=extended "
       "--set validation.alpha_step_deg=2.3 --out $D/ess_ext");
    ok("sweep " PSD "--units 4 --seed 4 --vary tolerance.dx_um=0,5 --out $D/psd_sweep");
    ok("budget " PSD "--units 10 --seed 4 --set report.budget_units=10 "
       "--set report.budget_steps=1 --out $D/psd_budget");
    ok("sensitivity " PSD "--units 10 --seed 4 --out $D/psd_sens");
    ok("curve " PSD "--unit 2 --out $D/psd_curve");
    /* 4 units decide no candidate: exit 1, design.tsv written */
    ok("design " PSD "--units 4 --out $D/psd_design > /dev/null; test $? -eq 1");
    ok("allocate configs/ess_type_a.ini --units 100 --quiet --set validation.alpha_step_deg=2.3 "
       "--out $D/ess_alloc");
    ok("simulate " PSD "--unit 3 --out $D/psd_sim > /dev/null");
    ok("calibrate --sensor psd --config configs/psd.ini $D/psd_sim/campaign.csv "
       "--out $D/psd_cal > /dev/null");
    ok("compensate $D/psd_cal/params.ini $D/psd_sim/validation.csv > $D/psd_comp.csv");
    load_doc_names();
    walk(dir);
    assert_true(checked_tsv >= 40);
    assert_true(checked_files >= 55);
}

/* The checks themselves: a repeated or undocumented name and a -0 or nan
 * field are found. */
static void the_checks_see_mistakes(void **state)
{
    (void)state;
    load_doc_names();
    assert_true(documented("rms_after_sys_beta_0_28_arcsec"));
    assert_true(documented("rms_after_alpha_0_62_deg_at_-30C"));
    assert_true(documented("rms_before_total_10_20_arcsec_worst"));
    assert_true(documented("campaign.alpha_step_deg"));
    assert_true(documented("fit_dx_um"));
    assert_false(documented("fit_dx_mm"));
    assert_false(documented("dx_um.1"));
    assert_false(documented("rms_after_gamma_0_28_arcsec"));
    assert_true(bad_field("-0", 2));
    assert_true(bad_field("-0.000", 6));
    assert_true(bad_field("-0e+00", 6));
    assert_true(bad_field("nan", 3));
    assert_false(bad_field("-0.001", 6));
    assert_false(bad_field("-", 1));
    assert_false(bad_field("0", 1));
    assert_false(bad_field("-1e-05", 6));
}

static int setup(void **state)
{
    (void)state;
    return test_private_dir(dir, sizeof dir, "names");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_checks_see_mistakes),
        cmocka_unit_test(every_column_unique_and_documented),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
