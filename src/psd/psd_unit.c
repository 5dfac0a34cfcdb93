/* psd_unit.c - the four-channel analog sun sensor family: its Monte Carlo
 * unit and its sensor_family struct (see psd_unit.h). */
#include "psd_unit.h"
#include "verdict.h"
#include "psd_thermal.h"
#include "thermal.h"
#include "lab.h"
#include "lab_onboard.h"
#include "psd_lab.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { ANGLE_ALPHA = 0, ANGLE_BETA, ANGLE_TOTAL, PSD_N_ANGLES };
static const char *const psd_angle_names[PSD_N_ANGLES] = {"alpha", "beta", "total"};
static const char *const psd_poly_par[] = {"poly_terms"};
/* units.tsv's fitted-parameter columns: fit_ and psd_param_names
 * (docs/outputs.md), apart from the deviation columns of the same names. */
static const char *const psd_par_col[PSD_NP] = {
    "fit_dx_um",     "fit_dy_um",     "fit_dh_um",     "fit_tilt_x_arcsec", "fit_tilt_y_arcsec",
    "fit_rot_z_arcsec", "fit_gain2_rel", "fit_gain3_rel", "fit_gain4_rel", "fit_dark1_raw",
    "fit_dark2_raw", "fit_dark3_raw", "fit_dark4_raw"};

PSD_DEVIATIONS(DEVIATION_X_COLUMNS)
static const deviation_spec psd_deviation_list[] = {
#define PSD_X_SPEC(name, unit, count, stream, ...)                                                \
    DEVIATION_SPEC(psd_config, psd_deviations, name, count, stream),
    PSD_DEVIATIONS(PSD_X_SPEC)
#undef PSD_X_SPEC
};

static long alpha_n(double amax, double step, double offset)
{
    return grid_count(-amax, amax, step, offset);
}

long psd_campaign_rows(const sunmc_config *c)
{
    const psd_config *p = psd_cfg(c);
    return alpha_n(p->cal_alpha_max_deg, p->cal_alpha_step_deg, 0) * p->cal_beta_deg.n *
           c->cal_repeats;
}

long psd_validation_points(const sunmc_config *c)
{
    const psd_config *p = psd_cfg(c);
    return alpha_n(p->val_alpha_max_deg, p->val_alpha_step_deg, p->val_alpha_offset_deg) *
           p->val_beta_deg.n;
}

long psd_campaign_line(const sunmc_config *c, long i)
{
    const psd_config *p = psd_cfg(c);
    return i / c->cal_repeats / alpha_n(p->cal_alpha_max_deg, p->cal_alpha_step_deg, 0);
}

long psd_validation_line(const sunmc_config *c, long i)
{
    const psd_config *p = psd_cfg(c);
    return i / alpha_n(p->val_alpha_max_deg, p->val_alpha_step_deg, p->val_alpha_offset_deg);
}

void psd_line_offsets(const sunmc_config *c, long unit, int which,
                      double off[CONFIG_LIST_MAX][2])
{
    const psd_config *p = psd_cfg(c);
    double sigma = p->table_line_arcsec * RAD_PER_ARCSEC;
    int n = which == FAMILY_GRID_CAMPAIGN ? p->cal_beta_deg.n : p->val_beta_deg.n;
    memset(off, 0, sizeof(double[CONFIG_LIST_MAX][2]));
    if (!(sigma > 0))
        return;
    rng_stream r;
    unit_stream_init(&r, c, unit,
                     which == FAMILY_GRID_CAMPAIGN ? RNG_STREAM_LINE_CAL : RNG_STREAM_LINE_VAL);
    for (int l = 0; l < n && l < CONFIG_LIST_MAX; l++) {
        off[l][0] = sigma * rng_normal(&r);
        off[l][1] = sigma * rng_normal(&r);
    }
}

void psd_campaign_angles(const sunmc_config *c, long i, double *alpha, double *beta)
{
    const psd_config *p = psd_cfg(c);
    long na = alpha_n(p->cal_alpha_max_deg, p->cal_alpha_step_deg, 0), pt = i / c->cal_repeats;
    *alpha = (-p->cal_alpha_max_deg + (double)(pt % na) * p->cal_alpha_step_deg) * RAD_PER_DEG;
    *beta = p->cal_beta_deg.v[pt / na] * RAD_PER_DEG;
}

