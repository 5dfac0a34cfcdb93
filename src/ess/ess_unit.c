/* ess_unit.c - the ESS family: sample -> physical sensor -> turntable
 * campaign -> fit -> validation, for one unit. */
#include "ess_unit.h"
#include "ess_curve.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const ess_par_names[ESS_N_PAR] = {
    "a", "b", "c", "k_deg", "t_rad", "fit_install_y_arcsec", "fit_install_z_arcsec",
    "fit_sun_y_arcsec"};
static const char *const ess_angle_names[] = {"alpha"};

void ess_unit_build(const sunmc_config *c, const ess_deviations *dev, ess_unit *u)
{
    u->dev = *dev;
    ess_sensor_init(&u->sensor, &ess_cfg(c)->design, dev);
    mat3 rx, ry, rz, t;
    rot_x(dev->install_x_arcsec * RAD_PER_ARCSEC, rx);
    rot_y(dev->install_y_arcsec * RAD_PER_ARCSEC, ry);
    rot_z(dev->install_z_arcsec * RAD_PER_ARCSEC, rz);
    mat3_mul(rx, ry, t);
    mat3_mul(t, rz, u->R_install);
    sun_direction(dev->sun_x_arcsec * RAD_PER_ARCSEC, dev->sun_y_arcsec * RAD_PER_ARCSEC, u->v_sun);
}

int ess_unit_read(const ess_unit *u, double alpha_rad, double beta_rad,
                  const double row_noise[ESS_FINE_ROWS], double *raw_rad, double *truth_rad)
{
    mat3 rx, ry, m;
    rot_x(alpha_rad, rx);
    rot_y(beta_rad, ry);
    mat3_mul(rx, ry, m);
    double w[3], s[3];
    mat3_vec(m, u->v_sun, w);
    mat3_vec(u->R_install, w, s);
    *truth_rad = atan2(s[1], s[2]);
    return ess_sensor_output(&u->sensor, s, row_noise, raw_rad);
}

size_t ess_campaign_size(const sunmc_config *c)
{
    const ess_config *ec = ess_cfg(c);
    return (size_t)grid_count(ec->cal_alpha_min_deg, ec->cal_alpha_max_deg, ec->cal_alpha_step_deg,
                              0) *
           (size_t)ec->cal_beta_deg.n;
}

void ess_row_noise(const sunmc_config *c, rng_stream *r, double noise[ESS_FINE_ROWS])
{
    double sigma = ess_cfg(c)->noise.row_current_pct * FRACTION_PER_PCT;
    for (int m = 0; m < ESS_FINE_ROWS; m++)
        noise[m] = sigma * rng_normal(r);
}

int ess_campaign_reading(const sunmc_config *c, const ess_unit *u, rng_stream *r, double a_rad,
                         double b_rad, double *a_true_rad, double *b_true_rad,
                         double *incidence_rad, double *raw_rad)
{
    /* The table's true angles differ from the recorded ones by the encoder
     * error; the readings at one position are averaged. */
    double enc = c->encoder_arcsec * RAD_PER_ARCSEC;
    *a_true_rad = a_rad + enc * rng_normal(r);
    *b_true_rad = b_rad + enc * rng_normal(r);
    double sum = 0;
    int seen = 1;
    *incidence_rad = 0;
    for (int rep = 0; rep < c->cal_repeats; rep++) {
        double noise[ESS_FINE_ROWS], raw;
        ess_row_noise(c, r, noise);
        if (ess_unit_read(u, *a_true_rad, *b_true_rad, noise, &raw, incidence_rad) != SUNMC_OK)
            seen = 0;
        else
            sum += raw;
    }
    *raw_rad = seen ? sum / c->cal_repeats : 0.0;
    return seen;
}

int ess_validation_reading(const sunmc_config *c, const ess_unit *u, rng_stream *r, double a_rad,
                           double b_rad, double *raw_rad, double *truth_rad)
{
    double noise[ESS_FINE_ROWS];
    ess_row_noise(c, r, noise);
    *raw_rad = 0;
    *truth_rad = 0;
    if (ess_unit_read(u, a_rad, b_rad, noise, raw_rad, truth_rad) != SUNMC_OK)
        return ESS_READING_UNSEEN;
    if (fabs(*raw_rad - *truth_rad) > 0.5 * ess_cfg(c)->design.theta0_deg * RAD_PER_DEG)
        return ESS_READING_GROSS;
    return ESS_READING_OK;
}

