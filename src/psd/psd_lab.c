/* psd_lab.c - the four-channel sensor's lab hooks (lab.h): simulate one
 * unit's campaign as a lab records it, calibrate a lab's data
 * (psd_labfit.c, psd_labreport.c), compensate raw readings. */
#include "psd_lab.h"
#include "psd_export.h"
#include "status.h"
#include "tsvnum.h"
#include "units.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- simulate ---- */

typedef struct {
    long n, nv;
    psd_deviations dev;
    double *m;        /* 4 n campaign, then 4 nv validation readings */
    int *ok;
} psd_sim;

static void sim_free(void *p)
{
    psd_sim *s = p;
    if (s) {
        free(s->m);
        free(s->ok);
    }
    free(s);
}

static int sim_run(const sunmc_config *c, long unit, void **out, char *err, size_t errlen)
{
    psd_sim *s = calloc(1, sizeof *s);
    if (s) {
        s->n = psd_campaign_rows(c);
        s->nv = psd_validation_points(c);
        s->m = malloc(4 * (size_t)(s->n + s->nv) * sizeof *s->m);
        s->ok = malloc((size_t)(s->n + s->nv) * sizeof *s->ok);
    }
    if (!s || !s->m || !s->ok) {
        sim_free(s);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    }
    psd_sensor sen;
    psd_unit_sample(c, unit, 1.0, &s->dev);
    psd_sensor_build(&psd_cfg(c)->design, &s->dev, &sen);
    rng_stream r;
    double off[CONFIG_LIST_MAX][2]; /* the table's line errors: read there, written nominal */
    unit_stream_init(&r, c, unit, RNG_STREAM_CAL_NOISE);
    psd_line_offsets(c, unit, FAMILY_GRID_CAMPAIGN, off);
    for (long i = 0; i < s->n; i++) {
        double a, b;
        const double *o = off[psd_campaign_line(c, i)];
        psd_campaign_angles(c, i, &a, &b);
        s->ok[i] = psd_unit_read(c, &sen, a + o[0], b + o[1], &r, s->m + 4 * i) == SUNMC_OK;
    }
    unit_stream_init(&r, c, unit, RNG_STREAM_VAL_NOISE);
    psd_line_offsets(c, unit, FAMILY_GRID_VALIDATION, off);
    for (long i = 0; i < s->nv; i++) {
        double a, b;
        const double *o = off[psd_validation_line(c, i)];
        psd_validation_angles(c, i, &a, &b);
        s->ok[s->n + i] =
            psd_unit_read(c, &sen, a + o[0], b + o[1], &r, s->m + 4 * (s->n + i)) == SUNMC_OK;
    }
    *out = s;
    return SUNMC_OK;
}

static void sim_head(FILE *f, const sunmc_config *c, const lab_unit_ref *ref)
{
    fprintf(f, "# sunmc simulate: unit %ld of %s (four-channel sensor); channels in fractions "
               "of the ADC's full scale\n", ref->unit, ref->config);
}

static int sim_write(const void *p, const sunmc_config *c, const lab_unit_ref *ref,
                     FILE *const f[LAB_SIM_FILES])
{
    const psd_sim *s = p;
    const psd_config *pc = psd_cfg(c);
    for (int k = 0; k < LAB_SIM_FILES; k++)
        sim_head(f[k], c, ref);
    fprintf(f[0], "alpha_deg,beta_deg,i1,i2,i3,i4,weight\n");
    for (long i = 0; i < s->n; i++) {
        double a, b;
        const double *m = s->m + 4 * i;
        psd_campaign_angles(c, i, &a, &b);
        fprintf(f[0], "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%d\n", a * DEG_PER_RAD,
                b * DEG_PER_RAD, m[0], m[1], m[2], m[3], s->ok[i]);
    }
    fprintf(f[1], "deviation,value\n");
    const char *names[UNIT_MAX_DEV];
    double v[UNIT_MAX_DEV];
    int n = psd_family.dev_columns(c, names, UNIT_MAX_DEV);
    deviations_values(psd_family.deviations, psd_family.n_deviations, &s->dev, v, UNIT_MAX_DEV);
    for (int k = 0; k < n; k++) {
        char num[64];
        tsv_num_fmt(num, sizeof num, "%.10g", v[k]);
        fprintf(f[1], "%s,%s\n", names[k], num);
    }
    /* the truth of a row follows from its table angles (compensate adds it) */
    fprintf(f[2], "# the readings the Monte Carlo validates on; `sunmc compensate` adds the "
                  "truth of campaign.table_order = %s\n",
            pc->table_order == PSD_TABLE_PROJECTED ? "projected"
            : pc->table_order == PSD_TABLE_ALPHA_OUTER ? "alpha_outer" : "beta_outer");
    fprintf(f[2], "alpha_deg,beta_deg,i1,i2,i3,i4\n");
    for (long i = 0; i < s->nv; i++) {
        double a, b;
        const double *m = s->m + 4 * (s->n + i);
        psd_validation_angles(c, i, &a, &b);
        if (s->ok[s->n + i])
            fprintf(f[2], "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", a * DEG_PER_RAD,
                    b * DEG_PER_RAD, m[0], m[1], m[2], m[3]);
    }
    for (int k = 0; k < LAB_SIM_FILES; k++)
        if (ferror(f[k]))
            return SUNMC_EIO;
    return SUNMC_OK;
}

