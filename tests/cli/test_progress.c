/* test_progress.c - the overall progress line of long commands: the ETA
 * arithmetic, the line's format, and off a terminal one line per stage
 * (no carriage return), nothing under --quiet. */
#include "test_util.h"
#include "progress.h"

#include <stdlib.h>
#include <unistd.h>

static void test_eta_arithmetic(void **state)
{
    /* 250 of 1000 in 10 s: 40 s for the other 750 at the same rate */
    assert_near(cli_eta_s(250, 1000, 10.0), 30.0, 0);
    assert_near(cli_eta_s(1, 4, 2.0), 6.0, 0);
    assert_near(cli_eta_s(1000, 1000, 10.0), 0.0, 0);
    /* unknown before the first unit, and without a total */
    assert_true(isnan(cli_eta_s(0, 1000, 10.0)));
    assert_true(isnan(cli_eta_s(5, 0, 10.0)));
}

static void test_line_format(void **state)
{
    char buf[256];
    cli_meter_line(buf, sizeof buf, "sweep", "units", 250, 1000, 10.0, "point 2/4 x=1");
    assert_string_equal(buf, "sunmc sweep: 250/1000 units (25%), ETA 30 s: point 2/4 x=1");
    cli_meter_line(buf, sizeof buf, "budget", "units", 0, 960, 3.0, "all sources (1/18)");
    assert_string_equal(buf, "sunmc budget: 0/960 units (0%), ETA -: all sources (1/18)");
    /* 100 of 1000 in 20 s: 180 s left; 10 of 1000 in 45 s: 4455 s */
    cli_meter_line(buf, sizeof buf, "run", "units", 100, 1000, 20.0, "");
    assert_string_equal(buf, "sunmc run: 100/1000 units (10%), ETA 3 min 00 s");
    cli_meter_line(buf, sizeof buf, "run", "units", 10, 1000, 45.0, NULL);
    assert_string_equal(buf, "sunmc run: 10/1000 units (1%), ETA 1 h 14 min");
    cli_meter_line(buf, sizeof buf, "run", "units", 61, 100, 61.0, "");
    assert_string_equal(buf, "sunmc run: 61/100 units (61%), ETA 39 s");
}

/* stderr to a file (not a terminal): one line per sweep point with the
 * overall count, no carriage return; --quiet: nothing. */
static void test_sweep_lines_off_terminal(void **state)
{
    char cmd[1024], out[8192];
    const char *log = test_tmp("sweep.log");
    snprintf(cmd, sizeof cmd,
             "%s sweep configs/ess_type_a.ini --units 6 --vary campaign.alpha_step_deg=0.3,0.2,0.25 "
             "--set validation.alpha_step_deg=3 > /dev/null 2> %s; cat %s",
             test_sunmc(), log, log);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_null(strchr(out, '\r'));
    assert_non_null(strstr(out, "sunmc sweep: 0/18 units (0%), ETA -: point 1/3 "
                                "campaign.alpha_step_deg=0.3\n"));
    assert_non_null(strstr(out, "sunmc sweep: 6/18 units (33%), ETA "));
    assert_non_null(strstr(out, ": point 2/3 campaign.alpha_step_deg=0.2\n"));
    assert_non_null(strstr(out, "sunmc sweep: 12/18 units (67%), ETA "));
    int lines = 0;
    for (const char *p = out; *p; p++)
        lines += *p == '\n';
    assert_int_equal(lines, 3);
    snprintf(cmd, sizeof cmd,
             "%s sweep configs/ess_type_a.ini --units 6 --vary campaign.alpha_step_deg=0.3,0.2 "
             "--set validation.alpha_step_deg=3 --quiet > /dev/null",
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_string_equal(out, "");
}

/* Off a terminal, many stages (design has hundreds) give the first line,
 * then one per 10 % of the total (the stages here take no time, so the
 * 30 s clause never fires): 200 stages of 1 unit -> lines at 0, 10, ...,
 * 90 % = 10 lines; 3 stages of a third each -> 3 lines, one per stage. */
static int stage_lines(int stages, long per)
{
    char path[] = "/tmp/sunmc_progress_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    fflush(stderr);
    int saved = dup(STDERR_FILENO);
    dup2(fd, STDERR_FILENO);
    cli_meter m;
    cli_meter_start(&m, "design", "steps", stages * per, 0);
    for (int i = 0; i < stages; i++)
        cli_meter_stage(&m, "candidate", i * per);
    cli_meter_end(&m);
    fflush(stderr);
    dup2(saved, STDERR_FILENO);
    close(saved);
    close(fd);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    int lines = 0, c;
    while ((c = fgetc(f)) != EOF) {
        lines += c == '\n';
        assert_true(c != '\r');
    }
    fclose(f);
    unlink(path);
    return lines;
}

static void test_many_stages_log_stays_short(void **state)
{
    assert_int_equal(stage_lines(200, 1), 10);
    assert_int_equal(stage_lines(3, 50), 3);
    assert_int_equal(stage_lines(1, 50), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_eta_arithmetic),
        cmocka_unit_test(test_line_format),
        cmocka_unit_test(test_sweep_lines_off_terminal),
        cmocka_unit_test(test_many_stages_log_stays_short),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
