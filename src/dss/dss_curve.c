/* dss_curve.c - one DSS unit's error maps (the family's curve hooks). */
#include "dss_curve.h"
#include "dss_prior.h"
#include "dss_thermal.h"
#include "thermal.h"
#include "rotation.h"
#include "dss_unit.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>

static const char *const dss_curve_axis_names[2] = {"alpha_deg", "beta_deg"};

/* Indices of the measured angles (the family's angle_names order). */
enum { CURVE_ALPHA = 0, CURVE_BETA, CURVE_TOTAL };

typedef struct {
    dss_calib_workspace *cw;
    dss_unit u;
    dss_calibration cal;
    int fit_ok;
} dss_curve_ws;

static long dss_curve_axis(const sunmc_config *c, int axis, double *values_deg, long max)
{
    const dss_config *dc = dss_cfg(c);
    (void)axis; /* both axes span the same validation grid */
    return grid_values(dc->val_b_min_deg, dc->val_b_max_deg, dc->val_b_step_deg,
                       dc->val_b_offset_deg, values_deg, max);
}

static void dss_curve_free(void *cv);

static void *dss_curve_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    const dss_config *dc = dss_cfg(c);
    size_t n = dss_campaign_size(c);
    dss_curve_ws *w = calloc(1, sizeof *w);
    if (w)
        w->cw = dss_calib_alloc_config(dc, n);
    if (!w || !w->cw) {
        free(w);
        sunmc_fail(err, errlen, SUNMC_ENOMEM,
                   "cannot set up the DSS calibration for a %zu-point campaign (out of memory, "
                   "or fewer points than parameters)", n);
        return NULL;
    }
    /* the same priors as `run`'s units (dss_unit.c) */
    calib_prior prior;
    dss_campaign_angles(c, w->cw->b1_rad, w->cw->b2_rad);
    if (dss_prior_apply(c, w->cw, &prior, err, errlen) != SUNMC_OK) {
        dss_curve_free(w);
        return NULL;
    }
    return w;
}

static void dss_curve_free(void *cv)
{
    dss_curve_ws *w = cv;
    if (!w)
        return;
    dss_calib_free(w->cw);
    free(w);
}

static int dss_curve_prepare(const sunmc_config *c, long unit, double dev_sign, void *cv, int *fit_ok)
{
    dss_curve_ws *w = cv;
    dss_calib_workspace *cw = w->cw;
    dss_deviations dev;
    dss_deviations_sample(c, (uint64_t)c->seed, unit, &dev);
    /* the measured direction scales with the deviations it measures */
    double sun[2];
    dss_sun_measured_arcsec(c, (uint64_t)c->seed, unit, &dev, sun);
    cw->sun_rad[0] = sun[0] * dev_sign * RAD_PER_ARCSEC;
    cw->sun_rad[1] = sun[1] * dev_sign * RAD_PER_ARCSEC;
    deviations_scale(dss_deviation_list, DSS_N_TOL, &dev, dev_sign);
    dss_unit_build(c, &dev, &w->u);
    dss_unit_set_pattern(c, (uint64_t)c->seed, unit, &w->u);
    dss_unit_campaign(c, &w->u, unit, cw->b1_rad, cw->b2_rad, cw->x_px, cw->y_px, cw->weight,
                      NULL, NULL);
    fit_result fr;
    int st = dss_calibrate(cw, c->max_iterations, &w->cal, &fr);
    w->fit_ok = st == SUNMC_OK;
    *fit_ok = w->fit_ok;
    /* the curve at the first operating temperature, when there are any */
    if (thermal_n_temps(c) > 0) {
        dss_deviations at;
        dss_deviations_at_temp(c, &dev, thermal_temp_c(c, 0), &at);
        dss_unit_build(c, &at, &w->u);
        dss_unit_set_pattern(c, (uint64_t)c->seed, unit, &w->u);
    }
    return SUNMC_OK;
}

/* Errors (arcsec) of measured angles (a, b) against the truth (a0, b0). */
static void errors_of(double a, double b, double a0, double b0, double out[UNIT_MAX_ANGLES])
{
    double u[3], v[3];
    sun_vector_of(a, b, u);
    sun_vector_of(a0, b0, v);
    out[CURVE_ALPHA] = (a - a0) * ARCSEC_PER_RAD;
    out[CURVE_BETA] = (b - b0) * ARCSEC_PER_RAD;
    out[CURVE_TOTAL] = angle_between(u, v) * ARCSEC_PER_RAD;
}

static int dss_curve_eval(const sunmc_config *c, const void *cv, double alpha_deg, double beta_deg,
                   double before[UNIT_MAX_ANGLES], double after[UNIT_MAX_ANGLES])
{
    (void)c;
    const dss_curve_ws *w = cv;
    /* Table angles that put the sun at (alpha, beta): invert eq. 3-4. */
    double b2 = -alpha_deg * RAD_PER_DEG;
    double b1 = atan(tan(beta_deg * RAD_PER_DEG) * cos(b2));
    double x, y, a0, b0, am, bm;
    int st = dss_sensor_read(&w->u.sensor, b1, b2, NULL, &x, &y);
    if (st != SUNMC_OK)
        return st;
    dss_sensor_truth(&w->u.sensor, b1, b2, &a0, &b0);
    if ((st = dss_sensor_angles(&w->u.sensor, x, y, &am, &bm)) != SUNMC_OK)
        return st;
    errors_of(am, bm, a0, b0, before);
    for (int a = 0; a <= CURVE_TOTAL; a++)
        after[a] = NAN;
    double ac, bc;
    if (w->fit_ok && dss_compensate(&w->cal, x, y, &ac, &bc) == SUNMC_OK)
        errors_of(ac, bc, a0, b0, after);
    return SUNMC_OK;
}

const family_curve dss_curve = {
    .axis_names = dss_curve_axis_names,
    .axis = dss_curve_axis,
    .alloc = dss_curve_alloc,
    .free = dss_curve_free,
    .prepare = dss_curve_prepare,
    .eval = dss_curve_eval,
};
