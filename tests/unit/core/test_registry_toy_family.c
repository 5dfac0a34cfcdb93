/* test_registry_toy_family.c - a third family (tests/toy_family.c, a tiny analytic
 * sensor) registered at run time goes through the registry, the config
 * (its keys, defaults, checks, the reference), run, sweep, budget and the
 * lab commands (simulate, calibrate, compensate), in core and through the
 * commands, with closed-form numbers; and the
 * built-in families' deviation lists keep their stream ids. */
#include "test_util.h"

#include "budget.h"
#include "cli.h"
#include "dss_sensor.h"
#include "ess_sensor.h"
#include "montecarlo.h"
#include "params_io.h"
#include "registry.h"
#include "report.h"
#include "status.h"
#include "sweep.h"
#include "toy_family.h"
#include "units.h"

#include <fcntl.h>
#include <unistd.h>

#define SCALE_PCT 2.0
#define OFFSET_ARCSEC 40.0

static char dir[] = "/tmp/sunmc_test_toy_XXXXXX";
static char ini[300];

static int setup(void **state)
{
    if (sensor_family_register(&toy_family) != 0 || !mkdtemp(dir))
        return -1;
    snprintf(ini, sizeof ini, "%s/toy.ini", dir);
    return test_write_file(ini, "[sensor]\nfamily = toy\n[tolerance]\nscale_pct = 2\n"
                                "scale_pct_dist = fixed\noffset_arcsec = 40\n"
                                "offset_arcsec_dist = fixed\n");
}

static int teardown(void **state)
{
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd);
}

static void build(config_state *st, const char *const *sets, int n)
{
    test_build(st, ini, sets, n);
}

static void expect_error(const char *path, const char *set, const char *needle)
{
    config_state st;
    char err[SUNMC_ERRLEN] = "";
    const char *sets[] = {set};
    assert_int_equal(config_build(&st, path, sets, 1, err, sizeof err), SUNMC_EINPUT);
    if (!strstr(err, needle))
        fail_msg("message '%s' lacks '%s'", err, needle);
}

static void registry_lookup(void **state)
{
    assert_int_equal(sensor_family_count(), 4); /* ess, dss, psd and the toy */
    assert_ptr_equal(sensor_family_find("toy"), &toy_family);
    assert_string_equal(sensor_family_at(0)->name, "ess");
    assert_null(sensor_family_find("nope"));
    assert_null(sensor_family_at(4));
    assert_int_equal(sensor_family_register(&toy_family), -1); /* name taken */
}

static void config_of_the_toy(void **state)
{
    config_state st;
    build(&st, NULL, 0);
    assert_ptr_equal(st.cfg.family, &toy_family);
    assert_string_equal(st.cfg.product, "toy");      /* the family's default of a shared key */
    assert_near(st.cfg.bands_deg.hi[2], 40, 0);
    assert_near(toy_cfg(&st.cfg)->tol.offset_arcsec.value, OFFSET_ARCSEC, 0);
    assert_int_equal(toy_cfg(&st.cfg)->tol.offset_arcsec.dist, DIST_FIXED);
    assert_near(toy_cfg(&st.cfg)->span_deg, 40, 0);
    char where[400];
    snprintf(where, sizeof where, "%s:2", ini);
    assert_string_equal(config_origin_of(&st, config_find("sensor", "family")), where);
    assert_string_equal(config_origin_of(&st, config_find("design", "span_deg")), "default");
    assert_null(config_origin_of(&st, config_find("design", "H_mm"))); /* not a toy key */
    char err[SUNMC_ERRLEN];
    /* the family is fixed once the config is built */
    assert_int_equal(config_set_value(&st, "sensor", "family", "ess", "test", err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "built for toy"));
    assert_int_equal(config_set_value(&st, "sensor", "family", "toy", "test", err, sizeof err),
                     SUNMC_OK);
    config_state_free(&st);
}

