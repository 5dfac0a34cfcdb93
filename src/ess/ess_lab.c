/* ess_lab.c - the ESS's lab hooks (lab.h): `simulate` writes a unit's
 * campaign, truth and validation readings; `calibrate` fits turntable data
 * (ess_labfit.h); `compensate` applies params.ini. */
#include "ess_export.h"
#include "ess_labfit.h"
#include "ess_lab.h"
#include "ess_prior.h"
#include "ess_unit.h"
#include "family.h"
#include "status.h"
#include "tolerance.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- simulate ---- */

typedef struct {
    ess_deviations dev;
    ess_calib_workspace *cw;   /* the campaign as `run` fits it */
    ess_campaign_point *truth; /* and the truth behind each point */
    int gross;                 /* campaign points dropped as gross errors */
    ess_val_readings val;      /* the readings `run` validates on */
    long n_val, n_val_gross, n_val_unseen;
    int sun_y_measured;        /* calibration.sun_y = measured: */
    double sun_y_meas_arcsec;  /* the unit's measured sun-simulator tilt */
} ess_sim;

static void sim_free(void *p)
{
    ess_sim *s = p;
    if (!s)
        return;
    ess_calib_free(s->cw);
    free(s->truth);
    ess_val_free(&s->val);
    free(s);
}

static int sim_run(const sunmc_config *c, long unit, void **out, char *err, size_t errlen)
{
    size_t n = ess_campaign_size(c);
    if (n <= ESS_NP)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "the campaign has %zu points, the ess model %d parameters", n, ESS_NP);
    ess_sim *s = calloc(1, sizeof *s);
    if (!s || !(s->cw = ess_calib_alloc(n)) || !(s->truth = malloc(n * sizeof *s->truth)) ||
        ess_val_alloc(c, &s->val) != SUNMC_OK) {
        sim_free(s);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    }
    ess_unit u;
    ess_deviations_sample(c, (uint64_t)c->seed, unit, &s->dev);
    s->sun_y_measured = ess_cfg(c)->sun_y_mode == ESS_SUN_Y_MEASURED;
    s->sun_y_meas_arcsec = ess_sun_y_measured_arcsec(c, (uint64_t)c->seed, unit, &s->dev);
    ess_unit_build(c, &s->dev, &u);
    ess_unit_campaign(c, &u, unit, s->cw, s->truth, &s->gross);
    ess_unit_read_validation(c, &u, unit, &s->val);
    for (size_t i = 0; i < s->val.n; i++) {
        s->n_val_unseen += s->val.status[i] == ESS_READING_UNSEEN;
        s->n_val_gross += s->val.status[i] == ESS_READING_GROSS;
        s->n_val += s->val.status[i] == ESS_READING_OK;
    }
    *out = s;
    return SUNMC_OK;
}

/* The conventions of every file simulate writes, as '#' lines (the same
 * as README "Calibrating a real sensor" and calibrate --help). */
static void write_conventions(FILE *f)
{
    fputs("# conventions: sensor frame X across the code rows, Y along them (the sensing\n"
          "#   direction), Z the boresight; incidence = atan2(s_y, s_z) of the sun s.\n"
          "# alpha_deg = turntable inner frame, about X; beta_deg = outer frame, about Y: the sun\n"
          "#   in the sensor frame is s = R_install Rx(alpha) Ry(beta) v_sun.\n"
          "# output_deg = the raw output (coarse + fine code); truth_deg = the true incidence;\n"
          "#   compensated_deg (sunmc compensate) estimates the incidence in the sensor frame.\n"
          "# seen: the sun in front of the sensor (incidence below 89 deg); a reading whose\n"
          "#   coarse and fine codes disagree by more than half a fine period is a gross error\n"
          "#   (weight 0 in campaign.csv, left out of validation.csv).\n",
          f);
}