void ess_unit_campaign(const sunmc_config *c, const ess_unit *u, long unit,
                       ess_calib_workspace *cw, int *gross)
{
    const ess_config *ec = ess_cfg(c);
    long na = grid_count(ec->cal_alpha_min_deg, ec->cal_alpha_max_deg, ec->cal_alpha_step_deg, 0);
    double half_period = 0.5 * ec->design.theta0_deg * RAD_PER_DEG;
    rng_stream r;
    rng_stream_init(&r, (uint64_t)c->seed, (uint64_t)unit, RNG_STREAM_CAL_NOISE);
    *gross = 0;
    size_t i = 0;
    for (int k = 0; k < ec->cal_beta_deg.n; k++)
        for (long j = 0; j < na; j++, i++) {
            double a = (ec->cal_alpha_min_deg + (double)j * ec->cal_alpha_step_deg) * RAD_PER_DEG;
            double b = ec->cal_beta_deg.v[k] * RAD_PER_DEG;
            double a_true, b_true, incidence;
            int seen = ess_campaign_reading(c, u, &r, a, b, &a_true, &b_true, &incidence,
                                            &cw->raw_rad[i]);
            cw->alpha_rad[i] = a;
            cw->beta_rad[i] = b;
            /* A lab drops a reading that is off the table angle by more than
             * half a fine period: the coarse code picked the wrong period. */
            cw->weight[i] = (seen && fabs(cw->raw_rad[i] - a) < half_period) ? 1.0 : 0.0;
            if (cw->weight[i] == 0.0)
                (*gross)++;
        }
}

void ess_model_report(const ess_model *m, double out[ESS_N_PAR])
{
    double k, t;
    ess_model_kt(m, &k, &t);
    out[0] = m->p[ESS_P_A];
    out[1] = m->p[ESS_P_B];
    out[2] = m->p[ESS_P_C];
    out[3] = k * DEG_PER_RAD;
    out[4] = t;
    out[5] = m->p[ESS_P_INST_Y] * ARCSEC_PER_RAD;
    out[6] = m->p[ESS_P_INST_Z] * ARCSEC_PER_RAD;
    out[7] = m->p[ESS_P_SUN_Y] * ARCSEC_PER_RAD;
}

/* ---- the family ---- */

static int ess_n_angles(const sunmc_config *c) { return 1; }

static void ess_model_label(const sunmc_config *c, char *buf, size_t len)
{
    snprintf(buf, len, "ESS paper eq. 9/12/13 (a, b, c, k, t; d = 1) + turntable installation, "
                       "roll fixed at its measurement");
}

static int ess_dev_columns(const sunmc_config *c, const char **names, int max)
{
    for (int i = 0; i < ESS_N_DEV && i < max; i++)
        names[i] = ess_deviation_names[i];
    return ESS_N_DEV;
}

static int ess_par_columns(const sunmc_config *c, const char **names, int max)
{
    for (int i = 0; i < ESS_N_PAR && i < max; i++)
        names[i] = ess_par_names[i];
    return ESS_N_PAR;
}

static void *ess_ws_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    size_t n = ess_campaign_size(c);
    if (n <= ESS_NP) {
        sunmc_fail(err, errlen, SUNMC_EINPUT,
                   "campaign has %zu points, fewer than the %d parameters to fit", n, ESS_NP + 1);
        return NULL;
    }
    ess_calib_workspace *cw = ess_calib_alloc(n);
    if (!cw)
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for a %zu-point campaign", n);
    return cw;
}

static void ess_ws_free(void *ws) { ess_calib_free(ws); }

/* Score the unit on the validation grid and betas, with fresh noise (RMS
 * before and after), and again on the same points without reading noise
 * (the systematic part of the after RMS). */
