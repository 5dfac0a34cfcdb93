/* test_lab_diagnosis.c - issue 36, rule 10: lab data the design cannot
 * read are refused with the likely cause named: one flipped column (each
 * column on its own), the outputs or the table angles in another unit
 * (radians, arcmin, arcsec, micrometres, millimetres), in the family's own
 * words; missing campaign points are listed; every warning is in the
 * report's warnings list. */
#include "test_util.h"

static char dir[512];

#define E "configs/ess_type_a.ini"
#define D "configs/dss.ini"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int shell(const char *fmt, const char *a)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "cd %s && ", dir);
    size_t n = strlen(cmd);
    snprintf(cmd + n, sizeof cmd - n, fmt, a);
    return system(cmd);
}

static int setup(void **state)
{
    if (test_private_dir(dir, sizeof dir, "labdiag") != 0)
        return -1;
    char out[16384];
    if (sunmc("simulate " E " --unit 3 --quiet --out $D/le", out, sizeof out) != 0 ||
        sunmc("simulate " D " --unit 3 --quiet --out $D/ld", out, sizeof out) != 0)
        return -1;
    return shell("grep -v '^#' le/campaign.csv > e0.csv && grep -v '^#' ld/campaign.csv > d0.csv%s",
                 "");
}

/* $D/NAME.csv: SRC.csv with the awk program PROG applied to its data rows. */
static void garble(const char *src, const char *name, const char *prog)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "awk -F, 'BEGIN { OFS = \",\" } NR > 1 { %s } { print }' %s.csv > %s.csv", prog, src,
             name);
    assert_int_equal(shell("%s", cmd), 0);
}

/* calibrate of NAME must be refused (exit 2) naming each of the texts. */
static void refused_with(const char *config, const char *name, const char *const *texts, int n)
{
    char args[512], out[1 << 16];
    snprintf(args, sizeof args, "calibrate --config %s $D/%s.csv --out $D/o_%s", config, name,
             name);
    int rc = sunmc(args, out, sizeof out);
    if (rc != 2)
        fail_msg("%s: exit %d: %s", name, rc, out);
    for (int i = 0; i < n; i++)
        if (!strstr(out, texts[i]))
            fail_msg("%s: '%s' not said: %s", name, texts[i], out);
}

/* One column's sign, each column on its own: the DSS's flipped x_px was
 * "is it this sensor's data, in degrees and pixels?". */
static void test_one_column_flipped(void **state)
{
    garble("d0", "dx", "$3 = -$3");
    const char *dx[] = {"with column 'x_px' sign-flipped", "check the columns"};
    refused_with(D, "dx", dx, 2);
    garble("d0", "dy", "$4 = -$4");
    const char *dy[] = {"with column 'y_px' sign-flipped"};
    refused_with(D, "dy", dy, 1);
    garble("d0", "db1", "$1 = -$1");
    const char *db1[] = {"with column 'b1_deg' sign-flipped"};
    refused_with(D, "db1", db1, 1);
    garble("d0", "db2", "$2 = -$2");
    const char *db2[] = {"with column 'b2_deg' sign-flipped"};
    refused_with(D, "db2", db2, 1);
    garble("e0", "ea", "$1 = -$1");
    const char *ea[] = {"with column 'alpha_deg' sign-flipped"};
    refused_with(E, "ea", ea, 1);
    garble("e0", "eo", "$3 = -$3");
    const char *eo[] = {"with every output's sign flipped"};
    refused_with(E, "eo", eo, 1);
}

/* Outputs or table angles in another unit: named, with what to convert. */
static void test_units_named(void **state)
{
    garble("d0", "dum", "$3 *= 5.5; $4 *= 5.5");
    const char *um[] = {"with the outputs read as micrometres on the detector",
                        "convert the output columns to the unit their names state"};
    refused_with(D, "dum", um, 2);
    garble("d0", "dmm", "$3 *= 0.0055; $4 *= 0.0055");
    const char *mm[] = {"with the outputs read as millimetres on the detector"};
    refused_with(D, "dmm", mm, 1);
    garble("e0", "erad", "$3 *= 0.017453292519943295");
    const char *rad[] = {"with the outputs read as radians"};
    refused_with(E, "erad", rad, 1);
    garble("e0", "eam", "$3 *= 60");
    const char *am[] = {"with the outputs read as arcmin"};
    refused_with(E, "eam", am, 1);
    garble("e0", "eas", "$3 *= 3600");
    const char *as[] = {"with the outputs read as arcsec"};
    refused_with(E, "eas", as, 1);
    garble("d0", "din", "$1 *= 60; $2 *= 60");
    const char *in[] = {"with the table angles read as arcmin", "convert the table angles to degrees"};
    refused_with(D, "din", in, 2);
}