static void write_campaign(const ess_sim *s, const sunmc_config *c, const lab_unit_ref *ref,
                           FILE *fc, FILE *ft)
{
    const ess_config *ec = ess_cfg(c);
    fprintf(fc, "# sunmc %s simulate: unit %ld of %s (%s), seed %ld\n", SUNMC_VERSION, ref->unit,
            ref->config, c->product, c->seed);
    fprintf(fc, "# measured installation roll: calibration.roll_measured_arcsec = %.17g\n",
            s->dev.roll_measured_arcsec);
    if (s->sun_y_measured)
        fprintf(fc, "# measured sun-simulator tilt toward Y: calibration.sun_y_measured_arcsec = "
                    "%.17g\n",
                s->sun_y_meas_arcsec);
    write_conventions(fc);
    fprintf(fc, "alpha_deg,beta_deg,output_deg,weight\n");
    double dv[ESS_N_DEV];
    ess_deviations_values(&s->dev, dv);
    lab_sim_truth_head(ft, c, ref, ess_deviation_names, dv, ESS_N_DEV);
    write_conventions(ft);
    fprintf(ft, "alpha_deg,beta_deg,alpha_true_deg,beta_true_deg,incidence_deg,output_deg,seen\n");
    long na = grid_count(ec->cal_alpha_min_deg, ec->cal_alpha_max_deg, ec->cal_alpha_step_deg, 0);
    const ess_calib_workspace *cw = s->cw;
    for (size_t i = 0; i < cw->n; i++) {
        const ess_campaign_point *p = &s->truth[i];
        /* The recorded angles as the campaign computes them, so that
         * reading them back gives the very same radians. */
        double a_deg = ec->cal_alpha_min_deg + (double)((long)i % na) * ec->cal_alpha_step_deg;
        double b_deg = ec->cal_beta_deg.v[(long)i / na];
        fprintf(fc, "%.17g,%.17g,%.17g,%g\n", a_deg, b_deg, cw->raw_rad[i] * DEG_PER_RAD,
                cw->weight[i]);
        fprintf(ft, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n", a_deg, b_deg,
                p->a_true_rad * DEG_PER_RAD, p->b_true_rad * DEG_PER_RAD,
                p->incidence_rad * DEG_PER_RAD, cw->raw_rad[i] * DEG_PER_RAD, p->seen);
    }
}

static int sim_write(const void *p, const sunmc_config *c, const lab_unit_ref *ref,
                     FILE *const f[LAB_SIM_FILES])
{
    const ess_sim *s = p;
    write_campaign(s, c, ref, f[0], f[1]);
    FILE *fv = f[2];
    fprintf(fv, "# sunmc %s simulate: validation readings of unit %ld of %s, seed %ld;\n"
                "# %ld readings off the truth by more than half a fine period and %ld with "
                "the sun unseen are left out, as in `run`\n",
            SUNMC_VERSION, ref->unit, ref->config, c->seed, s->n_val_gross, s->n_val_unseen);
    write_conventions(fv);
    fprintf(fv, "alpha_deg,beta_deg,output_deg,truth_deg\n");
    const ess_val_readings *v = &s->val;
    for (size_t i = 0; i < v->n; i++)
        if (v->status[i] == ESS_READING_OK)
            fprintf(fv, "%.17g,%.17g,%.17g,%.17g\n", v->alpha_rad[i] * DEG_PER_RAD,
                    v->beta_rad[i] * DEG_PER_RAD, v->raw_rad[i] * DEG_PER_RAD,
                    v->truth_rad[i] * DEG_PER_RAD);
    return SUNMC_OK;
}

static void sim_summary(const void *p, const sunmc_config *c, const lab_unit_ref *ref, char *buf,
                        size_t len)
{
    const ess_sim *s = p;
    char sun_y[128] = "";
    if (s->sun_y_measured)
        snprintf(sun_y, sizeof sun_y,
                 " --set calibration.sun_y=measured --set calibration.sun_y_measured_arcsec=%.17g",
                 s->sun_y_meas_arcsec);
    snprintf(buf, len,
             "unit %ld of %s (seed %ld): %zu campaign points (%d dropped as gross errors), "
             "%ld validation readings\n"
             "wrote %s/campaign.csv, %s/truth.csv, %s/validation.csv\n"
             "calibrate with the unit's measured %s:\n"
             "  sunmc calibrate --config %s --set "
             "calibration.roll_measured_arcsec=%.17g%s %s/campaign.csv --out DIR\n",
             ref->unit, c->product, c->seed, s->cw->n, s->gross, s->n_val, ref->out_dir,
             ref->out_dir, ref->out_dir, s->sun_y_measured ? "roll and sun tilt" : "roll",
             ref->config, s->dev.roll_measured_arcsec, sun_y, ref->out_dir);
}

