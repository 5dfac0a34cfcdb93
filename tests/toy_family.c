/* toy_family.c - the test-only toy family (toy_family.h): its keys, its
 * deviation list and its sensor_family hooks. */
#include "toy_family.h"
#include "verdict.h"
#include "deviation.h"
#include "rng.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define OFF(field) offsetof(toy_config, field)
#define TOY_GRID_EPS 1e-9

_Static_assert(sizeof(toy_config) <= sizeof(family_config), "toy_config must fit");

static const config_key toy_keys[] = {
    {"design", "span_deg", KEY_DOUBLE, "deg", "40", 1, 80, NULL, OFF(span_deg),
     "half range of the toy's turntable"},
    TOY_DEVIATIONS(DEVIATION_X_KEYS)
    {"noise", "reading_arcsec", KEY_DOUBLE, "arcsec", "0", 0, 100, NULL, OFF(reading_arcsec),
     "sigma of a reading"},
    {"campaign", "step_deg", KEY_DOUBLE, "deg", "5", 0.1, 40, NULL, OFF(cal_step_deg),
     "turntable step of the campaign"},
    {"validation", "step_deg", KEY_DOUBLE, "deg", "3.3", 0.1, 40, NULL, OFF(val_step_deg),
     "step of the validation grid"},
    {NULL}};

static const config_default toy_defaults[] = {
    {"sensor", "product", "toy"}, {"report", "bands_deg", "0:20, 20:40, 0:40"}, {NULL}};

TOY_DEVIATIONS(DEVIATION_X_COLUMNS)

static const deviation_spec toy_deviation_list[] = {
#define TOY_X_SPEC(name, unit, count, stream, ...)                                                \
    DEVIATION_SPEC(toy_config, toy_deviations, name, count, stream),
    TOY_DEVIATIONS(TOY_X_SPEC)
#undef TOY_X_SPEC
};
#define TOY_N_TOL ((int)(sizeof toy_deviation_list / sizeof toy_deviation_list[0]))

static int toy_validate(const sunmc_config *c, char *err, size_t errlen)
{
    const toy_config *t = toy_cfg(c);
    if (t->cal_step_deg > t->span_deg)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "campaign.step_deg = %g is more than design.span_deg = %g",
                          t->cal_step_deg, t->span_deg);
    return SUNMC_OK;
}

static long grid_n(double span, double step)
{
    return (long)floor(2 * span / step + TOY_GRID_EPS) + 1;
}

long toy_val_count(const sunmc_config *c)
{
    return grid_n(toy_cfg(c)->span_deg, toy_cfg(c)->val_step_deg);
}

double toy_val_alpha_deg(const sunmc_config *c, long i)
{
    return -toy_cfg(c)->span_deg + (double)i * toy_cfg(c)->val_step_deg;
}

double toy_read_rad(const toy_deviations *d, double a_rad, double noise_arcsec)
{
    return a_rad * (1 + d->scale_pct * FRACTION_PER_PCT) +
           (d->offset_arcsec + d->bow_arcsec * a_rad * a_rad + noise_arcsec) * RAD_PER_ARCSEC;
}

static int toy_n_angles(const sunmc_config *c) { return 1; }

static void toy_model_label(const sunmc_config *c, char *buf, size_t len)
{
    snprintf(buf, len, "straight line");
}

static int toy_dev_columns(const sunmc_config *c, const char **names, int max)
{
    return deviations_columns(toy_deviation_list, TOY_N_TOL, names, max);
}

static const char *const toy_par_names[] = {"p0_arcsec", "p1"};

static int toy_par_columns(const sunmc_config *c, const char **names, int max)
{
    for (int i = 0; i < 2 && i < max; i++)
        names[i] = toy_par_names[i];
    return 2;
}

long toy_cal_count(const sunmc_config *c)
{
    return grid_n(toy_cfg(c)->span_deg, toy_cfg(c)->cal_step_deg);
}

/* One walk over a grid of n alphas from -span in steps of step_deg: the
 * readings, noise from stream `stream` of (seed, unit). */