void psd_validation_angles(const sunmc_config *c, long i, double *alpha, double *beta)
{
    const psd_config *p = psd_cfg(c);
    long na = alpha_n(p->val_alpha_max_deg, p->val_alpha_step_deg, p->val_alpha_offset_deg);
    *alpha = (-p->val_alpha_max_deg + p->val_alpha_offset_deg +
              (double)(i % na) * p->val_alpha_step_deg) * RAD_PER_DEG;
    *beta = p->val_beta_deg.v[i / na] * RAD_PER_DEG;
}

void psd_unit_sample(const sunmc_config *c, long unit, double dev_sign, psd_deviations *dev)
{
    deviations_sample(psd_deviation_list, PSD_N_TOL, c, (uint64_t)c->seed, unit, dev);
    double *v = (double *)dev;
    for (size_t k = 0; k < sizeof *dev / sizeof(double); k++)
        v[k] *= dev_sign;
}

/* Readings of s for the table top's sun vector ut: m with noise from r,
 * and, when m0 is not NULL, m0 the same reading without noise (nor the
 * lamp's flicker).  The channel noise is drawn whether the sun is seen or
 * not, so the streams stay aligned; the lamp's draw only when it is on,
 * so configs without it keep their streams. */
static int read_pair(const psd_config *p, const psd_sensor *s, const double ut[3],
                     rng_stream *r, double m[4], double m0[4])
{
    double u[3], z[PSD_CHANNELS] = {0, 0, 0, 0}, clean[4];
    if (r)
        rng_normal_fill(r, z, PSD_CHANNELS);
    double light = r && p->lamp_pct > 0 ? 1.0 + p->lamp_pct * FRACTION_PER_PCT * rng_normal(r)
                                        : 1.0;
    /* drawn only when on, after the lamp's: configs without it keep their streams */
    double common = r && p->common_pct > 0 ? p->common_pct * FRACTION_PER_PCT * rng_normal(r)
                                           : 0.0;
    mat3_vec(s->M, ut, u);
    int st = psd_sensor_read_lit(s, u, light > 0 ? light : 0.0, m);
    if (m0) {
        if (light != 1.0)
            st |= psd_sensor_read_lit(s, u, 1.0, clean);
        else
            memcpy(clean, m, sizeof clean);
        for (int k = 0; k < PSD_CHANNELS; k++)
            m0[k] = psd_adc(clean[k], p->adc_bits);
    }
    for (int k = 0; k < PSD_CHANNELS; k++)
        m[k] = psd_adc(m[k] + p->noise_fs_pct * FRACTION_PER_PCT * z[k] +
                           common * p->common_signs.v[k],
                       p->adc_bits);
    return st;
}

int psd_unit_read(const sunmc_config *c, const psd_sensor *s, double alpha, double beta,
                  rng_stream *r, double m[4])
{
    const psd_config *p = psd_cfg(c);
    double ut[3];
    psd_table_sun(p, alpha, beta, ut);
    return read_pair(p, s, ut, r, m, NULL);
}

int psd_unit_fit(const sunmc_config *c, fit_workspace *fw, psd_rows *d, double *poly_work,
                 psd_cal *k, fit_result *fr)
{
    const psd_config *p = psd_cfg(c);
    memset(fr, 0, sizeof *fr);
    k->design = &p->design;
    k->model = p->cal_model;
    if (p->cal_model == PSD_MODEL_POLYNOMIAL) {
        psd_poly_init(&k->poly, p->poly_order, p->poly_form);
        return psd_poly_fit(&k->poly, d, poly_work);
    }
    if (p->cal_model == PSD_MODEL_SPLINE || p->cal_model == PSD_MODEL_TABLE)
        return psd_spline_fit(k, d, d->scratch);
    psd_phys_start(d, k->p);
    int st = psd_phys_fit(fw, d, p->fit_tilt, k->p, fr);
    psd_phys_set(&k->phys, &p->design, k->p);
    if (st == SUNMC_OK && p->cal_model == PSD_MODEL_HYBRID)
        st = psd_spline_fit(k, d, d->scratch);
    return st;
}

/* ---- the workspace ---- */