/* No hypothesis fits: the family's own columns, never another's units. */
static void test_generic_words_are_the_familys(void **state)
{
    garble("e0", "eg", "srand(NR); $3 = (rand() - 0.5) * 120");
    const char *eg[] = {"in the units its columns name (alpha_deg, beta_deg, output_deg)?"};
    refused_with(E, "eg", eg, 1);
    char out[1 << 16];
    sunmc("calibrate --config " E " $D/eg.csv", out, sizeof out);
    assert_null(strstr(out, "pixels"));
    garble("d0", "dg", "srand(NR); if ($5 > 0) { $3 = (rand() - 0.5) * 2000; $4 = (rand() - 0.5) * 2000 }");
    const char *dg[] = {"in the units its columns name (b1_deg, b2_deg, x_px, y_px)?"};
    refused_with(D, "dg", dg, 1);
}

/* Rows lost from a file on the config's grid are named in the report's
 * warnings; a complete file, or one on another grid, says nothing. */
static void test_missing_points_listed(void **state)
{
    char out[1 << 16];
    assert_int_equal(shell("sed '5d;50d;100d' d0.csv > dm.csv%s", ""), 0);
    assert_int_equal(sunmc("calibrate --config " D " $D/dm.csv", out, sizeof out), 0);
    const char *w = strstr(out, "warnings: ");
    assert_non_null(w);
    if (!strstr(w, "3 of the config's 625 campaign points have no row in") ||
        !strstr(w, "(-60, -45), (-55, 55), (-45, 55))"))
        fail_msg("%s", out);
    assert_int_equal(sunmc("calibrate --config " D " $D/d0.csv", out, sizeof out), 0);
    assert_null(strstr(out, "campaign points have no row"));
    assert_int_equal(shell("sed '3d' e0.csv > em.csv%s", ""), 0);
    assert_int_equal(sunmc("calibrate --config " E " $D/em.csv", out, sizeof out), 0);
    assert_non_null(strstr(out, "1 of the config's 534 campaign points have no row"));
    /* the lab ran another grid (every alpha 0.05 deg off): not the config's */
    garble("e0", "eoff", "$1 += 0.05");
    sunmc("calibrate --config " E " $D/eoff.csv", out, sizeof out);
    assert_null(strstr(out, "campaign points have no row"));
}

/* The repeated-rows warning is one of the report's warnings (it went to
 * stderr only). */
static void test_duplicate_warning_in_report(void **state)
{
    char out[1 << 16];
    assert_int_equal(shell("cp e0.csv ed.csv && sed -n 2p e0.csv >> ed.csv%s", ""), 0);
    assert_int_equal(sunmc("calibrate --config " E " $D/ed.csv --out $D/ced", out, sizeof out), 0);
    const char *w = strstr(out, "warnings: ");
    assert_non_null(w);
    assert_non_null(strstr(w, "1 row repeats an earlier row exactly"));
    char p[700];
    snprintf(p, sizeof p, "%s/ced/report.txt", dir);
    struct stat sb;
    if (stat(p, &sb) == 0)
        assert_true(test_file_has(p, "1 row repeats an earlier row exactly"));
}

/* Rows after a dropped repeat keep their own file lines (residuals.tsv's
 * line column): e0.csv's data row 1 logged twice at once. */
static void test_lines_after_a_dropped_repeat(void **state)
{
    char out[1 << 16], p[700];
    assert_int_equal(shell("awk 'NR == 2 { print } { print }' e0.csv > er.csv%s", ""), 0);
    assert_int_equal(sunmc("calibrate --config " E " $D/er.csv --duplicates average --out $D/cer",
                           out, sizeof out),
                     0);
    snprintf(p, sizeof p, "%s/cer/residuals.tsv", dir);
    FILE *f = fopen(p, "r");
    assert_non_null(f);
    char line[1024];
    assert_non_null(fgets(line, sizeof line, f));
    int want[] = {2, 4, 5, 6};
    for (int i = 0; i < 4; i++) {
        assert_non_null(fgets(line, sizeof line, f));
        assert_int_equal(atoi(line), want[i]);
    }
    fclose(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_one_column_flipped),
        cmocka_unit_test(test_units_named),
        cmocka_unit_test(test_generic_words_are_the_familys),
        cmocka_unit_test(test_missing_points_listed),
        cmocka_unit_test(test_duplicate_warning_in_report),
        cmocka_unit_test(test_lines_after_a_dropped_repeat),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
