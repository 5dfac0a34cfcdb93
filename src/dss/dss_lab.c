/* dss_lab.c - the DSS's lab hooks (lab.h): `simulate` writes a unit's
 * campaign, truth and validation readings; `calibrate` fits rotary-table
 * data (dss_calfit.h); `compensate` applies params.ini. */
#include "dss_calfit.h"
#include "dss_lab.h"
#include "dss_simulate.h"
#include "dss_unit.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- simulate ---- */

typedef struct {
    dss_deviations dev;
    size_t n, nv, n_spot;
    /* campaign, b1 varying slowest (dss_unit_campaign) */
    double *b1_rad, *b2_rad, *x_px, *y_px, *weight, *truth_a_rad, *truth_b_rad;
    /* validation (dss_validation_readings) */
    double *vb1_rad, *vb2_rad, *vx_px, *vy_px, *vtruth_a_rad, *vtruth_b_rad;
    int *vseen;
    long n_val;
} dss_sim;

static void sim_free(void *p)
{
    dss_sim *s = p;
    if (!s)
        return;
    double *arrays[] = {s->b1_rad, s->b2_rad, s->x_px, s->y_px, s->weight, s->truth_a_rad,
                        s->truth_b_rad, s->vb1_rad, s->vb2_rad, s->vx_px, s->vy_px,
                        s->vtruth_a_rad, s->vtruth_b_rad};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++)
        free(arrays[k]);
    free(s->vseen);
    free(s);
}

static dss_sim *sim_alloc(size_t n, size_t nv)
{
    dss_sim *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->n = n;
    s->nv = nv;
    double **camp[] = {&s->b1_rad, &s->b2_rad, &s->x_px, &s->y_px, &s->weight, &s->truth_a_rad,
                       &s->truth_b_rad};
    double **val[] = {&s->vb1_rad, &s->vb2_rad, &s->vx_px, &s->vy_px, &s->vtruth_a_rad,
                      &s->vtruth_b_rad};
    int ok = 1;
    for (size_t k = 0; k < sizeof camp / sizeof camp[0]; k++)
        ok &= (*camp[k] = malloc((n + 1) * sizeof(double))) != NULL;
    for (size_t k = 0; k < sizeof val / sizeof val[0]; k++)
        ok &= (*val[k] = malloc((nv + 1) * sizeof(double))) != NULL;
    ok &= (s->vseen = malloc((nv + 1) * sizeof(int))) != NULL;
    if (ok)
        return s;
    sim_free(s);
    return NULL;
}

static int sim_run(const sunmc_config *c, long unit, void **out, char *err, size_t errlen)
{
    dss_sim *s = sim_alloc(dss_campaign_size(c), dss_validation_size(c));
    if (!s)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    dss_unit u;
    dss_deviations_sample(c, (uint64_t)c->seed, unit, &s->dev);
    dss_unit_build(c, &s->dev, &u);
    s->n_spot = dss_unit_campaign(c, &u, unit, s->b1_rad, s->b2_rad, s->x_px, s->y_px, s->weight,
                                  s->truth_a_rad, s->truth_b_rad);
    dss_validation_readings(c, &u, unit, s->vb1_rad, s->vb2_rad, s->vx_px, s->vy_px,
                            s->vtruth_a_rad, s->vtruth_b_rad, s->vseen);
    for (size_t i = 0; i < s->nv; i++)
        s->n_val += s->vseen[i];
    *out = s;
    return SUNMC_OK;
}

static void write_campaign(const dss_sim *s, const sunmc_config *c, const lab_unit_ref *ref,
                           FILE *fc, FILE *ft)
{
    const dss_config *dc = dss_cfg(c);
    long nb = grid_count(dc->cal_b_min_deg, dc->cal_b_max_deg, dc->cal_b_step_deg, 0);
    fprintf(fc, "# sunmc %s simulate: unit %ld of %s (%s), seed %ld; weight 0: no spot\n",
            SUNMC_VERSION, ref->unit, ref->config, c->product, c->seed);
    fprintf(fc, "b1_deg,b2_deg,x_px,y_px,weight\n");
    fprintf(ft, "# sunmc %s simulate: truth of unit %ld of %s, seed %ld\n", SUNMC_VERSION,
            ref->unit, ref->config, c->seed);
    double dv[DSS_N_DEV];
    dss_deviations_values(&s->dev, dv);
    for (int i = 0; i < DSS_N_DEV; i++)
        fprintf(ft, "# %s = %.17g\n", dss_deviation_names[i], dv[i]);
    fprintf(ft, "b1_deg,b2_deg,truth_alpha_deg,truth_beta_deg,seen\n");
    for (size_t i = 0; i < s->n; i++) {
        /* b1 varies slowest; the degrees as the campaign computes them. */
        double b1 = dc->cal_b_min_deg + (double)((long)i / nb) * dc->cal_b_step_deg;
        double b2 = dc->cal_b_min_deg + (double)((long)i % nb) * dc->cal_b_step_deg;
        int spot = s->weight[i] > 0 && isfinite(s->x_px[i]) && isfinite(s->y_px[i]);
        fprintf(fc, "%.17g,%.17g,%.17g,%.17g,%g\n", b1, b2, spot ? s->x_px[i] : 0.0,
                spot ? s->y_px[i] : 0.0, spot ? s->weight[i] : 0.0);
        fprintf(ft, "%.17g,%.17g,%.17g,%.17g,%d\n", b1, b2, s->truth_a_rad[i] * DEG_PER_RAD,
                s->truth_b_rad[i] * DEG_PER_RAD, spot);
    }
}

