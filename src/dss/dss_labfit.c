/* dss_labfit.c - `sunmc calibrate` of a DSS: dss_calibrate plus the
 * report and params.ini. */
#include "dss_labfit.h"
#include "dss_prior.h"
#include "dss_sensor.h"
#include "rotation.h"
#include "family.h"
#include "lab.h"
#include "status.h"
#include "tsvnum.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DSS_CV_BLOCKS 4 /* grid quadrants by the signs of b1 and b2 */

/* Central-difference step (rad) of the table angles for the 2 x 2
 * derivatives d spot / d b and d (alpha, beta) / d b: the spot is smooth on
 * the scale of degrees, so the truncation error (~h^2) is ~1e-12 relative and
 * the rounding error (~eps / h) ~1e-10. */
#define DSS_SIGMA_DB_RAD 1e-6

int dss_labfit_sigma(const dss_model *m, const double *cov, const int *free_idx, int n_free,
                     double b1, double b2, double sigma_rad[2])
{
    double spot[2], J[2][DSS_NP], sp[2][2][2], tr[2][2][2];
    if (dss_model_spot(m, b1, b2, spot, J) != SUNMC_OK)
        return SUNMC_EDOM;
    const double h = DSS_SIGMA_DB_RAD;
    for (int k = 0; k < 2; k++)
        for (int s = 0; s < 2; s++) {
            double d = s ? h : -h;
            double c1 = b1 + (k == 0 ? d : 0.0), c2 = b2 + (k == 1 ? d : 0.0);
            if (dss_model_spot(m, c1, c2, sp[k][s], NULL) != SUNMC_OK)
                return SUNMC_EDOM;
            dss_model_truth(m, c1, c2, &tr[k][s][0], &tr[k][s][1]);
        }
    /* Fb[i][k] = d spot_i / d b_k, Tb[i][k] = d angle_i / d b_k. */
    double Fb[2][2], Tb[2][2];
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 2; k++) {
            Fb[i][k] = (sp[k][1][i] - sp[k][0][i]) / (2 * h);
            Tb[i][k] = (tr[k][1][i] - tr[k][0][i]) / (2 * h);
        }
    double det = Fb[0][0] * Fb[1][1] - Fb[0][1] * Fb[1][0];
    if (!(fabs(det) > 0) || !isfinite(det))
        return SUNMC_EDOM;
    double Fi[2][2] = {{Fb[1][1] / det, -Fb[0][1] / det}, {-Fb[1][0] / det, Fb[0][0] / det}};
    /* The compensated angles are g = truth(b(spot; p); p) with spot(b, p) =
     * spot, so at a fixed spot d b / d p = -Fb^-1 d spot / d p and
     * d g / d p = Tb d b / d p + d truth / d p at fixed b (the sun simulator's
     * direction, as_mounted; central differences). */
    double G[2][DSS_NP];
    for (int k = 0; k < n_free; k++) {
        int j = free_idx[k];
        double db0 = -(Fi[0][0] * J[0][j] + Fi[0][1] * J[1][j]);
        double db1 = -(Fi[1][0] * J[0][j] + Fi[1][1] * J[1][j]);
        double dt[2] = {0, 0};
        if (m->mount == DSS_MOUNT_AS_MOUNTED && (j == DSS_P_S1 || j == DSS_P_S2)) {
            double t[2][2];
            for (int s = 0; s < 2; s++) {
                dss_model q = *m;
                q.p[j] += s ? h : -h;
                dss_model_prepare(&q);
                dss_model_truth(&q, b1, b2, &t[s][0], &t[s][1]);
            }
            dt[0] = (t[1][0] - t[0][0]) / (2 * h);
            dt[1] = (t[1][1] - t[0][1]) / (2 * h);
        }
        G[0][k] = Tb[0][0] * db0 + Tb[0][1] * db1 + dt[0];
        G[1][k] = Tb[1][0] * db0 + Tb[1][1] * db1 + dt[1];
    }
    for (int a = 0; a < 2; a++) {
        double v = 0;
        for (int i = 0; i < n_free; i++)
            for (int j = 0; j < n_free; j++)
                v += G[a][i] * cov[i * n_free + j] * G[a][j];
        if (!(v >= 0))
            return SUNMC_EDOM;
        sigma_rad[a] = sqrt(v);
    }
    return SUNMC_OK;
}


static double field_deg(double a, double b)
{
    return atan(hypot(tan(a), tan(b))) * DEG_PER_RAD;
}

/* Angle errors per band over readings with use[i] > 0; sum of squares and
 * count over both angles into *sum, *n; readings the model cannot
 * compensate are left out and counted in *n_uncomp (may be NULL). */
static void angle_errors(const dss_calib_workspace *cw, const double *use,
                         const dss_calibration *cal, const band_list *bands, band_acc acc[2],
                         double *sum, long *n, long *n_uncomp)
{
    if (acc) {
        band_acc_reset(&acc[0]);
        band_acc_reset(&acc[1]);
    }
    *sum = 0;
    *n = 0;
    for (size_t i = 0; i < cw->n; i++) {
        if (!(use[i] > 0))
            continue;
        double a0, b0, a, b;
        dss_calib_truth(cal, cw->b1_rad[i], cw->b2_rad[i], &a0, &b0);
        if (dss_compensate(cal, cw->x_px[i], cw->y_px[i], &a, &b) != SUNMC_OK) {
            if (n_uncomp)
                (*n_uncomp)++;
            continue;
        }
        if (acc) {
            double fd = field_deg(a0, b0);
            band_acc_add(&acc[0], bands, fd, a - a0);
            band_acc_add(&acc[1], bands, fd, b - b0);
        }
        *sum += (a - a0) * (a - a0) + (b - b0) * (b - b0);
        *n += 2;
    }
}

