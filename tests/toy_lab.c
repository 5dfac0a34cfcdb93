/* toy_lab.c - the toy family's lab hooks (lab.h): simulate writes the toy's
 * campaign and validation readings, calibrate fits the straight line
 * (weighted least squares, cross-validated by the sign of alpha),
 * compensate inverts it.  Proof that a family's lab commands need no code
 * in cli or core. */
#include "lab.h"
#include "status.h"
#include "toy_family.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TOY_NP 2
#define TOY_MODEL "toy_line"

/* ---- simulate ---- */

typedef struct {
    long n, nv;
    double *a, *y, *va, *vy; /* campaign and validation: alphas and readings, rad */
} toy_sim;

static void sim_free(void *p)
{
    toy_sim *s = p;
    if (s)
        free(s->a);
    free(s);
}

static int sim_run(const sunmc_config *c, long unit, void **out, char *err, size_t errlen)
{
    toy_sim *s = calloc(1, sizeof *s);
    if (s) {
        s->n = toy_cal_count(c);
        s->nv = toy_val_count(c);
        s->a = malloc(2 * (size_t)(s->n + s->nv) * sizeof(double));
    }
    if (!s || !s->a) {
        sim_free(s);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    }
    s->y = s->a + s->n;
    s->va = s->y + s->n;
    s->vy = s->va + s->nv;
    toy_deviations d;
    toy_sample(c, unit, &d);
    toy_campaign(c, &d, unit, s->a, s->y);
    toy_validation(c, &d, unit, s->va, s->vy);
    *out = s;
    return SUNMC_OK;
}

static int sim_write(const void *p, const sunmc_config *c, const lab_unit_ref *ref,
                     FILE *const f[LAB_SIM_FILES])
{
    const toy_sim *s = p;
    fprintf(f[0], "alpha_deg,reading_deg,weight\n");
    fprintf(f[1], "alpha_deg\n");
    for (long i = 0; i < s->n; i++) {
        fprintf(f[0], "%.17g,%.17g,1\n", s->a[i] * DEG_PER_RAD, s->y[i] * DEG_PER_RAD);
        fprintf(f[1], "%.17g\n", s->a[i] * DEG_PER_RAD);
    }
    fprintf(f[2], "alpha_deg,reading_deg,truth_deg\n");
    for (long i = 0; i < s->nv; i++)
        fprintf(f[2], "%.17g,%.17g,%.17g\n", s->va[i] * DEG_PER_RAD, s->vy[i] * DEG_PER_RAD,
                s->va[i] * DEG_PER_RAD);
    return SUNMC_OK;
}

static void sim_summary(const void *p, const sunmc_config *c, const lab_unit_ref *ref, char *buf,
                        size_t len)
{
    const toy_sim *s = p;
    snprintf(buf, len, "toy unit %ld: %ld campaign readings, %ld validation readings\n",
             ref->unit, s->n, s->nv);
}

/* ---- calibrate ---- */

static const char *const cal_columns[] = {"alpha_deg", "reading_deg", "weight", NULL};

/* ---- the lab prediction: a unit is its deviations (lab_predict.c) ---- */

/* What the deviation list leaves out of a reading's spread (deg). */
static const double cal_margin[] = {0.01};

static void cal_unit_build(const sunmc_config *c, const double *dev_values, void *unit)
{
    memset(unit, 0, sizeof(toy_deviations));
    deviations_set_values(toy_family.deviations, toy_family.n_deviations, dev_values, unit);
}

static int cal_unit_read(const sunmc_config *c, const void *unit, const double *in, double *out)
{
    out[0] = toy_read_rad(unit, in[0] * RAD_PER_DEG, 0) * DEG_PER_RAD;
    return SUNMC_OK;
}

typedef struct {
    const lab_columns *d;
    double *a, *y, *w;  /* rad, rad, weight */
    double p[TOY_NP];   /* reading = p[0] + p[1] alpha, rad */
} toy_cal;

static void cal_free(void *p)
{
    toy_cal *k = p;
    if (k)
        free(k->a);
    free(k);
}

static size_t cal_min_rows(const sunmc_config *c, char *why, size_t len)
{
    snprintf(why, len, "the toy model has %d parameters: need at least %d rows", TOY_NP,
             TOY_NP + 1);
    return TOY_NP + 1;
}

/* Sum of squared angle errors (rad^2) of line p over rows with use[i] > 0. */
static double angle_sum2(const toy_cal *k, const double *use, const double p[TOY_NP], long *n)
{
    double s = 0;
    *n = 0;
    for (size_t i = 0; i < k->d->n; i++)
        if (use[i] > 0) {
            double e = (k->y[i] - p[0]) / p[1] - k->a[i];
            s += e * e;
            (*n)++;
        }
    return s;
}

static int sign_fold(const void *ctx, size_t i) { return ((const toy_cal *)ctx)->a[i] >= 0; }

static void sign_label(const void *ctx, int k, char *buf, size_t len)
{
    snprintf(buf, len, "%s", k ? "alpha>=0" : "alpha<0");
}

static int sign_refit(void *ctx, const double *held, double sum2[2], long n[2], double *cond)
{
    (void)cond; /* a closed-form line fit: no Jacobian condition */
    toy_cal *k = ctx;
    double p[TOY_NP];
    toy_line_fit((long)k->d->n, k->a, k->y, k->w, p);
    sum2[0] = angle_sum2(k, k->w, p, &n[0]);
    sum2[1] = angle_sum2(k, held, p, &n[1]);
    return isfinite(p[1]) && p[1] != 0;
}