static void sim_summary(const void *p, const sunmc_config *c, const lab_unit_ref *ref, char *buf,
                        size_t len)
{
    const psd_sim *s = p;
    snprintf(buf, len, "psd unit %ld: %ld campaign readings, %ld validation readings\n",
             ref->unit, s->n, s->nv);
}

/* ---- calibrate ---- */

/* calibrate --help and compensate --help (family_lab.cal_help, comp_help). */
static const char cal_help[] =
    "       the table's angles (campaign.table_order, table_alpha_sign, table_beta_sign\n"
    "       say how they put the sun in the table top) and the raw channel signals in\n"
    "       any one unit (dark signals and polarity are fitted); repeated readings as\n"
    "       repeated rows: their spread is the repeatability, each point counted once\n";
static const char comp_help[] =
    "       the sun's angles in the table top, atan(u_x/u_z), atan(u_y/u_z); the\n"
    "       truth columns by the calibration's table convention\n";

static const char *const cal_columns[] = {"alpha_deg", "beta_deg", "i1", "i2", "i3", "i4",
                                          "weight", NULL};
static const int cal_min_distinct[] = {2, 1};

static size_t cal_min_rows(const sunmc_config *c, char *why, size_t len)
{
    const psd_config *p = psd_cfg(c);
    int fr[PSD_NP];
    psd_poly q;
    int phys = PSD_MODEL_HAS_PHYSICS(p->cal_model);
    if (p->cal_model == PSD_MODEL_SPLINE || p->cal_model == PSD_MODEL_TABLE) {
        snprintf(why, len, "the %s model needs at least %d rows", psd_model_names[p->cal_model],
                 PSD_SPLINE_MIN_ROWS);
        return PSD_SPLINE_MIN_ROWS;
    }
    int np = phys ? psd_phys_free(&p->design, p->fit_tilt, fr)
                  : psd_poly_init(&q, p->poly_order, p->poly_form);
    size_t need = phys ? (size_t)np / 2 + 1 : (size_t)np + 1;
    if (p->cal_model == PSD_MODEL_HYBRID && need < PSD_SPLINE_MIN_ROWS)
        need = PSD_SPLINE_MIN_ROWS;
    snprintf(why, len, "the %s model has %d parameters: need at least %zu rows",
             psd_model_names[p->cal_model], np, need);
    return need;
}

static void cal_free(void *p) { psd_labcal_free(p); }

/* The fitted calibration's alpha, beta errors of row i (lab_drift). */
static int cal_row_error(const void *p, size_t i, double e[2])
{
    const psd_labcal *k = p;
    /* a campaign set aside is still compared with the others */
    if (!(k->w[i] > 0 || (k->aside && k->aside[i])) || !isfinite(k->err[3 * i]))
        return SUNMC_EDOM;
    e[0] = k->err[3 * i];
    e[1] = k->err[3 * i + 1];
    return SUNMC_OK;
}

static double cal_noise_arcsec(const sunmc_config *c);

