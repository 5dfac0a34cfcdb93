/* test_family_keys.c - issue 36, rule 4: a key that a family lists applies
 * to it, or the family does not list it.  calibration.priors did nothing for
 * the PSD family although the reference listed it for psd; --duplicates
 * was ignored for PSD; did-you-mean offered another family's keys. */
#include "test_util.h"

#include "family.h"
#include "registry.h"

static char dir[512];

#define P "configs/psd.ini"
#define D "configs/dss.ini"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    if (test_private_dir(dir, sizeof dir, "famkeys") != 0)
        return -1;
    char out[16384];
    if (sunmc("simulate " P " --unit 1 --quiet --out $D/p", out, sizeof out) != 0) {
        fprintf(stderr, "%s\n", out);
        return -1;
    }
    char cmd[2048];
    /* the campaign with its first data row logged twice */
    snprintf(cmd, sizeof cmd,
             "cd %s && grep -v '^#' p/campaign.csv > dup.csv && sed -n 2p dup.csv >> dup.csv", dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* The priors' keys are not the PSD family's: refused where they are set,
 * left out of its dumps, and the reference lists ess, dss only. */
static void test_priors_not_psd(void **state)
{
    char out[65536];
    const char *bad[] = {"run " P " --units 2 --quiet --set calibration.priors=off",
                         "run " P " --units 2 --quiet --set calibration.prior_units=9",
                         "calibrate --config " P " $D/p/campaign.csv --set calibration.priors=off"};
    for (int i = 0; i < 3; i++) {
        int rc = sunmc(bad[i], out, sizeof out);
        if (rc != 2 || !strstr(out, "applies to ess, dss sensors, but sensor.family is psd"))
            fail_msg("%s: exit %d: %s", bad[i], rc, out);
    }
    char cfg[700];
    snprintf(cfg, sizeof cfg, "%s/pri.ini", dir);
    assert_int_equal(test_write_file(cfg, "[sensor]\nfamily = psd\n\n[calibration]\npriors = off\n"),
                     0);
    int rc = sunmc("run $D/pri.ini --units 2 --quiet --out $D/pri", out, sizeof out);
    if (rc != 2 || !strstr(out, "pri.ini:5:"))
        fail_msg("exit %d: %s", rc, out);
    /* the ESS and DSS still take them */
    assert_int_equal(sunmc("run " D " --units 2 --quiet --set calibration.priors=off", out,
                           sizeof out),
                     0);
    /* a PSD run's config dump has no priors line, and runs again as it is */
    assert_int_equal(sunmc("run " P " --units 2 --quiet --out $D/r", out, sizeof out), 0);
    snprintf(cfg, sizeof cfg, "%s/r/config.ini", dir);
    assert_int_equal(test_file_has(cfg, "priors"), 0);
    assert_int_equal(sunmc("run $D/r/config.ini --units 2 --quiet", out, sizeof out), 0);
    rc = sunmc("config --reference", out, sizeof out);
    assert_int_equal(rc, 0);
    const char *pr = strstr(out, "# priors = tolerances");
    assert_non_null(pr);
    const char *scope = pr;
    while (scope > out && strncmp(scope, "#   families: ", 14) != 0)
        scope--;
    assert_int_equal(strncmp(scope, "#   families: ess, dss;", 23), 0);
}

/* config_family_omits: only the family's listed shared keys. */
static void test_family_omits(void **state)
{
    const sensor_family *psd = sensor_family_find("psd"), *ess = sensor_family_find("ess");
    assert_non_null(psd);
    assert_non_null(ess);
    const config_key *pri = config_find_in(NULL, "calibration", "priors");
    const config_key *pu = config_find_in(NULL, "calibration", "prior_units");
    const config_key *it = config_find_in(NULL, "calibration", "max_iterations");
    assert_non_null(pri);
    assert_non_null(pu);
    assert_non_null(it);
    assert_true(config_family_omits(psd, pri));
    assert_true(config_family_omits(psd, pu));
    assert_false(config_family_omits(psd, it));
    assert_false(config_family_omits(ess, pri));
    assert_false(config_family_omits(NULL, pri));
    assert_null(config_find_in(psd, "calibration", "priors"));
    assert_ptr_equal(config_find_in(ess, "calibration", "priors"), pri);
    assert_false(config_key_applies(pri, psd));
    assert_true(config_key_applies(pri, ess));
    assert_true(config_key_applies(it, psd));
    /* a name is matched whole, never by a prefix (priors / prior_units) */
    static const char *const only_priors[] = {"calibration.priors", NULL};
    sensor_family f = *ess;
    f.shared_keys_unused = only_priors;
    assert_true(config_family_omits(&f, pri));
    assert_false(config_family_omits(&f, pu));
    static const char *const other_section[] = {"run.priors", "calibration", NULL};
    f.shared_keys_unused = other_section;
    assert_false(config_family_omits(&f, pri));
}

/* --duplicates applies to PSD: refuse refuses, average counts once (with
 * the warning); without it the fit's own once-per-point counting stands
 * (quantised readings of one point may repeat exactly). */
static void test_duplicates_psd(void **state)
{
    char out[65536];
    int rc = sunmc("calibrate --config " P " $D/dup.csv --duplicates refuse --out $D/dr", out,
                   sizeof out);
    if (rc != 2 || !strstr(out, "dup.csv:47: repeats line 2 exactly"))
        fail_msg("refuse: exit %d: %s", rc, out);
    rc = sunmc("calibrate --config " P " $D/dup.csv --duplicates average", out, sizeof out);
    if (rc != 0 || !strstr(out, "1 row repeats an earlier row exactly"))
        fail_msg("average: exit %d: %s", rc, out);
    rc = sunmc("calibrate --config " P " $D/dup.csv", out, sizeof out);
    if (rc != 0 || strstr(out, "repeats an earlier row"))
        fail_msg("default: exit %d: %s", rc, out);
}

/* Did-you-mean stays in the config's family. */
static void test_suggest_own_family(void **state)
{
    char out[65536];
    int rc = sunmc("run " D " --units 2 --quiet --set tolerance.dh_mm=1", out, sizeof out);
    if (rc != 2 || strstr(out, "dH_um"))
        fail_msg("a DSS config offered an ESS key: %s", out);
    rc = sunmc("run " D " --units 2 --quiet --set tolerance.dh_um=1", out, sizeof out);
    if (rc != 2 || !strstr(out, "applies to psd sensors") ||
        !strstr(out, "(did you mean tolerance.dh_px?)"))
        fail_msg("exit %d: %s", rc, out);
    rc = sunmc("sweep " D " --units 2 --quiet --vary tolerance.dH_umm=1,2", out, sizeof out);
    if (rc != 2 || strstr(out, "tolerance.dH_um?"))
        fail_msg("sweep offered an ESS key: %s", out);
    rc = sunmc("curve " P " --quiet --only dh_umm=2 --out $D/cu", out, sizeof out);
    if (rc != 2 || !strstr(out, "(did you mean tolerance.dh_um?)"))
        fail_msg("curve: exit %d: %s", rc, out);
    char hint[128];
    config_suggest(sensor_family_find("dss"), "tolerance", "dH_um", hint, sizeof hint);
    assert_null(strstr(hint, "dH_um"));
    config_suggest(sensor_family_find("ess"), "tolerance", "dh_um", hint, sizeof hint);
    assert_string_equal(hint, " (did you mean tolerance.dH_um?)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_priors_not_psd),
        cmocka_unit_test(test_family_omits),
        cmocka_unit_test(test_duplicates_psd),
        cmocka_unit_test(test_suggest_own_family),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
