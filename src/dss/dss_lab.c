/* dss_lab.c - the DSS's lab hooks (lab.h): `simulate` writes a unit's
 * campaign, truth and validation readings; `calibrate` fits rotary-table
 * data (dss_labfit.h); `compensate` applies params.ini. */
#include "dss_labfit.h"
#include "dss_export.h"
#include "dss_lab.h"
#include "dss_unit.h"
#include "family.h"
#include "dss_sensor.h"
#include "status.h"
#include "tolerance.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- simulate ---- */

/* The campaign's columns (dss_unit_campaign), b1 varying slowest. */
enum { C_B1, C_B2, C_X, C_Y, C_WEIGHT, C_TRUTH_A, C_TRUTH_B, C_COLUMNS };

typedef struct {
    dss_deviations dev;
    size_t n, n_spot;
    double *col[C_COLUMNS];  /* the campaign as `run` fits it, and its truth */
    dss_val_readings val;    /* the readings `run` validates on */
    long n_val;
    int sun_measured;        /* calibration.sun = measured: */
    double sun_meas_arcsec[2]; /* the unit's measured sun_b1, sun_b2 */
} dss_sim;

static void sim_free(void *p)
{
    dss_sim *s = p;
    if (!s)
        return;
    for (int k = 0; k < C_COLUMNS; k++)
        free(s->col[k]);
    dss_val_free(&s->val);
    free(s);
}

static int sim_run(const sunmc_config *c, long unit, void **out, char *err, size_t errlen)
{
    dss_sim *s = calloc(1, sizeof *s);
    int ok = s && dss_val_alloc(c, &s->val) == SUNMC_OK;
    if (s)
        s->n = dss_campaign_size(c);
    for (int k = 0; ok && k < C_COLUMNS; k++)
        ok = (s->col[k] = malloc((s->n + 1) * sizeof(double))) != NULL;
    if (!ok) {
        sim_free(s);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    }
    dss_unit u;
    dss_deviations_sample(c, (uint64_t)c->seed, unit, &s->dev);
    const dss_config *dc = dss_cfg(c);
    s->sun_measured = dc->sun_mode == DSS_SUN_MEASURED && dc->design.mount == DSS_MOUNT_AS_MOUNTED;
    dss_sun_measured_arcsec(c, (uint64_t)c->seed, unit, &s->dev, s->sun_meas_arcsec);
    dss_unit_build(c, &s->dev, &u);
    dss_unit_set_pattern(c, (uint64_t)c->seed, unit, &u);
    double **v = s->col;
    s->n_spot = dss_unit_campaign(c, &u, unit, v[C_B1], v[C_B2], v[C_X], v[C_Y], v[C_WEIGHT],
                                  v[C_TRUTH_A], v[C_TRUTH_B]);
    dss_unit_read_validation(c, &u, unit, &s->val);
    for (size_t i = 0; i < s->val.n; i++)
        s->n_val += s->val.seen[i];
    *out = s;
    return SUNMC_OK;
}

/* The conventions of every file simulate writes, as '#' lines (the same
 * as README "Calibrating a real sensor" and calibrate --help). */
static void write_conventions(FILE *f, const sunmc_config *c)
{
    const dss_design *d = &dss_cfg(c)->design;
    fprintf(f,
            "# conventions: x_px, y_px = spot centroid in pixels from the detector centre, X along\n"
            "#   the pixel rows, Y along the columns; pixel i (0-based from the -X edge) has its\n"
            "#   centre at x_px = i - (%d - 1) / 2.  The pinhole inverts the image: a sun toward\n"
            "#   +X (alpha > 0) puts the spot at x_px < 0 (alpha ~ atan(-x_px pitch / h)).\n"
            "# b1_deg, b2_deg = rotary-table angles: the table top turned by b1 about the base's X,\n"
            "#   then by b2 about the new Y (R(b) = Ry(b2) Rx(b1), zxy order); a perfect sun\n"
            "#   simulator shines along the base's +Z.\n"
            "# h (design.h_mm = %g) = pinhole height over the detector surface, the cover glass\n"
            "#   (%g mm, lying on the detector) included.\n",
            d->detector_px, d->h_mm, d->glass_thickness_mm);
    if (d->mount == DSS_MOUNT_ALIGNED)
        fputs("# truth and compensated angles (campaign.mount = aligned): the table's angles,\n"
              "#   alpha0 = -b2, beta0 = atan(tan b1 / cos b2) (DSS paper eq. 3-4).\n",
              f);
    else
        fputs("# truth and compensated angles (campaign.mount = as_mounted): the sun's direction w\n"
              "#   in the mount's (table-top) frame, alpha = atan(w_x / w_z), beta = atan(w_y / w_z);\n"
              "#   with a perfect sun simulator alpha = -b2, beta = atan(tan b1 / cos b2).\n",
              f);
    fprintf(f, "# seen: the spot's whole %g um disc on the %d px detector (not design.dss_fov_deg).\n",
            d->pinhole_um, d->detector_px);
}

