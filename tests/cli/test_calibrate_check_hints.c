/* test_calibrate_check_hints.c - the diagnosis each lab-data refusal carries
 * (issue 29), asserted by its text and its counts: swapped DSS output
 * columns, a flipped sign, swapped table angles, and data no garbling
 * explains; the counts of rows against the rows with weight > 0 of the
 * file, counted here with awk. */
#include "test_util.h"

static char dir[128];

static int setup(void **state)
{
    char out[8192], cmd[1024];
    if (test_private_dir(dir, sizeof dir, "lab_hints"))
        return -1;
    snprintf(cmd, sizeof cmd,
             "D=%s; %s simulate configs/dss.ini --unit 1 --quiet --out $D/dss && "
             "%s simulate configs/ess_type_a.ini --unit 1 --quiet --out $D/ess",
             dir, test_sunmc(), test_sunmc());
    return test_run(cmd, out, sizeof out);
}

/* The family's campaign with its data rows rewritten by an awk statement,
 * calibrated; exit status, output in out. */
static int garbled(const char *fam, const char *config, const char *awk, char *out, size_t len)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "D=%s/%s; awk -F, 'BEGIN {OFS=\",\"} /^#/ {print; next} !h {h=1; print; next} "
             "{%s; print}' $D/campaign.csv > $D/g.csv && %s calibrate --config %s $D/g.csv "
             "--out $D/g.cal",
             dir, fam, awk, test_sunmc(), config);
    return test_run(cmd, out, len);
}

/* Data rows of the family's campaign with weight (last column) > 0. */
static long weighted_rows(const char *fam)
{
    char cmd[1024], out[64];
    snprintf(cmd, sizeof cmd,
             "awk -F, '/^#/ {next} !h {h=1; next} $NF > 0 {n++} END {print n}' %s/%s/campaign.csv",
             dir, fam);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    return strtol(out, NULL, 10);
}

static void expect(int st, const char *out, const char *needle)
{
    if (st != 2 || !strstr(out, needle))
        fail_msg("expected exit 2 and '%s', got %d:\n%s", needle, st, out);
}

static void dss_outputs_swapped(void **state)
{
    char out[16384], want[256];
    long n = weighted_rows("dss");
    assert_true(n > 100);
    int st = garbled("dss", "configs/dss.ini", "t = $3; $3 = $4; $4 = t", out, sizeof out);
    snprintf(want, sizeof want,
             "; with the two output columns swapped, %ld of them would fit: check the columns", n);
    expect(st, out, want);
    snprintf(want, sizeof want, " of %ld rows are inconsistent with their table angles;", n);
    expect(st, out, want);
    assert_null(strstr(out, "table-angle columns swapped"));
}

static void dss_sign_flipped(void **state)
{
    char out[16384], want[256];
    long n = weighted_rows("dss");
    int st = garbled("dss", "configs/dss.ini", "$3 = -$3; $4 = -$4", out, sizeof out);
    snprintf(want, sizeof want,
             "; with every output's sign flipped, %ld of them would fit: check the columns", n);
    expect(st, out, want);
}

static void ess_hints(void **state)
{
    char out[16384], want[256];
    long n = weighted_rows("ess");
    int st = garbled("ess", "configs/ess_type_a.ini", "$3 = -$3", out, sizeof out);
    snprintf(want, sizeof want,
             "; with every output's sign flipped, or with column 'alpha_deg' sign-flipped, %ld "
             "of them would fit: check the columns",
             n);
    expect(st, out, want);
    st = garbled("ess", "configs/ess_type_a.ini", "t = $1; $1 = $2; $2 = t", out, sizeof out);
    expect(st, out, "; with the two table-angle columns swapped, ");
    assert_null(strstr(out, "output columns swapped"));
    /* outputs 0: no garbling explains them, the generic question */
    st = garbled("ess", "configs/ess_type_a.ini", "$3 = 0", out, sizeof out);
    snprintf(want, sizeof want,
             " of %ld rows are inconsistent with their table angles; is it this sensor's data, "
             "in the units its columns name (alpha_deg, beta_deg, output_deg)?",
             n);
    expect(st, out, want);
    assert_null(strstr(out, "would fit"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dss_outputs_swapped),
        cmocka_unit_test(dss_sign_flipped),
        cmocka_unit_test(ess_hints),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