static void config_errors(void **state)
{
    expect_error(NULL, "design.span_deg=10", "applies to toy sensors, but sensor.family is ess");
    expect_error(ini, "design.H_mm=5", "applies to ess sensors, but sensor.family is toy");
    expect_error(ini, "sensor.family=nope", "one of ess|dss|psd|toy");
    expect_error(ini, "campaign.step_deg=41", "0.1 to 40 deg");
    /* a family without a thermal model: no operating temperature but the lab's */
    expect_error(ini, "environment.operating_temp_c=20,60", "toy has no thermal model");
    expect_error(ini, "environment.operating_temp_c=-40:120:10", "at most 16");
    config_state st;
    char err[SUNMC_ERRLEN] = "";
    const char *sets[] = {"design.span_deg=10", "campaign.step_deg=20"};
    assert_int_equal(config_build(&st, ini, sets, 2, err, sizeof err), SUNMC_EINPUT);
    /* both values came from --set: the message says so, not the file */
    if (strstr(err, "--set campaign.step_deg, --set design.span_deg: ") != err ||
        !strstr(err, "campaign.step_deg = 20 is more than"))
        fail_msg("validate hook: '%s'", err);
    /* one from the file, one from --set: both origins, in the message's order */
    char narrow[320];
    snprintf(narrow, sizeof narrow, "%s.narrow", ini);
    assert_int_equal(test_write_file(narrow, "[sensor]\nfamily = toy\n[design]\nspan_deg = 10\n"),
                     0);
    const char *one[] = {"campaign.step_deg=20"};
    assert_int_equal(config_build(&st, narrow, one, 1, err, sizeof err), SUNMC_EINPUT);
    char want[400];
    snprintf(want, sizeof want, "--set campaign.step_deg, %s:4: ", narrow);
    if (strstr(err, want) != err)
        fail_msg("validate hook, mixed origins: '%s', want '%s'", err, want);
}

static void reference_lists_the_toy(void **state)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    assert_int_equal(config_write_reference(f), SUNMC_OK);
    fclose(f);
    assert_non_null(strstr(buf, "Values shown are the ESS defaults; where the\n# DSS or PSD or TOY "));
    assert_non_null(strstr(buf, "or toy (a test-only analytic sensor)"));
    assert_non_null(strstr(buf, "#   families: ess, dss, psd, toy; allowed: one of ess|dss|psd|toy\n"));
    assert_non_null(strstr(buf, "; toy default: toy\n# product = ESS type A\n"));
    assert_non_null(strstr(buf, "#   families: toy; allowed: 1 to 80 deg\n# span_deg = 40\n"));
    free(buf);
}

/* RMS (arcsec) over the validation grid in band lo:hi of a*S + O. */
static double before_closed_form(const sunmc_config *c, double lo, double hi, double scale_pct,
                                 double offset_arcsec)
{
    double s2 = 0;
    long n = 0;
    for (long i = 0; i < toy_val_count(c); i++) {
        double a = toy_val_alpha_deg(c, i), x = fabs(a);
        if ((lo == 0 && x <= hi + 1e-9) || (x > lo + 1e-9 && x <= hi + 1e-9)) {
            double e = a * ARCSEC_PER_DEG * scale_pct / 100 + offset_arcsec;
            s2 += e * e;
            n++;
        }
    }
    return sqrt(s2 / (double)n);
}

static void run_in_core(void **state)
{
    config_state st;
    build(&st, NULL, 0);
    const sunmc_config *c = &st.cfg;
    unit_result r[3];
    char err[SUNMC_ERRLEN];
    assert_int_equal(mc_run(c, 0, 3, 2, r, NULL, NULL, err, sizeof err), SUNMC_OK);
    for (int u = 0; u < 3; u++) {
        assert_near(r[u].dev[0], SCALE_PCT, 0);
        assert_near(r[u].dev[1], OFFSET_ARCSEC, 0);
        assert_near(r[u].par[0], OFFSET_ARCSEC, 1e-9);
        assert_near(r[u].par[1], 1 + SCALE_PCT / 100, 1e-12);
        for (int b = 0; b < c->bands_deg.n; b++) {
            double want = before_closed_form(c, c->bands_deg.lo[b], c->bands_deg.hi[b],
                                             SCALE_PCT, OFFSET_ARCSEC);
            assert_near(r[u].rms_before[0][b], want, 1e-9 * want);
            assert_near(r[u].rms_after[0][b], 0, 1e-6);
        }
    }
    config_state_free(&st);
}