const char *const dss_calfit_models[DSS_N_MODELS] = {
    DSS_CALFIT_MODEL_PHYSICAL, DSS_CALFIT_MODEL_POLYNOMIAL, DSS_CALFIT_MODEL_SPLINE,
    DSS_CALFIT_MODEL_HYBRID, DSS_CALFIT_MODEL_TABLE};

/* Parameters before the fit (a spline's: the fewest rows it is fitted to,
 * less one; its effective degrees of freedom are known after). */
static int n_params(const dss_calib_workspace *cw)
{
    return DSS_MODEL_HAS_PHYSICS(cw->kind)  ? cw->n_free
           : cw->kind == DSS_MODEL_POLYNOMIAL ? dss_poly_n_terms(cw->poly_order)
                                              : DSS_SPLINE_MIN_ROWS - 1;
}

/* The spline's (table's) summary as the report's parameters, its degrees
 * of freedom from its effective ones, and what it is in words. */
static void spline_report(const dss_calibration *cal, size_t n_res, calreport *rep)
{
    const lab_spline *s = &cal->spline;
    const lab_table *t = &cal->table;
    int tab = cal->kind == DSS_MODEL_TABLE, hyb = cal->kind == DSS_MODEL_HYBRID;
    if (!hyb) {
        const char *names[] = {"smoothing", "edf_alpha", "edf_beta", "table_nodes", "table_bytes"};
        double v[] = {s->smooth, s->edf[0], s->edf[1], t->nodes, (double)lab_table_bytes(t)};
        calreport_set_values(rep, names, v, tab ? 5 : 3);
        rep->dof = (int)n_res - (int)lround(s->edf[0]);
    }
    calreport_warn(rep, "nothing to do: compare the held-out error below with the other models'",
                   "the %s's spline: %d breakpoints per input (a tensor product over the spot "
                   "x, y), smoothing %.3g chosen by the held-out error of %d interleaved folds, "
                   "%.1f effective degrees of freedom per angle; readings outside the calibrated "
                   "field are refused by compensate, not extrapolated",
                   hyb ? "correction" : "model", s->nbreak, s->smooth, DSS_SPLINE_FOLDS,
                   s->edf[0]);
    if (tab)
        calreport_warn(rep, "nothing to do: compare the held-out error below with the other "
                            "models'",
                       "the look-up table: %d x %d nodes (steps %.4g and %.4g px), the spline's "
                       "values at its nodes, the step the coarsest within %.0f %% of the best "
                       "held-out error of the folds; %zu bytes as 32-bit floats",
                       t->nodes, t->nodes, lab_table_step(t, 0), lab_table_step(t, 1),
                       100 * LAB_TABLE_STEP_TOL, lab_table_bytes(t));
}

/* Cross-validation by grid quadrant (lab_cross_validate's hooks). */
typedef struct {
    const sunmc_config *c;
    dss_calib_workspace *cw;
} quadrant_folds;

static int quadrant_of(const void *ctx, size_t i)
{
    const dss_calib_workspace *cw = ((const quadrant_folds *)ctx)->cw;
    return 2 * (cw->b1_rad[i] >= 0) + (cw->b2_rad[i] >= 0);
}

static void quadrant_label(const void *ctx, int k, char *buf, size_t len)
{
    static const char *const names[DSS_CV_BLOCKS] = {"b1<0,b2<0", "b1<0,b2>=0", "b1>=0,b2<0",
                                                     "b1>=0,b2>=0"};
    snprintf(buf, len, "%s", names[k]);
}

static int quadrant_refit(void *ctx, const double *held, double sum2[2], long n[2],
                          double *cond)
{
    quadrant_folds *f = ctx;
    dss_calibration ck;
    fit_result fr;
    if (dss_calibrate(f->cw, f->c->max_iterations, &ck, &fr) != SUNMC_OK)
        return 0;
    *cond = 1.0 / fr.rcond;
    angle_errors(f->cw, f->cw->weight, &ck, NULL, NULL, &sum2[0], &n[0], NULL);
    angle_errors(f->cw, held, &ck, NULL, NULL, &sum2[1], &n[1], NULL);
    return 1;
}

static void cross_validate(const sunmc_config *c, dss_calib_workspace *cw, calreport *rep)
{
    quadrant_folds f = {c, cw};
    lab_folds folds = {.n_folds = DSS_CV_BLOCKS, .min_fit_rows = (size_t)n_params(cw),
                       .fold_of = quadrant_of, .label = quadrant_label, .refit = quadrant_refit};
    lab_cross_validate(rep, cw->weight, cw->n, &folds, &f);
}

/* Physical model: parameters, standard errors and correlations; the scaled
 * covariance into cov_s (n_free x n_free) when the fit converged.  Returns
 * 1 when cov_s holds it. */
/* Why groups of the physical model's parameters correlate on a campaign
 * (dss_calib.h's identifiability table), with the campaign's own reach:
 * height, glass thickness and index all set the spot's scale and differ
 * only in how the glass bends wide rays; a principal-point shift, the
 * mount's tilt and the sun simulator's tilt all move the spots one way
 * and differ only as sec^2 of the field angle and through the table's
 * axes, which do not commute, at wide table angles. */
