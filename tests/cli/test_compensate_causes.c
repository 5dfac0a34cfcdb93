/* test_compensate_causes.c - issue 36 rule 2: compensate gives an angle only
 * for a reading the calibrated sensor can produce, in every family and
 * model; every other row is written '-' and counted on stderr by cause
 * (core: lab_comp_summary; each family's lab hook: reading_check). */
#include "test_util.h"

static char dir[512];

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

/* One simulated, calibrated unit per family and model. */
static int setup(void **state)
{
    (void)state;
    if (test_private_dir(dir, sizeof dir, "causes") != 0)
        return -1;
    static const char *const steps[] = {
        "simulate configs/ess_type_a.ini --unit 3 --quiet --out $D/se",
        "calibrate --config configs/ess_type_a.ini $D/se/campaign.csv --quiet --out $D/ce",
        "simulate configs/dss.ini --unit 3 --quiet --out $D/sd",
        "calibrate --config configs/dss.ini $D/sd/campaign.csv --quiet --out $D/cd",
        "simulate configs/psd.ini --unit 3 --quiet --out $D/sp",
        "calibrate --config configs/psd.ini $D/sp/campaign.csv --quiet --out $D/cp",
        "simulate configs/psd_aeroztark.ini --unit 1 --quiet --out $D/sz",
        "calibrate --config configs/psd_aeroztark.ini $D/sz/campaign.csv --quiet --out $D/cz",
        "simulate configs/psd_14og.ini --unit 2 --quiet --out $D/sq",
        "calibrate --config configs/psd_14og.ini $D/sq/campaign.csv --quiet --out $D/cq"};
    return test_sunmc_steps(dir, steps, (int)(sizeof steps / sizeof *steps));
}

/* compensate CAL's params.ini on text; every row of want_bad written '-'
 * (its compensated columns), every row of want_good a number; stderr
 * holds `says`. */
static void expect(const char *cal, const char *name, const char *text,
                   const char *const *bad, int n_bad, const char *const *good, int n_good,
                   const char *says)
{
    char path[700], args[1024], out[65536];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    assert_int_equal(test_write_file(path, text), 0);
    snprintf(args, sizeof args, "compensate $D/%s/params.ini $D/%s", cal, name);
    int rc = sunmc(args, out, sizeof out);
    if (rc != 0)
        fail_msg("%s: exit %d: %s", args, rc, out);
    for (int i = 0; i < n_bad; i++)
        if (!strstr(out, bad[i]))
            fail_msg("%s: '%s' not marked: %s", name, bad[i], out);
    for (int i = 0; i < n_good; i++)
        if (!strstr(out, good[i]))
            fail_msg("%s: '%s' not compensated: %s", name, good[i], out);
    if (!strstr(out, says))
        fail_msg("%s: stderr does not say '%s': %s", name, says, out);
    assert_null(strstr(out, "nan"));
}

/* ESS: an output at or beyond +-90 deg (the encoded tangent wrapped). */
static void ess_outside_range(void **state)
{
    (void)state;
    const char *bad[] = {"\n90,-\n", "\n-90.5,-\n"}, *good[] = {"\n89.5,8", "\n10,9.9"};
    expect("ce", "e.csv", "output_deg\n10\n90\n-90.5\n89.5\n", bad, 2, good, 2,
           "2 rows not compensated: 2 outside the output's range");
}

/* DSS: a weight-0 "no spot" row of the campaign format (was 0.0078 deg,
 * -0.018 deg), and a spot beyond the detector. */
static void dss_no_spot_and_outside(void **state)
{
    (void)state;
    const char *bad[] = {"\n-50,-50,0,0,0,-,-\n", "\n0,0,1024.1,0,1,-,-\n"};
    const char *good[] = {"\n0,0,1,1,1,-0.", "\n0,0,0,0,1,0."};
    expect("cd", "d.csv", "b1_deg,b2_deg,x_px,y_px,weight\n-50,-50,0,0,0\n0,0,1024.1,0,1\n"
                          "0,0,1,1,1\n0,0,0,0,1\n",
           bad, 2, good, 2,
           "2 rows not compensated: 1 no signal (no spot, or channels at or below the dark "
           "level), 1 outside the detector");
}

/* PSD physical model: channels at 0 or at the fitted darks (no signal),
 * one channel above its dark but the sum below (negative sum), negative
 * channels (no ADC reads them), a saturated spot (no inverse); an
 * ordinary reading compensated. */