/* Blocks for mc_stream's sink: each block's units in order. */
typedef struct {
    unit_result all[16];
    long n, blocks, stop_after;
} block_log;

static int log_block(const unit_result *r, long n, void *ctx, int *stop, char *err, size_t len)
{
    block_log *l = ctx;
    memcpy(&l->all[l->n], r, (size_t)n * sizeof *r);
    l->n += n;
    *stop = ++l->blocks == l->stop_after;
    return SUNMC_OK;
}

/* The most units a stream reported run (its progress callback). */
static void most_done(long done, long total, void *ctx)
{
    long *m = ctx;
    if (done > *m)
        *m = done;
}

/* mc_stream hands units 3..13 over in blocks of 4, 4, 2 in unit order, the
 * same bytes as mc_run; a sink's stop after block 2 ends at 8 units, and no
 * unit past them is run (issue 43: a stream that ran every unit and only
 * stopped handing them over passed). */
static void stream_in_blocks(void **state)
{
    config_state st;
    const char *sets[] = {"run.block_units=4", "noise.reading_arcsec=1"};
    build(&st, sets, 2);
    const sunmc_config *c = &st.cfg;
    unit_result whole[10];
    char err[SUNMC_ERRLEN];
    assert_int_equal(mc_run(c, 3, 13, 2, whole, NULL, NULL, err, sizeof err), SUNMC_OK);
    block_log *l = calloc(1, sizeof *l);
    mc_plan p = {3, 13, c->block_units, 2, log_block, l, NULL, NULL, 0};
    long done = 0;
    assert_int_equal(mc_stream(c, &p, &done, err, sizeof err), SUNMC_OK);
    assert_int_equal(done, 10);
    assert_int_equal(l->blocks, 3);
    for (long u = 0; u < 10; u++)
        assert_int_equal(l->all[u].unit, 3 + u);
    assert_memory_equal(l->all, whole, sizeof whole);
    memset(l, 0, sizeof *l);
    l->stop_after = 2;
    assert_int_equal(mc_stream(c, &p, &done, err, sizeof err), SUNMC_OK);
    assert_int_equal(done, 8);
    assert_int_equal(l->n, 8);
    long ran = 0;
    mc_plan p1 = {3, 13, c->block_units, 1, log_block, l, most_done, &ran, 0};
    memset(l, 0, sizeof *l);
    l->stop_after = 1;
    assert_int_equal(mc_stream(c, &p1, &done, err, sizeof err), SUNMC_OK);
    assert_int_equal(done, 4);
    assert_int_equal(ran, 4);
    free(l);
    config_state_free(&st);
}

/* The statistics accumulated block by block, read part-way and continued,
 * equal those of the whole array. */
static void statistics_in_blocks(void **state)
{
    config_state st;
    const char *sets[] = {"noise.reading_arcsec=1"};
    build(&st, sets, 1);
    const sunmc_config *c = &st.cfg;
    unit_result r[9];
    char err[SUNMC_ERRLEN];
    assert_int_equal(mc_run(c, 0, 9, 1, r, NULL, NULL, err, sizeof err), SUNMC_OK);
    int nr = report_n_rows(c);
    summary_row whole[CONFIG_BANDS_MAX], parts[CONFIG_BANDS_MAX];
    assert_int_equal(report_summarize(c, r, 9, whole), SUNMC_OK);
    report_acc *acc = report_acc_new(c);
    assert_int_equal(report_acc_add(acc, r, 4), SUNMC_OK);
    report_acc_rows(acc, parts);
    assert_int_equal(parts[0].units, 4);
    assert_int_equal(report_acc_add(acc, r + 4, 5), SUNMC_OK);
    report_acc_rows(acc, parts);
    assert_int_equal(report_acc_units(acc), 9);
    assert_memory_equal(parts, whole, (size_t)nr * sizeof *whole);
    report_acc_free(acc);
    config_state_free(&st);
}