static int sim_write(const void *p, const sunmc_config *c, const lab_unit_ref *ref,
                     FILE *const f[LAB_SIM_FILES])
{
    const dss_sim *s = p;
    write_campaign(s, c, ref, f[0], f[1]);
    FILE *fv = f[2];
    fprintf(fv, "# sunmc %s simulate: validation readings of unit %ld of %s, seed %ld; table "
                "at exactly b1, b2; %ld points without a spot left out, as in `run`\n",
            SUNMC_VERSION, ref->unit, ref->config, c->seed, (long)s->nv - s->n_val);
    fprintf(fv, "b1_deg,b2_deg,x_px,y_px,truth_alpha_deg,truth_beta_deg\n");
    for (size_t i = 0; i < s->nv; i++)
        if (s->vseen[i])
            fprintf(fv, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", s->vb1_rad[i] * DEG_PER_RAD,
                    s->vb2_rad[i] * DEG_PER_RAD, s->vx_px[i], s->vy_px[i],
                    s->vtruth_a_rad[i] * DEG_PER_RAD, s->vtruth_b_rad[i] * DEG_PER_RAD);
    return SUNMC_OK;
}

static void sim_summary(const void *p, const sunmc_config *c, const lab_unit_ref *ref, char *buf,
                        size_t len)
{
    const dss_sim *s = p;
    snprintf(buf, len,
             "unit %ld of %s (seed %ld): %zu campaign readings (%zu with a spot), %ld "
             "validation readings\n"
             "wrote %s/campaign.csv, %s/truth.csv, %s/validation.csv\n",
             ref->unit, c->product, c->seed, s->n, s->n_spot, s->n_val, ref->out_dir,
             ref->out_dir, ref->out_dir);
}

/* ---- calibrate ---- */

static const char *const cal_columns[] = {"b1_deg", "b2_deg", "x_px", "y_px", "weight", NULL};

typedef struct {
    dss_calib_workspace *cw;
    const int *line;
    dss_calibration cal;
} dss_cal;

static int model_params(const sunmc_config *c)
{
    const dss_config *dc = dss_cfg(c);
    return dc->cal_model == DSS_MODEL_PHYSICAL ? DSS_NP : dss_poly_n_terms(dc->poly_order);
}

static size_t cal_min_rows(const sunmc_config *c, char *why, size_t len)
{
    int np = model_params(c);
    snprintf(why, len, "the dss model has up to %d parameters: need at least %d rows", np, np + 1);
    return (size_t)np + 1;
}

static void cal_free(void *p)
{
    dss_cal *k = p;
    if (k)
        dss_calib_free(k->cw);
    free(k);
}

static int cal_run(const sunmc_config *c, const lab_columns *d, void **out, calreport *rep,
                   char *err, size_t errlen)
{
    const dss_config *dc = dss_cfg(c);
    dss_cal *k = calloc(1, sizeof *k);
    if (k)
        k->cw = dss_calib_alloc(&dc->design, d->n, dc->cal_model, dc->poly_order,
                                dc->fit_glass_index);
    if (!k || !k->cw) {
        cal_free(k);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "cannot set up the fit");
    }
    k->line = d->line;
    for (size_t i = 0; i < d->n; i++) {
        k->cw->b1_rad[i] = d->v[0][i] * RAD_PER_DEG;
        k->cw->b2_rad[i] = d->v[1][i] * RAD_PER_DEG;
        k->cw->x_px[i] = d->v[2][i];
        k->cw->y_px[i] = d->v[3][i];
        k->cw->weight[i] = d->v[4][i];
    }
    int st = dss_calfit_run(c, k->cw, &k->cal, rep, err, errlen);
    if (st != SUNMC_OK) {
        cal_free(k);
        return st;
    }
    *out = k;
    return SUNMC_OK;
}

static int params_fill(const void *p, const sunmc_config *c, const calreport *rep,
                       params_file *pf)
{
    return dss_params_fill(pf, &((const dss_cal *)p)->cal, rep);
}

static int write_residuals(const void *p, FILE *f)
{
    const dss_cal *k = p;
    return dss_calfit_write_residuals(f, k->cw, k->line, &k->cal);
}

/* ---- compensate ---- */

static const char *const raw_columns[] = {"x_px", "y_px", NULL};
static const char *const comp_columns[] = {"compensated_alpha_deg", "compensated_beta_deg", NULL};

static int params_load(const params_file *p, void *model, char *err, size_t errlen)
{
    return dss_params_load(p, model, err, errlen);
}

static int compensate(const void *model, const double *raw, double *comp_rad)
{
    return dss_compensate(model, raw[0], raw[1], &comp_rad[0], &comp_rad[1]);
}

const family_lab dss_lab = {
    .sim_run = sim_run,
    .sim_write = sim_write,
    .sim_summary = sim_summary,
    .sim_free = sim_free,
    .cal_columns = cal_columns,
    .cal_min_rows = cal_min_rows,
    .cal_run = cal_run,
    .params_title = "sunmc calibration of a pinhole digital sun sensor (DSS paper):\n"
                    "read by `sunmc compensate`; units are in the key names",
    .params_fill = params_fill,
    .write_residuals = write_residuals,
    .extra_files = NULL,
    .write_extra = NULL,
    .cal_free = cal_free,
    .raw_columns = raw_columns,
    .comp_columns = comp_columns,
    .comp_fail_note = NULL,
    .model_size = sizeof(dss_calibration),
    .params_load = params_load,
    .compensate = compensate,
};
