/* ess_curve.c - one ESS unit's error curves (the family's curve hooks). */
#include "ess_curve.h"
#include "ess_prior.h"
#include "ess_thermal.h"
#include "thermal.h"
#include "ess_unit.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const ess_curve_axis_names[2] = {"alpha_deg", "beta_deg"};

typedef struct {
    ess_calib_workspace *cw;
    ess_unit u;
    ess_model m;
    int fit_ok;
} ess_curve_ws;

static long ess_curve_axis(const sunmc_config *c, int axis, double *values_deg, long max)
{
    const ess_config *ec = ess_cfg(c);
    if (axis == 1)
        return list_values(&ec->val_beta_deg, values_deg, max);
    return grid_values(ec->val_alpha_min_deg, ec->val_alpha_max_deg, ec->val_alpha_step_deg,
                       ec->val_alpha_offset_deg, values_deg, max);
}

static void ess_curve_free(void *cv);

static void *ess_curve_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    size_t n = ess_campaign_size(c);
    if (n <= ESS_NP) {
        sunmc_fail(err, errlen, SUNMC_EINPUT,
                   "campaign has %zu points, fewer than the %d parameters to fit", n, ESS_NP + 1);
        return NULL;
    }
    ess_curve_ws *w = calloc(1, sizeof *w);
    if (w)
        w->cw = ess_calib_alloc_fix(n, ess_cfg(c)->cal_model,
                                    ess_cfg(c)->sun_y_mode == ESS_SUN_Y_MEASURED);
    if (!w || !w->cw) {
        free(w);
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for a %zu-point campaign", n);
        return NULL;
    }
    /* the same priors as `run`'s units (ess_unit.c) */
    calib_prior prior;
    ess_campaign_angles(c, w->cw);
    if (ess_prior_apply(c, w->cw, &prior, err, errlen) != SUNMC_OK) {
        ess_curve_free(w);
        return NULL;
    }
    return w;
}

static void ess_curve_free(void *cv)
{
    ess_curve_ws *w = cv;
    if (!w)
        return;
    ess_calib_free(w->cw);
    free(w);
}

static int ess_curve_prepare(const sunmc_config *c, long unit, double dev_sign, void *cv, int *fit_ok)
{
    const ess_config *ec = ess_cfg(c);
    ess_curve_ws *w = cv;
    ess_deviations dev;
    ess_deviations_sample(c, (uint64_t)c->seed, unit, &dev);
    /* the measured tilt scales with the deviations, as the measured roll */
    double sun_y_meas = ess_sun_y_measured_arcsec(c, (uint64_t)c->seed, unit, &dev) * dev_sign;
    deviations_scale(ess_deviation_list, ESS_N_TOL, &dev, dev_sign);
    dev.roll_measured_arcsec *= dev_sign; /* derived: the measurement of install_x */
    ess_unit_build(c, &dev, &w->u);
    int gross;
    ess_unit_campaign(c, &w->u, unit, w->cw, NULL, &gross);
    fit_result fr;
    w->cw->sun_y_rad = sun_y_meas * RAD_PER_ARCSEC;
    int st = ess_calibrate(w->cw, ec->design.theta0_deg * RAD_PER_DEG,
                           dev.roll_measured_arcsec * RAD_PER_ARCSEC, ec->alias_threshold,
                           c->max_iterations, &w->m, &fr);
    w->fit_ok = st == SUNMC_OK;
    *fit_ok = w->fit_ok;
    /* the curve at the first operating temperature, when there are any */
    if (thermal_n_temps(c) > 0) {
        ess_deviations at;
        ess_deviations_at_temp(c, &dev, thermal_temp_c(c, 0), &at);
        ess_unit_build(c, &at, &w->u);
    }
    return SUNMC_OK;
}

static int ess_curve_eval(const sunmc_config *c, const void *cv, double alpha_deg, double beta_deg,
                   double before[UNIT_MAX_ANGLES], double after[UNIT_MAX_ANGLES])
{
    const ess_curve_ws *w = cv;
    double raw, truth, comp;
    int st = ess_unit_read(&w->u, alpha_deg * RAD_PER_DEG, beta_deg * RAD_PER_DEG, NULL, &raw,
                           &truth);
    if (st != SUNMC_OK)
        return st;
    /* The coarse code picked the wrong fine period: a gross error, not a
     * point of the curve (the validation drops it the same way). */
    if (ess_is_gross(raw, truth, ess_half_period_rad(c)))
        return SUNMC_EDOM;
    before[0] = (raw - truth) * DEG_PER_RAD;
    after[0] = NAN;
    if (w->fit_ok && ess_model_compensate(&w->m, raw, &comp) == SUNMC_OK)
        after[0] = (comp - truth) * DEG_PER_RAD;
    return SUNMC_OK;
}

const family_curve ess_curve = {
    .axis_names = ess_curve_axis_names,
    .axis = ess_curve_axis,
    .alloc = ess_curve_alloc,
    .free = ess_curve_free,
    .prepare = ess_curve_prepare,
    .eval = ess_curve_eval,
};