static void write_campaign(const dss_sim *s, const sunmc_config *c, const lab_unit_ref *ref,
                           FILE *fc, FILE *ft)
{
    const dss_config *dc = dss_cfg(c);
    long nb = grid_count(dc->cal_b_min_deg, dc->cal_b_max_deg, dc->cal_b_step_deg, 0);
    fprintf(fc, "# sunmc %s simulate: unit %ld of %s (%s), seed %ld; weight 0: no spot\n",
            SUNMC_VERSION, ref->unit, ref->config, c->product, c->seed);
    if (s->sun_measured)
        fprintf(fc, "# measured sun-simulator direction: calibration.sun_b1_measured_arcsec = "
                    "%.17g, calibration.sun_b2_measured_arcsec = %.17g\n",
                s->sun_meas_arcsec[0], s->sun_meas_arcsec[1]);
    write_conventions(fc, c);
    fprintf(fc, "b1_deg,b2_deg,x_px,y_px,weight\n");
    double dv[DSS_N_DEV];
    dss_deviations_values(&s->dev, dv);
    lab_sim_truth_head(ft, c, ref, dss_deviation_names, dv, DSS_N_DEV);
    write_conventions(ft, c);
    fprintf(ft, "b1_deg,b2_deg,truth_alpha_deg,truth_beta_deg,seen\n");
    for (size_t i = 0; i < s->n; i++) {
        /* b1 varies slowest; the degrees as the campaign computes them. */
        double b1 = dc->cal_b_min_deg + (double)((long)i / nb) * dc->cal_b_step_deg;
        double b2 = dc->cal_b_min_deg + (double)((long)i % nb) * dc->cal_b_step_deg;
        double *const *v = s->col;
        int spot = v[C_WEIGHT][i] > 0 && isfinite(v[C_X][i]) && isfinite(v[C_Y][i]);
        fprintf(fc, "%.17g,%.17g,%.17g,%.17g,%g\n", b1, b2, spot ? v[C_X][i] : 0.0,
                spot ? v[C_Y][i] : 0.0, spot ? v[C_WEIGHT][i] : 0.0);
        fprintf(ft, "%.17g,%.17g,%.17g,%.17g,%d\n", b1, b2, v[C_TRUTH_A][i] * DEG_PER_RAD,
                v[C_TRUTH_B][i] * DEG_PER_RAD, spot);
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
            SUNMC_VERSION, ref->unit, ref->config, c->seed, (long)s->val.n - s->n_val);
    write_conventions(fv, c);
    fprintf(fv, "b1_deg,b2_deg,x_px,y_px,truth_alpha_deg,truth_beta_deg\n");
    const dss_val_readings *v = &s->val;
    for (size_t i = 0; i < v->n; i++)
        if (v->seen[i])
            fprintf(fv, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", v->b1_rad[i] * DEG_PER_RAD,
                    v->b2_rad[i] * DEG_PER_RAD, v->x_px[i], v->y_px[i],
                    v->truth_alpha_rad[i] * DEG_PER_RAD, v->truth_beta_rad[i] * DEG_PER_RAD);
    return SUNMC_OK;
}

static void sim_summary(const void *p, const sunmc_config *c, const lab_unit_ref *ref, char *buf,
                        size_t len)
{
    const dss_sim *s = p;
    int k = snprintf(buf, len,
                     "unit %ld of %s (seed %ld): %zu campaign readings (%zu with a spot), %ld "
                     "validation readings\n"
                     "wrote %s/campaign.csv, %s/truth.csv, %s/validation.csv\n",
                     ref->unit, c->product, c->seed, s->n, s->n_spot, s->n_val, ref->out_dir,
                     ref->out_dir, ref->out_dir);
    if (s->sun_measured && k >= 0 && (size_t)k < len)
        snprintf(buf + k, len - (size_t)k,
                 "calibrate with the unit's measured sun simulator:\n"
                 "  sunmc calibrate --config %s --set calibration.sun=measured "
                 "--set calibration.sun_b1_measured_arcsec=%.17g --set "
                 "calibration.sun_b2_measured_arcsec=%.17g %s/campaign.csv --out DIR\n",
                 ref->config, s->sun_meas_arcsec[0], s->sun_meas_arcsec[1], ref->out_dir);
}

