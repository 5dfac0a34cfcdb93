/* dss_unit.c - the DSS family: sample -> physical sensor -> rotary-table
 * campaign -> fit -> validation on its own grid, for one unit. */
#include "dss_unit.h"
#include "dss_thermal.h"
#include "thermal.h"
#include "dss_prior.h"
#include "dss_curve.h"
#include "dss_lab.h"
#include "dss_grid.h"
#include "rotation.h"
#include "dss_score.h"
#include "lab_onboard.h"
#include "family.h"
#include "verdict.h"
#include "rng.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* units.tsv code of the most correlated pair: i * CORR_PAIR_BASE + j. */
#define CORR_PAIR_BASE 100

enum { ANGLE_ALPHA = 0, ANGLE_BETA, ANGLE_TOTAL, DSS_N_ANGLES };
static const char *const dss_angle_names[DSS_N_ANGLES] = {"alpha", "beta", "total"};

/* After the parameters (dss_param_names, the same names as the calibrate
 * report and params.ini; the tilt's only with the model's tilt). */
static const char *const par_fit_quality[DSS_N_PAR_PHYSICAL - DSS_NP] = {
    "corr_max_abs", "corr_pair", "log10_rcond"};
static const char *const par_polynomial[DSS_N_PAR_POLYNOMIAL] = {
    "poly_order", "poly_terms", "corr_max_abs", "corr_pair", "log10_rcond"};
static const char *const par_spline[DSS_N_PAR_SPLINE] = {
    "spline_breakpoints", "edf_alpha", "edf_beta", "table_nodes", "table_bytes"};

void dss_unit_build(const sunmc_config *c, const dss_deviations *dev, dss_unit *u)
{
    dss_unit_build_amp(c, dev, NULL, u);
}

void dss_unit_build_amp(const sunmc_config *c, const dss_deviations *dev, const double *amp_px,
                        dss_unit *u)
{
    const dss_config *dc = dss_cfg(c);
    u->dev = *dev;
    dss_sensor_init_amp(&u->sensor, &dc->design, dev, dc->noise.s_curve, amp_px);
}

void dss_unit_set_pattern(const sunmc_config *c, uint64_t seed, long unit, dss_unit *u)
{
    u->sensor.pattern.key = dss_pattern_key(c, seed, unit);
}

static long cal_axis_count(const sunmc_config *c)
{
    const dss_config *dc = dss_cfg(c);
    return grid_count(dc->cal_b_min_deg, dc->cal_b_max_deg, dc->cal_b_step_deg, 0);
}

size_t dss_campaign_size(const sunmc_config *c)
{
    size_t n = (size_t)cal_axis_count(c);
    return n * n;
}

size_t dss_unit_campaign(const sunmc_config *c, const dss_unit *u, long unit, double *b1_rad,
                         double *b2_rad, double *x_px, double *y_px, double *weight,
                         double *truth_alpha_rad, double *truth_beta_rad)
{
    long nb = cal_axis_count(c);
    size_t n = (size_t)nb * (size_t)nb, seen = 0;
    rng_stream r;
    unit_stream_init(&r, c, unit, RNG_STREAM_CAL_NOISE);
    dss_campaign_angles(c, b1_rad, b2_rad);
    /* The table really stands at the recorded angles plus the encoder error;
     * the draws are made for every point so that a point's noise does not
     * depend on whether others are seen. */
    for (size_t i0 = 0; i0 < n; i0 += DSS_CHUNK) {
        dss_campaign_point p[DSS_CHUNK];
        size_t k = n - i0 < DSS_CHUNK ? n - i0 : DSS_CHUNK;
        dss_campaign_batch(c, u, &r, k, b1_rad + i0, b2_rad + i0, p);
        for (size_t q = 0; q < k; q++) {
            size_t i = i0 + q;
            x_px[i] = p[q].x_px;
            y_px[i] = p[q].y_px;
            weight[i] = p[q].seen ? 1.0 : 0.0;
            seen += (size_t)p[q].seen;
            if (truth_alpha_rad && truth_beta_rad)
                dss_sensor_truth(&u->sensor, p[q].b1_true_rad, p[q].b2_true_rad,
                                 &truth_alpha_rad[i], &truth_beta_rad[i]);
        }
    }
    return seen;
}

/* The dss_param columns units.tsv carries for design d: all but the
 * detector tilt's unless the model has it (calibration.fit_detector_tilt). */
