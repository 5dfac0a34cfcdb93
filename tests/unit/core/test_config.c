/* test_config.c - the key table, INI parsing, --set and every config error. */
#include "test_util.h"

#include "ess_config.h"

#include "config.h"
#include "registry.h"
#include "status.h"

#include <unistd.h>

static char path[64];

static int setup(void **state)
{
    snprintf(path, sizeof path, "/tmp/sunmc_test_config_%ld.ini", (long)getpid());
    return 0;
}

static int teardown(void **state)
{
    unlink(path);
    return 0;
}

/* Build from text; returns the status and leaves the message in err. */
static int build_text(const char *text, const char *const *sets, int n, config_state *st,
                      char *err)
{
    assert_int_equal(test_write_file(path, text), 0);
    int s = config_build(st, path, sets, n, err, SUNMC_ERRLEN);
    if (s == SUNMC_OK)
        config_state_free(st);
    return s;
}

static void expect_error(const char *text, int line, const char *needle)
{
    config_state st;
    char err[SUNMC_ERRLEN] = "";
    assert_int_equal(build_text(text, NULL, 0, &st, err), SUNMC_EINPUT);
    char where[128];
    snprintf(where, sizeof where, "%s:%d: ", path, line);
    if (strstr(err, where) != err)
        fail_msg("message '%s' does not start with '%s'", err, where);
    if (!strstr(err, needle))
        fail_msg("message '%s' does not name '%s'", err, needle);
}

static void test_defaults_every_key(void **state)
{
    /* Every default parses and validates, for both families. */
    config_state st;
    ess_config *ec = ess_cfg(&st.cfg);
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, NULL, NULL, 0, err, sizeof err), SUNMC_OK);
    assert_string_equal(st.cfg.family->name, "ess");
    assert_near(ec->design.H_mm, 4.124, 0);
    assert_near(ec->tol.dH_um.value, 2, 0);
    assert_int_equal(ec->tol.dH_um.dist, DIST_UNIFORM);
    assert_int_equal(st.cfg.bands_deg.n, 3);
    config_state_free(&st);
    const char *dss[] = {"sensor.family=dss"};
    assert_int_equal(config_build(&st, NULL, dss, 1, err, sizeof err), SUNMC_OK);
    assert_string_equal(st.cfg.family->name, "dss");
    assert_near(st.cfg.bands_deg.hi[0], 20, 0); /* DSS default differs */
    config_state_free(&st);
}

static void test_parse_values_and_sets(void **state)
{
    config_state st;
    ess_config *ec = ess_cfg(&st.cfg);
    char err[SUNMC_ERRLEN];
    const char *text = "# comment\n[design]\nH_mm = 6.584  # type B\n[campaign]\n"
                       "beta_deg = -10, 0, 10, 30\n[tolerance]\ndH_um_dist = truncnormal\n"
                       "[report]\nbands_deg = 0:10, 10:20\n";
    const char *sets[] = {"tolerance.dH_um=3", "run.seed=9"};
    assert_int_equal(test_write_file(path, text), 0);
    assert_int_equal(config_build(&st, path, sets, 2, err, sizeof err), SUNMC_OK);
    assert_near(ec->design.H_mm, 6.584, 0);
    assert_int_equal(ec->cal_beta_deg.n, 4);
    assert_near(ec->cal_beta_deg.v[3], 30, 0);
    assert_near(ec->tol.dH_um.value, 3, 0);
    assert_int_equal(ec->tol.dH_um.dist, DIST_TRUNCNORMAL);
    assert_int_equal(st.cfg.seed, 9);
    assert_int_equal(st.cfg.bands_deg.n, 2);
    /* the origin of each value is kept */
    const config_key *k = config_find("design", "H_mm");
    char want[128];
    snprintf(want, sizeof want, "%s:3", path);
    assert_string_equal(config_origin_of(&st, k), want);
    config_state_free(&st);
}

static void test_unknown_section(void **state)
{
    expect_error("[design]\nH_mm = 4\n[nonsense]\nx = 1\n", 3, "[nonsense]");
}

static void test_unknown_key(void **state)
{
    expect_error("[design]\nH_mm = 4\nHH_mm = 5\n", 3, "HH_mm");
}

static void test_duplicate_key(void **state)
{
    expect_error("[design]\nH_mm = 4\n\nH_mm = 5\n", 4, "duplicate key design.H_mm");
}

static void test_not_a_number(void **state)
{
    expect_error("[design]\nH_mm = four\n", 2, "design.H_mm");
    /* IEEE checks (isfinite) still work: only the vectorised kernels are
     * built with relaxed math-library flags */
    expect_error("[design]\nH_mm = nan\n", 2, "design.H_mm");
    expect_error("[design]\nH_mm = inf\n", 2, "design.H_mm");
    expect_error("[design]\n\nH_mm = -inf\n", 3, "design.H_mm");
    expect_error("[design]\nH_mm = 1e999\n", 2, "design.H_mm");
}