static void ess_unit_validate(const sunmc_config *c, const ess_unit *u, const ess_model *m,
                              long unit, unit_result *res)
{
    const ess_config *ec = ess_cfg(c);
    static const double no_noise[ESS_FINE_ROWS] = {0};
    band_acc before, after, after_sys;
    band_acc_reset(&before);
    band_acc_reset(&after);
    band_acc_reset(&after_sys);
    rng_stream r;
    rng_stream_init(&r, (uint64_t)c->seed, (uint64_t)unit, RNG_STREAM_VAL_NOISE);
    long na = grid_count(ec->val_alpha_min_deg, ec->val_alpha_max_deg, ec->val_alpha_step_deg,
                         ec->val_alpha_offset_deg);
    double half_period = 0.5 * ec->design.theta0_deg * RAD_PER_DEG;
    for (int k = 0; k < ec->val_beta_deg.n; k++)
        for (long j = 0; j < na; j++) {
            double a = (ec->val_alpha_min_deg + ec->val_alpha_offset_deg +
                        (double)j * ec->val_alpha_step_deg) *
                       RAD_PER_DEG;
            double b = ec->val_beta_deg.v[k] * RAD_PER_DEG;
            double raw, truth, comp;
            int st_read = ess_validation_reading(c, u, &r, a, b, &raw, &truth);
            if (st_read == ESS_READING_UNSEEN)
                continue;
            if (st_read == ESS_READING_GROSS) {
                res->gross_val++;
                continue;
            }
            double abs_deg = fabs(truth) * DEG_PER_RAD;
            band_acc_add(&before, &c->bands_deg, abs_deg, raw - truth);
            if (res->fit_status != UNIT_FIT_OK)
                continue;
            if (ess_model_compensate(m, raw, &comp) != SUNMC_OK) {
                res->fit_status = UNIT_FIT_FAILED;
                continue;
            }
            band_acc_add(&after, &c->bands_deg, abs_deg, comp - truth);
            if (ess_unit_read(u, a, b, no_noise, &raw, &truth) == SUNMC_OK &&
                fabs(raw - truth) <= half_period && ess_model_compensate(m, raw, &comp) == SUNMC_OK)
                band_acc_add(&after_sys, &c->bands_deg, abs_deg, comp - truth);
        }
    unit_result_set_rms(res, 0, &before, &after, &c->bands_deg, DEG_PER_RAD);
    unit_result_set_sys(res, 0, &after_sys, &c->bands_deg, DEG_PER_RAD);
}

static int ess_unit_run(const sunmc_config *c, long unit, void *ws, unit_result *res)
{
    const ess_config *ec = ess_cfg(c);
    ess_calib_workspace *cw = ws;
    double t = unit_clock();
    ess_deviations dev;
    ess_unit u;
    ess_deviations_sample(c, (uint64_t)c->seed, unit, &dev);
    ess_unit_build(c, &dev, &u);

    memset(res, 0, sizeof *res);
    res->unit = unit;
    ess_deviations_values(&dev, res->dev);

    ess_unit_campaign(c, &u, unit, cw, &res->gross_cal);
    unit_phase_end(res, UNIT_PHASE_CAMPAIGN, &t);

    ess_model m;
    fit_result fr;
    double theta0 = ec->design.theta0_deg * RAD_PER_DEG;
    int st = ess_calibrate(cw, theta0, dev.roll_measured_arcsec * RAD_PER_ARCSEC,
                           ec->alias_threshold, c->max_iterations, &m, &fr);
    res->fit_status = st == SUNMC_OK ? UNIT_FIT_OK : UNIT_FIT_FAILED;
    res->fit_gsl_status = fr.status;
    res->fit_iterations = (int)fr.iterations;
    res->alias_weak = cw->alias.n_weak;
    ess_model_report(&m, res->par);
    res->fit_rms = ess_calib_residual_rms(cw, &m) * DEG_PER_RAD;
    unit_phase_end(res, UNIT_PHASE_FIT, &t);

    ess_unit_validate(c, &u, &m, unit, res);
    unit_phase_end(res, UNIT_PHASE_VALIDATION, &t);
    return SUNMC_OK;
}

const sensor_family ess_family = {
    .name = "ess",
    .description = "encoded sun sensor",
    .keys = ess_keys,
    .defaults = ess_defaults,
    .validate = ess_config_validate,
    .alias_term = "the fine-code term",
    .rms_unit = "deg",
    .arcsec_per_rms_unit = ARCSEC_PER_DEG,
    .model_label = ess_model_label,
    .n_angles = ess_n_angles,
    .angle_names = ess_angle_names,
    .dev_columns = ess_dev_columns,
    .par_columns = ess_par_columns,
    .workspace_alloc = ess_ws_alloc,
    .workspace_free = ess_ws_free,
    .unit_run = ess_unit_run,
    /* curve hooks: ess_curve.c */
    .curve_axis_names = ess_curve_axis_names,
    .curve_axis = ess_curve_axis,
    .curve_alloc = ess_curve_alloc,
    .curve_free = ess_curve_free,
    .curve_prepare = ess_curve_prepare,
    .curve_eval = ess_curve_eval,
};