static int shown_params(const dss_design *d)
{
    return d->fit_tilt ? DSS_NP : DSS_P_TX;
}

int dss_par_names(const sunmc_config *c, const char **names, int max)
{
    int poly = dss_cfg(c)->cal_model == DSS_MODEL_POLYNOMIAL;
    int model = dss_cfg(c)->cal_model;
    if (model == DSS_MODEL_SPLINE || model == DSS_MODEL_TABLE) {
        for (int i = 0; i < DSS_N_PAR_SPLINE && i < max; i++)
            names[i] = par_spline[i];
        return DSS_N_PAR_SPLINE;
    }
    int np = shown_params(&dss_cfg(c)->design);
    int n = poly ? DSS_N_PAR_POLYNOMIAL : np + DSS_N_PAR_PHYSICAL - DSS_NP;
    for (int i = 0; i < n && i < max; i++)
        names[i] = poly ? par_polynomial[i]
                        : (i < np ? dss_param_names[i] : par_fit_quality[i - np]);
    return n;
}

int dss_par_values(const sunmc_config *c, const dss_calibration *cal, double corr, int i, int j,
                   double rcond, double *out, int max)
{
    const dss_config *dc = dss_cfg(c);
    double pair = (i >= 0 && j >= 0) ? (double)(i * CORR_PAIR_BASE + j) : NAN;
    double lrc = rcond > 0 ? log10(rcond) : NAN;
    if (dc->cal_model == DSS_MODEL_SPLINE || dc->cal_model == DSS_MODEL_TABLE) {
        int tab = dc->cal_model == DSS_MODEL_TABLE;
        double v[DSS_N_PAR_SPLINE] = {cal->spline.nbreak, cal->spline.edf[0], cal->spline.edf[1],
                                      tab ? cal->table.nodes : NAN,
                                      tab ? (double)lab_table_bytes(&cal->table) : NAN};
        memcpy(out, v, sizeof v < (size_t)max * sizeof *out ? sizeof v : (size_t)max * sizeof *out);
        return DSS_N_PAR_SPLINE;
    }
    if (dc->cal_model == DSS_MODEL_POLYNOMIAL) {
        double v[DSS_N_PAR_POLYNOMIAL] = {cal->poly.order, cal->poly.n_terms, corr, pair, lrc};
        memcpy(out, v, sizeof v < (size_t)max * sizeof *out ? sizeof v : (size_t)max * sizeof *out);
        return DSS_N_PAR_POLYNOMIAL;
    }
    double v[DSS_N_PAR_PHYSICAL];
    int np = shown_params(&dc->design), n = np + DSS_N_PAR_PHYSICAL - DSS_NP;
    for (int k = 0; k < np; k++)
        v[k] = dss_param_value(&cal->phys, k);
    v[np] = corr;
    v[np + 1] = pair;
    v[np + 2] = lrc;
    size_t bytes = (size_t)n * sizeof *v;
    memcpy(out, v, bytes < (size_t)max * sizeof *out ? bytes : (size_t)max * sizeof *out);
    return n;
}

/* ---- the family ---- */

static int dss_n_angles(const sunmc_config *c) { return DSS_N_ANGLES; }

static int dss_dev_columns(const sunmc_config *c, const char **names, int max)
{
    for (int i = 0; i < DSS_N_DEV && i < max; i++)
        names[i] = dss_deviation_names[i];
    return DSS_N_DEV;
}

/* A unit's readings (family.h: unit_read, unit_rd_block): for each
 * validation it reads (thermal_n_reads), the spots with and without noise,
 * the truths and the seen flags of the validation grid's n points, one
 * block each. */
#define DSS_RD_ARRAYS 6

static size_t dss_readings_bytes(const sunmc_config *c)
{
    return unit_rd_bytes(c, dss_validation_size(c), DSS_RD_ARRAYS);
}

/* Block k of readings rd as validation readings (the table angles of
 * grid). */
static dss_val_readings dss_rd_view(const dss_val_readings *grid, const void *rd, int k)
{
    dss_val_readings v = *grid;
    double *b = unit_rd_block(rd, grid->n, DSS_RD_ARRAYS, k);
    v.x_px = b;
    v.y_px = b + grid->n;
    v.x0_px = b + 2 * grid->n;
    v.y0_px = b + 3 * grid->n;
    v.truth_alpha_rad = b + 4 * grid->n;
    v.truth_beta_rad = b + 5 * grid->n;
    v.seen = unit_rd_flags(b, grid->n, DSS_RD_ARRAYS);
    return v;
}

