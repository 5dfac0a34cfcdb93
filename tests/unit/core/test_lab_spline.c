/* test_lab_spline.c - issue 39: the family-neutral spline calibration
 * (lab_spline.h).  A cubic B-spline reproduces a polynomial of degree <= 3
 * (unpenalised; a straight line at any smoothing), a sine to a stated error
 * and to the cubic's order, h^4, as the knots double;
 * a reading outside the calibrated field is refused, also inside the range
 * but in a cell the data never visited; the smoothing chosen by the folds
 * follows the noise; params.ini round-trips bit for bit and refuses a
 * damaged file at its line; the fit is deterministic. */
#include "test_util.h"

#include "lab_spline.h"
#include "status.h"

#include <gsl/gsl_errno.h>

#define N1 200

/* x in [-1, 1], y[j] = f_j(x) (j < n_out), one input per output. */
typedef struct {
    double x[2][N1], y[2][N1], w[N1];
    lab_spline_data d;
} data1;

static void make1(data1 *t, int n_out, double (*f)(double, int), double noise)
{
    memset(t, 0, sizeof *t);
    unsigned long r = 12345;
    for (int i = 0; i < N1; i++) {
        for (int j = 0; j < n_out; j++) {
            t->x[j][i] = -1.0 + 2.0 * i / (N1 - 1);
            r = r * 6364136223846793005UL + 1442695040888963407UL;
            double u = (double)(r >> 11) / 9007199254740992.0 - 0.5;
            t->y[j][i] = f(t->x[j][i], j) + noise * u;
        }
        t->w[i] = 1.0;
    }
    t->d = (lab_spline_data){.n = N1, .dims = 1, .n_out = n_out, .x = {t->x[0], t->x[1]},
                             .y = {t->y[0], t->y[1]}, .w = t->w};
}

static double cubic(double x, int j) { return j ? 0.3 - 2 * x : 0.1 + 0.5 * x - 0.7 * x * x + 0.4 * x * x * x; }
static double line(double x, int j) { return 0.2 - 1.5 * x; }
static double wave(double x, int j) { return sin(3.0 * x); }

static double max_err(const lab_spline *s, double (*f)(double, int), int n_out)
{
    double m = 0;
    for (int k = 0; k <= 400; k++) {
        double x[2] = {-1.0 + k / 200.0, -1.0 + k / 200.0}, y[2];
        assert_int_equal(lab_spline_eval(s, x, y), SUNMC_OK);
        for (int j = 0; j < n_out; j++)
            m = fmax(m, fabs(y[j] - f(x[j], j)));
    }
    return m;
}

static void test_polynomial_exact(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    make1(&t, 2, cubic, 0.0);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-14, 1, err, sizeof err), SUNMC_OK);
    assert_true(max_err(&s, cubic, 2) < 1e-9);
    /* 50 rows per coefficient of 4: the knot count follows the rows */
    assert_int_equal(s.nbreak, N1 / LAB_SPLINE_ROWS_PER_COEF - 2);
    /* at no penalty every coefficient counts */
    assert_true(fabs(s.edf[0] - s.n_coef) < 1e-3);
    /* a straight line at any smoothing, with 2 degrees of freedom at the largest */
    make1(&t, 1, line, 0.0);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e6, 1, err, sizeof err), SUNMC_OK);
    assert_true(max_err(&s, line, 1) < 1e-9);
    assert_true(s.edf[0] > 2.0 && s.edf[0] < 2.5);
}

static void test_sine_to_stated_error(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    make1(&t, 1, wave, 0.0);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-12, 1, err, sizeof err), SUNMC_OK);
    /* knot spacing h = 2/47: the cubic's error is of order h^4 f''''/384 */
    assert_true(max_err(&s, wave, 1) < 1e-6);
    /* heavy smoothing flattens it: not the sine any more */
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e4, 1, err, sizeof err), SUNMC_OK);
    assert_true(max_err(&s, wave, 1) > 0.1);
}

/* The knot spacing halved (rows 4 (nbreak + 2): 12 then 23 breakpoints
 * over [-1, 1]), a cubic's error on the sine falls as h^4: about 16. */
static void test_sine_order_as_knots_double(void **state)
{
    static double x[100], y[100], w[100];
    double e[2];
    const int rows[2] = {56, 100}, nbreak[2] = {12, 23};
    for (int t = 0; t < 2; t++) {
        for (int i = 0; i < rows[t]; i++) {
            x[i] = -1.0 + 2.0 * i / (rows[t] - 1);
            y[i] = sin(3.0 * x[i]);
            w[i] = 1.0;
        }
        lab_spline_data d = {.n = (size_t)rows[t], .dims = 1, .n_out = 1, .x = {x}, .y = {y},
                             .w = w};
        lab_spline s;
        char err[256];
        assert_int_equal(lab_spline_fit(&s, &d, 1e-14, 0, err, sizeof err), SUNMC_OK);
        assert_int_equal(s.nbreak, nbreak[t]);
        e[t] = max_err(&s, wave, 1);
    }
    assert_true(e[0] / e[1] > 10.0 && e[0] / e[1] < 25.0);
}