/* The report: the two parameters, the residual per band, cross-validation. */
static void toy_report(const sunmc_config *c, toy_cal *k, calreport *rep)
{
    rep->n_rows = k->d->n;
    rep->n_angles = 1;
    rep->angle_name[0] = "alpha";
    rep->bands = c->bands_deg;
    rep->np = TOY_NP;
    snprintf(rep->name[0], sizeof rep->name[0], "p0_arcsec");
    snprintf(rep->name[1], sizeof rep->name[1], "p1");
    rep->value[0] = k->p[0] * ARCSEC_PER_RAD;
    rep->value[1] = k->p[1];
    rep->se[0] = rep->se[1] = NAN;
    long n;
    double s2 = angle_sum2(k, k->w, k->p, &n);
    rep->dof = (int)rep->n_used - TOY_NP;
    rep->sigma_arcsec = sqrt(s2 / rep->dof) * ARCSEC_PER_RAD;
    band_acc acc;
    band_acc_reset(&acc);
    for (size_t i = 0; i < k->d->n; i++)
        if (k->w[i] > 0)
            band_acc_add(&acc, &c->bands_deg, fabs(k->a[i]) * DEG_PER_RAD,
                         (k->y[i] - k->p[0]) / k->p[1] - k->a[i]);
    band_acc_rms(&acc, &c->bands_deg, ARCSEC_PER_RAD, rep->resid_rms[0]);
    for (int b = 0; b < c->bands_deg.n; b++) {
        rep->band_n[0][b] = acc.n[b];
        rep->cal_sigma_rms[0][b] = rep->cal_sigma_max[0][b] = NAN;
    }
    calreport_predict(rep, 0, sqrt((double)rep->n_used / rep->dof));
    lab_folds folds = {.n_folds = 2, .min_fit_rows = TOY_NP, .fold_of = sign_fold,
                       .label = sign_label, .refit = sign_refit};
    lab_cross_validate(rep, k->w, k->d->n, &folds, k);
}

static int cal_run(const sunmc_config *c, const lab_columns *d, void **out, calreport *rep,
                   char *err, size_t errlen)
{
    toy_cal *k = calloc(1, sizeof *k);
    if (k)
        k->a = malloc(3 * (d->n + 1) * sizeof(double));
    if (!k || !k->a) {
        cal_free(k);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    }
    k->d = d;
    k->y = k->a + d->n + 1;
    k->w = k->y + d->n + 1;
    calreport_init(rep, "toy", TOY_MODEL);
    for (size_t i = 0; i < d->n; i++) {
        k->a[i] = d->v[0][i] * RAD_PER_DEG;
        k->y[i] = d->v[1][i] * RAD_PER_DEG;
        k->w[i] = d->v[2][i];
        rep->n_used += k->w[i] > 0;
    }
    if (rep->n_used <= TOY_NP) {
        cal_free(k);
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "only %zu usable rows", rep->n_used);
    }
    toy_line_fit((long)d->n, k->a, k->y, k->w, k->p);
    rep->fit_ok = isfinite(k->p[1]) && k->p[1] != 0;
    toy_report(c, k, rep);
    *out = k;
    return SUNMC_OK;
}

static int params_fill(const void *p, const sunmc_config *c, const calreport *rep,
                       params_file *pf)
{
    const toy_cal *k = p;
    int st = params_set_double(pf, "parameters", "p0_arcsec", k->p[0] * ARCSEC_PER_RAD, NULL);
    if (st == SUNMC_OK)
        st = params_set_double(pf, "parameters", "p1", k->p[1], NULL);
    return st;
}

static int write_residuals(const void *p, FILE *f)
{
    const toy_cal *k = p;
    fprintf(f, "line\talpha_deg\treading_deg\tweight\tangle_error_arcsec\n");
    for (size_t i = 0; i < k->d->n; i++)
        fprintf(f, "%d\t%.10g\t%.10g\t%g\t%.6g\n", k->d->line[i], k->a[i] * DEG_PER_RAD,
                k->y[i] * DEG_PER_RAD, k->w[i],
                ((k->y[i] - k->p[0]) / k->p[1] - k->a[i]) * ARCSEC_PER_RAD);
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

/* ---- compensate ---- */

static const char *const raw_columns[] = {"reading_deg", NULL};
static const char *const comp_columns[] = {"compensated_deg", NULL};

static int params_load(const params_file *p, void *model, char *err, size_t errlen)
{
    double *q = model;
    int st = params_get_double(p, "parameters", "p0_arcsec", &q[0], err, errlen);
    if (st == SUNMC_OK)
        st = params_get_double(p, "parameters", "p1", &q[1], err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "parameters", "p1", q[1] != 0, "not 0", err, errlen);
    q[0] *= RAD_PER_ARCSEC;
    return st;
}

static int compensate(const void *model, const double *raw, double *comp_rad)
{
    const double *q = model;
    comp_rad[0] = (raw[0] * RAD_PER_DEG - q[0]) / q[1];
    return isfinite(comp_rad[0]) ? SUNMC_OK : SUNMC_EDOM;
}

const family_lab toy_lab = {
    .sim_run = sim_run,
    .sim_write = sim_write,
    .sim_summary = sim_summary,
    .sim_free = sim_free,
    .cal_columns = cal_columns,
    .cal_n_inputs = 1,
    .cal_unit_bytes = sizeof(toy_deviations),
    .cal_unit_build = cal_unit_build,
    .cal_unit_read = cal_unit_read,
    .cal_predict_margin = cal_margin,
    .cal_min_rows = cal_min_rows,
    .cal_run = cal_run,
    .params_title = "sunmc calibration of the test-only toy sensor",
    .params_fill = params_fill,
    .write_residuals = write_residuals,
    .cal_free = cal_free,
    .raw_columns = raw_columns,
    .comp_columns = comp_columns,
    .model_size = 2 * sizeof(double),
    .params_load = params_load,
    .compensate = compensate,
};