typedef struct {
    long n;
    double *m[PSD_CHANNELS], *ut, *w, *scratch, *poly_work;
    fit_workspace *fw, *fw_channels;
    double *rd; /* one unit's readings (psd_readings_bytes) */
    lab_onboard ob;     /* calibration.onboard: its table built once, reused */
    psd_model_file *mf; /* the unit's calibration as the lab's model (onboard) */
    lab_spline_ws *sws; /* the spline models': their fits allocate nothing */
    int *fold;          /* n: their folds */
} psd_ws;

/* A unit's readings (family.h: unit_read): for each validation it reads
 * (thermal_n_reads), each grid point's PSD_RD_POINT doubles: the table
 * top's sun vector, the reading with and without noise, the nominal
 * design's errors, the field angle and a flag (1: no reading or no
 * nominal angles there, a gross point). */
enum { RD_UT = 0, RD_M = 3, RD_M0 = 7, RD_E0 = 11, RD_FIELD = 14, RD_BAD = 15, PSD_RD_POINT };

static size_t psd_readings_bytes(const sunmc_config *c)
{
    return (size_t)thermal_n_reads(c) * (size_t)psd_validation_points(c) * PSD_RD_POINT *
           sizeof(double);
}

static void psd_ws_free(void *ws)
{
    psd_ws *w = ws;
    if (!w)
        return;
    free(w->m[0]);
    free(w->rd);
    fit_workspace_free(w->fw);
    fit_workspace_free(w->fw_channels);
    lab_onboard_free(&w->ob);
    free(w->mf);
    lab_spline_ws_free(w->sws);
    free(w->fold);
    free(w);
}

#define PSD_POLY_WORK (PSD_POLY_MAX_TERMS * (PSD_POLY_MAX_TERMS + 2))

static void *psd_ws_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    psd_ws *w = calloc(1, sizeof *w);
    long n = psd_campaign_rows(c);
    if (w) {
        w->n = n;
        w->m[0] = malloc(((size_t)n * 16 + PSD_POLY_WORK) * sizeof(double));
        int fr[PSD_NP];
        w->fw = fit_workspace_alloc(2 * (size_t)n, (size_t)psd_phys_free(&psd_cfg(c)->design, psd_cfg(c)->fit_tilt, fr));
        w->fw_channels = fit_workspace_alloc(PSD_RESIDUALS_PER_ROW * (size_t)n,
                                             (size_t)psd_phys_free_channels(psd_cfg(c)->fit_tilt));
        w->rd = malloc(psd_readings_bytes(c));
        w->mf = malloc(sizeof *w->mf);
        if (PSD_MODEL_HAS_SPLINE(psd_cfg(c)->cal_model)) {
            w->sws = lab_spline_ws_alloc((size_t)n);
            w->fold = malloc(((size_t)n + 1) * sizeof *w->fold);
        }
    }
    if (!w || !w->m[0] || !w->fw || !w->fw_channels || !w->rd || !w->mf ||
        (PSD_MODEL_HAS_SPLINE(psd_cfg(c)->cal_model) && (!w->sws || !w->fold))) {
        psd_ws_free(w);
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for a PSD unit's workspace");
        return NULL;
    }
    for (int k = 1; k < PSD_CHANNELS; k++)
        w->m[k] = w->m[k - 1] + n;
    w->ut = w->m[3] + n;
    w->w = w->ut + 3 * n;
    w->scratch = w->w + n;
    w->poly_work = w->scratch + 8 * n;
    w->mf->cfg = *psd_cfg(c);
    if (lab_onboard_mc_init(&w->ob, c, err, errlen) != SUNMC_OK) {
        psd_ws_free(w);
        return NULL;
    }
    return w;
}

static double psd_ws_bytes(const sunmc_config *c)
{
    long n = psd_campaign_rows(c);
    return ((double)n * 16 + PSD_POLY_WORK) * sizeof(double) +
           fit_workspace_bytes(2 * (size_t)n, PSD_NP) +
           fit_workspace_bytes(PSD_RESIDUALS_PER_ROW * (size_t)n, PSD_NP) +
           (double)psd_readings_bytes(c) +
           (PSD_MODEL_HAS_SPLINE(psd_cfg(c)->cal_model)
                ? lab_spline_ws_bytes((size_t)n) + (double)(n + 1) * sizeof(int) : 0.0);
}