static void dss_check_correlations(calreport *rep)
{
    double b2 = 0, b1 = 0;
    if (rep->campaign.known) {
        b2 = fmax(fabs(rep->campaign.cal_lo[0]), fabs(rep->campaign.cal_hi[0]));
        b1 = fmax(fabs(rep->campaign.cal_lo[1]), fabs(rep->campaign.cal_hi[1]));
    }
    double corner = atan(hypot(tan(b1 * RAD_PER_DEG), tan(b2 * RAD_PER_DEG))) * DEG_PER_RAD;
    char why_scale[CALREPORT_TEXT_MAX / 2], why_tilt[CALREPORT_TEXT_MAX / 2];
    snprintf(why_scale, sizeof why_scale,
             "the pinhole height and the cover glass's thickness and index all set how far from "
             "the centre a spot lands; they differ only in how the glass bends wide rays, and "
             "this campaign reaches %.0f deg of field angle at its corners",
             corner);
    snprintf(why_tilt, sizeof why_tilt,
             "a principal-point shift, the mount's tilt and the sun simulator's tilt all move "
             "the spots one way; they differ only as sec^2 of the field angle and through the "
             "table's axes, which do not commute, at wide angles (this campaign: b1 to %.0f, b2 "
             "to %.0f deg)",
             b1, b2);
    static const char act_scale[] =
        "the spot's scale, which compensation needs, stays determined (cal.sigma shows it); to "
        "separate them hold the index at the glass maker's value (calibration.fit_glass_index "
        "= off) or calibrate to wider field angles";
    static const char act_tilt[] =
        "measure the sun simulator's direction and fix it (--set calibration.sun=measured --set "
        "calibration.sun_b1_measured_arcsec=B1 --set calibration.sun_b2_measured_arcsec=B2), "
        "calibrate in an aligned lab (campaign.mount = aligned: no simulator tilt to fit) or "
        "over wider table angles";
    static const char why_det[] =
        "a detector tilt about X (Y) moves a spot at field angle theta by about h a tan^2 theta "
        "along y (x), which a mount tilt c1 (c2) with the opposite principal-point shift also "
        "does (h c sec^2 theta - h c); they differ only through the table's axes and across "
        "the field at wide angles";
    static const char act_det[] =
        "the sum that compensation needs stays determined (cal.sigma shows it); to separate "
        "them calibrate over wider table angles, or keep calibration.fit_detector_tilt = off "
        "if the tilt's tolerance is small (the mount and the principal point then take it up)";
    const calreport_corr_cause causes[] = {
        {{"fit_dh_px", "fit_glass_thickness_um", "fit_glass_index", NULL}, why_scale, act_scale},
        {{"fit_dy_px", "fit_c1_arcsec", "fit_sun_b1_arcsec", NULL}, why_tilt, act_tilt},
        {{"fit_dx_px", "fit_c2_arcsec", "fit_sun_b2_arcsec", NULL}, why_tilt, act_tilt},
        {{"fit_dy_px", "fit_c1_arcsec", "fit_sun_b1_arcsec", "fit_detector_tilt_x_arcsec", NULL},
         why_det, act_det},
        {{"fit_dx_px", "fit_c2_arcsec", "fit_sun_b2_arcsec", "fit_detector_tilt_y_arcsec", NULL},
         why_det, act_det},
    };
    calreport_check_correlations_explained(rep, CALREPORT_CORR_WARN, causes,
                                           (int)(sizeof causes / sizeof *causes));
}

static int physical_covariance(const dss_calib_workspace *cw, const dss_calibration *cal,
                               const calib_prior *prior, calreport *rep, double *cov_s)
{
    int have_cov = 0;
    /* chisq is in px^2 over 2 n residuals (weighted). */
    double s2 = rep->fit.chisq / rep->dof;
    rep->np = cw->n_free;
    double scale[CALREPORT_MAX_PAR], nominal[CALREPORT_MAX_PAR];
    for (int k = 0; k < cw->n_free; k++) {
        int idx = cw->free_idx[k];
        snprintf(rep->name[k], sizeof rep->name[k], "%s", dss_param_names[idx]);
        rep->value[k] = dss_param_value(&cal->phys, idx);
        scale[k] = dss_param_scale(&cal->phys, idx);
        nominal[k] = cal->phys.nominal[idx];
    }
    calreport_set_priors(rep, prior, nominal, scale);
    /* the priors' weights assumed the config's row noise; the data say s2 */
    double k2 = prior->np > 0 && prior->sigma_row > 0 ? s2 / (prior->sigma_row * prior->sigma_row)
                                                      : 1.0;
    int cst = fit_covariance_rescaled(cw->fw, k2);
    if (cst == SUNMC_OK)
        cst = calreport_covariance(rep, cw->fw->covar, s2, scale);
    if (cst == SUNMC_OK && rep->fit_ok) {
        have_cov = 1;
        for (int i = 0; i < cw->n_free; i++)
            for (int j = 0; j < cw->n_free; j++)
                cov_s[i * cw->n_free + j] = s2 * gsl_matrix_get(cw->fw->covar, i, j);
    }
    if (cst != SUNMC_OK) {
        for (int k = 0; k < rep->np; k++)
            rep->se[k] = NAN;
        calreport_warn(rep, "widen the campaign or fix the parameters it cannot determine",
                       "the parameter covariance could not be computed");
    }
    dss_check_correlations(rep);
    return have_cov;
}

/* The polynomial's coefficients with their standard errors: the alpha and
 * beta fits share the design matrix (weighted monomials of the on-board
 * angles), so their covariances are C = (J^T J)^-1 times each axis's own
 * residual variance (n_used - n_terms degrees of freedom); the two axes are
 * fitted apart, so the correlation matrix is block-diagonal.  cov_s
 * receives s2_alpha C then s2_beta C (n_terms^2 each).  Returns 1 when the
 * covariance could be formed. */
