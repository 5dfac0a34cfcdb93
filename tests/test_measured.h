/* test_measured.h - shared checks of a lab measurement that a calibration
 * can fix instead of fit (ESS calibration.sun_y, DSS calibration.sun): its
 * noise source in `sensitivity` and `budget`, and its keys' error paths. */
#ifndef SUNMC_TEST_MEASURED_H
#define SUNMC_TEST_MEASURED_H

#include "test_util.h"

#include "budget.h"
#include "sensitivity.h"

/* Assert that config c has the measurement as an input `expected` (0 or 1)
 * times: in sensitivity as noise source sens_name on stream `stream`, in
 * budget as key budget_key. */
static inline void test_measurement_source(const sunmc_config *c, const char *sens_name,
                                           uint32_t stream, const char *budget_key, int expected)
{
    static sens_result s;
    static budget_result b;
    char err[SUNMC_ERRLEN];
    int in_sens = 0, in_budget = 0;
    assert_int_equal(sens_sources(c, &s, err, sizeof err), SUNMC_OK);
    for (int i = 0; i < s.n; i++)
        in_sens += strcmp(s.src[i].name, sens_name) == 0 && s.src[i].stream == stream;
    assert_int_equal(budget_sources(c, &b, err, sizeof err), SUNMC_OK);
    for (int i = 0; i < b.n; i++)
        in_budget += strcmp(b.src[i].name, budget_key) == 0;
    assert_int_equal(in_sens, expected);
    assert_int_equal(in_budget, expected);
}

/* Each cases[k][0], a line of [calibration] in a config of `family`, is
 * refused by `run`: exit 2, "FILE:5: cases[k][1]", nothing written. */
static inline void test_bad_calibration_lines(const char *family, const char *const (*cases)[2],
                                              size_t n)
{
    const char *ini = test_tmp("bad_calibration.ini"), *dir = test_tmp("bad_calibration_out");
    for (size_t k = 0; k < n; k++) {
        char text[256], cmd[1024], out[4096], want[512];
        snprintf(text, sizeof text, "[sensor]\nfamily = %s\n\n[calibration]\n%s", family,
                 cases[k][0]);
        assert_int_equal(test_write_file(ini, text), 0);
        snprintf(cmd, sizeof cmd, "%s run %s --units 2 --out %s", test_sunmc(), ini, dir);
        assert_int_equal(test_run(cmd, out, sizeof out), 2);
        snprintf(want, sizeof want, "%s:5: %s", ini, cases[k][1]);
        if (!strstr(out, want))
            fail_msg("case %zu: '%s' not in: %s", k, want, out);
        snprintf(cmd, sizeof cmd, "test -e %s", dir);
        assert_int_not_equal(system(cmd), 0);
    }
}

#endif
