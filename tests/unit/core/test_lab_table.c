/* test_lab_table.c - issue 39: the family-neutral look-up table calibration
 * (lab_table.h).  A straight line is tabulated exactly at any step; a
 * smooth function's interpolation error falls as step^2 and stays under
 * h^2 max|f''| / 8; a reading outside the tabulated field is refused, also
 * in a cell the data never visited; the step chosen by the folds is finer
 * for a clean curve than for a noisy one; the size is 4 bytes a node;
 * params.ini round-trips bit for bit and refuses a damaged file at its
 * line; the node limits both sides. */
#include "test_util.h"

#include "lab_table.h"
#include "status.h"

#include <gsl/gsl_errno.h>

#define N1 400

typedef struct {
    double x[2][N1], y[2][N1], w[N1];
    lab_spline_data d;
} data1;

static void make1(data1 *t, int n_out, double (*f)(double), double noise)
{
    memset(t, 0, sizeof *t);
    unsigned long r = 777;
    for (int i = 0; i < N1; i++) {
        for (int j = 0; j < n_out; j++) {
            t->x[j][i] = -1.0 + 2.0 * i / (N1 - 1);
            r = r * 6364136223846793005UL + 1442695040888963407UL;
            double u = (double)(r >> 11) / 9007199254740992.0 - 0.5;
            t->y[j][i] = f(t->x[j][i]) * (j ? -1.0 : 1.0) + noise * u;
        }
        t->w[i] = 1.0;
    }
    t->d = (lab_spline_data){.n = N1, .dims = 1, .n_out = n_out, .x = {t->x[0], t->x[1]},
                             .y = {t->y[0], t->y[1]}, .w = t->w};
}

static double line(double x) { return 0.25 - 1.5 * x; }
static double wave(double x) { return sin(3.0 * x); }

/* Largest |table - f| over a fine sweep of [-1, 1], output 0. */
static double max_err(const lab_table *t, double (*f)(double))
{
    double m = 0;
    for (int k = 0; k <= 2000; k++) {
        double x[2] = {-1.0 + k / 1000.0, -1.0 + k / 1000.0}, y[2];
        assert_int_equal(lab_table_eval(t, x, y), SUNMC_OK);
        m = fmax(m, fabs(y[0] - f(x[0])));
    }
    return m;
}

static void test_line_exact(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    lab_table tb;
    make1(&t, 2, line, 0.0);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e3, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_sample(&tb, &s, LAB_TABLE_MIN_LOG, err, sizeof err), SUNMC_OK);
    assert_int_equal(tb.nodes, 3);
    /* float nodes: exact to the float's rounding */
    assert_true(max_err(&tb, line) < 1e-6);
    double x[2] = {0.3, -0.7}, y[2];
    assert_int_equal(lab_table_eval(&tb, x, y), SUNMC_OK);
    assert_true(fabs(y[1] + line(-0.7)) < 1e-6);
    assert_int_equal((int)lab_table_bytes(&tb), 3 * 2 * 4);
    assert_true(fabs(lab_table_step(&tb, 0) - 1.0) < 1e-12);
}

/* A spline with the other input's cross term (lab_spline.h) has no
 * per-input table: refused, not tabulated with the term at nonsense. */
static void test_cross_spline_refused(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    lab_table tb;
    make1(&t, 2, line, 0.0);
    for (int i = 0; i < N1; i++) /* the other input moves on its own */
        t.x[1][i] = sin(3.0 * t.x[0][i]);
    t.d.cross = 1;
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e3, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_sample(&tb, &s, LAB_TABLE_MIN_LOG, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "cross term"));
}

/* The step halves, the error quarters: linear interpolation's h^2 f''/8. */
static void test_error_falls_as_step_squared(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    lab_table tb;
    make1(&t, 1, wave, 0.0);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-12, 0, err, sizeof err), SUNMC_OK);
    double prev = NAN;
    for (int lg = 3; lg <= 6; lg++) {
        assert_int_equal(lab_table_sample(&tb, &s, lg, err, sizeof err), SUNMC_OK);
        double h = lab_table_step(&tb, 0), e = max_err(&tb, wave);
        /* max |f''| = 9: the bound, and most of it reached */
        assert_true(e <= 9.0 * h * h / 8.0 * 1.001 + 1e-6);
        assert_true(e >= 0.8 * 9.0 * h * h / 8.0);
        if (isfinite(prev))
            assert_true(prev / e > 3.7 && prev / e < 4.3);
        prev = e;
    }
}

static void test_outside_field_refused(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    lab_table tb;
    make1(&t, 1, line, 0.0);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-6, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_sample(&tb, &s, 4, err, sizeof err), SUNMC_OK);
    double y[2], in[1] = {1.0}, past[1] = {nextafter(1.0, 2.0)}, low[1] = {-1.0001},
                 edge[1] = {-1.0}, nan_in[1] = {NAN};
    assert_int_equal(lab_table_eval(&tb, in, y), SUNMC_OK);
    assert_true(fabs(y[0] - line(1.0)) < 1e-6);
    assert_int_equal(lab_table_eval(&tb, edge, y), SUNMC_OK);
    assert_int_equal(lab_table_eval(&tb, past, y), SUNMC_EDOM);
    assert_true(isnan(y[0]));
    assert_int_equal(lab_table_eval(&tb, low, y), SUNMC_EDOM);
    assert_int_equal(lab_table_eval(&tb, nan_in, y), SUNMC_EDOM);
}

