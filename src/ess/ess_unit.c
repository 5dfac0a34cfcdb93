/* ess_unit.c - the ESS family: sample -> physical sensor -> turntable
 * campaign -> fit -> validation, for one unit. */
#include "ess_unit.h"
#include "ess_score.h"
#include "ess_thermal.h"
#include "thermal.h"
#include "ess_curve.h"
#include "ess_lab.h"
#include "ess_grid.h"
#include "ess_prior.h"
#include "lab_onboard.h"
#include "family.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* units.tsv's fitted-parameter columns: fit_ and the parameter's name
 * (docs/outputs.md), apart from the deviation columns of the same names. */
static const char *const ess_par_names[ESS_N_PAR] = {
    "fit_a", "fit_b", "fit_c", "fit_k_deg", "fit_t_rad", "fit_install_y_arcsec",
    "fit_install_z_arcsec", "fit_sun_y_arcsec"};
/* The units.tsv columns of the extended model's own parameters: fit_ and
 * the names of ess_param_names from ESS_NP on, in degrees. */
#define ESS_N_PAR_EXT (ESS_N_PAR + ESS_NP_EXT - ESS_NP)
static const char *const ess_par_names_ext[ESS_NP_EXT - ESS_NP] = {
    "fit_ks_cos4_deg", "fit_kc_cos4_deg", "fit_ks_cos8_deg", "fit_kc_cos8_deg", "fit_k1s_deg",
    "fit_k1c_deg",     "fit_k2s_deg",     "fit_k2c_deg",     "fit_k2s_cos2_deg", "fit_k2c_cos2_deg"};
static const char *const ess_angle_names[] = {"alpha"};