static void psd_physical(void **state)
{
    (void)state;
    char path[700], text[1024], out[4096];
    double dark[4];
    snprintf(path, sizeof path, "%s/cp/params.ini", dir);
    for (int k = 0; k < 4; k++) {
        char cmd[1024];
        snprintf(cmd, sizeof cmd, "sed -n 's/^dark%d_raw *= *\\([-0-9.e]*\\).*/\\1/p' %s", k + 1,
                 path);
        assert_int_equal(test_run(cmd, out, sizeof out), 0);
        dark[k] = strtod(out, NULL);
        assert_true(dark[k] > 0);
    }
    snprintf(text, sizeof text,
             "i1,i2,i3,i4\n0,0,0,0\n%.17g,%.17g,%.17g,%.17g\n%.17g,0,0,0\n-1,-1,-1,-1\n"
             "-0.1,-0.2,-0.15,-0.12\n1,0,0,0\n0.1,0.2,0.15,0.12\n",
             dark[0], dark[1], dark[2], dark[3], dark[0] + 0.01);
    const char *bad[] = {"\n0,0,0,0,-,-\n", "\n-1,-1,-1,-1,-,-\n", "\n-0.1,-0.2,-0.15,-0.12,-,-\n",
                         "\n1,0,0,0,-,-\n"};
    const char *good[] = {"\n0.1,0.2,0.15,0.12,-1"};
    expect("cp", "p.csv", text, bad, 4, good, 1,
           "6 rows not compensated: 2 no signal (no spot, or channels at or below the dark "
           "level), 1 negative sum (the dark-corrected channels add up below 0), 2 outside the "
           "output's range, 1 no inverse (the model cannot be inverted there)");
}

/* PSD physical model of an inverting sensor (design.polarity = inverted,
 * the aeroztark unit's): a lit channel reads below its dark.  Its own
 * campaign is compensated whole (the check used to call every reading "no
 * signal": the fitted gains are relative to channel 1's, so params.ini
 * carries the polarity), and a reading above every dark is no signal. */
static void psd_inverted(void **state)
{
    (void)state;
    char path[700], cmd[1400], out[65536];
    snprintf(path, sizeof path, "%s/cz/params.ini", dir);
    snprintf(cmd, sizeof cmd, "grep -q '^polarity *= *inverted' %s", path);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "compensate $D/cz/params.ini $D/sz/campaign.csv > $D/z.csv");
    int rc = sunmc(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s: exit %d: %s", cmd, rc, out);
    assert_null(strstr(out, "not compensated"));
    snprintf(cmd, sizeof cmd, "grep -c ',-,' %s/z.csv", dir);
    assert_int_not_equal(system(cmd), 0); /* grep -c finds none: exit 1 */
    const char *bad[] = {"\n4.9,4.9,4.9,4.9,-,-\n"};
    expect("cz", "z_bad.csv", "i1,i2,i3,i4\n4.9,4.9,4.9,4.9\n", bad, 1, NULL, 0,
           "1 row not compensated: 1 no signal");
}

/* PSD polynomial model (it used to give nan only for 0,0,0,0): no signal,
 * negative channels, a ratio beyond the calibrated field. */
static void psd_polynomial(void **state)
{
    (void)state;
    const char *bad[] = {"\n0,0,0,0,-,-\n", "\n-0.1,-0.2,-0.15,-0.12,-,-\n", "\n1,0,0,0,-,-\n"};
    expect("cq", "q.csv", "i1,i2,i3,i4\n0,0,0,0\n-0.1,-0.2,-0.15,-0.12\n1,0,0,0\n", bad, 3, NULL,
           0,
           "3 rows not compensated: 1 no signal (no spot, or channels at or below the dark "
           "level), 2 outside the output's range");
}

/* A data file with a header and no rows: refused as calibrate refuses it
 * (it used to exit 0 with a header). */
static void header_only_refused(void **state)
{
    (void)state;
    char path[700], out[4096];
    snprintf(path, sizeof path, "%s/empty.csv", dir);
    assert_int_equal(test_write_file(path, "# a comment\noutput_deg\n"), 0);
    assert_int_equal(sunmc("compensate $D/ce/params.ini $D/empty.csv", out, sizeof out), 2);
    assert_non_null(strstr(out, "empty.csv: no data rows"));
    assert_null(strstr(out, "compensated_deg"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ess_outside_range),
        cmocka_unit_test(dss_no_spot_and_outside),
        cmocka_unit_test(psd_physical),
        cmocka_unit_test(psd_inverted),
        cmocka_unit_test(psd_polynomial),
        cmocka_unit_test(header_only_refused),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