static void sweep_in_core(void **state)
{
    config_state st;
    build(&st, NULL, 0);
    sweep_axis ax;
    char err[SUNMC_ERRLEN];
    assert_int_equal(sweep_axis_parse("design.H_mm=4,5", st.cfg.family, &ax, err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "does not apply to this sensor family"));
    assert_int_equal(sweep_axis_parse("tolerance.offset_arcsec=0,80", st.cfg.family, &ax, err,
                                      sizeof err),
                     SUNMC_OK);
    for (long p = 0; p < 2; p++) {
        assert_int_equal(sweep_apply(&st, &ax, 1, p, err, sizeof err), SUNMC_OK);
        unit_result r;
        assert_int_equal(mc_run(&st.cfg, 0, 1, 1, &r, NULL, NULL, err, sizeof err),
                         SUNMC_OK);
        double want = before_closed_form(&st.cfg, 0, 40, SCALE_PCT, ax.v[p]);
        assert_near(r.rms_before[0][2], want, 1e-9 * want);
    }
    config_state_free(&st);
}

static void budget_in_core(void **state)
{
    config_state st;
    build(&st, NULL, 0);
    budget_result *b = calloc(1, sizeof *b);
    char err[SUNMC_ERRLEN];
    assert_int_equal(budget_run(&st.cfg, STUDY_MIN_UNITS, 1, 0, NULL, NULL, b, err, sizeof err), SUNMC_OK);
    assert_int_equal(b->n, 2);
    assert_int_equal(b->band, 2); /* 0:40, the widest */
    assert_string_equal(b->src[0].name, "scale_pct");
    assert_string_equal(b->src[1].name, "offset_arcsec");
    assert_near(b->src[1].alone.before_mean, OFFSET_ARCSEC, 1e-9);
    assert_near(b->src[0].alone.before_mean, before_closed_form(&st.cfg, 0, 40, SCALE_PCT, 0),
                1e-9);
    assert_near(b->all.before_mean, before_closed_form(&st.cfg, 0, 40, SCALE_PCT, OFFSET_ARCSEC),
                1e-9);
    free(b);
    config_state_free(&st);
}

/* Run a command in process (argv as main gets it); its exit status. */
static int command(int (*fn)(int, char **), const char *a1, const char *a2, const char *a3,
                   const char *a4)
{
    char units[] = "--units", n[] = "10", quiet[] = "--quiet", out[] = "--out";
    char *argv[] = {"sunmc", (char *)a1, ini, units, n, quiet, out, (char *)a2, (char *)a3,
                    (char *)a4, NULL};
    int argc = 8 + (a3 != NULL) + (a4 != NULL);
    return fn(argc, argv);
}


static void commands_run_the_toy(void **state)
{
    char out[400], path[500];
    snprintf(out, sizeof out, "%s/run", dir);
    assert_int_equal(command(cmd_run, "run", out, NULL, NULL), 0);
    snprintf(path, sizeof path, "%s/units.tsv", out);
    assert_true(test_file_has(path, "\tscale_pct\toffset_arcsec\tbow_arcsec\tp0_arcsec\tp1\tfit_rms_arcsec\t"));
    snprintf(path, sizeof path, "%s/summary.tsv", out);
    assert_true(test_file_has(path, "toy\ttoy\talpha\t0:20\t"));
    snprintf(path, sizeof path, "%s/config.ini", out);
    assert_true(test_file_has(path, "[design]\nspan_deg = 40  # default\n"));

    snprintf(out, sizeof out, "%s/sweep", dir);
    assert_int_equal(command(cmd_sweep, "sweep", out, "--vary", "tolerance.offset_arcsec=0,8"), 0);
    snprintf(path, sizeof path, "%s/sweep.tsv", out);
    assert_true(test_file_has(path, "tolerance.offset_arcsec\tlabel\taliased\tproduct\t"));

    snprintf(out, sizeof out, "%s/budget", dir);
    assert_int_equal(command(cmd_budget, "budget", out, NULL, NULL), 0);
    snprintf(path, sizeof path, "%s/budget.tsv", out);
    assert_true(test_file_has(path, "\toffset_arcsec\tarcsec\t40\tfixed\t"));
}