/* A thread's workspace: the campaign's fit, the validation grid and one
 * unit's readings. */
typedef struct {
    dss_calib_workspace *cw;
    dss_val_readings val;
    calib_prior prior; /* calibration.priors = tolerances: set on cw's fit */
    double amp_px[DSS_SCURVE_HARMONICS]; /* the design's S-curve, made once */
    double *rd;        /* dss_readings_bytes */
    lab_onboard ob;    /* calibration.onboard: its table built once, reused */
} dss_ws;

static void dss_ws_free(void *p)
{
    dss_ws *w = p;
    if (!w)
        return;
    dss_calib_free(w->cw);
    dss_val_free(&w->val);
    free(w->rd);
    lab_onboard_free(&w->ob);
    free(w);
}

/* The fit's workspace, the validation arrays (8 doubles and a flag a
 * point) and the readings. */
static double dss_ws_bytes(const sunmc_config *c)
{
    const dss_config *dc = dss_cfg(c);
    return dss_calib_bytes(dss_campaign_size(c), dc->cal_model, dc->poly_order) +
           (double)dss_validation_size(c) * (8.0 * sizeof(double) + sizeof(int)) +
           (double)dss_readings_bytes(c);
}

static void *dss_ws_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    const dss_config *dc = dss_cfg(c);
    size_t n = dss_campaign_size(c);
    dss_ws *w = calloc(1, sizeof *w);
    if (w)
        w->cw = dss_calib_alloc_config(dc, n);
    if (!w || !w->cw || dss_val_alloc(c, &w->val) != SUNMC_OK ||
        !(w->rd = malloc(dss_readings_bytes(c)))) {
        dss_ws_free(w);
        sunmc_fail(err, errlen, SUNMC_ENOMEM,
                   "cannot set up the DSS calibration for a %zu-point campaign (out of memory, "
                   "or fewer points than parameters)", n);
        return NULL;
    }
    dss_campaign_angles(c, w->cw->b1_rad, w->cw->b2_rad);
    dss_scurve_design(&dc->design, w->amp_px);
    if (dss_prior_apply(c, w->cw, &w->prior, err, errlen) != SUNMC_OK ||
        lab_onboard_mc_init(&w->ob, c, err, errlen) != SUNMC_OK) {
        dss_ws_free(w);
        return NULL;
    }
    return w;
}

/* Field angle (deg) of the sun direction with angles (alpha, beta). */
double dss_field_angle_deg(double alpha, double beta)
{
    return atan(hypot(tan(alpha), tan(beta))) * DEG_PER_RAD;
}

static long val_axis_count(const sunmc_config *c)
{
    const dss_config *dc = dss_cfg(c);
    return grid_count(dc->val_b_min_deg, dc->val_b_max_deg, dc->val_b_step_deg,
                      dc->val_b_offset_deg);
}

size_t dss_validation_size(const sunmc_config *c)
{
    size_t n = (size_t)val_axis_count(c);
    return n * n;
}

/* The validation grid's table angles (b1 varying slowest) and their
 * cosines and sines. */
static void val_grid_fill(const sunmc_config *c, dss_val_readings *v)
{
    const dss_config *dc = dss_cfg(c);
    size_t nb = (size_t)val_axis_count(c);
    for (size_t i = 0; i < v->n; i++) {
        v->b1_rad[i] = (dc->val_b_min_deg + dc->val_b_offset_deg +
                        (double)(i / nb) * dc->val_b_step_deg) * RAD_PER_DEG;
        v->b2_rad[i] = (dc->val_b_min_deg + dc->val_b_offset_deg +
                        (double)(i % nb) * dc->val_b_step_deg) * RAD_PER_DEG;
    }
    dss_trig_fill(v->n, v->b1_rad, v->b2_rad, v->trig);
}

int dss_val_alloc(const sunmc_config *c, dss_val_readings *v)
{
    size_t n = dss_validation_size(c);
    memset(v, 0, sizeof *v);
    v->n = n;
    double **arrays[] = {&v->b1_rad, &v->b2_rad, &v->x_px, &v->y_px, &v->x0_px, &v->y0_px,
                         &v->truth_alpha_rad, &v->truth_beta_rad};
    int ok = (v->seen = malloc((n + 1) * sizeof(int))) != NULL;
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++)
        ok &= (*arrays[k] = vm_alloc(n + 1)) != NULL;
    for (int k = 0; k < 4; k++)
        ok &= (v->trig[k] = vm_alloc(n + 1)) != NULL;
    if (ok) {
        val_grid_fill(c, v);
        return SUNMC_OK;
    }
    dss_val_free(v);
    return SUNMC_ENOMEM;
}

