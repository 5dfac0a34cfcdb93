/* toy_family.c - the test-only toy family (toy_family.h): its keys, its
 * deviation list and its sensor_family hooks. */
#include "toy_family.h"
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

static double toy_read_rad(const toy_deviations *d, double a_rad, double noise_arcsec)
{
    return a_rad * (1 + d->scale_pct * FRACTION_PER_PCT) +
           (d->offset_arcsec + noise_arcsec) * RAD_PER_ARCSEC;
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

static int toy_ws_dummy;
static void *toy_ws_alloc(const sunmc_config *c, char *err, size_t errlen) { return &toy_ws_dummy; }
static void toy_ws_free(void *ws) {}

/* Least-squares line through the campaign: p[0] + p[1] alpha (rad). */
static void toy_fit(const sunmc_config *c, const toy_deviations *d, long unit, double p[2])
{
    const toy_config *t = toy_cfg(c);
    rng_stream r;
    rng_stream_init(&r, (uint64_t)c->seed, (uint64_t)unit, RNG_STREAM_CAL_NOISE);
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    long n = grid_n(t->span_deg, t->cal_step_deg);
    for (long i = 0; i < n; i++) {
        double a = (-t->span_deg + (double)i * t->cal_step_deg) * RAD_PER_DEG;
        double y = toy_read_rad(d, a, t->reading_arcsec * rng_normal(&r));
        sx += a;
        sy += y;
        sxx += a * a;
        sxy += a * y;
    }
    p[1] = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    p[0] = (sy - p[1] * sx) / n;
}

static int toy_unit_run(const sunmc_config *c, long unit, void *ws, unit_result *res)
{
    toy_deviations d;
    double p[2];
    deviations_sample(toy_deviation_list, TOY_N_TOL, c, (uint64_t)c->seed, unit, &d);
    memset(res, 0, sizeof *res);
    res->unit = unit;
    deviations_values(toy_deviation_list, TOY_N_TOL, &d, res->dev, UNIT_MAX_DEV);
    toy_fit(c, &d, unit, p);
    res->par[0] = p[0] * ARCSEC_PER_RAD;
    res->par[1] = p[1];
    res->fit_status = UNIT_FIT_OK;

    band_acc before, after;
    band_acc_reset(&before);
    band_acc_reset(&after);
    rng_stream r;
    rng_stream_init(&r, (uint64_t)c->seed, (uint64_t)unit, RNG_STREAM_VAL_NOISE);
    for (long i = 0; i < toy_val_count(c); i++) {
        double a = toy_val_alpha_deg(c, i) * RAD_PER_DEG;
        double y = toy_read_rad(&d, a, toy_cfg(c)->reading_arcsec * rng_normal(&r));
        band_acc_add(&before, &c->bands_deg, fabs(a) * DEG_PER_RAD, y - a);
        band_acc_add(&after, &c->bands_deg, fabs(a) * DEG_PER_RAD, (y - p[0]) / p[1] - a);
    }
    unit_result_set_rms(res, 0, &before, &after, &c->bands_deg, ARCSEC_PER_RAD);
    return SUNMC_OK;
}

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
};