/* Repeat campaigns the cross-validation found unlike the others
 * (fold_outliers.h) leave the calibration (calibration.outlier_campaigns =
 * drop): their rows weighted 0, the model refitted and reported again
 * (their folds gone), and a warning naming them with the first pass's
 * numbers. */
static int drop_outliers(psd_labcal *k, calreport *rep, const char *model_line)
{
    char text[CALREPORT_TEXT_MAX / 2];
    calreport_outlier_text(rep, "left", text, sizeof text);
    int *fold = malloc((k->d->n + 1) * sizeof *fold), by_line, n_out = rep->cv_n_outliers;
    double line[CALREPORT_MAX_FOLDS], all = rep->cv_rms_out_all_arcsec;
    free(k->aside);
    k->aside = calloc(k->d->n + 1, 1);
    if (!fold || !k->aside) {
        free(fold);
        return SUNMC_ENOMEM;
    }
    int n_folds = psd_labcal_folds(k, fold, line, &by_line);
    size_t aside = 0;
    for (int f = 0; f < n_folds && f < rep->n_folds; f++) {
        if (!rep->fold[f].outlier)
            continue;
        for (size_t i = 0; i < k->d->n; i++)
            if (fold[i] == f) {
                aside += k->w[i] > 0;
                k->aside[i] = k->w[i] > 0;
                k->w[i] = 0.0;
            }
    }
    free(fold);
    int st = psd_labcal_fit(k, &k->fr);
    if (st == SUNMC_OK)
        psd_labcal_errors(k);
    calreport_init(rep, "psd", model_line);
    rep->n_set_aside = aside;
    rep->fit = k->fr;
    rep->fit_ok = st == SUNMC_OK;
    if (rep->fit_ok)
        psd_labcal_report(k, rep);
    calreport_warn(rep,
                   "look at the campaign's set-up and data (the light, the mounting, the "
                   "table's zero); to keep it in the calibration, set "
                   "calibration.outlier_campaigns = keep",
                   "dropped from the calibration: %d repeat campaign%s unlike the others: %s; "
                   "with %s, the estimate was %.2f arcsec",
                   n_out, n_out > 1 ? "s" : "", text, n_out > 1 ? "them" : "it", all);
    return SUNMC_OK;
}

static int cal_run(const sunmc_config *c, const lab_columns *d, void **out, calreport *rep,
                   char *err, size_t errlen)
{
    psd_labcal *k = psd_labcal_alloc(c, d, err, errlen);
    if (!k)
        return SUNMC_ENOMEM;
    static const char *const model_lines[] = {PSD_CALFIT_MODEL_PHYSICAL,
                                              PSD_CALFIT_MODEL_POLYNOMIAL,
                                              PSD_CALFIT_MODEL_SPLINE, PSD_CALFIT_MODEL_HYBRID,
                                              PSD_CALFIT_MODEL_TABLE};
    int model = psd_cfg(c)->cal_model;
    calreport_init(rep, "psd", model_lines[model]);
    if (PSD_MODEL_HAS_SPLINE(model)) {
        /* the smoothing (and the table's step): by the held-out error of calibrate's own folds */
        double line[CALREPORT_MAX_FOLDS];
        int by_line;
        k->spline_fold = malloc((d->n + 1) * sizeof *k->spline_fold);
        if (!k->spline_fold) {
            psd_labcal_free(k);
            return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
        }
        k->spline_n_folds = psd_labcal_folds(k, k->spline_fold, line, &by_line);
        if (k->spline_n_folds < 2) {
            free(k->spline_fold);
            k->spline_fold = NULL;
            k->spline_n_folds = 0;
        }
    }
    int st = psd_labcal_fit(k, &k->fr);
    if (st == SUNMC_OK) {
        /* rows the fitted model cannot read (saturated spots) leave, once */
        k->dropped = psd_labcal_errors(k);
        if (k->dropped) {
            for (size_t i = 0; i < d->n; i++)
                if (!isfinite(k->err[3 * i]))
                    k->w[i] = 0.0;
            st = psd_labcal_fit(k, &k->fr);
            psd_labcal_errors(k);
        }
    }
    /* the folds' refits keep the smoothing chosen on every row */
    k->spline_smooth = st == SUNMC_OK ? k->cal.spline.smooth : 0.0;
    k->table_log = st == SUNMC_OK && model == PSD_MODEL_TABLE ? psd_table_log(&k->cal.table) : 0;
    rep->fit = k->fr;
    rep->fit_ok = st == SUNMC_OK;
    if (rep->fit_ok) {
        psd_labcal_report(k, rep);
        if (rep->cv_n_outliers > 0 && c->cal_outlier_campaigns == CONFIG_OUTLIERS_DROP &&
            drop_outliers(k, rep, model_lines[model]) != SUNMC_OK) {
            psd_labcal_free(k);
            return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
        }
    } else {
        rep->n_rows = d->n;
        psd_labcal_report_conventions(k, rep);
    }
    /* data the model does not describe: say what is wrong with them */
    if (!rep->fit_ok || !(rep->sigma_arcsec <= c->max_residual_ratio *
                                                 fmax(cal_noise_arcsec(c), LAB_NOISE_FLOOR_ARCSEC)))
        psd_labcal_report_defects(k, rep);
    *out = k;
    return SUNMC_OK;
}