void dss_val_free(dss_val_readings *v)
{
    double *arrays[] = {v->b1_rad, v->b2_rad, v->x_px, v->y_px, v->x0_px, v->y0_px,
                        v->truth_alpha_rad, v->truth_beta_rad};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++)
        free(arrays[k]);
    for (int k = 0; k < 4; k++)
        free(v->trig[k]);
    free(v->seen);
    memset(v, 0, sizeof *v);
}

void dss_unit_read_validation(const sunmc_config *c, const dss_unit *u, long unit,
                         dss_val_readings *v)
{
    rng_stream r;
    unit_stream_init(&r, c, unit, RNG_STREAM_VAL_NOISE);
    for (size_t i0 = 0; i0 < v->n; i0 += DSS_CHUNK) {
        dss_validation_point p[DSS_CHUNK];
        size_t k = v->n - i0 < DSS_CHUNK ? v->n - i0 : DSS_CHUNK;
        const double *trig[4] = {v->trig[0] + i0, v->trig[1] + i0, v->trig[2] + i0,
                                 v->trig[3] + i0};
        dss_validation_batch_trig(c, u, &r, k, v->b1_rad + i0, v->b2_rad + i0, trig, p);
        for (size_t q = 0; q < k; q++) {
            size_t i = i0 + q;
            v->x_px[i] = p[q].x_px;
            v->y_px[i] = p[q].y_px;
            v->x0_px[i] = p[q].x0_px;
            v->y0_px[i] = p[q].y0_px;
            v->truth_alpha_rad[i] = p[q].alpha0_rad;
            v->truth_beta_rad[i] = p[q].beta0_rad;
            v->seen[i] = p[q].seen;
        }
    }
}

/* One validation chunk of k points, scored in vectorised passes: the
 * on-board angles, the truth's field angle and, with a fit, the
 * compensated angles of the noisy and of the noiseless readings, each with
 * its total angle error.  Arrays of DSS_CHUNK, the pads repeating lane 0. */
typedef struct {
    _Alignas(VM_ALIGN) double x[DSS_CHUNK], y[DSS_CHUNK], x0[DSS_CHUNK], y0[DSS_CHUNK];
    double a0[DSS_CHUNK], b0[DSS_CHUNK], field[DSS_CHUNK];
    double vx[DSS_CHUNK], vy[DSS_CHUNK], vz[DSS_CHUNK]; /* the truth's unit vector */
    double am[DSS_CHUNK], bm[DSS_CHUNK], tm[DSS_CHUNK];  /* before calibration */
    double ac[DSS_CHUNK], bc[DSS_CHUNK], tc[DSS_CHUNK];  /* after */
    double as[DSS_CHUNK], bs[DSS_CHUNK], ts[DSS_CHUNK];  /* after, without noise */
    int seen[DSS_CHUNK], st_m[DSS_CHUNK], st_c[DSS_CHUNK], st_s[DSS_CHUNK];
} dss_val_chunk;

/* Spots (x[q], y[q]), q < vm_pad(k), through the on-board form: angles
 * (rad) a, b and status st (SUNMC_EDOM, angles 0, where it gives none). */
static void onboard_chunk(const lab_onboard *ob, size_t k, const double *x, const double *y,
                          double *a, double *b, int *st)
{
    for (size_t q = 0; q < vm_pad(k); q++) {
        double raw[2] = {x[q], y[q]}, deg[2];
        int ok = lab_onboard_eval_raw(ob, raw, deg) == LAB_READING_OK;
        st[q] = ok ? SUNMC_OK : SUNMC_EDOM;
        a[q] = ok ? deg[0] * RAD_PER_DEG : 0.0;
        b[q] = ok ? deg[1] * RAD_PER_DEG : 0.0;
    }
}