/* The campaign of sensor s into w's rows; returns the rows seen. */
static long campaign(const sunmc_config *c, const psd_sensor *s, long unit, psd_ws *w)
{
    rng_stream r;
    unit_stream_init(&r, c, unit, RNG_STREAM_CAL_NOISE);
    double off[CONFIG_LIST_MAX][2];
    psd_line_offsets(c, unit, FAMILY_GRID_CAMPAIGN, off);
    long seen = 0;
    for (long i = 0; i < w->n; i++) {
        double a, b, m[4], ur[3];
        const double *o = off[psd_campaign_line(c, i)];
        psd_campaign_angles(c, i, &a, &b);
        psd_table_sun(psd_cfg(c), a, b, w->ut + 3 * i); /* the recorded truth */
        psd_table_sun(psd_cfg(c), a + o[0], b + o[1], ur); /* where the table stands */
        int ok = read_pair(psd_cfg(c), s, ur, &r, m, NULL) == SUNMC_OK;
        for (int k = 0; k < PSD_CHANNELS; k++)
            w->m[k][i] = m[k];
        w->w[i] = ok;
        seen += ok;
    }
    return seen;
}

/* Errors (rad) of calibration k on reading m against truth ut; through
 * the on-board form ob when not NULL (prepared with k). */
static int errors(const psd_cal *k, const lab_onboard *ob, const double m[4],
                  const double ut[3], double e[3])
{
    double a, b, ta, tb, uc[3], deg[2];
    if (ob && lab_onboard_eval_raw(ob, m, deg) != LAB_READING_OK)
        return SUNMC_EDOM;
    if (ob) {
        a = deg[0] * RAD_PER_DEG;
        b = deg[1] * RAD_PER_DEG;
    } else if (psd_cal_angles(k, m, &a, &b) != SUNMC_OK) {
        return SUNMC_EDOM;
    }
    sun_angles_of(ut, &ta, &tb);
    sun_vector_of(a, b, uc);
    e[ANGLE_ALPHA] = a - ta;
    e[ANGLE_BETA] = b - tb;
    e[ANGLE_TOTAL] = angle_between(uc, ut);
    return SUNMC_OK;
}

/* Sensor s's readings on the validation grid into rd (PSD_RD_POINT a
 * point), noise from the unit's validation stream. */
static void read_validation(const sunmc_config *c, const psd_sensor *s, long unit, double *rd)
{
    const psd_config *p = psd_cfg(c);
    psd_cal nominal;
    psd_cal_nominal(&nominal, &p->design);
    rng_stream r;
    unit_stream_init(&r, c, unit, RNG_STREAM_VAL_NOISE);
    double off[CONFIG_LIST_MAX][2];
    psd_line_offsets(c, unit, FAMILY_GRID_VALIDATION, off);
    long nv = psd_validation_points(c);
    for (long i = 0; i < nv; i++) {
        double a, b, ur[3], *x = rd + (size_t)i * PSD_RD_POINT;
        const double *o = off[psd_validation_line(c, i)];
        psd_validation_angles(c, i, &a, &b);
        psd_table_sun(p, a, b, x + RD_UT);
        psd_table_sun(p, a + o[0], b + o[1], ur);
        /* where the table stands (the recorded angles when the line has no
         * error: a + 0 is a), the noise-free reading too: the line's error
         * is the same for every repeat, so the systematic part holds it */
        int st = read_pair(p, s, ur, &r, x + RD_M, x + RD_M0);
        x[RD_FIELD] = acos(fmin(x[RD_UT + 2], 1.0)) * DEG_PER_RAD;
        x[RD_BAD] = st != SUNMC_OK || errors(&nominal, NULL, x + RD_M, x + RD_UT, x + RD_E0) != SUNMC_OK;
    }
}

/* The validation grid's readings rd: errors before (the nominal design's
 * reading), after and after without noise, per angle and band; gross:
 * points not read, or whose angles a calibration cannot give. */