/* Run fn(argc, argv) in process with its stdout into file path. */
static int command_to(const char *path, int (*fn)(int, char **), char **argv)
{
    int argc = 0;
    while (argv[argc])
        argc++;
    fflush(stdout);
    int saved = dup(1), fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(saved >= 0 && fd >= 0);
    dup2(fd, 1);
    close(fd);
    int rc = fn(argc, argv);
    fflush(stdout);
    dup2(saved, 1);
    close(saved);
    return rc;
}

/* simulate -> calibrate (the family from the config, no --sensor) ->
 * compensate, through the registry: noise-free, the line is the toy's own
 * (p1 = 1 + scale, p0 = offset) and compensation gives the truth back. */
static void lab_commands_run_the_toy(void **state)
{
    char sim[400], cal[400], csv[500], val[500], params[500], log[500], comp[500];
    snprintf(sim, sizeof sim, "%s/sim", dir);
    snprintf(cal, sizeof cal, "%s/cal", dir);
    snprintf(csv, sizeof csv, "%s/campaign.csv", sim);
    snprintf(val, sizeof val, "%s/validation.csv", sim);
    snprintf(params, sizeof params, "%s/params.ini", cal);
    snprintf(log, sizeof log, "%s/lab.stdout", dir);
    snprintf(comp, sizeof comp, "%s/comp.csv", dir);
    char *sim_argv[] = {"sunmc", "simulate", ini, "--unit", "2", "--out", sim, NULL};
    assert_int_equal(command_to(log, cmd_simulate, sim_argv), 0);
    assert_true(test_file_has(log, "toy unit 2: 17 campaign readings, 25 validation readings"));
    assert_true(test_file_has(csv, "alpha_deg,reading_deg,weight\n-40,"));

    char *cal_argv[] = {"sunmc", "calibrate", "--config", ini, csv, "--out", cal, NULL};
    assert_int_equal(command_to(log, cmd_calibrate, cal_argv), 0);
    assert_true(test_file_has(params, "sensor = toy"));
    params_file *pf = malloc(sizeof *pf);
    char err[SUNMC_ERRLEN];
    double p0, p1;
    assert_int_equal(params_read(params, pf, err, sizeof err), SUNMC_OK);
    assert_int_equal(params_get_double(pf, "parameters", "p0_arcsec", &p0, err, sizeof err), 0);
    assert_int_equal(params_get_double(pf, "parameters", "p1", &p1, err, sizeof err), 0);
    free(pf);
    assert_near(p0, OFFSET_ARCSEC, 1e-9);
    assert_near(p1, 1 + SCALE_PCT / 100, 1e-12);
    char folds[500];
    snprintf(folds, sizeof folds, "%s/crossval.tsv", cal);
    assert_true(test_file_has(folds, "alpha<0") && test_file_has(folds, "alpha>=0"));

    char *comp_argv[] = {"sunmc", "compensate", params, val, NULL};
    assert_int_equal(command_to(comp, cmd_compensate, comp_argv), 0);
    FILE *f = fopen(comp, "r");
    assert_non_null(f);
    char line[256];
    int rows = 0;
    assert_non_null(fgets(line, sizeof line, f));
    assert_string_equal(line, "alpha_deg,reading_deg,truth_deg,compensated_deg\n");
    while (fgets(line, sizeof line, f)) {
        double a, y, t, c;
        assert_int_equal(sscanf(line, "%lf,%lf,%lf,%lf", &a, &y, &t, &c), 4);
        assert_near(c, t, 1e-12);
        rows++;
    }
    fclose(f);
    assert_int_equal(rows, 25);

    /* --sensor must agree with the config's family, naming both. */
    char *bad_argv[] = {"sunmc", "calibrate", "--sensor", "ess", "--config", ini, csv, NULL};
    assert_int_equal(command_to(log, cmd_calibrate, bad_argv), EXIT_BAD_INPUT);
}