static void campaign_range(const sunmc_config *c, int k, double *lo, double *hi)
{
    const psd_config *p = psd_cfg(c);
    if (k == 0) {
        *lo = -p->cal_alpha_max_deg;
        *hi = p->cal_alpha_max_deg;
        return;
    }
    *lo = *hi = p->cal_beta_deg.v[0];
    for (int j = 1; j < p->cal_beta_deg.n; j++) {
        *lo = fmin(*lo, p->cal_beta_deg.v[j]);
        *hi = fmax(*hi, p->cal_beta_deg.v[j]);
    }
}

/* Ratio noise 2 sigma / signal (corner layout), through the nominal slope. */
static double cal_noise_arcsec(const sunmc_config *c)
{
    const psd_config *p = psd_cfg(c);
    psd_cal k;
    psd_cal_nominal(&k, &p->design);
    return 2.0 * p->noise_fs_pct * FRACTION_PER_PCT / p->design.signal_fs / k.phys.sens *
           ARCSEC_PER_RAD;
}

static const lab_measured_key cal_measured[] = {
    {"campaign", "table_order",
     "the table's axis order decides the truth angles: beta_outer and alpha_outer differ by "
     "up to atan(tan b / cos a) - b (1.2 deg at 20 deg, 18 deg)",
     "set campaign.table_order (and the signs) to your table's convention"},
    {"design", "h_mm", "the nominal geometry is the fit's start and the ratios' scale",
     "set design.h_mm, design.active_mm and design.aperture_um to your sensor's drawing"},
    {NULL, NULL, NULL, NULL}};