static void toy_walk(const sunmc_config *c, const toy_deviations *d, long unit, uint32_t stream,
                     double step_deg, long n, double *a_rad, double *y_rad)
{
    rng_stream r;
    rng_stream_init(&r, (uint64_t)c->seed, (uint64_t)unit, stream);
    for (long i = 0; i < n; i++) {
        a_rad[i] = (-toy_cfg(c)->span_deg + (double)i * step_deg) * RAD_PER_DEG;
        y_rad[i] = toy_read_rad(d, a_rad[i], toy_cfg(c)->reading_arcsec * rng_normal(&r));
    }
}

void toy_campaign(const sunmc_config *c, const toy_deviations *d, long unit, double *a_rad,
                  double *y_rad)
{
    toy_walk(c, d, unit, RNG_STREAM_CAL_NOISE, toy_cfg(c)->cal_step_deg, toy_cal_count(c), a_rad,
             y_rad);
}

void toy_validation(const sunmc_config *c, const toy_deviations *d, long unit, double *a_rad,
                    double *y_rad)
{
    toy_walk(c, d, unit, RNG_STREAM_VAL_NOISE, toy_cfg(c)->val_step_deg, toy_val_count(c), a_rad,
             y_rad);
}

void toy_line_fit(long n, const double *a, const double *y, const double *w, double p[2])
{
    double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (long i = 0; i < n; i++) {
        double wi = w ? w[i] : 1.0;
        sw += wi;
        sx += wi * a[i];
        sy += wi * y[i];
        sxx += wi * a[i] * a[i];
        sxy += wi * a[i] * y[i];
    }
    p[1] = (sw * sxy - sx * sy) / (sw * sxx - sx * sx);
    p[0] = (sy - p[1] * sx) / sw;
}

void toy_sample(const sunmc_config *c, long unit, toy_deviations *d)
{
    deviations_sample(toy_deviation_list, TOY_N_TOL, c, (uint64_t)c->seed, unit, d);
}

/* The thread's workspace: one grid's alphas and readings, and one unit's
 * validation readings. */
static void *toy_ws_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    long n = toy_cal_count(c) > toy_val_count(c) ? toy_cal_count(c) : toy_val_count(c);
    double *w = malloc((2 * (size_t)n + (size_t)toy_val_count(c)) * sizeof *w);
    if (!w)
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    return w;
}

static void toy_ws_free(void *ws) { free(ws); }

/* The toy's readings (family.h: unit_read): the validation walk's
 * readings, one double a grid point. */
static size_t toy_readings_bytes(const sunmc_config *c)
{
    return (size_t)toy_val_count(c) * sizeof(double);
}

static int toy_unit_read(const sunmc_config *c, long unit, void *ws, void *rd)
{
    toy_deviations d;
    toy_sample(c, unit, &d);
    toy_validation(c, &d, unit, ws, rd);
    return SUNMC_OK;
}

static int toy_unit_finish(const sunmc_config *c, long unit, void *ws, const void *rd,
                           unit_result *res)
{
    toy_deviations d;
    const double *yv = rd;
    double p[2], *a = ws, *y = a + (toy_cal_count(c) > toy_val_count(c) ? toy_cal_count(c)
                                                                            : toy_val_count(c));
    toy_sample(c, unit, &d);
    memset(res, 0, sizeof *res);
    res->unit = unit;
    deviations_values(toy_deviation_list, TOY_N_TOL, &d, res->dev, UNIT_MAX_DEV);
    toy_campaign(c, &d, unit, a, y);
    toy_line_fit(toy_cal_count(c), a, y, NULL, p);
    res->par[0] = p[0] * ARCSEC_PER_RAD;
    res->par[1] = p[1];
    res->fit_status = UNIT_FIT_OK;

    band_acc before, after;
    band_acc_reset(&before);
    band_acc_reset(&after);
    band_tail tail; /* the spec's order statistic (verdict.h) */
    band_tail_reset(&tail, verdict_tail_keep(c));
    long points[CONFIG_BANDS_MAX] = {0};
    for (long i = 0; i < toy_val_count(c); i++) {
        double ai = toy_val_alpha_deg(c, i) * RAD_PER_DEG, e = (yv[i] - p[0]) / p[1] - ai;
        unsigned m = band_mask(&c->bands_deg, fabs(ai) * DEG_PER_RAD);
        band_count_chunk(points, c->bands_deg.n, 1, &m);
        band_acc_add(&before, &c->bands_deg, fabs(ai) * DEG_PER_RAD, yv[i] - ai);
        band_acc_add(&after, &c->bands_deg, fabs(ai) * DEG_PER_RAD, e);
        band_tail_add_mask(&tail, c->bands_deg.n, m, e * e);
    }
    unit_result_set_rms(res, 0, &before, &after, &c->bands_deg, ARCSEC_PER_RAD);
    unit_result_set_stat(res, c, 0, &after, &tail, points, ARCSEC_PER_RAD);
    return SUNMC_OK;
}