static void test_out_of_range(void **state)
{
    expect_error("[design]\n\nH_mm = 99\n", 3, "0.5 to 50 mm");
}

static void test_bad_enum_and_list(void **state)
{
    expect_error("[tolerance]\ndH_um_dist = gaussian\n", 2, "fixed|uniform|normal|truncnormal");
    expect_error("[campaign]\nbeta_deg = 0, x\n", 2, "campaign.beta_deg");
    expect_error("[report]\nbands_deg = 0-30\n", 2, "LO:HI");
}

static void test_wrong_family_key(void **state)
{
    expect_error("[sensor]\nfamily = ess\n[design]\nh_mm = 3\n", 4, "applies to dss");
}

static void test_syntax_errors(void **state)
{
    expect_error("H_mm = 4\n", 1, "before any [section]");
    expect_error("[design\n", 1, "malformed section");
    expect_error("[design]\nH_mm\n", 2, "key = value");
}

static void test_line_too_long(void **state)
{
    static char text[1400];
    snprintf(text, sizeof text, "[design]\nH_mm = 4%01300d\n", 0);
    expect_error(text, 2, "longer than");
}

static void test_missing_file(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    assert_int_equal(config_build(&st, "/nonexistent/x.ini", NULL, 0, err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "/nonexistent/x.ini"));
}

static void test_bad_set(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    const char *s1[] = {"design.H_mm"};
    assert_int_equal(config_build(&st, NULL, s1, 1, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "section.key=value"));
    const char *s2[] = {"design.H_mm=0.1"};
    assert_int_equal(config_build(&st, NULL, s2, 1, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "--set design.H_mm"));
    const char *s3[] = {"design.nope=1"};
    assert_int_equal(config_build(&st, NULL, s3, 1, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "nope"));
}

static void test_cross_checks(void **state)
{
    config_state st;
    char err[SUNMC_ERRLEN];
    const char *s1[] = {"design.fine_rows_x_mm=1,2,3"};
    assert_int_equal(config_build(&st, NULL, s1, 1, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "exactly 4"));
    const char *s2[] = {"campaign.alpha_max_deg=70"};
    assert_int_equal(config_build(&st, NULL, s2, 1, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "field of view"));
    const char *s3[] = {"design.coarse_rows_x_mm=1,2,3"};
    assert_int_equal(config_build(&st, NULL, s3, 1, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "coarse rows"));
}

/* The dump of the effective config reads back to the same config. */
static void test_dump_round_trip(void **state)
{
    config_state a, b;
    char err[SUNMC_ERRLEN];
    const char *sets[] = {"design.H_mm=5.5", "campaign.beta_deg=-7,7", "tolerance.dd_um_dist=normal"};
    assert_int_equal(config_build(&a, NULL, sets, 3, err, sizeof err), SUNMC_OK);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    assert_int_equal(config_write(f, &a), SUNMC_OK);
    fclose(f);
    assert_int_equal(config_build(&b, path, NULL, 0, err, sizeof err), SUNMC_OK);
    char va[1024], vb[1024];
    assert_int_equal(a.n_keys, b.n_keys);
    for (size_t i = 0; i < a.n_keys; i++) {
        config_format_value(a.keys[i], &a.cfg, va, sizeof va);
        config_format_value(a.keys[i], &b.cfg, vb, sizeof vb);
        assert_string_equal(va, vb);
    }
    config_state_free(&a);
    config_state_free(&b);
}

/* configs/reference.ini is what the key table generates (make reference). */
static void test_reference_is_current(void **state)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    assert_int_equal(config_write_reference(f), SUNMC_OK);
    fclose(f);
    char cmd[256], out[4096];
    snprintf(cmd, sizeof cmd, "diff -u configs/reference.ini %s | head -20", path);
    test_run(cmd, out, sizeof out);
    if (out[0])
        fail_msg("configs/reference.ini is stale, run `make reference`:\n%s", out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_every_key), cmocka_unit_test(test_parse_values_and_sets),
        cmocka_unit_test(test_unknown_section),   cmocka_unit_test(test_unknown_key),
        cmocka_unit_test(test_duplicate_key),     cmocka_unit_test(test_not_a_number),
        cmocka_unit_test(test_out_of_range),      cmocka_unit_test(test_bad_enum_and_list),
        cmocka_unit_test(test_wrong_family_key),  cmocka_unit_test(test_syntax_errors),
        cmocka_unit_test(test_line_too_long),     cmocka_unit_test(test_missing_file),      cmocka_unit_test(test_bad_set),
        cmocka_unit_test(test_cross_checks),      cmocka_unit_test(test_dump_round_trip),
        cmocka_unit_test(test_reference_is_current),
    };
    return cmocka_run_group_tests_name("config", tests, setup, teardown);
}