static void test_outside_field_refused(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    make1(&t, 1, line, 0.0);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-6, 0, err, sizeof err), SUNMC_OK);
    double y[2], in[1] = {1.0}, past[1] = {nextafter(1.0, 2.0)}, low[1] = {-1.0001};
    assert_int_equal(lab_spline_eval(&s, in, y), SUNMC_OK);
    assert_int_equal(lab_spline_eval(&s, past, y), SUNMC_EDOM);
    assert_true(isnan(y[0]));
    assert_int_equal(lab_spline_eval(&s, low, y), SUNMC_EDOM);
}

/* Two inputs on a grid with a hole: a reading in the hole is refused. */
#define G 21
static void test_two_inputs_and_hole(void **state)
{
    static double x0[G * G], x1[G * G], y0[G * G], y1[G * G], w[G * G];
    int n = 0;
    for (int a = 0; a < G; a++)
        for (int b = 0; b < G; b++) {
            double u = -1 + 2.0 * a / (G - 1), v = -1 + 2.0 * b / (G - 1);
            if (fabs(u - 0.5) < 0.3 && fabs(v - 0.5) < 0.3)
                continue; /* the hole */
            x0[n] = u, x1[n] = v;
            y0[n] = 0.1 + u - 0.3 * v + 0.2 * u * v;
            y1[n] = -0.2 + 0.5 * u + v;
            w[n++] = 1;
        }
    lab_spline_data d = {.n = (size_t)n, .dims = 2, .n_out = 2, .x = {x0, x1}, .y = {y0, y1},
                         .w = w};
    lab_spline s;
    char err[256];
    assert_int_equal(lab_spline_fit(&s, &d, 1e-3, 1, err, sizeof err), SUNMC_OK);
    double x[2] = {-0.55, 0.35}, y[2];
    assert_int_equal(lab_spline_eval(&s, x, y), SUNMC_OK);
    /* u v is linear along each input: the penalty leaves it (almost) free */
    assert_true(fabs(y[0] - (0.1 - 0.55 - 0.105 - 0.0385)) < 1e-4);
    assert_true(fabs(y[1] - (-0.2 - 0.275 + 0.35)) < 1e-9);
    double hole[2] = {0.5, 0.5};
    assert_int_equal(lab_spline_eval(&s, hole, y), SUNMC_EDOM);
}

static double noisy_wave(double x, int j) { return sin(3.0 * x); }

/* Folds of alternate blocks of 20 rows: the smoothing chosen, held-out RMS
 * near the noise, and fewer degrees of freedom at more noise. */
static void test_choose_by_folds(void **state)
{
    static data1 t;
    static int fold[N1];
    for (int i = 0; i < N1; i++)
        fold[i] = (i / 5) % 4;
    char err[256];
    lab_spline s, s2;
    double rms, rms2;
    long out;
    make1(&t, 1, noisy_wave, 0.02);
    assert_int_equal(lab_spline_choose(&s, &t.d, fold, 4, &rms, &out, err, sizeof err), SUNMC_OK);
    /* uniform noise of width 0.02: sd 0.0058 */
    assert_true(rms > 0.004 && rms < 0.009);
    make1(&t, 1, noisy_wave, 0.4);
    assert_int_equal(lab_spline_choose(&s2, &t.d, fold, 4, &rms2, &out, err, sizeof err),
                     SUNMC_OK);
    assert_true(s2.edf[0] < s.edf[0]);
    assert_true(s2.smooth > s.smooth);
    /* deterministic */
    lab_spline s3;
    assert_int_equal(lab_spline_choose(&s3, &t.d, fold, 4, &rms, &out, err, sizeof err), SUNMC_OK);
    assert_memory_equal(&s2, &s3, sizeof s2);
}