static void validation_chunk(const dss_unit *u, const dss_calibration *cal,
                             const lab_onboard *ob, const dss_val_readings *r, size_t i0,
                             size_t k, int fit_ok, int sys, dss_val_chunk *v)
{
    for (size_t i = 0; i < vm_pad(k); i++) {
        size_t j = i0 + (i < k ? i : 0);
        v->x[i] = r->x_px[j];
        v->y[i] = r->y_px[j];
        v->x0[i] = r->x0_px[j];
        v->y0[i] = r->y0_px[j];
        v->a0[i] = r->truth_alpha_rad[j];
        v->b0[i] = r->truth_beta_rad[j];
        v->seen[i] = r->seen[j];
    }
    const dss_sensor *s = &u->sensor;
    dss_onboard_chunk(&s->onboard, k, v->x, v->y, v->am, v->bm, v->st_m);
    dss_truth_vector_chunk(k, v->a0, v->b0, v->vx, v->vy, v->vz, v->field);
    dss_total_error_vec_chunk(k, v->am, v->bm, v->vx, v->vy, v->vz, v->tm);
    if (!fit_ok)
        return;
    if (ob) {
        onboard_chunk(ob, k, v->x, v->y, v->ac, v->bc, v->st_c);
        dss_total_error_vec_chunk(k, v->ac, v->bc, v->vx, v->vy, v->vz, v->tc);
        if (!sys)
            return;
        onboard_chunk(ob, k, v->x0, v->y0, v->as, v->bs, v->st_s);
        dss_total_error_vec_chunk(k, v->as, v->bs, v->vx, v->vy, v->vz, v->ts);
        return;
    }
    if (!sys) {
        dss_compensate_batch(cal, vm_pad(k), v->x, v->y, v->ac, v->bc, v->st_c);
        dss_total_error_vec_chunk(k, v->ac, v->bc, v->vx, v->vy, v->vz, v->tc);
        return;
    }
    dss_compensate_pair_batch(cal, vm_pad(k), v->x, v->y, v->x0, v->y0, v->ac, v->bc, v->st_c,
                              v->as, v->bs, v->st_s);
    dss_total_error_vec_chunk(k, v->ac, v->bc, v->vx, v->vy, v->vz, v->tc);
    dss_total_error_vec_chunk(k, v->as, v->bs, v->vx, v->vy, v->vz, v->ts);
}

/* Which readings of a chunk each set of accumulators takes, as one
 * reading at a time would: before = seen with on-board angles (beyond 86
 * deg no spot falls on any detector of the config); after = those while
 * the fit is good and compensates them (the first that it cannot fails
 * the unit's fit and ends the after sums; a spline model's reading outside
 * its calibrated field, field = 1, is a counted gross error instead: the
 * model refuses to extrapolate, as compensate does); after_sys = after's
 * whose noise-free twin compensates (none without the systematic pass, sys 0). */
static void chunk_uses(const dss_val_chunk *v, size_t k, int sys, int field, unit_result *res,
                       int *use_b, int *use_a, int *use_s)
{
    for (size_t q = 0; q < k; q++) {
        use_b[q] = v->seen[q] && v->st_m[q] == SUNMC_OK;
        use_a[q] = use_s[q] = 0;
        if (!use_b[q] || res->fit_status != UNIT_FIT_OK)
            continue;
        if (v->st_c[q] != SUNMC_OK || (field && sys && v->st_s[q] != SUNMC_OK)) {
            if (field)
                res->gross_val++;
            else
                res->fit_status = UNIT_FIT_FAILED;
            continue;
        }
        use_a[q] = 1;
        use_s[q] = sys && v->st_s[q] == SUNMC_OK;
    }
}

/* Add the errors (rad) of readings q < k with use[q] to acc (alpha a - a0,
 * beta b - b0, total t) in the bands of mask[q], as band_acc_add would
 * one reading at a time (band_acc_add_chunks: the three angles' sums
 * interleaved); and to tail (NULL: none), the spec's largest errors. */
static void add_chunk(band_acc acc[DSS_N_ANGLES], band_tail *tail, int nb, size_t k,
                      const unsigned *mask, const int *use, const double *a, const double *b,
                      const double *a0, const double *b0, const double *t)
{
    unsigned m[DSS_CHUNK];
    double e2[DSS_N_ANGLES][DSS_CHUNK];
    for (size_t q = 0; q < k; q++) {
        m[q] = use[q] ? mask[q] : 0u;
        e2[ANGLE_ALPHA][q] = (a[q] - a0[q]) * (a[q] - a0[q]);
        e2[ANGLE_BETA][q] = (b[q] - b0[q]) * (b[q] - b0[q]);
        e2[ANGLE_TOTAL][q] = t[q] * t[q];
    }
    band_acc *const accs[DSS_N_ANGLES] = {&acc[ANGLE_ALPHA], &acc[ANGLE_BETA], &acc[ANGLE_TOTAL]};
    const unsigned *const ms[DSS_N_ANGLES] = {m, m, m};
    const double *const es[DSS_N_ANGLES] = {e2[ANGLE_ALPHA], e2[ANGLE_BETA], e2[ANGLE_TOTAL]};
    band_acc_add_chunks(DSS_N_ANGLES, accs, nb, k, ms, es);
    for (int g = 0; tail && g < DSS_N_ANGLES; g++)
        band_tail_add_chunk(&tail[g], nb, k, m, e2[g]);
}