/* ---- calibrate ---- */

/* calibrate --help and compensate --help (family_lab.cal_help, comp_help). */
static const char cal_help[] =
    "       x_px, y_px = spot centroid in pixels from the detector centre (pixel i at\n"
    "       i - (N - 1)/2), X along the rows; the image is inverted (sun toward +X:\n"
    "       x_px < 0); b1 turns the table top about the base's X, then b2 about the new Y;\n"
    "       design.h_mm includes the cover glass; only spots wholly on the detector are\n"
    "       readings\n";
static const char comp_help[] =
    "       with params.ini's design.mount = as_mounted the sun's direction w in the\n"
    "       mount's (table-top) frame, alpha = atan(w_x/w_z), beta = atan(w_y/w_z);\n"
    "       aligned: the table's angles of the DSS paper's eq. 3-4, alpha = -b2,\n"
    "       beta = atan(tan b1 / cos b2)\n";

static const char *const cal_columns[] = {"b1_deg", "b2_deg", "x_px", "y_px", "weight", NULL};

/* ---- calibrate: what the data must look like (lab_check_data) ---- */

/* Any grid the fit can take: a degenerate one shows in the Jacobian's rank. */
static const int cal_min_distinct[] = {1, 1};

static void cal_campaign_range(const sunmc_config *c, int k, double *lo, double *hi)
{
    *lo = dss_cfg(c)->cal_b_min_deg;
    *hi = dss_cfg(c)->cal_b_max_deg;
}

/* What the deviation list leaves out of a spot's spread: noise, the
 * S-curve and the centroid's margins (px). */
#define DSS_PREDICT_BASE_PX 2.0
static const double cal_margin[] = {DSS_PREDICT_BASE_PX, DSS_PREDICT_BASE_PX};

/* A unit with deviations dev_values (list order). */
static void cal_unit_build(const sunmc_config *c, const double *dev_values, void *unit)
{
    dss_deviations dev;
    memset(&dev, 0, sizeof dev);
    deviations_set_values(dss_deviation_list, DSS_N_TOL, dev_values, &dev);
    dss_unit_build(c, &dev, unit);
}

/* Its spot (px) at table angles in_deg, ray-traced through its glass, noiseless. */
static int cal_unit_read(const sunmc_config *c, const void *unit, const double *in, double *out)
{
    const dss_unit *u = unit;
    return dss_sensor_read(&u->sensor, in[0] * RAD_PER_DEG, in[1] * RAD_PER_DEG, NULL, &out[0],
                           &out[1]);
}

/* The centroid noise seen from the pinhole, with the table's encoder,
 * averaged over the repeats. */
static double cal_noise_arcsec(const sunmc_config *c)
{
    const dss_config *d = dss_cfg(c);
    double centroid = d->noise.centroid_px * d->design.pixel_um * MM_PER_UM / d->design.h_mm *
                      ARCSEC_PER_RAD;
    return hypot(centroid, c->encoder_arcsec) / sqrt((double)c->cal_repeats);
}

typedef struct {
    dss_calib_workspace *cw;
    const int *line;
    dss_calibration cal;
} dss_cal;

static int model_params(const sunmc_config *c)
{
    const dss_config *dc = dss_cfg(c);
    if (dc->cal_model == DSS_MODEL_POLYNOMIAL)
        return dss_poly_n_terms(dc->poly_order);
    if (dc->cal_model == DSS_MODEL_SPLINE || dc->cal_model == DSS_MODEL_TABLE)
        return DSS_SPLINE_MIN_ROWS - 1;
    return dc->design.fit_tilt ? DSS_NP : DSS_P_TX; /* the tilt's two only when fitted */
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
        k->cw = dss_calib_alloc_config(dc, d->n);
    if (!k || !k->cw) {
        cal_free(k);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "cannot set up the fit");
    }
    k->line = d->line;
    k->cw->sun_rad[0] = dc->sun_b1_measured_arcsec * RAD_PER_ARCSEC;
    k->cw->sun_rad[1] = dc->sun_b2_measured_arcsec * RAD_PER_ARCSEC;
    for (size_t i = 0; i < d->n; i++) {
        k->cw->b1_rad[i] = d->v[0][i] * RAD_PER_DEG;
        k->cw->b2_rad[i] = d->v[1][i] * RAD_PER_DEG;
        k->cw->x_px[i] = d->v[2][i];
        k->cw->y_px[i] = d->v[3][i];
        k->cw->weight[i] = d->v[4][i];
    }
    int st = dss_labfit_run(c, k->cw, &k->cal, rep, err, errlen);
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
    return dss_labfit_write_residuals(f, k->cw, k->line, &k->cal);
}