/* A unit: its readings into the workspace's second half, then the rest. */
static int toy_unit_run(const sunmc_config *c, long unit, void *ws, unit_result *res)
{
    long n = toy_cal_count(c) > toy_val_count(c) ? toy_cal_count(c) : toy_val_count(c);
    double *rd = (double *)ws + 2 * n;
    toy_unit_read(c, unit, ws, rd);
    return toy_unit_finish(c, unit, ws, rd, res);
}

/* The readings depend on the validation's step, the span, the tolerances,
 * the reading noise and the seed, not on the campaign's step. */
static const char *const toy_readings_ignore[] = {"campaign", NULL};

/* ---- curve: one unit's error over the validation grid (axis 1 has one
 * value, the toy has no second axis). ---- */
static const char *const toy_curve_axis_names[] = {"alpha_deg", "beta_deg"};

static long toy_curve_axis(const sunmc_config *c, int axis, double *values_deg, long max)
{
    long n = axis == 0 ? toy_val_count(c) : 1;
    for (long i = 0; i < n && i < max; i++)
        values_deg[i] = axis == 0 ? toy_val_alpha_deg(c, i) : 0;
    return n;
}

typedef struct {
    toy_deviations d;
    double p[2];
} toy_curve_unit;

static void *toy_curve_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    toy_curve_unit *u = calloc(1, sizeof *u);
    if (!u)
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    return u;
}

static int toy_curve_prepare(const sunmc_config *c, long unit, double dev_sign, void *cv,
                             int *fit_ok)
{
    toy_curve_unit *u = cv;
    long n = toy_cal_count(c);
    double *a = malloc(2 * (size_t)n * sizeof *a);
    if (!a)
        return SUNMC_ENOMEM;
    toy_sample(c, unit, &u->d);
    deviations_scale(toy_deviation_list, TOY_N_TOL, &u->d, dev_sign);
    toy_campaign(c, &u->d, unit, a, a + n);
    toy_line_fit(n, a, a + n, NULL, u->p);
    free(a);
    *fit_ok = 1;
    return SUNMC_OK;
}

static int toy_curve_eval(const sunmc_config *c, const void *cv, double a0_deg, double a1_deg,
                          double before[UNIT_MAX_ANGLES], double after[UNIT_MAX_ANGLES])
{
    const toy_curve_unit *u = cv;
    double a = a0_deg * RAD_PER_DEG, y = toy_read_rad(&u->d, a, 0);
    before[0] = (y - a) * ARCSEC_PER_RAD;
    after[0] = ((y - u->p[0]) / u->p[1] - a) * ARCSEC_PER_RAD;
    return SUNMC_OK;
}

static const family_curve toy_curve = {
    .axis_names = toy_curve_axis_names,
    .axis = toy_curve_axis,
    .alloc = toy_curve_alloc,
    .free = free,
    .prepare = toy_curve_prepare,
    .eval = toy_curve_eval,
};

static const char *const toy_angle_names[] = {"alpha"};

const sensor_family toy_family = {
    .name = "toy",
    .description = "a test-only analytic sensor",
    .rms_unit = "arcsec",
    .arcsec_per_rms_unit = 1.0,
    .keys = toy_keys,
    .defaults = toy_defaults,
    .validate = toy_validate,
    .model_label = toy_model_label,
    .n_angles = toy_n_angles,
    .angle_names = toy_angle_names,
    .dev_columns = toy_dev_columns,
    .par_columns = toy_par_columns,
    .workspace_alloc = toy_ws_alloc,
    .workspace_free = toy_ws_free,
    .unit_run = toy_unit_run,
    .readings_bytes = toy_readings_bytes,
    .unit_read = toy_unit_read,
    .unit_finish = toy_unit_finish,
    .readings_ignore = toy_readings_ignore,
    .deviations = toy_deviation_list,
    .n_deviations = TOY_N_TOL,
    .curve = &toy_curve,
    .lab = &toy_lab, /* toy_lab.c */
};