/* ---- calibrate ---- */

/* calibrate --help and compensate --help (family_lab.cal_help, comp_help). */
static const char cal_help[] =
    "       (turntable inner/outer angle, raw output); alpha = inner frame about the\n"
    "       sensor's X (across the code rows), beta = outer frame about Y: sun s =\n"
    "       R_install Rx(alpha) Ry(beta) v_sun; output = raw incidence atan2(s_y, s_z) with\n"
    "       its errors; gross errors (codes off by > half a fine period) must be dropped\n"
    "       (weight 0); the known installation roll is calibration.roll_measured_arcsec\n"
    "       (default 0); calibration.model = paper (eq. 12 + k sin(4 pi alpha + t)) or\n"
    "       extended (the fine period's 1st, 2nd and incidence-dependent 4th harmonics,\n"
    "       eq. 7 exact); the report compares both by cross-validation and recommends one\n";
static const char comp_help[] =
    "       compensated_deg: the incidence atan2(s_y, s_z) in the sensor frame\n";

static const char *const cal_columns[] = {"alpha_deg", "beta_deg", "output_deg", "weight", NULL};

/* ---- calibrate: what the data must look like (lab_check_data) ---- */

/* The fit's eight parameters need as many distinct alphas and more; one
 * beta is enough to fit. */
static const int cal_min_distinct[] = {ESS_NP + 1, 1};

static void cal_campaign_range(const sunmc_config *c, int k, double *lo, double *hi)
{
    const ess_config *e = ess_cfg(c);
    if (k == 0) {
        *lo = e->cal_alpha_min_deg;
        *hi = e->cal_alpha_max_deg;
        return;
    }
    *lo = INFINITY;
    *hi = -INFINITY;
    for (int i = 0; i < e->cal_beta_deg.n; i++) {
        *lo = fmin(*lo, e->cal_beta_deg.v[i]);
        *hi = fmax(*hi, e->cal_beta_deg.v[i]);
    }
}

/* What the deviation list leaves out of a reading's spread: the fine
 * code's ripple, the noise and the gross margins (deg). */
#define ESS_PREDICT_BASE_DEG 0.5
static const double cal_margin[] = {ESS_PREDICT_BASE_DEG};

/* A unit with deviations dev_values (list order), installed on the table
 * as the Monte Carlo installs it. */
static void cal_unit_build(const sunmc_config *c, const double *dev_values, void *unit)
{
    ess_deviations dev;
    memset(&dev, 0, sizeof dev);
    deviations_set_values(ess_deviation_list, ESS_N_TOL, dev_values, &dev);
    ess_unit_build(c, &dev, unit);
}

/* Its raw output (deg) at table angles in_deg, noiseless. */
static int cal_unit_read(const sunmc_config *c, const void *unit, const double *in, double *out)
{
    double raw, truth;
    int st = ess_unit_read(unit, in[0] * RAD_PER_DEG, in[1] * RAD_PER_DEG, NULL, &raw, &truth);
    out[0] = raw * DEG_PER_RAD;
    return st;
}

typedef struct {
    ess_calib_workspace *cw;
    const int *line;
    ess_labfit_result res;
} ess_cal;

static size_t cal_min_rows(const sunmc_config *c, char *why, size_t len)
{
    int kind = ess_cfg(c)->cal_model;
    int np = ess_model_np(kind) - (ess_cfg(c)->sun_y_mode == ESS_SUN_Y_MEASURED);
    if (ESS_MODEL_HAS_SPLINE(kind) && np < ESS_SPLINE_MIN_ROWS - 1)
        np = ESS_SPLINE_MIN_ROWS - 1;
    static const char *const what[ESS_N_MODELS] = {"", "extended ", "spline ", "hybrid ",
                                                    "table "};
    snprintf(why, len, "the ess %smodel has %d parameters: need at least %d rows", what[kind], np,
             np + 1);
    return (size_t)np + 1;
}