static int poly_covariance(const dss_calib_workspace *cw, const dss_calibration *cal,
                           calreport *rep, double *cov_s)
{
    const dss_poly *q = &cal->poly;
    int nt = q->n_terms;
    rep->np = 2 * nt;
    double s2[2] = {0, 0}, scale[CALREPORT_MAX_PAR];
    for (int k = 0; k < nt; k++) {
        snprintf(rep->name[k], sizeof rep->name[k], "ca_%d", k);
        snprintf(rep->name[nt + k], sizeof rep->name[nt + k], "cb_%d", k);
        rep->value[k] = q->ca[k];
        rep->value[nt + k] = q->cb[k];
        scale[k] = scale[nt + k] = 1.0; /* rad, as params.ini */
    }
    long used = 0;
    for (size_t i = 0; i < cw->n; i++) {
        double am, bm, a0, b0;
        if (!(cw->weight[i] > 0) ||
            dss_onboard_angles(&q->onboard, cw->x_px[i], cw->y_px[i], &am, &bm) != SUNMC_OK)
            continue;
        const double *t = cw->basis + i * (size_t)nt;
        table_truth(cw->b1_rad[i], cw->b2_rad[i], &a0, &b0); /* the polynomial's truth */
        double ra = am - a0, rb = bm - b0;
        for (int k = 0; k < nt; k++) {
            ra += q->ca[k] * t[k];
            rb += q->cb[k] * t[k];
        }
        s2[0] += cw->weight[i] * ra * ra;
        s2[1] += cw->weight[i] * rb * rb;
        used++;
    }
    int ok = used > nt && fit_covariance(cw->fw) == SUNMC_OK;
    gsl_matrix *M = ok ? gsl_matrix_calloc(2 * (size_t)nt, 2 * (size_t)nt) : NULL;
    if (M) {
        for (int a = 0; a < 2; a++) {
            s2[a] /= (double)(used - nt);
            for (int i = 0; i < nt; i++)
                for (int j = 0; j < nt; j++) {
                    double v = s2[a] * gsl_matrix_get(cw->fw->covar, (size_t)i, (size_t)j);
                    gsl_matrix_set(M, (size_t)(a * nt + i), (size_t)(a * nt + j), v);
                    cov_s[a * nt * nt + i * nt + j] = v;
                }
        }
        ok = calreport_covariance(rep, M, 1.0, scale) == SUNMC_OK;
        gsl_matrix_free(M);
    }
    if (!ok) {
        for (int k = 0; k < rep->np; k++)
            rep->se[k] = NAN;
        calreport_warn(rep, "widen the campaign or lower calibration.poly_order",
                       "the polynomial's coefficient covariance could not be computed");
    }
    return ok && rep->fit_ok;
}

/* The polynomial's propagated uncertainty (rad) at reading i: t^T cov t
 * per axis, t the reading's monomials. */
static void poly_sigma(const dss_calib_workspace *cw, int nt, const double *cov_s, size_t i,
                       double sg[2])
{
    const double *t = cw->basis + i * (size_t)nt;
    for (int a = 0; a < 2; a++) {
        double v = 0;
        for (int k = 0; k < nt; k++)
            for (int l = 0; l < nt; l++)
                v += t[k] * cov_s[a * nt * nt + k * nt + l] * t[l];
        sg[a] = sqrt(fmax(v, 0.0));
    }
}

/* Residual per angle and band, the calibration's own uncertainty across
 * the field (the parameter covariance propagated to the compensated angles
 * at each campaign point's fitted-model spot) and the predicted accuracy. */
static void band_stats(const sunmc_config *c, const dss_calib_workspace *cw,
                       const dss_calibration *cal, const double *cov_s, int have_cov,
                       size_t n_res, calreport *rep)
{
    const band_list *bands = &c->bands_deg;
    band_acc acc[2], sig[2];
    double sum;
    long n;
    long n_uncomp = 0;
    angle_errors(cw, cw->weight, cal, bands, acc, &sum, &n, &n_uncomp);
    if (n_uncomp)
        calreport_warn(rep,
                       "check those rows (residuals.tsv: nan angles) for spots beyond the field "
                       "the fitted model covers",
                       "%ld readings could not be compensated with the fitted model: they are "
                       "nan in residuals.tsv and left out of the band statistics",
                       n_uncomp);
    /* Angle-domain residual scaled to the degrees of freedom. */
    rep->sigma_arcsec = n ? sqrt(sum / n * (double)n_res / rep->dof) * ARCSEC_PER_RAD : NAN;
    band_acc_reset(&sig[0]);
    band_acc_reset(&sig[1]);
    double smax[2][CONFIG_BANDS_MAX] = {{0}};
    for (size_t i = 0; have_cov && i < cw->n; i++) {
        double sg[2], a0, b0;
        if (!(cw->weight[i] > 0))
            continue;
        if (cal->kind == DSS_MODEL_POLYNOMIAL)
            poly_sigma(cw, cal->poly.n_terms, cov_s, i, sg);
        else if (dss_labfit_sigma(&cal->phys, cov_s, cw->free_idx, cw->n_free, cw->b1_rad[i],
                                  cw->b2_rad[i], sg) != SUNMC_OK)
            continue;
        dss_calib_truth(cal, cw->b1_rad[i], cw->b2_rad[i], &a0, &b0);
        double fd = field_deg(a0, b0);
        for (int a = 0; a < 2; a++) {
            band_acc_add(&sig[a], bands, fd, sg[a]);
            band_max_add(smax[a], bands, fd, sg[a] * ARCSEC_PER_RAD);
        }
    }
    for (int a = 0; a < 2; a++) {
        band_acc_rms(&acc[a], bands, ARCSEC_PER_RAD, rep->resid_rms[a]);
        band_acc_rms(&sig[a], bands, ARCSEC_PER_RAD, rep->cal_sigma_rms[a]);
        for (int b = 0; b < bands->n; b++) {
            rep->band_n[a][b] = acc[a].n[b];
            if (!have_cov || !sig[a].n[b]) {
                rep->cal_sigma_rms[a][b] = NAN; /* no covariance */
                smax[a][b] = NAN;
            }
            rep->cal_sigma_max[a][b] = smax[a][b];
        }
        calreport_predict(rep, a, sqrt((double)n_res / rep->dof));
    }
}