static int params_fill(const void *p, const sunmc_config *c, const calreport *rep,
                       params_file *pf)
{
    const psd_labcal *k = p;
    const psd_config *pc = psd_cfg(c);
    const psd_design *d = &pc->design;
    static const char *const detectors[] = {"lateral", "quadrant"}, *const laterals[] = {"duo", "tetra"};
    static const char *const orders[] = {"projected", "alpha_outer", "beta_outer"};
    static const char *const signs[] = {"plus", "minus"};
    static const char *const polarities[] = {"positive", "inverted"};
    int st = params_set_text(pf, "design", "detector", detectors[d->detector], NULL);
    st |= params_set_text(pf, "design", "lateral", laterals[d->lateral], NULL);
    st |= params_set_text(pf, "design", "polarity", polarities[d->polarity],
                          "inverted: the spot lowers the channels (compensate's signal check)");
    st |= params_set_double(pf, "design", "h_mm", d->h_mm, "nominal");
    st |= params_set_double(pf, "design", "active_mm", d->active_mm, NULL);
    st |= params_set_double(pf, "design", "aperture_um", d->aperture_um, NULL);
    st |= params_set_double(pf, "design", "gap_um", d->gap_um, NULL);
    st |= params_set_double(pf, "design", "pincushion", d->pincushion, NULL);
    st |= params_set_double(pf, "design", "glass_thickness_mm", d->glass_thickness_mm, NULL);
    st |= params_set_double(pf, "design", "glass_index", d->glass_index, NULL);
    st |= params_set_text(pf, "campaign", "table_order", orders[pc->table_order],
                          "the truth columns' convention");
    st |= params_set_text(pf, "campaign", "table_alpha_sign", signs[pc->table_alpha_sign], NULL);
    st |= params_set_text(pf, "campaign", "table_beta_sign", signs[pc->table_beta_sign], NULL);
    if (k->cal.model == PSD_MODEL_SPLINE)
        return st | lab_spline_params_fill(&k->cal.spline, pf, "spline");
    if (k->cal.model == PSD_MODEL_TABLE)
        return st | lab_table_params_fill(&k->cal.table, pf, "table");
    if (k->cal.model == PSD_MODEL_HYBRID)
        st |= lab_spline_params_fill(&k->cal.spline, pf, "correction");
    if (k->cal.model == PSD_MODEL_POLYNOMIAL) {
        st |= params_set_double(pf, "polynomial", "order", k->cal.poly.order, NULL);
        st |= params_set_text(pf, "polynomial", "form",
                              k->cal.poly.form == PSD_POLY_FSS20 ? "fss20" : "full", NULL);
        st |= params_set_double(pf, "polynomial", "scale", k->cal.poly.scale,
                                "x and y enter the terms divided by it");
        for (int t = 0; t < k->cal.poly.nt && st == SUNMC_OK; t++) {
            char ka[32], kb[32];
            snprintf(ka, sizeof ka, "tana_x%dy%d", k->cal.poly.ex[t], k->cal.poly.ey[t]);
            snprintf(kb, sizeof kb, "tanb_x%dy%d", k->cal.poly.ex[t], k->cal.poly.ey[t]);
            st |= params_set_double(pf, "polynomial", ka, k->cal.poly.ca[t], NULL);
            st |= params_set_double(pf, "polynomial", kb, k->cal.poly.cb[t], NULL);
        }
        return st;
    }
    for (int j = 0; j < PSD_NP && st == SUNMC_OK; j++)
        st |= params_set_double(pf, "parameters", psd_param_names[j],
                                k->cal.p[j] * psd_param_scale[j], NULL);
    return st;
}

