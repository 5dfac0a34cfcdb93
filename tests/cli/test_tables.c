/* test_tables.c - the printed tables a person reads: each numeric column
 * right-aligned under its header whatever the values' size, the band
 * column named for what the family bands (ESS |alpha|, DSS the field
 * angle), brackets balanced in every line. */
#include "test_util.h"

#define DSS_SETS "--set validation.b_step_deg=10 --set campaign.b_step_deg=10 " \
                 "--set report.bands_deg=0:60"
#define FAST_DSS DSS_SETS " --units 4 --quiet"

/* Offset just past the end of word in line (the first match), or -1. */
static int end_of(const char *line, const char *word)
{
    const char *p = strstr(line, word);
    return p ? (int)(p - line + (long)strlen(word)) : -1;
}

/* Offset just past the end of whitespace-separated field k (0-based). */
static int field_end(const char *line, int k)
{
    int i = 0, f = -1;
    while (line[i]) {
        while (line[i] == ' ')
            i++;
        if (!line[i] || line[i] == '\n')
            break;
        f++;
        while (line[i] && line[i] != ' ' && line[i] != '\n')
            i++;
        if (f == k)
            return i;
    }
    return -1;
}

/* Improvements past 100,000 (DSS, the paper's on-board formula, nearly no
 * noise): every row's before, after, p95 and improvement end where their
 * headers end, the row with small values as the one with large. */
static void test_sweep_columns_fit_values(void **state)
{
    char out[16384], cmd[2048];
    snprintf(cmd, sizeof cmd,
             "%s sweep configs/dss.ini " FAST_DSS " --set design.onboard_refraction=ignored "
             "--set campaign.mount=aligned --set noise.encoder_arcsec=0 --set noise.s_curve=off "
             "--vary noise.centroid_px=0.01,0.0001",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    char *save = NULL, *head = NULL;
    int rows = 0, big = 0;
    static const char *const heads[] = {"before", "after", "p95 after", "improve"};
    for (char *line = strtok_r(out, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        if (strstr(line, "improve")) {
            head = line;
            continue;
        }
        if (!head || !strstr(line, "0:60") || strncmp(line, "band yield:", 11) == 0)
            continue;
        rows++;
        /* fields: value, angle, band, before, after, p95, improve */
        for (int k = 0; k < 4; k++)
            if (end_of(head, heads[k]) != field_end(line, 3 + k))
                fail_msg("column '%s' misaligned:\n%s\n%s", heads[k], head, line);
        big += atof(line + field_end(line, 5) + 1) >= 1000;
    }
    assert_int_equal(rows, 6);
    assert_true(big >= 3);
}

/* Every line of out has as many '[' as ']'. */
static void assert_brackets_balanced(const char *out)
{
    int open = 0;
    for (const char *p = out; *p; p++) {
        open += *p == '[';
        open -= *p == ']';
        if (*p == '\n' && open != 0)
            fail_msg("unbalanced brackets in a line of:\n%s", out);
    }
}

static void test_band_header_per_family(void **state)
{
    char out[16384], cmd[2048];
    snprintf(cmd, sizeof cmd, "%s run configs/dss.ini " FAST_DSS, test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "field angle deg"));
    assert_null(strstr(out, "|x|"));
    assert_brackets_balanced(out);
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 4 --quiet --set campaign.alpha_step_deg=1.3 "
             "--set validation.alpha_step_deg=2.3",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "|alpha| deg"));
    assert_null(strstr(out, "|x|"));
    assert_brackets_balanced(out);
}

/* A run whose every fit fails (per-row gains of 40 %, on the former 0.8
 * deg campaign over -62..62; the shipped 0.7 deg fits them) has no statistic:
 * Table 1 prints "-" (never nan), a WARNING says why with the count, and
 * the yield, over all units, is 0 with its Wilson interval (3 units:
 * upper bound z^2 / (n + z^2) = 3.84 / 6.84 = 56.1 %). */
static void test_all_fits_failed_no_nan(void **state)
{
    char out[16384], cmd[2048];
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 3 --set tolerance.gain_pct=40 "
             "--set campaign.alpha_step_deg=0.8 --set campaign.alpha_min_deg=-62 "
             "--set campaign.alpha_max_deg=62 --set validation.alpha_step_deg=2.3",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_null(strstr(out, "nan"));
    assert_non_null(strstr(out, " - [-, -] "));
    assert_non_null(strstr(out, "0.0% [0.0, 56.1]"));
    assert_non_null(strstr(out, "WARNING: no statistic ('-') where no unit has a fit and a "
                                "reading: 3 of 3 units' fits failed"));
    assert_brackets_balanced(out);
    /* a healthy run has no such warning */
    snprintf(cmd, sizeof cmd,
             "%s run configs/ess_type_a.ini --units 3 --set validation.alpha_step_deg=2.3",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_null(strstr(out, "no statistic"));
}

/* calibrate's per-band table says what it bands too. */
static void test_calibrate_band_header(void **state)
{
    char out[32768], args[2048];
    const char *d = test_tmp("cal_dss");
    snprintf(args, sizeof args,
             "simulate configs/dss.ini --unit 1 --out $D --quiet " DSS_SETS
             " > /dev/null && %s calibrate --config configs/dss.ini " DSS_SETS " $D/campaign.csv",
             test_sunmc());
    assert_int_equal(test_sunmc_in(d, args, out, sizeof out), 0);
    assert_non_null(strstr(out, "  angle  field angle deg  points"));
    assert_null(strstr(out, "|x|"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sweep_columns_fit_values),
        cmocka_unit_test(test_band_header_per_family),
        cmocka_unit_test(test_calibrate_band_header),
        cmocka_unit_test(test_all_fits_failed_no_nan),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