int dss_labfit_run(const sunmc_config *c, dss_calib_workspace *cw, dss_calibration *cal,
                   calreport *rep, char *err, size_t errlen)
{
    int phys = DSS_MODEL_HAS_PHYSICS(cw->kind), spl = DSS_MODEL_HAS_SPLINE(cw->kind);
    calreport_init(rep, "dss", dss_calfit_models[cw->kind]);
    rep->n_rows = cw->n;
    campaign_cost(c, cw->b2_rad, cw->b1_rad, (long)cw->n, DEG_PER_RAD, &rep->campaign);
    rep->n_angles = 2;
    rep->angle_name[0] = "alpha";
    rep->angle_name[1] = "beta";
    rep->bands = c->bands_deg;
    for (size_t i = 0; i < cw->n; i++)
        rep->n_used += cw->weight[i] > 0;
    int np = n_params(cw);
    /* Physical: two residuals (x, y) per reading; polynomial: one per axis. */
    size_t n_res = phys ? 2 * rep->n_used : rep->n_used;
    if ((int)n_res <= np)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "only %zu usable readings (weight > 0); the %s model has %d parameters",
                          rep->n_used, rep->model, np);
    calib_prior prior;
    int st = dss_prior_apply(c, cw, &prior, err, errlen);
    if (st != SUNMC_OK)
        return st;
    if (c->cal_priors == CONFIG_PRIORS_TOLERANCES && prior.np == 0 && phys)
        calreport_warn(rep, "check the config's design values and tolerances against this sensor",
                       "calibration.priors = tolerances: the priors could not be formed (fewer "
                       "than two of the pilot's %d units could be fitted); fitted without them",
                       c->prior_units);
    st = dss_calibrate(cw, c->max_iterations, cal, &rep->fit);
    if (st == SUNMC_EINPUT)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "too few usable readings for the %s model",
                          rep->model);
    rep->fit_ok = st == SUNMC_OK;
    rep->cond_jacobian = 1.0 / rep->fit.rcond;
    rep->dof = (int)n_res - np;
    if (!rep->fit_ok)
        calreport_warn(rep,
                       "check the data (spot coordinates in px from the detector centre, table "
                       "angles in deg) and the config's design values; if the iteration limit was "
                       "hit, raise calibration.max_iterations",
                       "the fit did not converge: %s (GSL status %d, %zu iterations); its "
                       "parameters must not be used",
                       fit_reason(&rep->fit), rep->fit.status, rep->fit.iterations);
    double cov_s[2 * DSS_POLY_MAX_TERMS * DSS_POLY_MAX_TERMS]; /* >= DSS_NP^2 */
    int have_cov = phys ? physical_covariance(cw, cal, &prior, rep, cov_s)
                   : spl ? 0 : poly_covariance(cw, cal, rep, cov_s);
    if (spl && rep->fit_ok) {
        /* the covariance of a penalised fit is not the parameters' spread:
         * none propagated (the hybrid's physical one would understate) */
        have_cov = 0;
        spline_report(cal, n_res, rep);
    }
    calreport_check_priors(rep);
    band_stats(c, cw, cal, cov_s, have_cov, n_res, rep);
    cross_validate(c, cw, rep);
    dss_labfit_compare(c, cw, rep);
    return SUNMC_OK;
}

int dss_labfit_row(const dss_calib_workspace *cw, const dss_calibration *cal, size_t i,
                   double *a, double *b, double *a0, double *b0)
{
    dss_calib_truth(cal, cw->b1_rad[i], cw->b2_rad[i], a0, b0);
    /* weight 0: no spot (the lab file's convention), so no angle; the
     * (0, 0) it carries is no reading of the boresight */
    if (!(cw->weight[i] > 0) || dss_compensate(cal, cw->x_px[i], cw->y_px[i], a, b) != SUNMC_OK) {
        *a = *b = NAN;
        return SUNMC_EDOM;
    }
    return SUNMC_OK;
}