/* Score the unit's validation readings r (RMS before and after), and the
 * same points without centroid noise (the systematic part of the after
 * RMS; the S-curve bias, a property of the detector, stays in; NaN under
 * c->no_systematic). */
static void dss_unit_score_validation(const sunmc_config *c, const dss_unit *u,
                              const dss_calibration *cal, const lab_onboard *ob,
                              const dss_val_readings *r, unit_result *res)
{
    band_acc before[DSS_N_ANGLES], after[DSS_N_ANGLES], after_sys[DSS_N_ANGLES];
    band_tail tail[DSS_N_ANGLES]; /* the spec's order statistic (verdict.h) */
    long points[CONFIG_BANDS_MAX] = {0};
    for (int a = 0; a < DSS_N_ANGLES; a++) {
        band_acc_reset(&before[a]);
        band_acc_reset(&after[a]);
        band_acc_reset(&after_sys[a]);
        band_tail_reset(&tail[a], verdict_tail_keep(c));
    }
    dss_val_chunk v;
    int sys = !c->no_systematic;
    int nb = c->bands_deg.n, use_b[DSS_CHUNK], use_a[DSS_CHUNK], use_s[DSS_CHUNK];
    unsigned mask[DSS_CHUNK];
    for (size_t i0 = 0; i0 < r->n; i0 += DSS_CHUNK) {
        size_t k = r->n - i0 < DSS_CHUNK ? r->n - i0 : DSS_CHUNK;
        int fit_ok = res->fit_status == UNIT_FIT_OK;
        validation_chunk(u, cal, ob, r, i0, k, fit_ok, sys, &v);
        for (size_t q = 0; q < k; q++)
            mask[q] = band_mask(&c->bands_deg, v.field[q]);
        band_count_chunk(points, nb, k, mask);
        chunk_uses(&v, k, sys, DSS_MODEL_HAS_SPLINE(cal->kind), res, use_b, use_a, use_s);
        add_chunk(before, NULL, nb, k, mask, use_b, v.am, v.bm, v.a0, v.b0, v.tm);
        if (!fit_ok)
            continue;
        add_chunk(after, tail, nb, k, mask, use_a, v.ac, v.bc, v.a0, v.b0, v.tc);
        if (sys)
            add_chunk(after_sys, NULL, nb, k, mask, use_s, v.as, v.bs, v.a0, v.b0, v.ts);
    }
    for (int a = 0; a < DSS_N_ANGLES; a++) {
        unit_result_set_rms(res, a, &before[a], &after[a], &c->bands_deg, ARCSEC_PER_RAD);
        unit_result_set_stat(res, c, a, &after[a], &tail[a], points, ARCSEC_PER_RAD);
        unit_result_set_sys(res, a, sys ? &after_sys[a] : NULL, &c->bands_deg, ARCSEC_PER_RAD);
    }
}

/* The unit's validation readings into rd (family.h): the lab's, then at
 * each operating temperature other than the lab's its deviations at that
 * temperature, rebuilt (thermal_validate_all's order). */
static int dss_unit_take_readings(const sunmc_config *c, long unit, void *ws, void *rd)
{
    dss_ws *w = ws;
    dss_deviations dev, dev_t;
    dss_unit u;
    dss_deviations_sample(c, (uint64_t)c->seed, unit, &dev);
    dss_unit_build_amp(c, &dev, w->amp_px, &u);
    dss_unit_set_pattern(c, (uint64_t)c->seed, unit, &u);
    dss_unit_set_pattern(c, (uint64_t)c->seed, unit, &u);
    dss_val_readings v = dss_rd_view(&w->val, rd, 0);
    dss_unit_read_validation(c, &u, unit, &v);
    for (int k = 1; k < thermal_n_reads(c); k++) {
        dss_deviations_at_temp(c, &dev, thermal_read_temp_c(c, k), &dev_t);
        dss_unit_build_amp(c, &dev_t, w->amp_px, &u);
        dss_unit_set_pattern(c, (uint64_t)c->seed, unit, &u);
        v = dss_rd_view(&w->val, rd, k);
        dss_unit_read_validation(c, &u, unit, &v);
    }
    return SUNMC_OK;
}