void ess_unit_build(const sunmc_config *c, const ess_deviations *dev, ess_unit *u)
{
    u->dev = *dev;
    ess_sensor_init(&u->sensor, &ess_cfg(c)->design, dev);
    mat3 rx, ry, rz, t;
    rot_x(dev->install_x_arcsec * RAD_PER_ARCSEC, rx);
    rot_y(-(dev->install_y_arcsec * RAD_PER_ARCSEC), ry); /* active, as the table */
    rot_z(dev->install_z_arcsec * RAD_PER_ARCSEC, rz);
    mat3_mul(rx, ry, t);
    mat3_mul(t, rz, u->R_install);
    sun_direction(dev->sun_x_arcsec * RAD_PER_ARCSEC, dev->sun_y_arcsec * RAD_PER_ARCSEC, u->v_sun);
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

double ess_half_period_rad(const sunmc_config *c)
{
    return 0.5 * ess_cfg(c)->design.theta0_deg * RAD_PER_DEG;
}

void ess_unit_campaign(const sunmc_config *c, const ess_unit *u, long unit,
                       ess_calib_workspace *cw, ess_campaign_point *truth, int *gross)
{
    rng_stream r;
    unit_stream_init(&r, c, unit, RNG_STREAM_CAL_NOISE);
    ess_campaign_angles(c, cw);
    ess_campaign_read(c, u, &r, cw, truth, gross);
}

void ess_campaign_angles(const sunmc_config *c, ess_calib_workspace *cw)
{
    const ess_config *ec = ess_cfg(c);
    long na = grid_count(ec->cal_alpha_min_deg, ec->cal_alpha_max_deg, ec->cal_alpha_step_deg, 0);
    size_t i = 0;
    for (int k = 0; k < ec->cal_beta_deg.n; k++)
        for (long j = 0; j < na; j++, i++) {
            cw->alpha_rad[i] = (ec->cal_alpha_min_deg + (double)j * ec->cal_alpha_step_deg) *
                               RAD_PER_DEG;
            cw->beta_rad[i] = ec->cal_beta_deg.v[k] * RAD_PER_DEG;
        }
}

void ess_campaign_read(const sunmc_config *c, const ess_unit *u, rng_stream *r,
                       ess_calib_workspace *cw, ess_campaign_point *truth, int *gross)
{
    double half_period = ess_half_period_rad(c);
    *gross = 0;
    for (size_t i0 = 0; i0 < cw->n; i0 += ESS_CHUNK) {
        ess_campaign_point chunk[ESS_CHUNK];
        size_t np = cw->n - i0 < ESS_CHUNK ? cw->n - i0 : ESS_CHUNK;
        ess_campaign_point *p = truth ? truth + i0 : chunk;
        ess_campaign_batch(c, u, r, np, cw->alpha_rad + i0, cw->beta_rad + i0, p);
        for (size_t q = 0; q < np; q++) {
            cw->raw_rad[i0 + q] = p[q].raw_rad;
            int keep = p[q].seen && !ess_is_gross(p[q].raw_rad, cw->alpha_rad[i0 + q], half_period);
            cw->weight[i0 + q] = keep ? 1.0 : 0.0;
            *gross += !keep;
        }
    }
}

size_t ess_validation_size(const sunmc_config *c)
{
    const ess_config *ec = ess_cfg(c);
    return (size_t)grid_count(ec->val_alpha_min_deg, ec->val_alpha_max_deg, ec->val_alpha_step_deg,
                              ec->val_alpha_offset_deg) *
           (size_t)ec->val_beta_deg.n;
}

int ess_val_alloc(const sunmc_config *c, ess_val_readings *v)
{
    const ess_config *ec = ess_cfg(c);
    size_t n = ess_validation_size(c);
    long na = grid_count(ec->val_alpha_min_deg, ec->val_alpha_max_deg, ec->val_alpha_step_deg,
                         ec->val_alpha_offset_deg);
    v->n = n;
    v->alpha_rad = vm_alloc(n);
    v->beta_rad = vm_alloc(n);
    v->raw_rad = malloc((n + 1) * sizeof(double));
    v->raw0_rad = malloc((n + 1) * sizeof(double));
    v->truth_rad = malloc((n + 1) * sizeof(double));
    v->status = malloc((n + 1) * sizeof(int));
    v->trig.ca = vm_alloc(n);
    v->trig.sa = vm_alloc(n);
    v->trig.cb = vm_alloc(n);
    v->trig.sb = vm_alloc(n);
    if (!(v->alpha_rad && v->beta_rad && v->raw_rad && v->raw0_rad && v->truth_rad && v->status &&
          v->trig.ca && v->trig.sa && v->trig.cb && v->trig.sb)) {
        ess_val_free(v);
        return SUNMC_ENOMEM;
    }
    for (size_t i = 0; i < n; i++) {
        v->alpha_rad[i] = (ec->val_alpha_min_deg + ec->val_alpha_offset_deg +
                           (double)(i % (size_t)na) * ec->val_alpha_step_deg) *
                          RAD_PER_DEG;
        v->beta_rad[i] = ec->val_beta_deg.v[i / (size_t)na] * RAD_PER_DEG;
    }
    ess_table_trig_fill(n, v->alpha_rad, v->beta_rad, &v->trig);
    return SUNMC_OK;
}

void ess_val_free(ess_val_readings *v)
{
    free(v->alpha_rad);
    free(v->beta_rad);
    free(v->raw_rad);
    free(v->raw0_rad);
    free(v->truth_rad);
    free(v->status);
    free(v->trig.ca);
    free(v->trig.sa);
    free(v->trig.cb);
    free(v->trig.sb);
    memset(v, 0, sizeof *v);
}

void ess_unit_read_validation(const sunmc_config *c, const ess_unit *u, long unit,
                         ess_val_readings *v)
{
    rng_stream r;
    unit_stream_init(&r, c, unit, RNG_STREAM_VAL_NOISE);
    ess_validation_batch(c, u, &r, v->n, &v->trig, v->raw_rad, v->raw0_rad, v->truth_rad,
                         v->status);
}

void ess_model_report(const ess_model *m, double out[ESS_N_PAR_MAX])
{
    for (int j = ESS_NP; j < m->np; j++)
        out[ESS_N_PAR + j - ESS_NP] = m->p[j] * DEG_PER_RAD;
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

/* The random inputs besides the tolerances (family.h).  Encoder and row
 * noise of the campaign share one stream, so sensitivity sees them as one
 * input (the campaign's noise, which reaches the result through the fit);
 * the validation's row noise is the sensor's repeatability. */
static const char *const ess_cal_noise_keys[] = {"noise.row_current_pct", "noise.encoder_arcsec",
                                                 NULL};
static const char *const ess_val_noise_keys[] = {"noise.row_current_pct", NULL};
static const char *const ess_roll_keys[] = {"calibration.roll_sigma_arcsec", NULL};
static const char *const ess_sun_y_keys[] = {"calibration.sun_y_sigma_arcsec", NULL};
/* The sun tilt's measurement is an input only when the tilt is measured. */
static int ess_sun_y_measured(const sunmc_config *c)
{
    return ess_cfg(c)->sun_y_mode == ESS_SUN_Y_MEASURED;
}
static const family_noise ess_random_noise[] = {
    {"campaign_noise", RNG_STREAM_CAL_NOISE, ess_cal_noise_keys, NULL, 1},
    {"validation_noise", RNG_STREAM_VAL_NOISE, ess_val_noise_keys, NULL, 0},
    {"roll_measurement", RNG_STREAM_ALIGNMENT, ess_roll_keys, NULL, 1},
    {"sun_y_measurement", RNG_STREAM_SUN_Y, ess_sun_y_keys, ess_sun_y_measured, 1},
    {NULL, 0, NULL, NULL, 0}};

static int ess_n_angles(const sunmc_config *c) { return 1; }

static void ess_model_label(const sunmc_config *c, char *buf, size_t len)
{
    const char *fixed = ess_sun_y_measured(c) ? "roll and sun-simulator tilt toward Y fixed at "
                                                "their measurements"
                                              : "roll fixed at its measurement";
    int model = ess_cfg(c)->cal_model;
    if (model == ESS_MODEL_SPLINE || model == ESS_MODEL_TABLE)
        snprintf(buf, len, "%s of the true angle over the measured one (1-D; its fit_ columns "
                           "are the nominal paper model's, which gives the truth), %s",
                 model == ESS_MODEL_TABLE ? "look-up table (linear, the spline's values at its "
                                            "nodes)"
                                          : "penalised cubic B-spline",
                 fixed);
    else if (model == ESS_MODEL_EXTENDED)
        snprintf(buf, len, "extended: ESS paper eq. 12/13 (a, b, c; d = 1), the fine period's 1st "
                           "and 2nd harmonics, the 4th (eq. 7 exact) with cos^4, cos^8 incidence "
                           "terms + turntable installation, %s", fixed);
    else
        snprintf(buf, len, "ESS paper eq. 9/12/13 (a, b, c, k, t; d = 1) + turntable "
                           "installation, %s%s", fixed,
                 model == ESS_MODEL_HYBRID ? "; a spline of its residual over the measured angle"
                                           : "");
}

static int ess_dev_columns(const sunmc_config *c, const char **names, int max)
{
    for (int i = 0; i < ESS_N_DEV && i < max; i++)
        names[i] = ess_deviation_names[i];
    return ESS_N_DEV;
}

static int ess_par_columns(const sunmc_config *c, const char **names, int max)
{
    int n = ess_cfg(c)->cal_model == ESS_MODEL_EXTENDED ? ESS_N_PAR_EXT : ESS_N_PAR;
    for (int i = 0; i < n && i < max; i++)
        names[i] = i < ESS_N_PAR ? ess_par_names[i] : ess_par_names_ext[i - ESS_N_PAR];
    return n;
}

/* A unit's readings (family.h: unit_read, unit_rd_block): for each
 * validation it reads (thermal_n_reads), the raw readings with and without
 * noise, the truths and the statuses of the validation grid's n points,
 * one block each. */
#define ESS_RD_ARRAYS 3

static size_t ess_readings_bytes(const sunmc_config *c)
{
    return unit_rd_bytes(c, ess_validation_size(c), ESS_RD_ARRAYS);
}

/* Block k of readings rd as validation readings (the grid's angles and
 * their trig from grid). */
static ess_val_readings ess_rd_view(const ess_val_readings *grid, const void *rd, int k)
{
    ess_val_readings v = *grid;
    double *b = unit_rd_block(rd, grid->n, ESS_RD_ARRAYS, k);
    v.raw_rad = b;
    v.raw0_rad = b + grid->n;
    v.truth_rad = b + 2 * grid->n;
    v.status = unit_rd_flags(b, grid->n, ESS_RD_ARRAYS);
    return v;
}

/* A thread's workspace: the campaign's fit, the validation grid and one
 * unit's readings. */
typedef struct {
    ess_calib_workspace *cw;
    ess_val_readings val;
    calib_prior prior; /* calibration.priors = tolerances: set on cw's fit */
    double *rd;        /* ess_readings_bytes */
    lab_onboard ob;    /* calibration.onboard: its table built once, reused */
} ess_ws;

static void ess_ws_free(void *p)
{
    ess_ws *w = p;
    if (!w)
        return;
    ess_calib_free(w->cw);
    ess_val_free(&w->val);
    free(w->rd);
    lab_onboard_free(&w->ob);
    free(w);
}

/* The fit's workspace, the validation arrays (5 doubles and a status a
 * point) and the readings. */
static double ess_ws_bytes(const sunmc_config *c)
{
    size_t n = ess_campaign_size(c);
    int kind = ess_cfg(c)->cal_model;
    double jfull = ess_sun_y_measured(c) ? (double)sizeof(double) * (double)ess_model_np(kind) *
                                               (double)(n + (size_t)ess_calib_prior_rows(kind))
                                         : 0.0;
    return ess_calib_bytes(n, kind) + jfull +
           (double)ess_validation_size(c) * (5.0 * sizeof(double) + sizeof(int)) +
           (double)ess_readings_bytes(c);
}

static void *ess_ws_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    size_t n = ess_campaign_size(c);
    int kind = ess_cfg(c)->cal_model, fix = ess_sun_y_measured(c);
    int np = ess_model_np(kind) - fix;
    if (n <= (size_t)np) {
        sunmc_fail(err, errlen, SUNMC_EINPUT,
                   "campaign has %zu points, fewer than the %d parameters to fit", n, np + 1);
        return NULL;
    }
    ess_ws *w = calloc(1, sizeof *w);
    if (!w || !(w->cw = ess_calib_alloc_fix(n, kind, fix)) || ess_val_alloc(c, &w->val) != SUNMC_OK ||
        !(w->rd = malloc(ess_readings_bytes(c)))) {
        ess_ws_free(w);
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for a %zu-point campaign", n);
        return NULL;
    }
    ess_campaign_angles(c, w->cw);
    if (ess_prior_apply(c, w->cw, &w->prior, err, errlen) != SUNMC_OK ||
        lab_onboard_mc_init(&w->ob, c, err, errlen) != SUNMC_OK) {
        ess_ws_free(w);
        return NULL;
    }
    return w;
}

/* The unit's validation readings into rd (family.h): the lab's, then at
 * each operating temperature other than the lab's its deviations at that
 * temperature, rebuilt (thermal_validate_all's order). */
static int ess_unit_take_readings(const sunmc_config *c, long unit, void *ws, void *rd)
{
    const ess_ws *w = ws;
    ess_deviations dev, dev_t;
    ess_unit u;
    ess_deviations_sample(c, (uint64_t)c->seed, unit, &dev);
    ess_unit_build(c, &dev, &u);
    ess_val_readings v = ess_rd_view(&w->val, rd, 0);
    ess_unit_read_validation(c, &u, unit, &v);
    for (int k = 1; k < thermal_n_reads(c); k++) {
        ess_deviations_at_temp(c, &dev, thermal_read_temp_c(c, k), &dev_t);
        ess_unit_build(c, &dev_t, &u);
        v = ess_rd_view(&w->val, rd, k);
        ess_unit_read_validation(c, &u, unit, &v);
    }
    return SUNMC_OK;
}

/* The calibrated unit at one operating temperature (thermal_validate_all):
 * the next block of its readings scored. */
typedef struct {
    const ess_model *m;
    const lab_onboard *ob;
    const ess_ws *w;
    const void *rd;
    int next; /* the block of the next temperature */
} ess_temp_ctx;

static void ess_validate_at(const sunmc_config *c, double temp_c, void *ctx, unit_result *at)
{
    ess_temp_ctx *k = ctx;
    ess_val_readings v = ess_rd_view(&k->w->val, k->rd, k->next++);
    ess_score_validation(c, k->m, k->ob, &v, at);
}

/* Campaign, fit and the scores of the unit's readings rd (family.h). */
static int ess_unit_finish(const sunmc_config *c, long unit, void *ws, const void *rd,
                           unit_result *res)
{
    const ess_config *ec = ess_cfg(c);
    ess_ws *w = ws;
    ess_calib_workspace *cw = w->cw;
    double t = unit_clock();
    ess_deviations dev;
    ess_unit u;
    ess_deviations_sample(c, (uint64_t)c->seed, unit, &dev);
    ess_unit_build(c, &dev, &u);

    memset(res, 0, sizeof *res);
    res->unit = unit;
    ess_deviations_values(&dev, res->dev);

    ess_unit_campaign(c, &u, unit, cw, NULL, &res->gross_cal);
    unit_phase_end(res, UNIT_PHASE_CAMPAIGN, &t);

    ess_model m;
    fit_result fr;
    double theta0 = ec->design.theta0_deg * RAD_PER_DEG;
    cw->sun_y_rad =
        ess_sun_y_measured_arcsec(c, (uint64_t)c->seed, unit, &dev) * RAD_PER_ARCSEC;
    int st = ess_calibrate(cw, theta0, dev.roll_measured_arcsec * RAD_PER_ARCSEC,
                           ec->alias_threshold, c->max_iterations, &m, &fr);
    res->fit_status = st == SUNMC_OK ? UNIT_FIT_OK : UNIT_FIT_FAILED;
    res->fit_gsl_status = fr.status;
    res->fit_iterations = (int)fr.iterations;
    res->alias_weak = cw->alias.n_weak;
    ess_model_report(&m, res->par);
    res->fit_rms = ess_calib_residual_rms(cw, &m) * DEG_PER_RAD;
    unit_phase_end(res, UNIT_PHASE_FIT, &t);

    /* validation at the lab's temperature (u itself), then at each
     * operating temperature (thermal.h) with the same calibration */
    ess_val_readings v = ess_rd_view(&w->val, rd, 0);
    int fit_ok = res->fit_status == UNIT_FIT_OK;
    const lab_onboard *ob = lab_onboard_mc_unit(&w->ob, &m, &fit_ok);
    res->fit_status = fit_ok ? res->fit_status : UNIT_FIT_FAILED;
    ess_score_validation(c, &m, ob, &v, res);
    ess_temp_ctx tc = {&m, ob, w, rd, 1};
    thermal_validate_all(c, res, ess_validate_at, &tc);
    unit_phase_end(res, UNIT_PHASE_VALIDATION, &t);
    return SUNMC_OK;
}

static int ess_unit_run(const sunmc_config *c, long unit, void *ws, unit_result *res)
{
    ess_ws *w = ws;
    return unit_read_finish(c, unit, ws, w->rd, 0, res);
}

/* The readings depend on neither the campaign nor its fit. */
static const char *const ess_readings_ignore[] = {"campaign", "calibration",
                                                  "noise.encoder_arcsec", NULL};

const sensor_family ess_family = {
    .name = "ess",
    .description = "encoded sun sensor",
    .keys = ess_keys,
    .defaults = ess_defaults,
    .validate = ess_config_validate,
    .alias_term = "the fine-code term",
    .rms_unit = "deg",
    .arcsec_per_rms_unit = ARCSEC_PER_DEG,
    .rms_decimals = 4,
    .model_label = ess_model_label,
    .n_angles = ess_n_angles,
    .angle_names = ess_angle_names,
    .band_name = "|alpha|",
    .deviations = ess_deviation_list,
    .n_deviations = ESS_N_TOL,
    .thermal = 1,
    .noise = ess_random_noise,
    .dev_columns = ess_dev_columns,
    .par_columns = ess_par_columns,
    .workspace_alloc = ess_ws_alloc,
    .workspace_bytes = ess_ws_bytes,
    .workspace_free = ess_ws_free,
    .unit_run = ess_unit_run,
    .readings_bytes = ess_readings_bytes,
    .unit_read = ess_unit_take_readings,
    .unit_finish = ess_unit_finish,
    .readings_ignore = ess_readings_ignore,
    .grid = &ess_grid,       /* ess_grid.c */
    .curve = &ess_curve,     /* ess_curve.c */
    .lab = &ess_lab, /* ess_lab.c */
};