int dss_labfit_write_residuals(FILE *f, const dss_calib_workspace *cw, const int *line,
                               const dss_calibration *cal)
{
    fprintf(f, "line\tb1_deg\tb2_deg\tx_px\ty_px\tweight\talpha_deg\tbeta_deg\t"
               "alpha_error_arcsec\tbeta_error_arcsec\n");
    for (size_t i = 0; i < cw->n; i++) {
        double a0, b0, a, b;
        dss_labfit_row(cw, cal, i, &a, &b, &a0, &b0);
        tsv_printf(f, "%d\t%.10g\t%.10g\t%.10g\t%.10g\t%g\t%.10g\t%.10g\t%.6g\t%.6g\n",
                line ? line[i] : (int)i + 1, cw->b1_rad[i] * DEG_PER_RAD,
                cw->b2_rad[i] * DEG_PER_RAD, cw->x_px[i], cw->y_px[i], cw->weight[i],
                a * DEG_PER_RAD, b * DEG_PER_RAD, (a - a0) * ARCSEC_PER_RAD,
                (b - b0) * ARCSEC_PER_RAD);
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

int dss_params_fill(params_file *p, const dss_calibration *cal, const calreport *rep)
{
    int st = SUNMC_OK;
    char key[PARAMS_KEY_MAX], comment[PARAMS_COMMENT_MAX];
    if (cal->kind == DSS_MODEL_SPLINE)
        return lab_spline_params_fill(&cal->spline, p, "spline");
    if (cal->kind == DSS_MODEL_TABLE)
        return lab_table_params_fill(&cal->table, p, "table");
    if (DSS_MODEL_HAS_PHYSICS(cal->kind)) {
        const dss_model *m = &cal->phys;
        st = params_set_double(p, "design", "pixel_um", m->pixel_um, "detector pitch");
        if (st == SUNMC_OK && m->half_px > 0)
            st = params_set_double(p, "design", "detector_px", 2 * m->half_px,
                                   "detector side: compensate marks readings beyond it nan");
        if (st == SUNMC_OK && m->disc_c_rad2 > 0)
            st = params_set_double(p, "design", "sun_disc_c_rad2", m->disc_c_rad2,
                                   "the sun's disc: its second moment / 4 (design.sun_disc_deg, "
                                   "limb_darkening); compensate removes its centroid bias");
        if (st == SUNMC_OK)
            st = params_set_double(p, "design", "h_mm", m->nominal[DSS_P_H],
                                   "nominal pinhole height over the detector, glass included");
        if (st == SUNMC_OK)
            st = params_set_double(p, "design", "glass_thickness_mm", m->nominal[DSS_P_T],
                                   "nominal cover-glass thickness");
        if (st == SUNMC_OK)
            st = params_set_double(p, "design", "glass_index", m->nominal[DSS_P_N],
                                   "nominal cover-glass index");
        if (st == SUNMC_OK)
            st = params_set_text(p, "design", "mount",
                                 m->mount == DSS_MOUNT_ALIGNED ? "aligned" : "as_mounted",
                                 "campaign.mount: the frame of the compensated angles");
        for (int k = 0; k < (m->tilt ? DSS_NP : DSS_P_TX) && st == SUNMC_OK; k++) {
            comment[0] = '\0';
            for (int j = 0; rep && j < rep->np; j++)
                if (strcmp(rep->name[j], dss_param_names[k]) == 0 && isfinite(rep->se[j]))
                    snprintf(comment, sizeof comment, "standard error %.3g", rep->se[j]);
            int measured = cal->sun_measured && (k == DSS_P_S1 || k == DSS_P_S2);
            st = params_set_double(p, "parameters", dss_param_names[k], dss_param_value(m, k),
                                   comment[0] ? comment
                                              : measured ? "measured, not fitted (calibration.sun)"
                                                         : "fixed");
        }
        if (st == SUNMC_OK && cal->kind == DSS_MODEL_HYBRID)
            st = lab_spline_params_fill(&cal->spline, p, "correction");
        return st;
    }
    const dss_poly *q = &cal->poly;
    st = params_set_double(p, "design", "order", q->order, "polynomial order");
    if (st == SUNMC_OK)
        st = params_set_double(p, "design", "scale_rad", q->scale_rad, "angle normalisation");
    if (st == SUNMC_OK)
        st = params_set_double(p, "design", "h_mm", q->onboard.h_mm,
                               "on-board formula height, glass included");
    if (st == SUNMC_OK)
        st = params_set_double(p, "design", "pixel_um", q->onboard.pixel_um, "detector pitch");
    if (st == SUNMC_OK)
        st = params_set_double(p, "design", "glass_thickness_mm", q->onboard.glass_t_mm,
                               "on-board formula's cover glass (0: ignored)");
    if (st == SUNMC_OK)
        st = params_set_double(p, "design", "glass_index", q->onboard.glass_n,
                               "on-board formula's cover-glass index");
    for (int k = 0; k < q->n_terms && st == SUNMC_OK; k++) {
        for (int a = 0; a < 2 && st == SUNMC_OK; a++) {
            snprintf(key, sizeof key, "%s_%d", a ? "cb" : "ca", k);
            int j = a * q->n_terms + k;
            if (rep && j < rep->np && isfinite(rep->se[j]))
                snprintf(comment, sizeof comment, "%s correction term, rad, standard error %.3g",
                         a ? "beta" : "alpha", rep->se[j]);
            else
                snprintf(comment, sizeof comment, "%s correction term, rad", a ? "beta" : "alpha");
            st = params_set_double(p, "parameters", key, a ? q->cb[k] : q->ca[k], comment);
        }
    }
    return st;
}

/* The values a DSS calibration can physically have: the design within
 * the config's keys' ranges (design.pixel_um, h_mm, glass_thickness_mm,
 * glass_index), each fitted deviation within its tolerance key's range.
 * Anything else is a damaged or foreign file: compensating with it gives
 * constant or NaN angles. */
static const params_range dss_phys_ranges[] = {
    {"design", "pixel_um", 0.5, 100, "um", "design.pixel_um's range"},
    {"design", "h_mm", 0.2, 50, "mm", "design.h_mm's range"},
    {"design", "glass_thickness_mm", 0, 5, "mm", "design.glass_thickness_mm's range"},
    {"design", "glass_index", 1, 3, "", "design.glass_index's range"},
    {"parameters", "fit_dx_px", -1000, 1000, "px", "tolerance.dx_px's range"},
    {"parameters", "fit_dy_px", -1000, 1000, "px", "tolerance.dy_px's range"},
    {"parameters", "fit_dh_px", -1000, 1000, "px", "tolerance.dh_px's range"},
    {"parameters", "fit_glass_thickness_um", -1000, 1000, "um",
     "tolerance.glass_thickness_um's range"},
    {"parameters", "fit_c1_arcsec", -36000, 36000, "arcsec", "tolerance.c1_arcsec's range"},
    {"parameters", "fit_c2_arcsec", -36000, 36000, "arcsec", "tolerance.c2_arcsec's range"},
    {"parameters", "fit_c3_arcsec", -36000, 36000, "arcsec", "tolerance.c3_arcsec's range"},
    {"parameters", "fit_glass_index", -0.5, 0.5, "", "tolerance.glass_index's range"},
    {"parameters", "fit_sun_b1_arcsec", -36000, 36000, "arcsec", "an angle within 10 deg"},
    {"parameters", "fit_sun_b2_arcsec", -36000, 36000, "arcsec", "an angle within 10 deg"},
};
/* The detector tilt's (calibration.fit_detector_tilt = on), both or neither. */
static const params_range dss_tilt_ranges[] = {
    {"parameters", "fit_detector_tilt_x_arcsec", -36000, 36000, "arcsec",
     "tolerance.detector_tilt_x_arcsec's range"},
    {"parameters", "fit_detector_tilt_y_arcsec", -36000, 36000, "arcsec",
     "tolerance.detector_tilt_y_arcsec's range"},
};
static const params_range dss_poly_ranges[] = {
    {"design", "h_mm", 0.2, 50, "mm", "design.h_mm's range"},
    {"design", "pixel_um", 0.5, 100, "um", "design.pixel_um's range"},
    {"design", "glass_thickness_mm", 0, 5, "mm", "design.glass_thickness_mm's range"},
    {"design", "glass_index", 1, 3, "", "design.glass_index's range"},
    {"design", "scale_rad", 1e-6, 10, "rad", "the polynomial's angle scale"},
};
#define N_RANGES(r) ((int)(sizeof(r) / sizeof(r)[0]))
/* The physical model of a params.ini: [design] nominal values and mount,
 * [parameters] the named deviations. */
static int load_physical(const params_file *p, dss_model *m, char *err, size_t errlen)
{
    static const char *const design_keys[] = {"pixel_um", "h_mm", "glass_thickness_mm",
                                              "glass_index"};
    double dv[4];
    const char *mount = NULL;
    static const char *const known[] = {"pixel_um",    "detector_px", "sun_disc_c_rad2", "h_mm",
                                        "glass_thickness_mm", "glass_index", "mount"};
    int st = params_check_keys(p, "parameters", dss_param_names, DSS_NP, err, errlen);
    if (st == SUNMC_OK)
        st = params_check_keys(p, "design", known, N_RANGES(known), err, errlen);
    if (st == SUNMC_OK)
        st = params_check_ranges(p, dss_phys_ranges, N_RANGES(dss_phys_ranges), err, errlen);
    for (int k = 0; k < 4 && st == SUNMC_OK; k++)
        st = params_get_double(p, "design", design_keys[k], &dv[k], err, errlen);
    if (st == SUNMC_OK)
        st = params_get_text(p, "design", "mount", &mount, err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "design", "mount",
                            strcmp(mount, "aligned") == 0 || strcmp(mount, "as_mounted") == 0,
                            "aligned or as_mounted", err, errlen);
    /* What the inverse cannot work with: no pitch, no height, an index
     * below 1. */
    if (st == SUNMC_OK)
        st = params_require(p, "design", "pixel_um", dv[0] > 0, "> 0", err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "design", "h_mm", dv[1] > 0, "> 0", err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "design", "glass_index", dv[3] >= 1, ">= 1", err, errlen);
    if (st != SUNMC_OK)
        return st;
    dss_design d = {.h_mm = dv[1], .pixel_um = dv[0], .glass_thickness_mm = dv[2],
                    .glass_index = dv[3],
                    .mount = strcmp(mount, "aligned") == 0 ? DSS_MOUNT_ALIGNED
                                                           : DSS_MOUNT_AS_MOUNTED};
    dss_model_init(m, &d);
    m->half_px = 0; /* older params.ini: no detector side, no check */
    int side = 0;
    if (params_find(p, "design", "detector_px") &&
        (st = params_get_int(p, "design", "detector_px", &side, err, errlen)) == SUNMC_OK &&
        (st = params_require(p, "design", "detector_px", side >= 1, ">= 1", err, errlen)) ==
            SUNMC_OK)
        m->half_px = 0.5 * side;
    if (st == SUNMC_OK && params_find(p, "design", "sun_disc_c_rad2") &&
        (st = params_get_double(p, "design", "sun_disc_c_rad2", &m->disc_c_rad2, err,
                                errlen)) == SUNMC_OK)
        st = params_require(p, "design", "sun_disc_c_rad2",
                            m->disc_c_rad2 >= 0 && m->disc_c_rad2 <= DSS_DISC_C_MAX_RAD2,
                            "in [0, 1e-4] (a sun disc of at most 2 deg)", err, errlen);
    if (st != SUNMC_OK)
        return st;
    int tx = params_find(p, "parameters", dss_param_names[DSS_P_TX]) != NULL;
    int ty = params_find(p, "parameters", dss_param_names[DSS_P_TY]) != NULL;
    if (tx || ty)
        st = params_check_ranges(p, dss_tilt_ranges, N_RANGES(dss_tilt_ranges), err, errlen);
    m->tilt = tx && ty;
    for (int k = 0; k < (m->tilt ? DSS_NP : DSS_P_TX) && st == SUNMC_OK; k++) {
        double v;
        st = params_get_double(p, "parameters", dss_param_names[k], &v, err, errlen);
        dss_param_set(m, k, v);
    }
    const double *q = m->p;
    if (st == SUNMC_OK)
        st = params_require(p, "parameters", "fit_dh_px", q[DSS_P_H] > 0,
                            "> -design.h_mm / design.pixel_um, in mm (a pinhole above the detector)",
                            err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "parameters", "fit_glass_thickness_um", q[DSS_P_T] < q[DSS_P_H],
                            "such that the glass lies under the pinhole", err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "parameters", "fit_glass_index", q[DSS_P_N] >= 1,
                            ">= 1 - design.glass_index (a glass index of at least 1)", err,
                            errlen);
    if (st == SUNMC_OK)
        dss_model_prepare(m);
    return st;
}

/* Every key of the polynomial's [design] and [parameters]: a coefficient
 * ca_K, cb_K beyond the order's terms is refused, never dropped. */
static int poly_keys_known(const params_file *p, const dss_poly *q, char *err, size_t errlen)
{
    static const char *const design[] = {"order",    "scale_rad",          "h_mm",
                                         "pixel_um", "glass_thickness_mm", "glass_index"};
    int st = params_check_keys(p, "design", design, N_RANGES(design), err, errlen);
    char buf[2 * DSS_POLY_MAX_TERMS][16];
    const char *names[2 * DSS_POLY_MAX_TERMS];
    for (int k = 0; k < 2 * q->n_terms; k++) {
        snprintf(buf[k], sizeof buf[k], "%s_%d", k % 2 ? "cb" : "ca", k / 2);
        names[k] = buf[k];
    }
    const params_entry *e = params_unknown_key(p, "parameters", names, 2 * q->n_terms);
    int term = 0, n = 0;
    if (st != SUNMC_OK || !e)
        return st;
    if ((sscanf(e->key, "ca_%d%n", &term, &n) == 1 || sscanf(e->key, "cb_%d%n", &term, &n) == 1) &&
        e->key[n] == '\0' && term >= q->n_terms)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: unknown key parameters.%s: not a term of order %d (ca_0, cb_0 "
                          ".. ca_%d, cb_%d): a coefficient beyond the order",
                          p->path, e->line, e->key, q->order, q->n_terms - 1, q->n_terms - 1);
    return params_check_keys(p, "parameters", names, 2 * q->n_terms, err, errlen);
}

/* The polynomial model of a params.ini: [design] its order, scale and the
 * on-board formula's geometry, [parameters] ca_K, cb_K. */
static int load_poly(const params_file *p, dss_poly *q, char *err, size_t errlen)
{
    int order = 0;
    int st = params_get_int(p, "design", "order", &order, err, errlen);
    char whole[32];
    snprintf(whole, sizeof whole, "1..%d", DSS_POLY_MAX_ORDER);
    if (st == SUNMC_OK)
        st = params_require(p, "design", "order", order >= 1 && order <= DSS_POLY_MAX_ORDER,
                            whole, err, errlen);
    if (st != SUNMC_OK)
        return st;
    q->order = order;
    q->n_terms = dss_poly_n_terms(q->order);
    st = poly_keys_known(p, q, err, errlen);
    if (st == SUNMC_OK)
        st = params_check_ranges(p, dss_poly_ranges, N_RANGES(dss_poly_ranges), err, errlen);
    dss_onboard *o = &q->onboard;
    const char *const keys[] = {"scale_rad", "h_mm", "pixel_um", "glass_thickness_mm",
                                "glass_index"};
    double *v[] = {&q->scale_rad, &o->h_mm, &o->pixel_um, &o->glass_t_mm, &o->glass_n};
    for (int k = 0; k < 5 && st == SUNMC_OK; k++)
        st = params_get_double(p, "design", keys[k], v[k], err, errlen);
    o->pixel_mm = o->pixel_um * MM_PER_UM;
    if (st == SUNMC_OK)
        st = params_require(p, "design", "scale_rad", q->scale_rad > 0, "> 0", err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "design", "h_mm", o->h_mm > 0, "> 0", err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "design", "pixel_um", o->pixel_um > 0, "> 0", err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "design", "glass_thickness_mm",
                            o->glass_t_mm >= 0 && o->glass_t_mm < o->h_mm,
                            ">= 0 and below design.h_mm", err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "design", "glass_index", o->glass_n >= 1, ">= 1", err, errlen);
    char key[PARAMS_KEY_MAX];
    for (int k = 0; k < q->n_terms && st == SUNMC_OK; k++) {
        snprintf(key, sizeof key, "ca_%d", k);
        st = params_get_double(p, "parameters", key, &q->ca[k], err, errlen);
        snprintf(key, sizeof key, "cb_%d", k);
        if (st == SUNMC_OK)
            st = params_get_double(p, "parameters", key, &q->cb[k], err, errlen);
    }
    return st;
}

static int load_current(const params_file *p, dss_calibration *cal, char *err, size_t errlen)
{
    const char *model;
    int st = params_get_text(p, "calibration", "model", &model, err, errlen);
    if (st != SUNMC_OK)
        return st;
    memset(cal, 0, sizeof *cal);
    if (strcmp(model, DSS_CALFIT_MODEL_PHYSICAL) == 0) {
        cal->kind = DSS_MODEL_PHYSICAL;
        return load_physical(p, &cal->phys, err, errlen);
    }
    if (strcmp(model, DSS_CALFIT_MODEL_POLYNOMIAL) == 0) {
        cal->kind = DSS_MODEL_POLYNOMIAL;
        return load_poly(p, &cal->poly, err, errlen);
    }
    if (strcmp(model, DSS_CALFIT_MODEL_SPLINE) == 0) {
        cal->kind = DSS_MODEL_SPLINE;
        return lab_spline_params_load(p, "spline", &cal->spline, err, errlen);
    }
    if (strcmp(model, DSS_CALFIT_MODEL_TABLE) == 0) {
        cal->kind = DSS_MODEL_TABLE;
        return lab_table_params_load(p, "table", &cal->table, err, errlen);
    }
    if (strcmp(model, DSS_CALFIT_MODEL_HYBRID) == 0) {
        st = load_physical(p, &cal->phys, err, errlen);
        cal->kind = DSS_MODEL_HYBRID;
        return st == SUNMC_OK ? lab_spline_params_load(p, "correction", &cal->spline, err, errlen)
                              : st;
    }
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: unknown dss model '%s'", p->path,
                      params_find(p, "calibration", "model")->line, model);
}

/* Files written before these keys took their config keys' names:
 * h_nom_mm, glass_t_mm and glass_n (the polynomial's) and pixel_mm (both
 * models, in mm) are read as h_mm, glass_thickness_mm, glass_index and
 * pixel_um (docs/outputs.md). */
static void rename_earlier_keys(params_file *q)
{
    params_rename(q, "design", "h_nom_mm", "h_mm");
    params_rename(q, "design", "glass_t_mm", "glass_thickness_mm");
    params_rename(q, "design", "glass_n", "glass_index");
    if (!params_rename(q, "design", "pixel_mm", "pixel_um"))
        return;
    params_entry *e = (params_entry *)params_find(q, "design", "pixel_um");
    char *end;
    double mm = strtod(e->value, &end);
    while (*end == ' ' || *end == '\t')
        end++;
    if (end != e->value && *end == '\0')
        snprintf(e->value, sizeof e->value, "%.17g", mm * UM_PER_MM);
}

int dss_params_load(const params_file *p, dss_calibration *cal, char *err, size_t errlen)
{
    params_file *q = malloc(sizeof *q);
    if (!q)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory reading %s", p->path);
    *q = *p;
    rename_earlier_keys(q);
    int st = load_current(q, cal, err, errlen);
    free(q);
    return st;
}
