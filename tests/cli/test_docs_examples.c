/* test_docs_examples.c - the examples docs/ ships: the Python loader of
 * docs/outputs.md (docs/examples/load_run.py) reads a run's summary.tsv and
 * units.tsv, and the mean it recomputes from units.tsv's per-unit column
 * equals the summary's, row by row; docs/examples/my_dss.ini is a valid
 * config; the lab templates are CSVs calibrate's reader takes. */
#include "test_util.h"

static int setup(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd, "%s run configs/ess_type_a.ini --units 24 --out %s --quiet "
             "--set validation.alpha_step_deg=2.3", test_sunmc(), test_tmp("run"));
    if (test_run(cmd, out, sizeof out) != 0) {
        fprintf(stderr, "setup failed: %s\n%s\n", cmd, out);
        return -1;
    }
    return 0;
}

/* Every summary row printed, and the script's mean of units.tsv equals the
 * summary's mean (units.tsv rounds to 6 significant digits). */
static void python_loader_agrees_with_summary(void **state)
{
    char out[16384], cmd[4096];
    if (test_run("command -v python3", out, sizeof out) != 0)
        skip();
    snprintf(cmd, sizeof cmd, "python3 docs/examples/load_run.py %s", test_tmp("run"));
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s exited %d: %s", cmd, rc, out);
    int rows = 0;
    for (char *line = strtok(out, "\n"); line; line = strtok(NULL, "\n")) {
        double mean, lo, hi, again;
        char *p = strstr(line, "from units.tsv: ");
        assert_non_null(p);
        assert_int_equal(sscanf(strchr(strchr(line, '\t') + 1, '\t') + 1, "%lf\t[%lf, %lf]", &mean,
                                &lo, &hi), 3);
        assert_int_equal(sscanf(p + strlen("from units.tsv: "), "%lf", &again), 1);
        assert_true(lo < mean && mean < hi);
        assert_near(again, mean, 1e-5 * mean);
        rows++;
    }
    assert_int_equal(rows, 3); /* alpha in three bands */
}

static void example_config_is_valid(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd, "%s config docs/examples/my_dss.ini", test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "detector_px = 1024  # docs/examples/my_dss.ini"));
}

/* The templates have the header the docs promise and rows the reader takes:
 * compensate reads each one's rows (a reader error would exit 2). */
static void lab_templates_are_read(void **state)
{
    char out[16384], cmd[4096];
    assert_true(test_file_has("docs/examples/lab_ess.csv", "\nalpha_deg,beta_deg,output_deg,weight\n"));
    assert_true(test_file_has("docs/examples/lab_dss.csv", "\nb1_deg,b2_deg,x_px,y_px,weight\n"));
    snprintf(cmd, sizeof cmd, "%s simulate configs/ess_type_a.ini --unit 3 --quiet --out %s && "
             "%s calibrate --config configs/ess_type_a.ini %s/campaign.csv --quiet --out %s && "
             "%s compensate %s/params.ini docs/examples/lab_ess.csv", test_sunmc(), test_tmp("e3"),
             test_sunmc(), test_tmp("e3"), test_tmp("e3cal"), test_sunmc(), test_tmp("e3cal"));
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s exited %d: %s", cmd, rc, out);
    assert_non_null(strstr(out, "compensated_deg"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(python_loader_agrees_with_summary),
        cmocka_unit_test(example_config_is_valid),
        cmocka_unit_test(lab_templates_are_read),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