/* The calibrated unit at one operating temperature (thermal_validate_all):
 * its deviations at temp_c, rebuilt, the next block of its readings
 * scored. */
typedef struct {
    const dss_deviations *dev;
    const dss_calibration *cal;
    const lab_onboard *ob;
    const dss_ws *w;
    const void *rd;
    int next; /* the block of the next temperature */
} dss_temp_ctx;

static void dss_validate_at(const sunmc_config *c, double temp_c, void *ctx, unit_result *at)
{
    dss_temp_ctx *k = ctx;
    dss_deviations dev_t;
    dss_unit u;
    dss_deviations_at_temp(c, k->dev, temp_c, &dev_t);
    dss_unit_build_amp(c, &dev_t, k->w->amp_px, &u);
    dss_val_readings v = dss_rd_view(&k->w->val, k->rd, k->next++);
    dss_unit_score_validation(c, &u, k->cal, k->ob, &v, at);
}

/* Campaign, fit and the scores of the unit's readings rd (family.h). */
static int dss_unit_finish(const sunmc_config *c, long unit, void *ws, const void *rd,
                           unit_result *res)
{
    dss_ws *w = ws;
    dss_calib_workspace *cw = w->cw;
    double t = unit_clock();
    dss_deviations dev;
    dss_unit u;
    dss_deviations_sample(c, (uint64_t)c->seed, unit, &dev);
    dss_unit_build_amp(c, &dev, w->amp_px, &u);
    dss_unit_set_pattern(c, (uint64_t)c->seed, unit, &u);

    memset(res, 0, sizeof *res);
    res->unit = unit;
    dss_deviations_values(&dev, res->dev);

    dss_unit_campaign(c, &u, unit, cw->b1_rad, cw->b2_rad, cw->x_px, cw->y_px, cw->weight, NULL,
                      NULL);
    unit_phase_end(res, UNIT_PHASE_CAMPAIGN, &t);

    dss_calibration cal;
    fit_result fr;
    double sun[2];
    dss_sun_measured_arcsec(c, (uint64_t)c->seed, unit, &dev, sun);
    cw->sun_rad[0] = sun[0] * RAD_PER_ARCSEC;
    cw->sun_rad[1] = sun[1] * RAD_PER_ARCSEC;
    int st = dss_calibrate(cw, c->max_iterations, &cal, &fr);
    res->fit_status = st == SUNMC_OK ? UNIT_FIT_OK : UNIT_FIT_FAILED;
    res->fit_gsl_status = fr.status;
    res->fit_iterations = (int)fr.iterations;
    double corr = NAN;
    int ci = -1, cj = -1;
    if (st == SUNMC_OK)
        dss_calib_correlation(cw, &corr, &ci, &cj); /* NaN when it cannot be formed */
    dss_par_values(c, &cal, corr, ci, cj, fr.rcond, res->par, UNIT_MAX_PAR);
    res->fit_rms = st == SUNMC_OK ? dss_calib_residual_rms(cw, &cal) * ARCSEC_PER_RAD : NAN;
    unit_phase_end(res, UNIT_PHASE_FIT, &t);

    /* validation at the lab's temperature (u itself), then at each
     * operating temperature (thermal.h) with the same calibration */
    dss_val_readings v = dss_rd_view(&w->val, rd, 0);
    int fit_ok = res->fit_status == UNIT_FIT_OK;
    const lab_onboard *ob = lab_onboard_mc_unit(&w->ob, &cal, &fit_ok);
    res->fit_status = fit_ok ? res->fit_status : UNIT_FIT_FAILED;
    dss_unit_score_validation(c, &u, &cal, ob, &v, res);
    dss_temp_ctx tc = {&dev, &cal, ob, w, rd, 1};
    thermal_validate_all(c, res, dss_validate_at, &tc);
    unit_phase_end(res, UNIT_PHASE_VALIDATION, &t);
    return SUNMC_OK;
}

static int dss_unit_run(const sunmc_config *c, long unit, void *ws, unit_result *res)
{
    dss_ws *w = ws;
    return unit_read_finish(c, unit, ws, w->rd, 0, res);
}

