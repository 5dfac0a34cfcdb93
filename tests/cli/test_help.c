/* test_help.c - what a newcomer reads first: --help per family with balanced
 * brackets, and "did you mean" for a mistyped key (in a file and in --set). */
#include "test_util.h"

#include "lab.h"
#include "registry.h"

static char out[65536];

static int sunmc(const char *args)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s %s", test_sunmc(), args);
    return test_run(cmd, out, sizeof out);
}

/* Every '[' closed by a ']' on the same line, and never nested. */
static void assert_brackets_balanced(const char *text)
{
    int depth = 0, line = 1;
    for (const char *p = text; *p; p++) {
        if (*p == '[' && ++depth > 1)
            fail_msg("nested '[' on line %d", line);
        if (*p == ']' && --depth < 0)
            fail_msg("unopened ']' on line %d", line);
        if (*p == '\n') {
            if (depth != 0)
                fail_msg("'[' left open on line %d", line);
            line++;
        }
    }
}

static void test_main_help_lists_first_family_keys(void **state)
{
    assert_int_equal(sunmc("--help"), 0);
    assert_brackets_balanced(out);
    assert_non_null(strstr(out, "config keys of the ess family"));
    assert_non_null(strstr(out, "    design.H_mm = 4.124  mm\n"));
    assert_non_null(strstr(out, "  [tolerance]\n"));
    assert_null(strstr(out, "design.pixel_um"));    /* a DSS key */
}

static void test_help_family_dss_lists_dss_keys_only(void **state)
{
    assert_int_equal(sunmc("--help --family dss"), 0);
    assert_brackets_balanced(out);
    assert_non_null(strstr(out, "config keys of the dss family"));
    assert_non_null(strstr(out, "    sensor.family = dss\n"));
    assert_null(strstr(out, "design.H_mm"));        /* an ESS key */
    assert_null(strstr(out, "fine_rows_x_mm"));
}

static void test_command_help_follows_config_family(void **state)
{
    assert_int_equal(sunmc("run --help configs/dss.ini"), 0);
    assert_brackets_balanced(out);
    assert_non_null(strstr(out, "usage: sunmc run CONFIG"));
    assert_non_null(strstr(out, "config keys of the dss family"));
    assert_int_equal(sunmc("run --help --family ess"), 0);
    assert_non_null(strstr(out, "config keys of the ess family"));
    assert_int_equal(sunmc("run --help"), 0);      /* no family asked: no key list */
    assert_null(strstr(out, "config keys of"));
}

static void test_unknown_family_is_refused(void **state)
{
    assert_int_equal(sunmc("--help --family sss"), 2);
    assert_non_null(strstr(out, "--family takes one of ess|dss"));
}

static void test_every_command_help_balanced(void **state)
{
    const char *cmds[] = {"run", "config", "sweep", "budget", "sensitivity",
                          "curve", "simulate", "calibrate",
                          "compensate", "export"};
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++) {
        char args[64];
        snprintf(args, sizeof args, "%s --help", cmds[i]);
        assert_int_equal(sunmc(args), 0);
        assert_brackets_balanced(out);
    }
}

/* calibrate --help and compensate --help name every registered family's
 * columns, read from its lab descriptor (nothing per family in src/cli). */
static void test_lab_help_from_descriptors(void **state)
{
    for (int i = 0; i < sensor_family_count(); i++) {
        const sensor_family *f = sensor_family_at(i);
        if (!f->lab)
            continue;
        char want[256];
        size_t n = (size_t)snprintf(want, sizeof want, "  %s: ", f->name);
        for (int k = 0; f->lab->cal_columns[k]; k++) {
            int last = f->lab->cal_columns[k + 1] == NULL;
            n += (size_t)snprintf(want + n, sizeof want - n, last ? "[,%s]" : "%s%s",
                                  last ? f->lab->cal_columns[k] : k ? "," : "",
                                  f->lab->cal_columns[k]);
        }
        assert_int_equal(sunmc("calibrate --help"), 0);
        assert_non_null(strstr(out, want));
        snprintf(want, sizeof want, "  %s: %s", f->name, f->lab->raw_columns[0]);
        assert_int_equal(sunmc("compensate --help"), 0);
        assert_non_null(strstr(out, want));
        assert_non_null(strstr(out, f->lab->comp_columns[0]));
    }
}

static void test_suggest_names_nearest_key(void **state)
{
    char hint[128];
    config_suggest(NULL, "tolerance", "dh_um", hint, sizeof hint);
    assert_string_equal(hint, " (did you mean tolerance.dH_um?)");
    config_suggest(NULL, "design", "dH_um", hint, sizeof hint);          /* right key, wrong section */
    assert_string_equal(hint, " (did you mean tolerance.dH_um?)");
    config_suggest(NULL, "design", "slitwidth_um", hint, sizeof hint);   /* one edit */
    assert_string_equal(hint, " (did you mean design.slit_width_um?)");
    config_suggest(NULL, "design", "xyz", hint, sizeof hint);            /* nothing near */
    assert_string_equal(hint, "");
    config_suggest(NULL, "design", "H", hint, sizeof hint);              /* too short to guess */
    assert_string_equal(hint, "");
    config_suggest(NULL, "run", "se", hint, sizeof hint);                /* seed: 2 edits of 2 letters */
    assert_string_equal(hint, "");
    config_suggest(NULL, "tolerance", "DH_UM", hint, sizeof hint);       /* case is not an edit */
    assert_string_equal(hint, " (did you mean tolerance.dH_um?)");
    config_suggest(NULL, "validation", "beta_dg", hint, sizeof hint);    /* own section first */
    assert_string_equal(hint, " (did you mean validation.beta_deg?)");
}

static void test_mistyped_key_suggested_in_file_and_set(void **state)
{
    assert_int_equal(sunmc("run configs/ess_type_a.ini --units 1 --set tolerance.dH_un=2"),
                     2);
    assert_non_null(strstr(out, "unknown key 'dH_un' in section [tolerance] (did you mean "
                                "tolerance.dH_um?)"));
    const char *ini = test_tmp("typo.ini");
    assert_int_equal(test_write_file(ini, "[sensor]\nfamily = ess\n[tolerance]\ndH_un = 2\n"), 0);
    char args[512];
    snprintf(args, sizeof args, "config %s", ini);
    assert_int_equal(sunmc(args), 2);
    assert_non_null(strstr(out, ":4: unknown key 'dH_un' in section [tolerance] (did you mean "
                                "tolerance.dH_um?)"));
}

/* The ESS table is in degrees: the spec is printed in degrees too
 * (54 arcsec / 3600 = 0.015 deg); the DSS table is in arcsec already. */
static void test_spec_in_table_unit(void **state)
{
    assert_int_equal(sunmc("run configs/ess_type_a.ini --units 1 --quiet"), 0);
    assert_non_null(strstr(out, ", spec 54 arcsec = 0.01500 deg\n"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_main_help_lists_first_family_keys),
        cmocka_unit_test(test_help_family_dss_lists_dss_keys_only),
        cmocka_unit_test(test_command_help_follows_config_family),
        cmocka_unit_test(test_unknown_family_is_refused),
        cmocka_unit_test(test_every_command_help_balanced),
        cmocka_unit_test(test_lab_help_from_descriptors),
        cmocka_unit_test(test_suggest_names_nearest_key),
        cmocka_unit_test(test_mistyped_key_suggested_in_file_and_set),
        cmocka_unit_test(test_spec_in_table_unit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
