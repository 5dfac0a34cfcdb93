/* test_golden.c - the recorded outputs of a fixed set of commands (both
 * families: run, sweep, budget, curve, simulate, calibrate, compensate; small
 * unit counts, fixed seeds) are reproduced byte for byte.  A guard for
 * refactoring: a change that moves a number must re-record them on purpose
 * (`make golden`) and say why in its commit. */
#include "test_util.h"

#include <unistd.h>

static void golden_outputs_identical(void **state)
{
    (void)state;
    char dir[] = "/tmp/sunmc_golden_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char cmd[1024], out[16384];
    snprintf(cmd, sizeof cmd, "bash tests/golden.sh %s %s/g && diff -r tests/golden %s/g",
             test_sunmc(), dir, dir);
    int st = test_run(cmd, out, sizeof out);
    if (st != 0)
        fail_msg("golden outputs differ (exit %d):\n%.4000s", st, out);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(golden_outputs_identical),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