static void cal_free(void *p)
{
    ess_cal *k = p;
    if (k)
        ess_calib_free(k->cw);
    free(k);
}

static int cal_run(const sunmc_config *c, const lab_columns *d, void **out, calreport *rep,
                   char *err, size_t errlen)
{
    ess_cal *k = calloc(1, sizeof *k);
    if (k)
        k->cw = ess_calib_alloc_fix(d->n, ess_cfg(c)->cal_model,
                                    ess_cfg(c)->sun_y_mode == ESS_SUN_Y_MEASURED);
    if (!k || !k->cw) {
        cal_free(k);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    }
    k->line = d->line;
    for (size_t i = 0; i < d->n; i++) {
        k->cw->alpha_rad[i] = d->v[0][i] * RAD_PER_DEG;
        k->cw->beta_rad[i] = d->v[1][i] * RAD_PER_DEG;
        k->cw->raw_rad[i] = d->v[2][i] * RAD_PER_DEG;
        k->cw->weight[i] = d->v[3][i];
    }
    int st = ess_labfit_run(c, k->cw, k->line, &k->res, rep, err, errlen);
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
    const ess_cal *k = p;
    return ess_params_fill(pf, &k->res, rep, ess_cfg(c)->design.theta0_deg);
}

static int write_residuals(const void *p, FILE *f)
{
    const ess_cal *k = p;
    return ess_labfit_write_residuals(f, k->cw, k->line, &k->res.m);
}

/* Row i's angle error (lab_drift): the ESS measures alpha only, so its
 * error stands for both directions (a campaign sweeps alpha). */
static int cal_row_error(const void *p, size_t i, double e[2])
{
    const ess_cal *k = p;
    const ess_calib_workspace *cw = k->cw;
    if (!(cw->weight[i] > 0) ||
        ess_angle_error(&k->res.m, cw->alpha_rad[i], cw->beta_rad[i], cw->raw_rad[i], &e[0]) !=
            SUNMC_OK)
        return SUNMC_EDOM;
    e[1] = e[0];
    return SUNMC_OK;
}

static const char *const extra_files[] = {"field.tsv", NULL};

/* field.tsv: the propagated sigma over the campaign's alpha range (the
 * config's, widened to the data's). */
static int write_extra(const void *p, const sunmc_config *c, int which, FILE *f)
{
    const ess_cal *k = p;
    const ess_config *ec = ess_cfg(c);
    double amin = ec->cal_alpha_min_deg, amax = ec->cal_alpha_max_deg;
    for (size_t i = 0; i < k->cw->n; i++) {
        amin = fmin(amin, k->cw->alpha_rad[i] * DEG_PER_RAD);
        amax = fmax(amax, k->cw->alpha_rad[i] * DEG_PER_RAD);
    }
    return ess_labfit_write_field(f, &k->res, amin, amax);
}

/* ---- compensate ---- */

static const char *const raw_columns[] = {"output_deg", NULL};
static const char *const comp_columns[] = {"compensated_deg", NULL};

/* The paper's model and the extended one; only the extended has the
 * fine code's cos-4 terms. */