/* Row i's alpha, beta errors (lab_drift), as residuals.tsv has them. */
static int cal_row_error(const void *p, size_t i, double e[2])
{
    const dss_cal *k = p;
    double a0, b0, a, b;
    if (dss_labfit_row(k->cw, &k->cal, i, &a, &b, &a0, &b0) != SUNMC_OK)
        return SUNMC_EDOM;
    e[0] = a - a0;
    e[1] = b - b0;
    return SUNMC_OK;
}

/* ---- compensate ---- */

static const char *const raw_columns[] = {"x_px", "y_px", NULL};
static const char *const comp_columns[] = {"compensated_alpha_deg", "compensated_beta_deg", NULL};

/* The physical model (its named deviations) and the polynomial (its
 * order in [design]). */
static const lab_params_model params_models[] = {
    {DSS_CALFIT_MODEL_PHYSICAL, "design parameters", "parameters", "fit_dx_px", NULL},
    {DSS_CALFIT_MODEL_POLYNOMIAL, "design parameters", "design", "order", NULL},
    {DSS_CALFIT_MODEL_SPLINE, "spline", "spline", "breakpoints", NULL},
    {DSS_CALFIT_MODEL_HYBRID, "design parameters correction", "correction", "breakpoints",
     DSS_CALFIT_MODEL_PHYSICAL},
    {DSS_CALFIT_MODEL_TABLE, "table", "table", "nodes", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static int params_load(const params_file *p, void *model, char *err, size_t errlen)
{
    return dss_params_load(p, model, err, errlen);
}

/* Optional: the campaign's weight column; weight 0 marks a row without a
 * spot (the DSS's "no spot" reading). */
static const char *const opt_columns[] = {"weight", NULL};

/* A spot beyond the detector, or a row that says it saw none, is no
 * reading this sensor can produce: marked, never turned into a plausible
 * angle (family_lab.reading_check). */
static int reading_check(const void *model, const double *raw)
{
    const dss_calibration *cal = model;
    if (isfinite(raw[2]) && raw[2] == 0)
        return LAB_NO_SIGNAL;
    double half = DSS_MODEL_HAS_PHYSICS(cal->kind) ? cal->phys.half_px : 0;
    if (half > 0 && !(fabs(raw[0]) <= half && fabs(raw[1]) <= half))
        return LAB_OUTSIDE_DETECTOR;
    double a, b;
    if (DSS_MODEL_HAS_SPLINE(cal->kind) &&
        dss_spline_compensate(cal, raw[0], raw[1], &a, &b) != SUNMC_OK)
        return LAB_OUTSIDE_FIELD;
    return LAB_READING_OK;
}

static int compensate(const void *model, const double *raw, double *comp_rad)
{
    return dss_compensate(model, raw[0], raw[1], &comp_rad[0], &comp_rad[1]);
}

/* The spot's position written in micrometres or millimetres on the
 * detector instead of pixels (lab_check). */
static int cal_output_units(const sunmc_config *c, double *factor, const char **what, int max)
{
    double pixel_um = dss_cfg(c)->design.pixel_um;
    int n = max < 2 ? max : 2;
    if (n > 0) {
        factor[0] = 1.0 / pixel_um;
        what[0] = "micrometres on the detector";
    }
    if (n > 1) {
        factor[1] = UM_PER_MM / pixel_um;
        what[1] = "millimetres on the detector";
    }
    return n;
}

const family_lab dss_lab = {
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
    .cal_unit_bytes = sizeof(dss_unit),
    .cal_unit_build = cal_unit_build,
    .cal_unit_read = cal_unit_read,
    .cal_predict_margin = cal_margin,
    .cal_noise_arcsec = cal_noise_arcsec,
    .params_title = "sunmc calibration of a pinhole digital sun sensor (DSS paper):\n"
                    "read by `sunmc compensate`; units are in the key names",
    .params_fill = params_fill,
    .write_residuals = write_residuals,
    .cal_row_error = cal_row_error,
    .cal_models_tsv = 1,
    .cal_free = cal_free,
    .raw_columns = raw_columns,
    .comp_columns = comp_columns,
    .comp_help = comp_help,
    .comp_fail_note = NULL,
    .opt_columns = opt_columns,
    .reading_check = reading_check,
    .params_models = params_models,
    .model_size = sizeof(dss_calibration),
    .params_load = params_load,
    .compensate = compensate,
    .export = &dss_export,
};