static void test_refusals(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    make1(&t, 1, line, 0.0);
    for (int i = 0; i < N1; i++)
        t.x[0][i] = 0.5;
    assert_int_equal(lab_spline_fit(&s, &t.d, 1, 0, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "does not vary"));
    make1(&t, 1, line, 0.0);
    t.d.n_out = 3;
    assert_int_equal(lab_spline_fit(&s, &t.d, 1, 0, err, sizeof err), SUNMC_EINPUT);
    make1(&t, 1, line, 0.0);
    t.d.n = 3; /* fewest: 2 breakpoints' worth, 4 rows */
    assert_int_equal(lab_spline_fit(&s, &t.d, 1, 0, err, sizeof err), SUNMC_EINPUT);
    t.d.n = 4;
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-3, 0, err, sizeof err), SUNMC_OK);
    assert_int_equal(s.nbreak, LAB_SPLINE_MIN_BREAK);
}

/* The cross term (dims 1, two outputs): single-axis sweeps whose other
 * ratio moves with the swept one (cross-talk), outputs y0 = F0(x0) +
 * G0(x1), y1 = F1(x1) + G1(x0).  With the term, a cubic F and a linear G
 * are reproduced (the term's penalty leaves a line free at any smoothing);
 * without it, the cross-talk stays in the error. */
#define NX 160
typedef struct {
    double x[2][NX], y[2][NX], w[NX];
    lab_spline_data d;
} datax;

static double f0(double x) { return 0.1 + 0.5 * x - 0.7 * x * x + 0.4 * x * x * x; }
static double f1(double x) { return -0.2 + 0.8 * x + 0.3 * x * x * x; }
static double g0(double x) { return 0.3 * x; }
static double g1(double x) { return 0.1 - 0.2 * x; }

static void make_cross(datax *t, int cubic_f)
{
    memset(t, 0, sizeof *t);
    for (int i = 0; i < NX; i++) {
        double u = -1.0 + 2.0 * (i % (NX / 2)) / (NX / 2 - 1);
        int beta = i >= NX / 2; /* the first half an alpha sweep, then a beta sweep */
        t->x[0][i] = beta ? 0.15 * u * u : u;
        t->x[1][i] = beta ? u : 0.2 * u * u - 0.05;
        double a = cubic_f ? f0(t->x[0][i]) : 0.1 + 0.5 * t->x[0][i];
        double b = cubic_f ? f1(t->x[1][i]) : -0.2 + 0.8 * t->x[1][i];
        t->y[0][i] = a + g0(t->x[1][i]);
        t->y[1][i] = b + g1(t->x[0][i]);
        t->w[i] = 1.0;
    }
    t->d = (lab_spline_data){.n = NX, .dims = 1, .n_out = 2, .cross = 1,
                             .x = {t->x[0], t->x[1]}, .y = {t->y[0], t->y[1]}, .w = t->w};
}

static double rows_err(const lab_spline *s, const datax *t)
{
    double m = 0;
    for (int i = 0; i < NX; i++) {
        double x[2] = {t->x[0][i], t->x[1][i]}, y[2];
        assert_int_equal(lab_spline_eval(s, x, y), SUNMC_OK);
        m = fmax(m, fmax(fabs(y[0] - t->y[0][i]), fabs(y[1] - t->y[1][i])));
    }
    return m;
}

static void test_cross_term(void **state)
{
    static datax t;
    char err[256];
    lab_spline s;
    make_cross(&t, 1);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-12, 1, err, sizeof err), SUNMC_OK);
    assert_int_equal(s.cross, 1);
    assert_int_equal(s.n_coef, s.nbreak + LAB_SPLINE_ORDER - 2 + LAB_SPLINE_CROSS_COEF);
    assert_true(rows_err(&s, &t) < 1e-8);
    /* off the sweeps, the additive model's value: F0(0.5) + G0(0.5) */
    double x[2] = {0.5, 0.5}, y[2];
    assert_int_equal(lab_spline_eval(&s, x, y), SUNMC_OK);
    assert_true(fabs(y[0] - f0(0.5) - g0(0.5)) < 1e-6);
    assert_true(fabs(y[1] - f1(0.5) - g1(0.5)) < 1e-6);
    /* lines at the largest smoothing: F and G straight, both free */
    make_cross(&t, 0);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e6, 1, err, sizeof err), SUNMC_OK);
    assert_true(rows_err(&s, &t) < 1e-8);
    /* without the term the other input's share is an error */
    make_cross(&t, 1);
    t.d.cross = 0;
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-12, 1, err, sizeof err), SUNMC_OK);
    assert_int_equal(s.cross, 0);
    assert_true(rows_err(&s, &t) > 1e-2);
    /* only for one input per output and two outputs */
    t.d.cross = 1;
    t.d.n_out = 1;
    assert_int_equal(lab_spline_fit(&s, &t.d, 1, 0, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "cross term"));
    t.d.n_out = 2;
    t.d.dims = 2;
    assert_int_equal(lab_spline_fit(&s, &t.d, 1, 0, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "cross term"));
}