static const lab_params_model params_models[] = {
    {ESS_CALFIT_MODEL, "design parameters fixed derived", NULL, NULL, NULL},
    {ESS_CALFIT_MODEL_EXT, "design parameters fixed derived", "parameters", "ks_cos4_deg", NULL},
    {ESS_CALFIT_MODEL_SPLINE, "design parameters fixed derived spline", "spline", "breakpoints",
     NULL},
    {ESS_CALFIT_MODEL_HYBRID, "design parameters fixed derived correction", "correction",
     "breakpoints", ESS_CALFIT_MODEL},
    {ESS_CALFIT_MODEL_TABLE, "design parameters fixed derived table", "table", "nodes", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static int params_load(const params_file *p, void *model, char *err, size_t errlen)
{
    return ess_params_load(p, model, err, errlen);
}

/* An ESS encodes the incidence's tangent: no output reaches +-90 deg, and
 * an inverse that lands there (the tangent wrapped) is no angle the sensor
 * saw.  Such readings are marked, never turned into a plausible angle. */
#define ESS_OUTPUT_LIMIT_DEG 90.0

static int reading_check(const void *model, const double *raw)
{
    return fabs(raw[0]) < ESS_OUTPUT_LIMIT_DEG ? LAB_READING_OK : LAB_OUTSIDE_RANGE;
}

static int compensate(const void *model, const double *raw, double *comp_rad)
{
    int st = ess_model_compensate(model, raw[0] * RAD_PER_DEG, &comp_rad[0]);
    if (st == SUNMC_OK && !(fabs(comp_rad[0]) < ESS_OUTPUT_LIMIT_DEG * RAD_PER_DEG))
        return SUNMC_EDOM;
    return st;
}

/* The roll is fixed, not fitted (ess_calib.h): a rotation about X is
 * eq. 12's a = d, b = -c, so no turntable data separate them. */
static const lab_measured_key cal_measured[] = {
    {"calibration", "roll_measured_arcsec",
     "the fit fixes the installation roll at this measured value (a roll about X is eq. 12's "
     "a = d, b = -c: no turntable data separate them), so the unit's real roll goes into b and "
     "c, and every compensated angle is off by the difference between the real roll and this value",
     "measure the roll of the mounted unit (e.g. against its alignment cube) and give it: "
     "--set calibration.roll_measured_arcsec=VALUE (`sunmc simulate` prints a simulated unit's "
     "value); set it explicitly, even to 0, to say it was measured"},
    {NULL, NULL, NULL, NULL},
};

/* The output angle written in radians, arcmin or arcsec (lab_check). */
static int cal_output_units(const sunmc_config *c, double *factor, const char **what, int max)
{
    static const char *const names[] = {"radians", "arcmin", "arcsec"};
    const double f[] = {DEG_PER_RAD, 1.0 / 60.0, 1.0 / ARCSEC_PER_DEG};
    int n = max < 3 ? max : 3;
    for (int u = 0; u < n; u++) {
        factor[u] = f[u];
        what[u] = names[u];
    }
    return n;
}

const family_lab ess_lab = {
    .sim_run = sim_run,
    .sim_write = sim_write,
    .sim_summary = sim_summary,
    .sim_free = sim_free,
    .cal_columns = cal_columns,
    .cal_help = cal_help,
    .cal_min_rows = cal_min_rows,
    .cal_run = cal_run,
    .cal_n_inputs = 2,
    .cal_output_units = cal_output_units,
    .cal_min_distinct = cal_min_distinct,
    .cal_campaign_range = cal_campaign_range,
    .cal_unit_bytes = sizeof(ess_unit),
    .cal_unit_build = cal_unit_build,
    .cal_unit_read = cal_unit_read,
    .cal_predict_margin = cal_margin,
    .cal_noise_arcsec = ess_reading_noise_arcsec, /* ess_prior.h */
    .cal_measured = cal_measured,
    .params_title = "sunmc calibration of an encoded sun sensor (ESS paper eq. 12-14):\n"
                    "read by `sunmc compensate`; units are in the key names, standard "
                    "errors in the comments",
    .params_fill = params_fill,
    .write_residuals = write_residuals,
    .cal_row_error = cal_row_error,
    .extra_files = extra_files,
    .write_extra = write_extra,
    .cal_models_tsv = 1,
    .cal_free = cal_free,
    .raw_columns = raw_columns,
    .comp_columns = comp_columns,
    .comp_help = comp_help,
    .comp_fail_note = "the model is not invertible there",
    .reading_check = reading_check,
    .params_models = params_models,
    .model_size = sizeof(ess_model),
    .params_load = params_load,
    .compensate = compensate,
    .export = &ess_export,
};