/* A family without lab hooks: simulate and calibrate refuse its config
 * (exit 2, naming the family), nothing written. */
static void lab_commands_refuse_a_family_without_lab(void **state)
{
    static sensor_family bare;
    bare = toy_family;
    bare.name = "bare";
    bare.lab = NULL;
    assert_int_equal(sensor_family_register(&bare), 0);
    char cfg[400], out[400], log[400];
    snprintf(cfg, sizeof cfg, "%s/bare.ini", dir);
    snprintf(out, sizeof out, "%s/bare_out", dir);
    snprintf(log, sizeof log, "%s/bare.stdout", dir);
    assert_int_equal(test_write_file(cfg, "[sensor]\nfamily = bare\n"), 0);
    char *sim_argv[] = {"sunmc", "simulate", cfg, "--unit", "0", "--out", out, NULL};
    assert_int_equal(command_to(log, cmd_simulate, sim_argv), EXIT_BAD_INPUT);
    char *cal_argv[] = {"sunmc", "calibrate", "--config", cfg, log, "--out", out, NULL};
    assert_int_equal(command_to(log, cmd_calibrate, cal_argv), EXIT_BAD_INPUT);
    assert_int_equal(access(out, F_OK), -1);
}

/* The built-in lists: stream ids unique and today's, columns counted, and
 * each line has its two config keys. */
static void deviation_lists(void **state)
{
    const struct {
        const deviation_spec *list;
        int n, columns;
        const char *family;
    } lists[] = {{ess_deviation_list, ESS_N_TOL, ESS_N_TOL_COLUMNS, "ess"},
                 {dss_deviation_list, DSS_N_TOL, DSS_N_DEV, "dss"}};
    for (int l = 0; l < 2; l++) {
        const sensor_family *fam = sensor_family_find(lists[l].family);
        int cols = 0;
        for (int i = 0; i < lists[l].n; i++) {
            const deviation_spec *d = &lists[l].list[i];
            assert_int_equal(d->stream, (uint32_t)i); /* today's ids: the list order */
            cols += d->count;
            char dist[80];
            snprintf(dist, sizeof dist, "%s_dist", d->name);
            assert_true(config_is_tolerance(config_find_in(fam, "tolerance", d->name), fam));
            assert_non_null(config_find_in(fam, "tolerance", dist));
        }
        assert_int_equal(cols, lists[l].columns);
    }
    assert_int_equal(ESS_N_DEV, 22);
    assert_string_equal(ess_deviation_names[5], "gain1_pct");
    assert_string_equal(ess_deviation_names[12], "etch4_um");
    assert_string_equal(ess_deviation_names[18], "spacer_cte_ppm_k");
    assert_string_equal(ess_deviation_names[20], "dial_tilt_deg");
    assert_string_equal(ess_deviation_names[21], "roll_measured_arcsec");
    assert_int_equal(DSS_N_DEV, 19);
    assert_string_equal(dss_deviation_names[16], "prnu_pct");
    assert_string_equal(dss_deviation_names[17], "dsnu_pct");
    assert_string_equal(dss_deviation_names[18], "glass_ghost");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(registry_lookup),      cmocka_unit_test(config_of_the_toy),
        cmocka_unit_test(config_errors),        cmocka_unit_test(reference_lists_the_toy),
        cmocka_unit_test(run_in_core),          cmocka_unit_test(sweep_in_core),
        cmocka_unit_test(stream_in_blocks),     cmocka_unit_test(statistics_in_blocks),
        cmocka_unit_test(budget_in_core),       cmocka_unit_test(commands_run_the_toy),
        cmocka_unit_test(lab_commands_run_the_toy),
        cmocka_unit_test(lab_commands_refuse_a_family_without_lab),
        cmocka_unit_test(deviation_lists),
    };
    return cmocka_run_group_tests_name("toy family", tests, setup, teardown);
}