static void roundtrip(const lab_spline *s)
{
    params_file p;
    params_init(&p);
    assert_int_equal(lab_spline_params_fill(s, &p, "spline"), SUNMC_OK);
    const char *path = test_tmp("spline.ini");
    FILE *f = fopen(path, "w");
    params_write(f, &p, "test");
    fclose(f);
    params_file q;
    char err[512];
    assert_int_equal(params_read(path, &q, err, sizeof err), SUNMC_OK);
    lab_spline back;
    assert_int_equal(lab_spline_params_load(&q, "spline", &back, err, sizeof err), SUNMC_OK);
    assert_memory_equal(back.coef, s->coef, sizeof s->coef);
    assert_memory_equal(back.cell, s->cell, sizeof s->cell);
    assert_true(back.lo[0] == s->lo[0] && back.hi[0] == s->hi[0] && back.edf[0] == s->edf[0]);
    assert_int_equal(back.n_coef, s->n_coef);
    assert_int_equal(back.cross, s->cross);
}

/* Write the spline's params with the line of key replaced by `to`;
 * expect a refusal naming what, at the file's line. */
static void damaged(const lab_spline *s, const char *key, const char *to, const char *what)
{
    params_file p;
    params_init(&p);
    assert_int_equal(lab_spline_params_fill(s, &p, "spline"), SUNMC_OK);
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    params_write(m, &p, "test");
    fclose(m);
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
    lab_spline back;
    assert_int_equal(params_read(path, &q, err, sizeof err), SUNMC_OK);
    assert_int_equal(lab_spline_params_load(&q, "spline", &back, err, sizeof err), SUNMC_EINPUT);
    if (!strstr(err, what) || !strstr(err, "bad.ini:"))
        fail_msg("%s: %s", key, err);
}

static void test_params_roundtrip(void **state)
{
    static data1 t;
    char err[256];
    lab_spline s;
    make1(&t, 2, cubic, 0.01);
    assert_int_equal(lab_spline_fit(&s, &t.d, 1e-3, 1, err, sizeof err), SUNMC_OK);
    roundtrip(&s);
    damaged(&s, "dims", "dims = 3", "dims");
    damaged(&s, "c1_0", "c1_0 = 1 2", "c1_0");
    damaged(&s, "c0_1", "c0_1 = x", "c0_1");
    damaged(&s, "smoothing", "smoothing = 1\nsmoothness = 1", "smoothness");
    damaged(&s, "hi_0", "hi_0 = -5", "hi_0");
    damaged(&s, "breakpoints", "breakpoints = 301", "breakpoints");
    /* dims 2 with its field */
    static double x0[100], x1[100], y0[100], w[100];
    for (int i = 0; i < 100; i++) {
        x0[i] = i % 10, x1[i] = i / 10, y0[i] = x0[i] * x1[i], w[i] = 1;
    }
    lab_spline_data d = {.n = 100, .dims = 2, .n_out = 1, .x = {x0, x1}, .y = {y0}, .w = w};
    assert_int_equal(lab_spline_fit(&s, &d, 1e-3, 1, err, sizeof err), SUNMC_OK);
    roundtrip(&s);
    damaged(&s, "field_0", "field_0 = 2", "field_0");
    /* the right length, a cell neither 0 nor 1 */
    char line[64] = "field_0 = ";
    size_t at = strlen(line);
    for (int c = 0; c < s.nbreak - 1; c++)
        line[at++] = c ? '1' : '2';
    line[at] = '\0';
    damaged(&s, "field_0", line, "field_0");
    damaged(&s, "breakpoints", "breakpoints = 12", "breakpoints");
    /* the cross term: written when on, its coefficients counted; 1 only,
     * and only for dims 1 with two outputs */
    static datax t2;
    make_cross(&t2, 1);
    assert_int_equal(lab_spline_fit(&s, &t2.d, 1e-3, 1, err, sizeof err), SUNMC_OK);
    roundtrip(&s);
    damaged(&s, "cross", "cross = 2", "cross");
    damaged(&s, "cross", "cross = 0", "cross");
    damaged(&s, "outputs", "outputs = 1", "cross");
    damaged(&s, "c1_3", "c1_3 = 1", "c1_3"); /* 52 coefficients: 4 blocks, the last short */
}

int main(void)
{
    gsl_set_error_handler_off();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_polynomial_exact),
        cmocka_unit_test(test_sine_to_stated_error),
        cmocka_unit_test(test_sine_order_as_knots_double),
        cmocka_unit_test(test_outside_field_refused),
        cmocka_unit_test(test_two_inputs_and_hole),
        cmocka_unit_test(test_choose_by_folds),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_params_roundtrip),
        cmocka_unit_test(test_cross_term),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