static void validate(const sunmc_config *c, const psd_cal *k, const lab_onboard *ob, int fit_ok,
                     const double *rd, unit_result *res)
{
    band_acc bef[PSD_N_ANGLES], aft[PSD_N_ANGLES], sys[PSD_N_ANGLES];
    band_tail tail[PSD_N_ANGLES]; /* the spec's order statistic (verdict.h) */
    long points[CONFIG_BANDS_MAX] = {0};
    int nb = c->bands_deg.n;
    for (int a = 0; a < PSD_N_ANGLES; a++) {
        band_acc_reset(&bef[a]);
        band_acc_reset(&aft[a]);
        band_acc_reset(&sys[a]);
        band_tail_reset(&tail[a], verdict_tail_keep(c));
    }
    long nv = psd_validation_points(c);
    for (long i = 0; i < nv; i++) {
        const double *x = rd + (size_t)i * PSD_RD_POINT;
        double e1[3], e2[3];
        unsigned m = band_mask(&c->bands_deg, x[RD_FIELD]);
        band_count_chunk(points, nb, 1, &m);
        if (x[RD_BAD] != 0 ||
            (fit_ok && (errors(k, ob, x + RD_M, x + RD_UT, e1) != SUNMC_OK ||
                        errors(k, ob, x + RD_M0, x + RD_UT, e2) != SUNMC_OK))) {
            res->gross_val++;
            continue;
        }
        for (int q = 0; q < PSD_N_ANGLES; q++) {
            band_acc_add(&bef[q], &c->bands_deg, x[RD_FIELD], x[RD_E0 + q]);
            if (fit_ok) {
                band_acc_add(&aft[q], &c->bands_deg, x[RD_FIELD], e1[q]);
                band_acc_add(&sys[q], &c->bands_deg, x[RD_FIELD], e2[q]);
                band_tail_add_mask(&tail[q], nb, m, e1[q] * e1[q]);
            }
        }
    }
    for (int q = 0; q < PSD_N_ANGLES; q++) {
        unit_result_set_rms(res, q, &bef[q], &aft[q], &c->bands_deg, ARCSEC_PER_RAD);
        unit_result_set_stat(res, c, q, &aft[q], &tail[q], points, ARCSEC_PER_RAD);
        unit_result_set_sys(res, q, &sys[q], &c->bands_deg, ARCSEC_PER_RAD);
    }
}

/* Residual RMS (arcsec) of the fitted calibration on its campaign. */
static double fit_rms(const psd_ws *w, const psd_cal *k)
{
    double s2 = 0;
    long n = 0;
    for (long i = 0; i < w->n; i++) {
        double m[4] = {w->m[0][i], w->m[1][i], w->m[2][i], w->m[3][i]}, e[3];
        if (w->w[i] > 0 && errors(k, NULL, m, w->ut + 3 * i, e) == SUNMC_OK) {
            s2 += e[ANGLE_TOTAL] * e[ANGLE_TOTAL];
            n++;
        }
    }
    return n ? sqrt(s2 / (double)n) * ARCSEC_PER_RAD : NAN;
}

/* The unit's validation readings into rd (family.h): the lab's, then at
 * each operating temperature other than the lab's its sensor at that
 * temperature (thermal_validate_all's order). */
static int psd_unit_take_readings(const sunmc_config *c, long unit, void *ws, void *rd)
{
    const psd_config *p = psd_cfg(c);
    psd_deviations dev;
    psd_sensor s, sT;
    psd_unit_sample(c, unit, 1.0, &dev);
    psd_sensor_build(&p->design, &dev, &s);
    size_t block = (size_t)psd_validation_points(c) * PSD_RD_POINT;
    read_validation(c, &s, unit, rd);
    for (int k = 1; k < thermal_n_reads(c); k++) {
        psd_sensor_at_temp(c, &s, thermal_read_temp_c(c, k), &sT);
        read_validation(c, &sT, unit, (double *)rd + (size_t)k * block);
    }
    return SUNMC_OK;
}

/* The calibrated unit at one operating temperature (thermal_validate_all):
 * the lab's calibration on the next block of its readings. */
typedef struct {
    const psd_cal *k;
    const lab_onboard *ob;
    int fit_ok;
    const double *rd;
    int next; /* the block of the next temperature */
} psd_temp_ctx;