/* Two inputs on a grid with a hole: bilinear exact on u v; the hole refused. */
#define G 21
static void test_two_inputs_and_hole(void **state)
{
    static double x0[G * G], x1[G * G], y0[G * G], y1[G * G], w[G * G];
    int n = 0;
    for (int a = 0; a < G; a++)
        for (int b = 0; b < G; b++) {
            double u = -1 + 2.0 * a / (G - 1), v = -1 + 2.0 * b / (G - 1);
            if (fabs(u - 0.5) < 0.3 && fabs(v - 0.5) < 0.3)
                continue;
            x0[n] = u, x1[n] = v;
            y0[n] = 0.1 + u - 0.3 * v + 0.2 * u * v;
            y1[n] = -0.2 + 0.5 * u + v;
            w[n++] = 1;
        }
    lab_spline_data d = {.n = (size_t)n, .dims = 2, .n_out = 2, .x = {x0, x1}, .y = {y0, y1},
                         .w = w};
    lab_spline s;
    lab_table tb;
    char err[256];
    assert_int_equal(lab_spline_fit(&s, &d, 1e-9, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_sample(&tb, &s, LAB_TABLE_MAX_LOG2, err, sizeof err), SUNMC_OK);
    assert_int_equal((int)lab_table_bytes(&tb), 17 * 17 * 2 * 4);
    double x[2] = {-0.55, 0.35}, y[2];
    assert_int_equal(lab_table_eval(&tb, x, y), SUNMC_OK);
    /* bilinear interpolation reproduces 1, u, v, u v */
    assert_true(fabs(y[0] - (0.1 - 0.55 - 0.105 - 0.0385)) < 1e-4);
    assert_true(fabs(y[1] - (-0.2 - 0.275 + 0.35)) < 1e-5);
    double hole[2] = {0.5, 0.5};
    assert_int_equal(lab_table_eval(&tb, hole, y), SUNMC_EDOM);
    assert_true(isnan(y[0]) && isnan(y[1]));
}

static void test_choose_by_folds(void **state)
{
    static data1 t;
    static int fold[N1];
    for (int i = 0; i < N1; i++)
        fold[i] = (i / 5) % 4;
    char err[256];
    lab_spline s;
    lab_table clean, noisy, again;
    double rms, rms2;
    long out;
    make1(&t, 1, wave, 1e-5);
    assert_int_equal(lab_spline_choose(&s, &t.d, fold, 4, &rms, &out, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_choose(&clean, &s, &t.d, fold, 4, &rms, &out, err, sizeof err),
                     SUNMC_OK);
    /* a clean curve: a fine table, its held-out RMS near its interpolation error */
    assert_true(clean.nodes >= 65);
    assert_true(rms < 5e-4);
    make1(&t, 1, wave, 0.4);
    assert_int_equal(lab_spline_choose(&s, &t.d, fold, 4, &rms2, &out, err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(lab_table_choose(&noisy, &s, &t.d, fold, 4, &rms2, &out, err, sizeof err),
                     SUNMC_OK);
    assert_true(noisy.nodes < clean.nodes);
    /* uniform noise of width 0.4: sd 0.115 */
    assert_true(rms2 > 0.1 && rms2 < 0.14);
    assert_int_equal(lab_table_choose(&again, &s, &t.d, fold, 4, &rms, &out, err, sizeof err),
                     SUNMC_OK);
    assert_memory_equal(&again, &noisy, sizeof noisy);
    /* one fold: nothing held out, the finest table */
    assert_int_equal(lab_table_choose(&again, &s, &t.d, fold, 1, &rms, &out, err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(again.nodes, LAB_TABLE_MAX_NODES1);
    assert_true(isnan(rms));
}

/* A bump only one fold's rows see: held out, no refit can know it, so the
 * step's held-out error is large; a refit that saw the fold would hide it. */
static void test_choose_holds_folds_out(void **state)
{
    static data1 t;
    static int fold[N1];
    make1(&t, 1, wave, 0.0);
    for (int i = 0; i < N1; i++) {
        double x = t.x[0][i];
        t.y[0][i] += 0.5 * exp(-((x - 0.4) / 0.03) * ((x - 0.4) / 0.03));
        fold[i] = x >= 0.3 && x <= 0.5 ? 0 : 1 + i % 3;
    }
    char err[256];
    lab_spline s;
    lab_table tb;
    double rms;
    long out;
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-6, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_choose(&tb, &s, &t.d, fold, 4, &rms, &out, err, sizeof err),
                     SUNMC_OK);
    assert_true(rms > 0.02);
}

static void test_node_limits(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    lab_table tb;
    make1(&t, 1, line, 0.0);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_sample(&tb, &s, LAB_TABLE_MIN_LOG - 1, err, sizeof err),
                     SUNMC_EINPUT);
    assert_non_null(strstr(err, "nodes"));
    assert_int_equal(lab_table_sample(&tb, &s, LAB_TABLE_MAX_LOG1, err, sizeof err), SUNMC_OK);
    assert_int_equal(tb.nodes, 257);
    assert_int_equal(lab_table_sample(&tb, &s, LAB_TABLE_MAX_LOG1 + 1, err, sizeof err),
                     SUNMC_EINPUT);
    s.dims = 2;
    assert_int_equal(lab_table_sample(&tb, &s, LAB_TABLE_MAX_LOG2 + 1, err, sizeof err),
                     SUNMC_EINPUT);
}

static void write_params(const lab_table *tb, char **buf)
{
    params_file p;
    params_init(&p);
    assert_int_equal(lab_table_params_fill(tb, &p, "table"), SUNMC_OK);
    size_t len = 0;
    FILE *m = open_memstream(buf, &len);
    params_write(m, &p, "test");
    fclose(m);
}

static void roundtrip(const lab_table *tb)
{
    char *buf = NULL;
    write_params(tb, &buf);
    const char *path = test_tmp("table.ini");
    FILE *f = fopen(path, "w");
    fputs(buf, f);
    fclose(f);
    free(buf);
    params_file q;
    char err[512];
    assert_int_equal(params_read(path, &q, err, sizeof err), SUNMC_OK);
    lab_table back;
    assert_int_equal(lab_table_params_load(&q, "table", &back, err, sizeof err), SUNMC_OK);
    assert_memory_equal(&back, tb, sizeof back);
}

static void damaged(const lab_table *tb, const char *key, const char *to, const char *what)
{
    char *buf = NULL;
    write_params(tb, &buf);
    char from[64];
    snprintf(from, sizeof from, "\n%s ", key);
    char *at = strstr(buf, from);
    assert_non_null(at);
    char *end = strchr(at + 1, '\n');
    const char *path = test_tmp("bad.ini");
    FILE *f = fopen(path, "w");
    fprintf(f, "%.*s\n%s%s", (int)(at - buf), buf, to, end ? end : "\n");
    fclose(f);
    free(buf);
    params_file q;
    char err[512];
    lab_table back;
    assert_int_equal(params_read(path, &q, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_params_load(&q, "table", &back, err, sizeof err), SUNMC_EINPUT);
    if (!strstr(err, what) || !strstr(err, "bad.ini:"))
        fail_msg("%s: %s", key, err);
}

static void test_params_roundtrip(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    lab_table tb;
    make1(&t, 2, wave, 0.01);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-3, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_sample(&tb, &s, 6, err, sizeof err), SUNMC_OK);
    roundtrip(&tb);
    damaged(&tb, "dims", "dims = 3", "dims");
    damaged(&tb, "nodes", "nodes = 64", "nodes");
    damaged(&tb, "nodes", "nodes = 2", "nodes");
    damaged(&tb, "nodes", "nodes = 513", "nodes");
    damaged(&tb, "v1_0", "v1_0 = 1 2", "v1_0");
    damaged(&tb, "v0_1", "v0_1 = x", "v0_1");
    damaged(&tb, "v0_2", "v0_2 = 1e50", "v0_2");
    damaged(&tb, "hi_0", "hi_0 = -5", "hi_0");
    damaged(&tb, "lo_1", "lo_1 = -1\nlo_2 = 1", "lo_2");
    /* a node value a float cannot hold, in a block of the right length */
    lab_table t3;
    assert_int_equal(lab_table_sample(&t3, &s, LAB_TABLE_MIN_LOG, err, sizeof err), SUNMC_OK);
    roundtrip(&t3);
    damaged(&t3, "v0_0", "v0_0 = 1e50 0 0", "v0_0");
    /* dims 2 with its field */
    static double x0[100], x1[100], y0[100], w[100];
    for (int i = 0; i < 100; i++) {
        x0[i] = i % 10, x1[i] = i / 10, y0[i] = x0[i] * x1[i], w[i] = 1;
    }
    lab_spline_data d = {.n = 100, .dims = 2, .n_out = 1, .x = {x0, x1}, .y = {y0}, .w = w};
    assert_int_equal(lab_spline_fit(&s, &d, 1e-3, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_table_sample(&tb, &s, LAB_TABLE_MAX_LOG2, err, sizeof err), SUNMC_OK);
    roundtrip(&tb);
    damaged(&tb, "nodes", "nodes = 33", "nodes");
    damaged(&tb, "field_0", "field_0 = 2", "field_0");
    damaged(&tb, "field_cells", "field_cells = 11", "field_cells");
}

int main(void)
{
    gsl_set_error_handler_off();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_line_exact),
        cmocka_unit_test(test_cross_spline_refused),
        cmocka_unit_test(test_error_falls_as_step_squared),
        cmocka_unit_test(test_outside_field_refused),
        cmocka_unit_test(test_two_inputs_and_hole),
        cmocka_unit_test(test_choose_by_folds),
        cmocka_unit_test(test_choose_holds_folds_out),
        cmocka_unit_test(test_node_limits),
        cmocka_unit_test(test_params_roundtrip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