/* The readings depend on neither the campaign's grid and repeats nor the
 * fit (the sun simulator's measurement, calibration.sun_*, is drawn apart);
 * campaign.mount sets the sensor's mount, which they do depend on. */
static const char *const dss_readings_ignore[] = {
    "campaign.b_min_deg", "campaign.b_max_deg", "campaign.b_step_deg", "campaign.repeats",
    "calibration", "noise.encoder_arcsec", NULL};

static void dss_model_label(const sunmc_config *c, char *buf, size_t len)
{
    const dss_config *dc = dss_cfg(c);
    if (dc->cal_model == DSS_MODEL_POLYNOMIAL)
        snprintf(buf, len, "2-D polynomial of order %d in the alpha and beta errors",
                 dc->poly_order);
    else if (dc->cal_model == DSS_MODEL_SPLINE)
        snprintf(buf, len, "penalised cubic B-spline of alpha, beta over the spot x, y");
    else if (dc->cal_model == DSS_MODEL_TABLE)
        snprintf(buf, len, "look-up table of alpha, beta on a grid of the spot x, y (bilinear, "
                           "the spline's values at its nodes)");
    else
        snprintf(buf, len, "physical: principal point, height, cover glass%s, mount c1-c3%s%s%s",
                 dc->fit_glass_index ? " (thickness and index)" : " (thickness)",
                 dc->design.mount == DSS_MOUNT_ALIGNED ? " (aligned lab)"
                 : dc->sun_mode == DSS_SUN_MEASURED    ? " (sun simulator measured)"
                                                       : ", sun simulator sun_b1, sun_b2",
                 dc->design.fit_tilt ? ", detector tilt (calibration.fit_detector_tilt)" : "",
                 dc->cal_model == DSS_MODEL_HYBRID ? "; a spline of its residual over the spot"
                                                   : "");
}

/* The random inputs besides the tolerances (family.h); encoder and centroid
 * noise of the campaign share one stream. */
static const char *const dss_cal_noise_keys[] = {"noise.centroid_px", "noise.encoder_arcsec", NULL};
static const char *const dss_val_noise_keys[] = {"noise.centroid_px", NULL};
static const char *const dss_sun_keys[] = {"calibration.sun_sigma_arcsec", NULL};
/* The sun simulator's measurement is an input only when it is made. */
static int dss_sun_measured(const sunmc_config *c)
{
    const dss_config *dc = dss_cfg(c);
    return dc->sun_mode == DSS_SUN_MEASURED && dc->design.mount == DSS_MOUNT_AS_MOUNTED;
}
static const family_noise dss_random_noise[] = {
    {"campaign_noise", RNG_STREAM_CAL_NOISE, dss_cal_noise_keys, NULL, 1},
    {"validation_noise", RNG_STREAM_VAL_NOISE, dss_val_noise_keys, NULL, 0},
    {"sun_measurement", RNG_STREAM_SUN_B, dss_sun_keys, dss_sun_measured, 1},
    {NULL, 0, NULL, NULL, 0}};

const sensor_family dss_family = {
    .name = "dss",
    .description = "pinhole digital sun sensor",
    .keys = dss_keys,
    .defaults = dss_defaults,
    .sections_after_shared = dss_sections_after_shared,
    .validate = dss_config_validate,
    .alias_term = NULL,
    .rms_unit = "arcsec",
    .arcsec_per_rms_unit = 1.0,
    .rms_decimals = 2,
    .model_label = dss_model_label,
    .n_angles = dss_n_angles,
    .angle_names = dss_angle_names,
    .band_name = "field angle",
    .deviations = dss_deviation_list,
    .n_deviations = DSS_N_TOL,
    .thermal = 1,
    .noise = dss_random_noise,
    .dev_columns = dss_dev_columns,
    .par_columns = dss_par_names,
    .workspace_alloc = dss_ws_alloc,
    .workspace_bytes = dss_ws_bytes,
    .workspace_free = dss_ws_free,
    .unit_run = dss_unit_run,
    .readings_bytes = dss_readings_bytes,
    .unit_read = dss_unit_take_readings,
    .unit_finish = dss_unit_finish,
    .readings_ignore = dss_readings_ignore,
    .grid = &dss_grid,       /* dss_grid.c */
    .curve = &dss_curve,     /* dss_curve.c */
    .lab = &dss_lab, /* dss_lab.c */
};