static void psd_validate_at(const sunmc_config *c, double temp_c, void *ctx, unit_result *at)
{
    psd_temp_ctx *t = ctx;
    size_t block = (size_t)psd_validation_points(c) * PSD_RD_POINT;
    validate(c, t->k, t->ob, t->fit_ok, t->rd + (size_t)t->next++ * block, at);
}

/* Campaign, fit and the scores of the unit's readings rd (family.h). */
static int psd_unit_finish(const sunmc_config *c, long unit, void *ws, const void *rd,
                           unit_result *res)
{
    psd_ws *w = ws;
    const psd_config *p = psd_cfg(c);
    double t = unit_clock();
    psd_deviations dev;
    psd_sensor s;
    psd_unit_sample(c, unit, 1.0, &dev);
    psd_sensor_build(&p->design, &dev, &s);
    memset(res, 0, sizeof *res);
    res->unit = unit;
    deviations_values(psd_deviation_list, PSD_N_TOL, &dev, res->dev, UNIT_MAX_DEV);
    campaign(c, &s, unit, w);
    unit_phase_end(res, UNIT_PHASE_CAMPAIGN, &t);

    psd_rows d = {.n = (size_t)w->n, .ut = w->ut, .w = w->w, .design = &p->design,
                  .scratch = w->scratch, .fw_channels = w->fw_channels, .sws = w->sws,
                  .fold_buf = w->fold};
    for (int k = 0; k < PSD_CHANNELS; k++)
        d.m[k] = w->m[k];
    psd_cal k;
    fit_result fr;
    int st = psd_unit_fit(c, w->fw, &d, w->poly_work, &k, &fr);
    res->fit_status = st == SUNMC_OK ? UNIT_FIT_OK : UNIT_FIT_FAILED;
    res->fit_gsl_status = fr.status;
    res->fit_iterations = (int)fr.iterations;
    if (PSD_MODEL_HAS_PHYSICS(p->cal_model))
        for (int j = 0; j < PSD_NP; j++)
            res->par[j] = k.p[j] * psd_param_scale[j];
    else
        res->par[0] = k.poly.nt;
    res->fit_rms = st == SUNMC_OK ? fit_rms(w, &k) : NAN;
    unit_phase_end(res, UNIT_PHASE_FIT, &t);

    int fit_ok = st == SUNMC_OK;
    w->mf->cal = k;
    const lab_onboard *ob = lab_onboard_mc_unit(&w->ob, w->mf, &fit_ok);
    res->fit_status = fit_ok ? res->fit_status : UNIT_FIT_FAILED;
    validate(c, &k, ob, fit_ok, rd, res);
    /* at each operating temperature, the same calibration (thermal.h) */
    psd_temp_ctx tc = {.k = &k, .ob = ob, .fit_ok = fit_ok, .rd = rd, .next = 1};
    thermal_validate_all(c, res, psd_validate_at, &tc);
    unit_phase_end(res, UNIT_PHASE_VALIDATION, &t);
    return SUNMC_OK;
}

static int psd_unit_run(const sunmc_config *c, long unit, void *ws, unit_result *res)
{
    psd_ws *w = ws;
    return unit_read_finish(c, unit, ws, w->rd, 0, res);
}

/* The readings depend on neither the campaign's grid and repeats nor the
 * fit; the table's order and signs (campaign keys) move the validation's
 * sun too. */
static const char *const psd_readings_ignore[] = {
    "campaign.alpha_max_deg", "campaign.alpha_step_deg", "campaign.beta_deg", "campaign.repeats",
    "calibration", "noise.encoder_arcsec", NULL};

/* ---- error curves (`sunmc curve`): one unit, noiseless readings ---- */

typedef struct {
    psd_ws *ws;
    psd_sensor s;
    psd_cal k, nominal;
} psd_curve;

static void psd_curve_free(void *p)
{
    psd_curve *cv = p;
    if (cv)
        psd_ws_free(cv->ws);
    free(cv);
}

static void *psd_curve_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    psd_curve *cv = calloc(1, sizeof *cv);
    if (cv)
        cv->ws = psd_ws_alloc(c, err, errlen);
    if (!cv || !cv->ws) {
        psd_curve_free(cv);
        if (!cv)
            sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
        return NULL;
    }
    return cv;
}

