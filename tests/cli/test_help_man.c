/* test_help_man.c - the man page and the bash completion say what --help says:
 * man/sunmc.1 is what scripts/dev/gen-man.sh makes from the binary (run
 * `make man` after changing a help text), and completion offers the
 * commands, a command's options and the config keys. */
#include "test_util.h"

static char out[1 << 16];

static void test_man_page_in_step_with_help(void **state)
{
    const char *fresh = test_tmp("sunmc.1");
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "bash scripts/dev/gen-man.sh %s > %s && cmp %s man/sunmc.1",
             test_sunmc(), fresh, fresh);
    if (test_run(cmd, out, sizeof out) != 0)
        fail_msg("man/sunmc.1 is out of step with --help: run `make man` (%s)", out);
}

static void test_man_page_renders_without_warnings(void **state)
{
    if (test_run("command -v groff", out, sizeof out) != 0)
        skip();
    assert_int_equal(test_run("groff -man -Tutf8 -ww -z man/sunmc.1", out, sizeof out), 0);
    assert_string_equal(out, "");
}

/* The completions bash offers for the words of line (the last one is the
 * word being completed). */
static const char *complete(const char *line)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd,
             "bash -c 'source scripts/sunmc-completion.bash; COMP_WORDS=(%s %s); "
             "COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); _sunmc; echo \" ${COMPREPLY[*]} \"'",
             test_sunmc(), line);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    return out;
}

static void test_completion_commands_options_keys(void **state)
{
    assert_non_null(strstr(complete("ca"), " calibrate "));
    assert_null(strstr(out, " run "));
    assert_non_null(strstr(complete("r"), " run "));
    assert_non_null(strstr(complete("run --pro"), " --profile "));
    assert_non_null(strstr(complete("sweep --va"), " --vary "));
    assert_non_null(strstr(complete("run x.ini --set tolerance.dH"), " tolerance.dH_um= "));
    assert_non_null(strstr(complete("run x.ini --set design.pix"), " design.pixel_um= "));
    assert_non_null(strstr(complete("--help --family d"), " dss "));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_man_page_in_step_with_help),
        cmocka_unit_test(test_man_page_renders_without_warnings),
        cmocka_unit_test(test_completion_commands_options_keys),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
