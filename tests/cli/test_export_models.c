/* test_export_models.c - issue 39 item 3: `sunmc export` of the spline,
 * table and hybrid models.  Their model form (no C closed form) is
 * refused at the params' model line with a message naming the table form
 * (exit 2, nothing written); their table form is written and its test
 * program, compiled as C99 with -Werror, reproduces compensate's status on
 * every test vector (none refused that sunmc reads, none read that it
 * refuses) within the table's interpolation error; the PSD's hybrid, whose
 * correction does not follow from the raw ratios, is refused in both
 * forms. */
#include "test_util.h"

static char dir[512];

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static const struct {
    const char *cal, *sim, *config, *model, *name, *step;
    double max_err_deg;
} cases[] = {
    {"ps", "sp", "configs/psd.ini", "spline", "psd_spline", "table:0.01", 2e-3},
    {"pt", "sp", "configs/psd.ini", "table", "psd_table", "table:0.01", 2e-3},
    {"ds", "sd", "configs/dss.ini", "spline", "dss_spline", "table:16", 1e-2},
    {"dh", "sd", "configs/dss.ini", "hybrid", "dss_hybrid", "table:16", 1e-2},
    {"es", "se", "configs/ess_type_a.ini", "spline", "ess_spline", "table:0.05", 1e-4},
    {"eh", "se", "configs/ess_type_a.ini", "hybrid", "ess_hybrid", "table:0.01", 1e-3},
    {"et", "se", "configs/ess_type_a.ini", "table", "ess_table", "table:0.05", 1e-4},
};
#define N_CASES (sizeof cases / sizeof *cases)

static int setup(void **state)
{
    if (test_private_dir(dir, sizeof dir, "exportmodels") != 0)
        return -1;
    char out[16384], args[1024];
    const char *sims[] = {"simulate configs/psd.ini --unit 3 --quiet --out $D/sp",
                          "simulate configs/dss.ini --unit 3 --quiet --out $D/sd",
                          "simulate configs/ess_type_a.ini --unit 3 --quiet --out $D/se"};
    for (int i = 0; i < 3; i++)
        if (sunmc(sims[i], out, sizeof out) != 0)
            return -1;
    for (size_t i = 0; i < N_CASES; i++) {
        snprintf(args, sizeof args,
                 "calibrate --config %s --set calibration.model=%s "
                 "--set calibration.max_residual_ratio=1000 $D/%s/campaign.csv --quiet --out $D/%s",
                 cases[i].config, cases[i].model, cases[i].sim, cases[i].cal);
        if (sunmc(args, out, sizeof out) != 0) {
            fprintf(stderr, "%s: %s\n", args, out);
            return -1;
        }
    }
    if (sunmc("calibrate --config configs/psd.ini --set calibration.model=hybrid "
              "$D/sp/campaign.csv --quiet --out $D/ph",
              out, sizeof out) != 0)
        return -1;
    return 0;
}

static void test_model_form_refused(void **state)
{
    static char out[16384];
    for (size_t i = 0; i < N_CASES; i++) {
        char args[1024];
        snprintf(args, sizeof args, "export $D/%s/params.ini --out $D/mf_%s", cases[i].cal,
                 cases[i].cal);
        assert_int_equal(sunmc(args, out, sizeof out), 2);
        char want[128];
        snprintf(want, sizeof want, "params.ini:%d: the %s model", cases[i].config[8] == 'e' ||
                 cases[i].config[8] == 'd' ? 7 : 6, cases[i].name);
        if (!strstr(out, want) || !strstr(out, "--form table:STEP"))
            fail_msg("%s: want '%s' and --form table:STEP: %s", cases[i].cal, want, out);
        snprintf(args, sizeof args, "true; test ! -e $D/mf_%s", cases[i].cal);
        assert_int_equal(sunmc(args, out, sizeof out), 0);
    }
}

static void test_table_form_matches(void **state)
{
    static char out[16384];
    for (size_t i = 0; i < N_CASES; i++) {
        char args[2048];
        snprintf(args, sizeof args,
                 "true; %s export $D/%s/params.ini --form %s --quiet --out $D/tf_%s && cd "
                 "$D/tf_%s && cc -std=c99 -Wall -Wextra -Werror -pedantic -O1 test_main.c "
                 "sunmc_%s_cal.c -o t -lm && ./t",
                 test_sunmc(), cases[i].cal, cases[i].step, cases[i].cal, cases[i].cal,
                 cases[i].name);
        if (sunmc(args, out, sizeof out) != 0)
            fail_msg("%s: %s", args, out);
        long ok, mis;
        const char *p = strstr(out, " ok ");
        assert_non_null(p);
        assert_int_equal(sscanf(p, " ok %ld status_mismatch %ld", &ok, &mis), 2);
        if (mis != 0 || ok < 700)
            fail_msg("%s: %ld ok, %ld status mismatches", cases[i].cal, ok, mis);
        double e;
        p = strstr(out, "max_abs_error_deg[0] ");
        assert_non_null(p);
        assert_int_equal(sscanf(p, "max_abs_error_deg[0] %lf", &e), 1);
        if (!(e < cases[i].max_err_deg))
            fail_msg("%s: table error %g deg, stated %g", cases[i].cal, e, cases[i].max_err_deg);
    }
}

static void test_psd_hybrid_refused(void **state)
{
    static char out[16384];
    const char *forms[] = {"", "--form table:0.01"};
    for (int f = 0; f < 2; f++) {
        char args[512];
        snprintf(args, sizeof args, "export $D/ph/params.ini %s --out $D/never", forms[f]);
        assert_int_equal(sunmc(args, out, sizeof out), 2);
        if (!strstr(out, "params.ini:6: the psd_hybrid model cannot be exported"))
            fail_msg("%s", out);
    }
    assert_int_equal(sunmc("true; test ! -e $D/never", out, sizeof out), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_model_form_refused),
        cmocka_unit_test(test_table_form_matches),
        cmocka_unit_test(test_psd_hybrid_refused),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