static int psd_curve_prepare(const sunmc_config *c, long unit, double dev_sign, void *p,
                             int *fit_ok)
{
    psd_curve *cv = p;
    const psd_config *pc = psd_cfg(c);
    psd_deviations dev;
    psd_unit_sample(c, unit, dev_sign, &dev);
    psd_sensor_build(&pc->design, &dev, &cv->s);
    campaign(c, &cv->s, unit, cv->ws);
    psd_rows d = {.n = (size_t)cv->ws->n, .ut = cv->ws->ut, .w = cv->ws->w,
                  .design = &pc->design, .scratch = cv->ws->scratch,
                  .fw_channels = cv->ws->fw_channels, .sws = cv->ws->sws,
                  .fold_buf = cv->ws->fold};
    for (int k = 0; k < PSD_CHANNELS; k++)
        d.m[k] = cv->ws->m[k];
    fit_result fr;
    *fit_ok = psd_unit_fit(c, cv->ws->fw, &d, cv->ws->poly_work, &cv->k, &fr) == SUNMC_OK;
    psd_cal_nominal(&cv->nominal, &pc->design);
    /* the curve at the first operating temperature, when there are any */
    if (thermal_n_temps(c) > 0) {
        psd_sensor lab = cv->s;
        psd_sensor_at_temp(c, &lab, thermal_temp_c(c, 0), &cv->s);
    }
    return SUNMC_OK;
}

static int psd_curve_eval(const sunmc_config *c, const void *p, double a0_deg, double a1_deg,
                          double before[UNIT_MAX_ANGLES], double after[UNIT_MAX_ANGLES])
{
    const psd_curve *cv = p;
    double a = a0_deg * RAD_PER_DEG, b = a1_deg * RAD_PER_DEG, ut[3], m[4], e0[3], e1[3];
    psd_table_sun(psd_cfg(c), a, b, ut);
    if (psd_unit_read(c, &cv->s, a, b, NULL, m) != SUNMC_OK ||
        errors(&cv->nominal, NULL, m, ut, e0) != SUNMC_OK)
        return SUNMC_EDOM;
    int ok = errors(&cv->k, NULL, m, ut, e1) == SUNMC_OK;
    for (int q = 0; q < PSD_N_ANGLES; q++) {
        before[q] = e0[q] * ARCSEC_PER_RAD;
        after[q] = ok ? e1[q] * ARCSEC_PER_RAD : NAN;
    }
    return SUNMC_OK;
}

static long psd_curve_axis(const sunmc_config *c, int axis, double *v, long max)
{
    const psd_config *p = psd_cfg(c);
    if (axis == 1)
        return list_values(&p->val_beta_deg, v, max);
    long na = alpha_n(p->val_alpha_max_deg, p->val_alpha_step_deg, p->val_alpha_offset_deg);
    for (long i = 0; i < na && i < max; i++) {
        double a, b;
        psd_validation_angles(c, i, &a, &b);
        v[i] = a * DEG_PER_RAD;
    }
    return na;
}

static const char *const psd_curve_axes[] = {"alpha_deg", "beta_deg"};

/* ---- the family's descriptions ---- */

static int psd_n_angles(const sunmc_config *c) { return PSD_N_ANGLES; }

static void psd_model_label(const sunmc_config *c, char *buf, size_t len)
{
    const psd_config *p = psd_cfg(c);
    if (p->cal_model == PSD_MODEL_POLYNOMIAL)
        snprintf(buf, len, "polynomial of order %d (%s) in the raw ratios", p->poly_order,
                 p->poly_form == PSD_POLY_FSS20 ? "FSScalibration's 20 terms" : "every term");
    else if (p->cal_model == PSD_MODEL_SPLINE)
        snprintf(buf, len, "penalised cubic B-spline of tan alpha, tan beta in the raw ratios");
    else if (p->cal_model == PSD_MODEL_TABLE)
        snprintf(buf, len, "look-up table of tan alpha, tan beta in the raw ratios "
                           "((bi)linear, the spline's values at its nodes)");
    else
        snprintf(buf, len, "physical: aperture dx, dy, dh, mount tilt_x, tilt_y, rot_z, "
                           "channel gains and darks%s",
                 p->cal_model == PSD_MODEL_HYBRID ? "; a spline of its residual" : "");
}