static int write_residuals(const void *p, FILE *f)
{
    const psd_labcal *k = p;
    fprintf(f, "line\talpha_deg\tbeta_deg\tweight\ttruth_alpha_deg\ttruth_beta_deg\t"
               "alpha_error_arcsec\tbeta_error_arcsec\ttotal_error_arcsec\n");
    for (size_t i = 0; i < k->d->n; i++) {
        double ta, tb;
        const double *e = k->err + 3 * i;
        sun_angles_of(k->ut + 3 * i, &ta, &tb);
        tsv_printf(f, "%d\t%.10g\t%.10g\t%g\t%.10g\t%.10g\t%.6g\t%.6g\t%.6g\n", k->d->line[i],
                k->d->v[0][i], k->d->v[1][i], k->w[i], ta * DEG_PER_RAD, tb * DEG_PER_RAD,
                e[0] * ARCSEC_PER_RAD, e[1] * ARCSEC_PER_RAD, e[2] * ARCSEC_PER_RAD);
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

/* ---- compensate ---- */

static const char *const raw_columns[] = {"i1", "i2", "i3", "i4", NULL};
static const char *const comp_columns[] = {"compensated_alpha_deg", "compensated_beta_deg", NULL};
static const char *const table_columns[] = {"alpha_deg", "beta_deg", NULL};
static const char *const truth_columns[] = {"truth_alpha_deg", "truth_beta_deg", NULL};


static int enum_of(const params_file *p, const char *sec, const char *key,
                   const char *const *choices, int n, int *out, char *err, size_t errlen)
{
    const char *t;
    int st = params_get_text(p, sec, key, &t, err, errlen);
    for (int i = 0; st == SUNMC_OK && i < n; i++)
        if (strcmp(t, choices[i]) == 0) {
            *out = i;
            return SUNMC_OK;
        }
    return st != SUNMC_OK ? st
                          : params_require(p, sec, key, 0, "one of the documented values", err,
                                           errlen);
}

static int load_design(const params_file *p, psd_config *c, char *err, size_t errlen)
{
    static const char *const detectors[] = {"lateral", "quadrant"}, *const laterals[] = {"duo", "tetra"};
    static const char *const orders[] = {"projected", "alpha_outer", "beta_outer"};
    static const char *const signs[] = {"plus", "minus"};
    static const char *const design_keys[] = {"detector", "lateral", "h_mm", "active_mm",
                                              "aperture_um", "gap_um", "pincushion",
                                              "glass_thickness_mm", "glass_index", "polarity"};
    static const char *const polarities[] = {"positive", "inverted"};
    static const char *const campaign_keys[] = {"table_order", "table_alpha_sign",
                                                "table_beta_sign"};
    psd_design *d = &c->design;
    int st = params_check_keys(p, "design", design_keys, 10, err, errlen);
    if (st == SUNMC_OK)
        st = params_check_keys(p, "campaign", campaign_keys, 3, err, errlen);
    if (st == SUNMC_OK)
        st = enum_of(p, "design", "detector", detectors, 2, &d->detector, err, errlen);
    if (st == SUNMC_OK)
        st = enum_of(p, "design", "lateral", laterals, 2, &d->lateral, err, errlen);
    /* written since issue 39; a file without it was of a positive sensor */
    if (st == SUNMC_OK && params_find(p, "design", "polarity"))
        st = enum_of(p, "design", "polarity", polarities, 2, &d->polarity, err, errlen);
    const params_range r[] = {
        {"design", "h_mm", 0.01, 1000, "mm", NULL},   {"design", "active_mm", 0.01, 1000, "mm", NULL},
        {"design", "aperture_um", 0, 1e5, "um", NULL}, {"design", "gap_um", 0, 1e4, "um", NULL},
        {"design", "pincushion", -1, 1, "", NULL},     {"design", "glass_thickness_mm", 0, 100, "mm", NULL},
        {"design", "glass_index", 1, 3, "", NULL}};
    if (st == SUNMC_OK)
        st = params_check_ranges(p, r, 7, err, errlen);
    double *v[] = {&d->h_mm, &d->active_mm, &d->aperture_um, &d->gap_um, &d->pincushion,
                   &d->glass_thickness_mm, &d->glass_index};
    for (int i = 0; i < 7 && st == SUNMC_OK; i++)
        st = params_get_double(p, r[i].section, r[i].key, v[i], err, errlen);
    if (st == SUNMC_OK)
        st = enum_of(p, "campaign", "table_order", orders, 3, &c->table_order, err, errlen);
    if (st == SUNMC_OK)
        st = enum_of(p, "campaign", "table_alpha_sign", signs, 2, &c->table_alpha_sign, err, errlen);
    if (st == SUNMC_OK)
        st = enum_of(p, "campaign", "table_beta_sign", signs, 2, &c->table_beta_sign, err, errlen);
    return st;
}

/* Every key of [polynomial] is order, form, scale or a coefficient of a
 * term of q (its order and form): a coefficient beyond them, or any other
 * key, is refused at its line, never dropped. */
static int poly_keys_known(const params_file *p, const psd_poly *q, char *err, size_t errlen)
{
    static const char *const fixed[] = {"order", "form", "scale"};
    const char *names[3 + 2 * PSD_POLY_MAX_TERMS];
    char buf[2 * PSD_POLY_MAX_TERMS][32];
    int n = 0;
    for (; n < 3; n++)
        names[n] = fixed[n];
    for (int t = 0; t < q->nt; t++)
        for (int ab = 0; ab < 2; ab++) {
            char *b = buf[2 * t + ab];
            snprintf(b, sizeof buf[0], "tan%c_x%dy%d", ab ? 'b' : 'a', q->ex[t], q->ey[t]);
            names[n++] = b;
        }
    const params_entry *e = params_unknown_key(p, "polynomial", names, n);
    int ex, ey, end = 0;
    if (e && sscanf(e->key, "tan%*1[ab]_x%dy%d%n", &ex, &ey, &end) == 2 && e->key[end] == '\0')
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: unknown key polynomial.%s: not a term of order %d (%s): a "
                          "coefficient beyond the order",
                          p->path, e->line, e->key, q->order,
                          q->form == PSD_POLY_FSS20 ? "fss20" : "full");
    return params_check_keys(p, "polynomial", names, n, err, errlen);
}

static int load_poly(const params_file *p, psd_cal *k, char *err, size_t errlen)
{
    static const char *const forms[] = {"full", "fss20"};
    int order = 0, form = 0;
    const params_range r[] = {{"polynomial", "order", 1, PSD_POLY_MAX_ORDER, "", NULL},
                              {"polynomial", "scale", 1e-300, 1e300, "", NULL}};
    int st = params_check_ranges(p, r, 2, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_int(p, "polynomial", "order", &order, err, errlen);
    if (st == SUNMC_OK)
        st = enum_of(p, "polynomial", "form", forms, 2, &form, err, errlen);
    if (st == SUNMC_OK && form == PSD_POLY_FSS20 && order != 5)
        st = params_require(p, "polynomial", "form", 0, "full unless the order is 5", err, errlen);
    if (st != SUNMC_OK)
        return st;
    psd_poly_init(&k->poly, order, form);
    st = poly_keys_known(p, &k->poly, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_double(p, "polynomial", "scale", &k->poly.scale, err, errlen);
    for (int t = 0; t < k->poly.nt && st == SUNMC_OK; t++) {
        char ka[32], kb[32];
        snprintf(ka, sizeof ka, "tana_x%dy%d", k->poly.ex[t], k->poly.ey[t]);
        snprintf(kb, sizeof kb, "tanb_x%dy%d", k->poly.ex[t], k->poly.ey[t]);
        st = params_get_double(p, "polynomial", ka, &k->poly.ca[t], err, errlen);
        if (st == SUNMC_OK)
            st = params_get_double(p, "polynomial", kb, &k->poly.cb[t], err, errlen);
    }
    return st;
}

static int params_load(const params_file *p, void *model, char *err, size_t errlen)
{
    psd_model_file *m = model;
    memset(m, 0, sizeof *m);
    int st = load_design(p, &m->cfg, err, errlen);
    if (st != SUNMC_OK)
        return st;
    m->cal.design = &m->cfg.design;
    if (params_find(p, "polynomial", "order")) {
        m->cal.model = PSD_MODEL_POLYNOMIAL;
        return load_poly(p, &m->cal, err, errlen);
    }
    if (params_find(p, "spline", "breakpoints")) {
        m->cal.model = PSD_MODEL_SPLINE;
        return lab_spline_params_load(p, "spline", &m->cal.spline, err, errlen);
    }
    if (params_find(p, "table", "nodes")) {
        m->cal.model = PSD_MODEL_TABLE;
        return lab_table_params_load(p, "table", &m->cal.table, err, errlen);
    }
    m->cal.model = PSD_MODEL_PHYSICAL;
    if (params_find(p, "correction", "breakpoints")) {
        m->cal.model = PSD_MODEL_HYBRID;
        st = lab_spline_params_load(p, "correction", &m->cal.spline, err, errlen);
    }
    if (st == SUNMC_OK)
        st = params_check_keys(p, "parameters", psd_param_names, PSD_NP, err, errlen);
    for (int j = 0; j < PSD_NP && st == SUNMC_OK; j++) {
        st = params_get_double(p, "parameters", psd_param_names[j], &m->cal.p[j], err, errlen);
        m->cal.p[j] /= psd_param_scale[j];
    }
    for (int j = PSD_P_G2; j <= PSD_P_G4 && st == SUNMC_OK; j++)
        st = params_require(p, "parameters", psd_param_names[j], m->cal.p[j] != 0, "not 0", err,
                            errlen);
    if (st == SUNMC_OK)
        psd_phys_set(&m->cal.phys, &m->cfg.design, m->cal.p);
    return st;
}

/* The physical model (its aperture offset among [parameters]) and the
 * field's polynomial ([polynomial] and its order). */
static const lab_params_model params_models[] = {
    {PSD_CALFIT_MODEL_PHYSICAL, "design campaign parameters", "parameters", "dx_um", NULL},
    {PSD_CALFIT_MODEL_POLYNOMIAL, "design campaign polynomial", "polynomial", "order", NULL},
    {PSD_CALFIT_MODEL_SPLINE, "design campaign spline", "spline", "breakpoints", NULL},
    {PSD_CALFIT_MODEL_HYBRID, "design campaign parameters correction", "correction",
     "breakpoints", PSD_CALFIT_MODEL_PHYSICAL},
    {PSD_CALFIT_MODEL_TABLE, "design campaign table", "table", "nodes", NULL},
    {NULL, NULL, NULL, NULL, NULL}};


/* Can the calibrated sensor produce channels raw[0..3]
 * (family_lab.reading_check)?  An ADC reads no negative value; a spot
 * gives every model a signal: beyond the fitted darks on the side of
 * design.polarity (physical model; the
 * polynomial's raw channels have none), with a positive sum; the
 * polynomial's ratios stay within what its campaign saw. */
static int reading_check(const void *model, const double *raw)
{
    const psd_model_file *m = model;
    int phys = PSD_MODEL_HAS_PHYSICS(m->cal.model), any = 0;
    double sum = 0;
    for (int k = 0; k < PSD_CHANNELS; k++)
        if (!(raw[k] >= 0))
            return LAB_OUTSIDE_RANGE;
    /* an inverting amplifier lowers the channels below their darks */
    double sign = phys && m->cfg.design.polarity == PSD_INVERTED ? -1.0 : 1.0;
    for (int k = 0; k < PSD_CHANNELS; k++) {
        double s = phys ? sign * (raw[k] - m->cal.phys.dark[k]) / m->cal.phys.gain[k] : raw[k];
        any |= s > 0;
        sum += s;
    }
    if (!any)
        return LAB_NO_SIGNAL;
    if (!(sum > 0))
        return LAB_NEGATIVE_SUM;
    int spl = PSD_MODEL_HAS_SPLINE(m->cal.model);
    double in[2], t[2];
    if (spl && psd_spline_inputs(&m->cal, raw, in) != SUNMC_OK)
        return LAB_NO_INVERSE;
    if (spl && psd_spline_eval(&m->cal, in, t) != SUNMC_OK)
        return LAB_OUTSIDE_FIELD;
    double x, y;
    if (m->cal.model == PSD_MODEL_POLYNOMIAL && psd_poly_ratios(&m->cfg.design, raw, &x, &y) == SUNMC_OK &&
        fmax(fabs(x), fabs(y)) > m->cal.poly.scale * (1 + PSD_POLY_RANGE_MARGIN))
        return LAB_OUTSIDE_RANGE;
    return LAB_READING_OK;
}

/* raw: i1..i4 and, when given, the table's alpha_deg, beta_deg (NaN when
 * not); comp_rad: the compensated angles, then the truth angles. */
static int compensate(const void *model, const double *raw, double *comp_rad)
{
    const psd_model_file *m = model;
    if (isfinite(raw[4]) && isfinite(raw[5])) {
        double ut[3];
        psd_table_sun(&m->cfg, raw[4] * RAD_PER_DEG, raw[5] * RAD_PER_DEG, ut);
        sun_angles_of(ut, &comp_rad[2], &comp_rad[3]);
    }
    return psd_cal_angles(&m->cal, raw, &comp_rad[0], &comp_rad[1]);
}

const family_lab psd_lab = {
    .cal_counts_repeats_once = 1,
    .sim_run = sim_run,
    .sim_write = sim_write,
    .sim_summary = sim_summary,
    .sim_free = sim_free,
    .cal_columns = cal_columns,
    .cal_help = cal_help,
    .cal_min_rows = cal_min_rows,
    .cal_run = cal_run,
    .cal_n_inputs = 2,
    .cal_min_distinct = cal_min_distinct,
    .cal_campaign_range = campaign_range,
    /* no cal_unit_build: raw channels are in the lab's own unit */
    .cal_noise_arcsec = cal_noise_arcsec,
    .cal_measured = cal_measured,
    .params_title = "sunmc calibration of a four-channel analog sun sensor (psd)",
    .params_fill = params_fill,
    .write_residuals = write_residuals,
    .cal_row_error = cal_row_error,
    .cal_models_tsv = 1,
    .cal_free = cal_free,
    .raw_columns = raw_columns,
    .comp_columns = comp_columns,
    .comp_help = comp_help,
    .opt_columns = table_columns,
    .opt_comp_columns = truth_columns,
    .reading_check = reading_check,
    .comp_fail_note = "a saturated spot (beyond the linear field) or a reading the model cannot "
                      "invert",
    .params_models = params_models,
    .model_size = sizeof(psd_model_file),
    .params_load = params_load,
    .compensate = compensate,
    .export = &psd_export,
};