static int psd_dev_columns(const sunmc_config *c, const char **names, int max)
{
    return deviations_columns(psd_deviation_list, PSD_N_TOL, names, max);
}

static int psd_par_columns(const sunmc_config *c, const char **names, int max)
{
    int phys = PSD_MODEL_HAS_PHYSICS(psd_cfg(c)->cal_model), n = phys ? PSD_NP : 1;
    for (int i = 0; i < n && i < max; i++)
        names[i] = phys ? psd_par_col[i] : psd_poly_par[i];
    return n;
}

static long psd_table_grid(const sunmc_config *c, int which, double *a0, double *a1, long max)
{
    int val = which == FAMILY_GRID_VALIDATION;
    long n = val ? psd_validation_points(c) : psd_campaign_rows(c) / c->cal_repeats;
    for (long i = 0; i < n && i < max && a0 && a1; i++) {
        double a, b;
        if (val)
            psd_validation_angles(c, i, &a, &b);
        else
            psd_campaign_angles(c, i * c->cal_repeats, &a, &b);
        a0[i] = a * DEG_PER_RAD;
        a1[i] = b * DEG_PER_RAD;
    }
    return n;
}

static const char *const psd_table_axes[] = {"alpha", "beta"};
static const char *const psd_cal_noise_keys[] = {"noise.channel_pct", "noise.lamp_pct",
                                                 "noise.common_pct", NULL};
static const char *const psd_val_noise_keys[] = {"noise.channel_pct", "noise.lamp_pct",
                                                 "noise.common_pct", NULL};
static const char *const psd_line_keys[] = {"noise.table_line_arcsec", NULL};
static const family_noise psd_noise[] = {
    {"campaign_noise", RNG_STREAM_CAL_NOISE, psd_cal_noise_keys, NULL, 1},
    {"validation_noise", RNG_STREAM_VAL_NOISE, psd_val_noise_keys, NULL, 0},
    {"campaign_table_lines", RNG_STREAM_LINE_CAL, psd_line_keys, NULL, 1},
    {"validation_table_lines", RNG_STREAM_LINE_VAL, psd_line_keys, NULL, 0},
    {NULL, 0, NULL, NULL, 0}};

static const family_grid psd_grid_hooks = {
    .points = psd_table_grid,
    .axis_names = psd_table_axes,
    .design_step_key = "campaign.alpha_step_deg",
    .design_lines_key = "campaign.beta_deg",
};

static const family_curve psd_curve_hooks = {
    .axis_names = psd_curve_axes,
    .axis = psd_curve_axis,
    .alloc = psd_curve_alloc,
    .free = psd_curve_free,
    .prepare = psd_curve_prepare,
    .eval = psd_curve_eval,
};

/* The priors' pilot (prior.h) is the ESS's and DSS's: the PSD fit has no
 * prior rows (its channel fit determines every parameter from the
 * campaign; docs/priors.md). */
static const char *const psd_shared_unused[] = {"calibration.priors", "calibration.prior_units",
                                                NULL};

const sensor_family psd_family = {
    .name = "psd",
    .description = "four-channel analog sun sensor: lateral PSD or quadrant photodiode",
    .rms_unit = "arcsec",
    .arcsec_per_rms_unit = 1.0,
    .rms_decimals = 2,
    .keys = psd_keys,
    .defaults = psd_defaults,
    .shared_keys_unused = psd_shared_unused,
    .validate = psd_validate,
    .model_label = psd_model_label,
    .n_angles = psd_n_angles,
    .angle_names = psd_angle_names,
    .band_name = "field angle",
    .deviations = psd_deviation_list,
    .n_deviations = PSD_N_TOL,
    .noise = psd_noise,
    .dev_columns = psd_dev_columns,
    .par_columns = psd_par_columns,
    .workspace_alloc = psd_ws_alloc,
    .workspace_bytes = psd_ws_bytes,
    .workspace_free = psd_ws_free,
    .unit_run = psd_unit_run,
    .readings_bytes = psd_readings_bytes,
    .unit_read = psd_unit_take_readings,
    .unit_finish = psd_unit_finish,
    .readings_ignore = psd_readings_ignore,
    .thermal = 1,
    .grid = &psd_grid_hooks,
    .curve = &psd_curve_hooks,
    .lab = &psd_lab,
};
