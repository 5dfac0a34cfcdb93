/* ess_labfit.c - `sunmc calibrate` of an ESS: the Monte Carlo's fit
 * (ess_calibrate) plus uncertainty, residuals, cross-validation and
 * params.ini. */
#include "ess_labfit.h"
#include "ess_prior.h"
#include "ess_unit.h"
#include "family.h"
#include "lab.h"
#include "status.h"
#include "tsvnum.h"
#include "units.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Line numbers of gross-error rows quoted in the warning. */
#define GROSS_LINES_QUOTED 5
/* Two beta lines closer than this (rad) are the same line. */
#define BETA_SAME_RAD 1e-9

/* Parameter display units: internal value * scale = value in name's unit. */
static const double par_scale[ESS_NP_MAX] = {
    1.0,         1.0,         1.0,         DEG_PER_RAD, DEG_PER_RAD, ARCSEC_PER_RAD,
    ARCSEC_PER_RAD, ARCSEC_PER_RAD, DEG_PER_RAD, DEG_PER_RAD, DEG_PER_RAD, DEG_PER_RAD,
    DEG_PER_RAD, DEG_PER_RAD, DEG_PER_RAD, DEG_PER_RAD, DEG_PER_RAD, DEG_PER_RAD};

/* d raw / d alpha_d (G) and d raw / d p of the fine-code parameters at
 * alpha_d = ad: the paper's term, or the extended model's. */
static double fine_partials(const ess_model *m, double ad, double draw_dp[ESS_NP_MAX])
{
    const double *p = m->p;
    if (m->kind == ESS_MODEL_EXTENDED) {
        double dF;
        ess_model_ext_fine(m, ad, &dF, draw_dp);
        for (int j = 0; j < ESS_NP_MAX; j++)
            draw_dp[j] = -draw_dp[j];
        return 1.0 - dF;
    }
    double wa = m->omega * ad;
    draw_dp[ESS_P_KS] = -sin(wa);
    draw_dp[ESS_P_KC] = -cos(wa);
    return 1.0 - m->omega * (p[ESS_P_KS] * cos(wa) - p[ESS_P_KC] * sin(wa));
}

void ess_compensate_gradient(const ess_model *m, double alpha_rad, double h[ESS_NP_MAX])
{
    const double *p = m->p;
    double T = tan(alpha_rad);
    double N = p[ESS_P_A] * T + p[ESS_P_B], D = p[ESS_P_C] * T + 1.0;
    double q = N * N + D * D;
    double draw_dp[ESS_NP_MAX] = {0};
    double G = fine_partials(m, atan2(N, D), draw_dp);
    double draw_dalpha = G * (p[ESS_P_A] * D - N * p[ESS_P_C]) / q * (1.0 + T * T);
    draw_dp[ESS_P_A] = G * T * D / q;
    draw_dp[ESS_P_B] = G * D / q;
    draw_dp[ESS_P_C] = -G * N * T / q;
    draw_dp[ESS_P_INST_Y] = draw_dp[ESS_P_INST_Z] = draw_dp[ESS_P_SUN_Y] = 0.0;
    for (int j = 0; j < m->np; j++)
        h[j] = -draw_dp[j] / draw_dalpha;
}

double ess_labfit_sigma(const ess_model *m, const double cov[ESS_NP_MAX][ESS_NP_MAX],
                        double alpha_rad)
{
    double h[ESS_NP_MAX], v = 0;
    ess_compensate_gradient(m, alpha_rad, h);
    for (int i = 0; i < m->np; i++)
        for (int j = 0; j < m->np; j++)
            v += h[i] * cov[i][j] * h[j];
    return sqrt(fmax(v, 0.0));
}

int ess_angle_error(const ess_model *m, double alpha_rad, double beta_rad, double raw_rad,
                    double *err_rad)
{
    mat3 rx, ry, M;
    rot_x(alpha_rad, rx);
    rot_y(-beta_rad, ry); /* the table turns the sensor: active */
    mat3_mul(rx, ry, M);
    double w[3], s[3], comp;
    mat3_vec(M, m->v, w);
    mat3_vec(m->R, w, s);
    int st = ess_model_compensate(m, raw_rad, &comp);
    if (st != SUNMC_OK)
        return st;
    *err_rad = comp - atan2(s[1], s[2]);
    return SUNMC_OK;
}

static void gross_check(const sunmc_config *c, ess_calib_workspace *cw, const int *line,
                        ess_labfit_result *res, calreport *rep)
{
    const ess_config *ec = ess_cfg(c);
    double half_period = ess_half_period_rad(c);
    char lines[CALREPORT_TEXT_MAX / 2] = "";
    size_t used = 0;
    res->n_gross = 0;
    for (size_t i = 0; i < cw->n; i++) {
        if (!(cw->weight[i] > 0) || !ess_is_gross(cw->raw_rad[i], cw->alpha_rad[i], half_period))
            continue;
        cw->weight[i] = 0.0;
        if (res->n_gross < GROSS_LINES_QUOTED && line && used < sizeof lines)
            used += (size_t)snprintf(lines + used, sizeof lines - used, "%s%d",
                                     res->n_gross ? ", " : "", line[i]);
        res->n_gross++;
    }
    if (res->n_gross)
        calreport_warn(rep,
                       "check those rows (table angle recorded right? sensor in its field?) and "
                       "repeat the readings; they were left out of the fit",
                       "%d readings differ from the table alpha by more than half a fine "
                       "period (%g deg)%s%s%s: the coarse code picked the wrong period or the "
                       "row is mis-recorded",
                       res->n_gross, ec->design.theta0_deg / 2, line ? " (lines " : "", lines,
                       line ? (res->n_gross > GROSS_LINES_QUOTED ? ", ...)" : ")") : "");
}

static void alias_warnings(const sunmc_config *c, const ess_calib_workspace *cw, calreport *rep)
{
    const ess_config *ec = ess_cfg(c);
    const ess_alias *a = &cw->alias.h[0];
    for (int j = 0; j < 2; j++)
        if (a->weak[j])
            calreport_warn(rep,
                           "record the campaign with an alpha step that is not a multiple of "
                           "theta0/8 (e.g. 0.2 deg for theta0 = 2 deg) so the readings fall on "
                           "many phases of the fine-code period",
                           "fine-code term aliased by the campaign step: the alpha values sample "
                           "the %g-deg fine-code period at too few phases; the direction (ks, "
                           "kc) = (%+.3f, %+.3f) has %.3g of a full spread's variance (below "
                           "calibration.alias_threshold = %g), so it was regularised to 0 and "
                           "that part of the fine-code error stays uncorrected",
                           ec->design.theta0_deg / 4, a->evec[j][0], a->evec[j][1],
                           a->eig_norm[j], ec->alias_threshold);
    for (int h = 1; h < cw->alias.n_h; h++)
        if (cw->alias.h[h].n_weak)
            calreport_warn(rep,
                           "record the campaign with an alpha step that samples every harmonic "
                           "of the fine period apart (for theta0 = 2 deg e.g. 0.2, 0.7 or 0.9 "
                           "deg: not 0.8, which samples the 1st harmonic as the 4th), or use "
                           "calibration.model = paper",
                           "harmonic %d of the %g-deg fine period aliased by the campaign step: "
                           "%d of its 2 directions keep %.3g of a full spread's variance once "
                           "the harmonics before it are fitted (below "
                           "calibration.alias_threshold = %g); they were regularised to 0 with "
                           "all their incidence terms",
                           cw->alias.harmonic[h], ec->design.theta0_deg, cw->alias.h[h].n_weak,
                           cw->alias.h[h].eig_norm[0], ec->alias_threshold);
}

/* Cross-validation by beta line (lab_cross_validate's hooks). */
typedef struct {
    const sunmc_config *c;
    ess_calib_workspace *cw;
    double theta0, roll;
    int nb;
    double betas[CALREPORT_MAX_FOLDS];
} beta_folds;

int ess_beta_line_of(const double *betas, int nb, double beta_rad)
{
    for (int k = 0; k < nb; k++)
        if (fabs(beta_rad - betas[k]) <= BETA_SAME_RAD)
            return k;
    return -1;
}

int ess_beta_lines(const ess_calib_workspace *cw, double *betas, int max)
{
    int nb = 0;
    for (size_t i = 0; i < cw->n; i++) {
        if (!(cw->weight[i] > 0) || ess_beta_line_of(betas, nb, cw->beta_rad[i]) >= 0)
            continue;
        if (nb == max)
            return -1;
        betas[nb++] = cw->beta_rad[i];
    }
    return nb;
}

static int beta_fold_of(const void *ctx, size_t i)
{
    const beta_folds *f = ctx;
    return ess_beta_line_of(f->betas, f->nb, f->cw->beta_rad[i]);
}

static void beta_fold_label(const void *ctx, int k, char *buf, size_t len)
{
    snprintf(buf, len, "beta = %g deg", ((const beta_folds *)ctx)->betas[k] * DEG_PER_RAD);
}

/* Angle-domain sum of squares (rad^2) over rows with use[i] > 0 that can be
 * compensated; *n counts them. */
static double angle_sum2(const ess_calib_workspace *cw, const double *use, const ess_model *m,
                         long *n)
{
    double sum = 0;
    *n = 0;
    for (size_t i = 0; i < cw->n; i++) {
        double e;
        if (use[i] > 0 &&
            ess_angle_error(m, cw->alpha_rad[i], cw->beta_rad[i], cw->raw_rad[i], &e) == SUNMC_OK) {
            sum += e * e;
            (*n)++;
        }
    }
    return sum;
}

static int beta_fold_refit(void *ctx, const double *held, double sum2[2], long n[2],
                           double *cond)
{
    beta_folds *f = ctx;
    ess_model mk;
    fit_result fr;
    if (ess_calibrate(f->cw, f->theta0, f->roll, ess_cfg(f->c)->alias_threshold,
                      f->c->max_iterations, &mk, &fr) != SUNMC_OK)
        return 0;
    *cond = 1.0 / fr.rcond;
    sum2[0] = angle_sum2(f->cw, f->cw->weight, &mk, &n[0]);
    sum2[1] = angle_sum2(f->cw, held, &mk, &n[1]);
    return 1;
}

static void cross_validate(const sunmc_config *c, ess_calib_workspace *cw, calreport *rep,
                           double theta0, double roll)
{
    beta_folds f = {.c = c, .cw = cw, .theta0 = theta0, .roll = roll};
    f.nb = ess_beta_lines(cw, f.betas, CALREPORT_MAX_FOLDS);
    int too_many = f.nb < 0;
    if (too_many || f.nb < 2) {
        snprintf(rep->cv_note, sizeof rep->cv_note,
                 too_many ? "more than %d beta lines" : "the campaign has %d beta line: hold-out "
                                                         "needs at least two",
                 too_many ? CALREPORT_MAX_FOLDS : f.nb);
        return;
    }
    lab_folds folds = {.n_folds = f.nb, .min_fit_rows = cw->np_fit, .fold_of = beta_fold_of,
                       .label = beta_fold_label, .refit = beta_fold_refit};
    lab_cross_validate(rep, cw->weight, cw->n, &folds, &f);
}

/* Residual per band (angle domain), propagated sigma across the field, and
 * the predicted after-calibration RMS. */
static void band_stats(const sunmc_config *c, const ess_calib_workspace *cw,
                       const ess_labfit_result *res, calreport *rep, int *n_uncomp)
{
    const band_list *bands = &c->bands_deg;
    band_acc resid, cal;
    band_acc_reset(&resid);
    band_acc_reset(&cal);
    double amin = INFINITY, amax = -INFINITY;
    *n_uncomp = 0;
    for (size_t i = 0; i < cw->n; i++) {
        if (!(cw->weight[i] > 0))
            continue;
        amin = fmin(amin, cw->alpha_rad[i]);
        amax = fmax(amax, cw->alpha_rad[i]);
        double e, comp;
        if (ess_angle_error(&res->m, cw->alpha_rad[i], cw->beta_rad[i], cw->raw_rad[i], &e) !=
            SUNMC_OK) {
            (*n_uncomp)++;
            continue;
        }
        comp = cw->raw_rad[i];
        ess_model_compensate(&res->m, cw->raw_rad[i], &comp);
        band_acc_add(&resid, bands, fabs(comp) * DEG_PER_RAD, e);
    }
    for (int b = 0; b < bands->n; b++)
        rep->cal_sigma_max[0][b] = 0;
    long na = isfinite(amin) ? grid_count(amin * DEG_PER_RAD, amax * DEG_PER_RAD,
                                          ESS_FIELD_STEP_DEG, 0)
                             : 0;
    for (long j = 0; j < na; j++) {
        double a_deg = amin * DEG_PER_RAD + (double)j * ESS_FIELD_STEP_DEG;
        double s = ess_labfit_sigma(&res->m, res->cov, a_deg * RAD_PER_DEG);
        band_acc_add(&cal, bands, fabs(a_deg), s);
        band_max_add(rep->cal_sigma_max[0], bands, fabs(a_deg), s * ARCSEC_PER_RAD);
    }
    band_acc_rms(&resid, bands, ARCSEC_PER_RAD, rep->resid_rms[0]);
    band_acc_rms(&cal, bands, ARCSEC_PER_RAD, rep->cal_sigma_rms[0]);
    /* The in-sample residual underestimates the noise by (n - p) / n. */
    double dof_factor = rep->dof > 0 ? sqrt((double)rep->n_used / (double)rep->dof) : NAN;
    for (int b = 0; b < bands->n; b++) {
        rep->band_n[0][b] = resid.n[b];
        if (!cal.n[b])
            rep->cal_sigma_max[0][b] = NAN;
    }
    calreport_predict(rep, 0, dof_factor);
}

/* Residual variance, parameters with standard errors and correlations
 * (of the fitted parameters: a measured sun tilt is not one), and the
 * scaled covariance res->cov (model order; 0 for a fixed parameter). */
static void parameters(const ess_calib_workspace *cw, const calib_prior *prior,
                       ess_labfit_result *res, calreport *rep)
{
    /* Residual variance with the degrees of freedom the data leave: the
     * regularised (aliased) directions are fixed by their priors. */
    double chi2 = 0;
    for (size_t i = 0; i < cw->n; i++)
        if (cw->weight[i] > 0) {
            double r = ess_model_predict(&res->m, cw->alpha_rad[i], cw->beta_rad[i], NULL) -
                       cw->raw_rad[i];
            chi2 += cw->weight[i] * r * r;
        }
    int np = cw->np_fit;
    rep->dof = (int)rep->n_used - np + cw->alias.n_prior;
    res->s2 = chi2 / rep->dof;
    rep->sigma_arcsec = sqrt(res->s2) * ARCSEC_PER_RAD;
    rep->np = np;
    double scale[ESS_NP_MAX];
    for (int j = 0; j < np; j++) {
        int q = ess_calib_param_of(cw, j);
        snprintf(rep->name[j], sizeof rep->name[j], "%s", ess_param_names[q]);
        scale[j] = par_scale[q];
        rep->value[j] = res->m.p[q] * scale[j];
    }
    calreport_set_priors(rep, prior, NULL, scale);
    /* the priors' weights assumed the config's row noise; the data say s2 */
    double k = prior->np > 0 && prior->sigma_row > 0 ? res->s2 / (prior->sigma_row * prior->sigma_row)
                                                     : 1.0;
    int cst = fit_covariance_rescaled(cw->fw, k);
    if (cst == SUNMC_OK)
        cst = calreport_covariance(rep, cw->fw->covar, res->s2, scale);
    if (cst == SUNMC_OK) {
        for (int i = 0; i < np; i++)
            for (int j = 0; j < np; j++)
                res->cov[ess_calib_param_of(cw, i)][ess_calib_param_of(cw, j)] =
                    res->s2 * gsl_matrix_get(cw->fw->covar, (size_t)i, (size_t)j);
    } else {
        for (int i = 0; i < np; i++)
            rep->se[i] = NAN;
        calreport_warn(rep, "widen the campaign or fix parameters the data cannot determine",
                       "the parameter covariance could not be computed (singular Jacobian): "
                       "standard errors and the propagated accuracy are unavailable");
    }
}

/* Why eq. 12's b and c correlate with the sun simulator's tilt toward Y
 * on a campaign, with its own widest beta line.  At beta = 0 the tilt is
 * a rotation about X, alpha -> alpha + tilt, which eq. 12 makes with
 * b = -c = tan(tilt) (tan(alpha + d) = (T + tan d) / (1 - T tan d)); the
 * outer frame turns the tilt away from X by beta, so only the beta lines
 * tell them apart, by about 1 - cos(beta). */
static void ess_check_correlations(calreport *rep)
{
    double bmax = 0;
    if (rep->campaign.known)
        bmax = fmax(fabs(rep->campaign.cal_lo[1]), fabs(rep->campaign.cal_hi[1]));
    char why[CALREPORT_TEXT_MAX / 2], action[CALREPORT_TEXT_MAX];
    snprintf(why, sizeof why,
             "at beta = 0 the sun simulator's tilt toward Y turns alpha as eq. 12's b = -c does "
             "(tan(alpha + d)); only the beta lines separate them, by 1 - cos(beta) = %.2f at "
             "this campaign's widest |beta| = %g deg",
             1 - cos(bmax * RAD_PER_DEG), bmax);
    snprintf(action, sizeof action,
             "b and c are what compensation uses, so their spread is in cal.sigma: put beta "
             "lines farther out (1 - cos(beta) = 0.29 at 45 deg, 0.50 at 60 deg) or measure the "
             "sun simulator's tilt toward Y and fix it (--set calibration.sun_y=measured --set "
             "calibration.sun_y_measured_arcsec=VALUE); the sum that the beta = 0 line sees "
             "stays determined");
    const calreport_corr_cause causes[] = {
        {{"b", "c", "fit_sun_y_arcsec", NULL}, why, action},
    };
    calreport_check_correlations_explained(rep, CALREPORT_CORR_WARN, causes,
                                           (int)(sizeof causes / sizeof *causes));
}

static const char *const calfit_models[ESS_N_MODELS] = {
    ESS_CALFIT_MODEL, ESS_CALFIT_MODEL_EXT, ESS_CALFIT_MODEL_SPLINE, ESS_CALFIT_MODEL_HYBRID,
    ESS_CALFIT_MODEL_TABLE};
/* The params.ini section of a spline model's spline (or table). */
static const char *const spline_sections[ESS_N_MODELS] = {NULL, NULL, "spline", "correction",
                                                          "table"};

const char *ess_labfit_model_name(int kind)
{
    return calfit_models[kind >= 0 && kind < ESS_N_MODELS ? kind : ESS_MODEL_PAPER];
}

/* The spline's (table's) summary: the report's parameters for spline and
 * table (nothing of the physics is fitted), and in words for all three. */
static void spline_report(const ess_model *m, size_t n_used, calreport *rep)
{
    const lab_spline *s = &m->spline;
    const lab_table *t = &m->table;
    int tab = m->kind == ESS_MODEL_TABLE, hyb = m->kind == ESS_MODEL_HYBRID;
    if (!hyb) {
        const char *names[] = {"smoothing", "edf", "table_nodes", "table_step_deg", "table_bytes"};
        double v[] = {s->smooth, s->edf[0], t->nodes, lab_table_step(t, 0) * DEG_PER_RAD,
                      (double)lab_table_bytes(t)};
        calreport_set_values(rep, names, v, tab ? 5 : 2);
        rep->dof = (int)n_used - (int)lround(s->edf[0]);
    }
    calreport_warn(rep, "nothing to do: compare the models' held-out errors below",
                   "the %s's spline: %d breakpoints over the measured angle, smoothing %.3g "
                   "chosen by the held-out error of %d interleaved folds, %.1f effective degrees "
                   "of freedom; one input: what the true angle owes to beta (the incidence) it "
                   "cannot follow; readings outside the calibrated field are refused by "
                   "compensate, not extrapolated",
                   hyb ? "correction" : "model", s->nbreak, s->smooth, ESS_SPLINE_FOLDS,
                   s->edf[0]);
    if (tab)
        calreport_warn(rep, "nothing to do: compare the models' held-out errors below",
                       "the look-up table: %d nodes (step %.4g deg of the measured angle), the "
                       "spline's values at its nodes, the step the coarsest within %.0f %% of "
                       "the best held-out error of the folds; %zu bytes as 32-bit floats",
                       t->nodes, lab_table_step(t, 0) * DEG_PER_RAD, 100 * LAB_TABLE_STEP_TOL,
                       lab_table_bytes(t));
}

int ess_labfit_run(const sunmc_config *c, ess_calib_workspace *cw, const int *line,
                   ess_labfit_result *res, calreport *rep, char *err, size_t errlen)
{
    const ess_config *ec = ess_cfg(c);
    calreport_init(rep, "ess", ess_labfit_model_name(cw->kind));
    memset(res, 0, sizeof *res);
    double theta0 = ec->design.theta0_deg * RAD_PER_DEG;
    double roll = ec->roll_measured_arcsec * RAD_PER_ARCSEC;
    rep->n_rows = cw->n;
    campaign_cost(c, cw->alpha_rad, cw->beta_rad, (long)cw->n, DEG_PER_RAD, &rep->campaign);
    rep->n_angles = 1;
    rep->angle_name[0] = "alpha";
    rep->bands = c->bands_deg;

    gross_check(c, cw, line, res, rep);
    for (size_t i = 0; i < cw->n; i++)
        rep->n_used += cw->weight[i] > 0;
    int np = cw->np_fit;
    cw->sun_y_rad = ec->sun_y_measured_arcsec * RAD_PER_ARCSEC;
    if (rep->n_used <= (size_t)np)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "only %zu usable data rows (weight > 0, within half a fine period of "
                          "the table alpha); the ess %smodel has %d parameters: need at least %d",
                          rep->n_used, cw->kind == ESS_MODEL_EXTENDED ? "extended " : "", np,
                          np + 1);

    calib_prior prior;
    int st = ess_prior_apply(c, cw, &prior, err, errlen);
    if (st != SUNMC_OK)
        return st;
    if (c->cal_priors == CONFIG_PRIORS_TOLERANCES && prior.np == 0 &&
        cw->kind != ESS_MODEL_SPLINE && cw->kind != ESS_MODEL_TABLE)
        calreport_warn(rep, "check the config's design values and tolerances against this sensor",
                       "calibration.priors = tolerances: the priors could not be formed (fewer "
                       "than two of the pilot's %d units could be fitted); fitted without them",
                       c->prior_units);
    st = ess_calibrate(cw, theta0, roll, ec->alias_threshold, c->max_iterations, &res->m, &rep->fit);
    rep->fit_ok = st == SUNMC_OK;
    rep->cond_jacobian = 1.0 / rep->fit.rcond;
    alias_warnings(c, cw, rep);
    if (!rep->fit_ok)
        calreport_warn(rep,
                       "check the data for outliers and the config's design values (H_mm, "
                       "theta0_deg); if the iteration limit was hit, raise "
                       "calibration.max_iterations",
                       "the fit did not converge: %s (GSL status %d, %zu iterations); its "
                       "parameters must not be used",
                       fit_reason(&rep->fit), rep->fit.status, rep->fit.iterations);

    if (cw->kind == ESS_MODEL_SPLINE || cw->kind == ESS_MODEL_TABLE) {
        if (rep->fit_ok)
            spline_report(&res->m, rep->n_used, rep);
    } else {
        parameters(cw, &prior, res, rep);
        ess_check_correlations(rep);
        calreport_check_priors(rep);
        if (rep->fit_ok && cw->kind == ESS_MODEL_HYBRID)
            spline_report(&res->m, rep->n_used, rep);
    }

    int n_uncomp;
    band_stats(c, cw, res, rep, &n_uncomp);
    if (n_uncomp)
        calreport_warn(rep,
                       "the fitted fine-code amplitude makes the model non-invertible (omega k "
                       ">= 1; extended: its terms' slope bound >= 1): check theta0_deg and the "
                       "data",
                       "%d readings could not be compensated with the fitted model", n_uncomp);
    cross_validate(c, cw, rep, theta0, roll);
    return ess_labfit_compare(c, cw, rep, err, errlen);
}

int ess_labfit_write_residuals(FILE *f, const ess_calib_workspace *cw, const int *line,
                               const ess_model *m)
{
    fprintf(f, "line\talpha_deg\tbeta_deg\toutput_deg\tweight\tresidual_arcsec\t"
               "angle_error_arcsec\n");
    for (size_t i = 0; i < cw->n; i++) {
        double r = ess_model_predict(m, cw->alpha_rad[i], cw->beta_rad[i], NULL) - cw->raw_rad[i];
        double e;
        if (ess_angle_error(m, cw->alpha_rad[i], cw->beta_rad[i], cw->raw_rad[i], &e) != SUNMC_OK)
            e = NAN;
        tsv_printf(f, "%d\t%.10g\t%.10g\t%.12g\t%g\t%.6g\t%.6g\n", line ? line[i] : (int)i + 1,
                cw->alpha_rad[i] * DEG_PER_RAD, cw->beta_rad[i] * DEG_PER_RAD,
                cw->raw_rad[i] * DEG_PER_RAD, cw->weight[i], r * ARCSEC_PER_RAD,
                e * ARCSEC_PER_RAD);
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

int ess_labfit_write_field(FILE *f, const ess_labfit_result *res, double alpha_min_deg,
                           double alpha_max_deg)
{
    fprintf(f, "alpha_deg\tsigma_arcsec\n");
    long na = grid_count(alpha_min_deg, alpha_max_deg, ESS_FIELD_STEP_DEG, 0);
    for (long j = 0; j < na; j++) {
        double a = alpha_min_deg + (double)j * ESS_FIELD_STEP_DEG;
        tsv_printf(f, "%.6g\t%.6g\n", a,
                ess_labfit_sigma(&res->m, res->cov, a * RAD_PER_DEG) * ARCSEC_PER_RAD);
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

static const char *const par_units[ESS_NP_MAX] = {
    "1", "1", "1", "deg", "deg", "arcsec", "arcsec", "arcsec", "deg",
    "deg", "deg", "deg", "deg", "deg", "deg", "deg", "deg", "deg"};

int ess_params_fill(params_file *p, const ess_labfit_result *res, const calreport *rep,
                    double theta0_deg)
{
    int st = params_set_double(p, "design", "theta0_deg", theta0_deg, "fine-code period");
    /* rep's standard errors are the fitted parameters': k counts those */
    for (int j = 0, k = 0; j < res->m.np && st == SUNMC_OK; j++) {
        if (j == ESS_P_SUN_Y && res->m.sun_y_fixed)
            continue;
        char comment[PARAMS_COMMENT_MAX];
        if (rep && isfinite(rep->se[k]))
            snprintf(comment, sizeof comment, "unit %s, standard error %.3g", par_units[j],
                     rep->se[k]);
        else
            snprintf(comment, sizeof comment, "unit %s", par_units[j]);
        st = params_set_double(p, "parameters", ess_param_names[j], res->m.p[j] * par_scale[j],
                               comment);
        k++;
    }
    double k, t;
    ess_model_kt(&res->m, &k, &t);
    if (st == SUNMC_OK)
        st = params_set_double(p, "fixed", "d", 1.0, "eq. 12 d: the common scale of a, b, c, d");
    if (st == SUNMC_OK)
        st = params_set_double(p, "fixed", "roll_measured_arcsec",
                               res->m.roll_rad * ARCSEC_PER_RAD,
                               "installation roll: measured, not fitted");
    if (st == SUNMC_OK && res->m.sun_y_fixed)
        st = params_set_double(p, "fixed", ESS_SUN_Y_MEASURED_KEY,
                               res->m.p[ESS_P_SUN_Y] * ARCSEC_PER_RAD,
                               "sun-simulator tilt toward Y: measured, not fitted");
    if (st == SUNMC_OK)
        st = params_set_double(p, "fixed", "sun_x_arcsec", res->m.sun_x_rad * ARCSEC_PER_RAD,
                               "sun tilt toward X: invisible to an alpha sensor");
    if (st == SUNMC_OK)
        st = params_set_double(p, "derived", "k_deg", k * DEG_PER_RAD,
                               "fine-code amplitude (ESS paper eq. 9)");
    if (st == SUNMC_OK)
        st = params_set_double(p, "derived", "t_rad", t, "fine-code phase (ESS paper eq. 9)");
    if (st == SUNMC_OK && res->m.kind == ESS_MODEL_TABLE)
        st = lab_table_params_fill(&res->m.table, p, "table");
    else if (st == SUNMC_OK && ESS_MODEL_HAS_SPLINE(res->m.kind))
        st = lab_spline_params_fill(&res->m.spline, p, spline_sections[res->m.kind]);
    return st;
}

/* The values an ESS calibration can physically have, from the config's
 * ranges: a fine-code period of design.theta0_deg's range, eq. 12's scale a
 * (H + dH over H: a slit between the dial and ten times its height) and
 * offsets b, c (an offset up to twice the height: design.H_mm down to 0.5
 * mm, tolerance.dd_um up to 1 mm), installation and sun angles within the
 * tolerances' +-36000 arcsec.  Anything else is a damaged or foreign file:
 * compensating with it gives constant or NaN angles. */
static const params_range ess_ranges[] = {
    {"design", "theta0_deg", 0.1, 10, "deg", "design.theta0_deg's range"},
    {"fixed", "roll_measured_arcsec", -36000, 36000, "arcsec",
     "calibration.roll_measured_arcsec's range"},
    {"parameters", "a", 0.1, 10, "", "eq. 12's scale: (H + dH) / H"},
    {"parameters", "b", -2, 2, "", "eq. 12's offset: up to twice the slit height"},
    {"parameters", "c", -2, 2, "", "eq. 12's offset: up to twice the slit height"},
    {"parameters", "fit_install_y_arcsec", -36000, 36000, "arcsec",
     "tolerance.install_y_arcsec's range"},
    {"parameters", "fit_install_z_arcsec", -36000, 36000, "arcsec",
     "tolerance.install_z_arcsec's range"},
};
/* The sun tilt: fitted (in [parameters]) or measured (in [fixed]). */
static const params_range ess_sun_y_ranges[2] = {
    {"parameters", "fit_sun_y_arcsec", -36000, 36000, "arcsec", "tolerance.sun_y_arcsec's range"},
    {"fixed", ESS_SUN_Y_MEASURED_KEY, -36000, 36000, "arcsec",
     "calibration.sun_y_measured_arcsec's range"},
};

/* The fine-code term must leave the output monotonic (omega k < 1), else the
 * compensation has no unique inverse. */
static int ess_params_invertible(const params_file *p, const ess_model *m, char *err,
                                 size_t errlen)
{
    double bound;
    if (m->kind == ESS_MODEL_EXTENDED && !ess_model_ext_invertible(m, &bound)) {
        const params_entry *e = params_find(p, "parameters", "ks_deg");
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: parameters ks_deg .. k2c_cos2_deg: the fine-code terms' slope "
                          "may reach %.3g (must stay below 1), else the output is not monotonic "
                          "and cannot be compensated",
                          p->path, e ? e->line : 0, bound);
    }
    double k = hypot(m->p[ESS_P_KS], m->p[ESS_P_KC]);
    if (m->omega * k < 1.0)
        return SUNMC_OK;
    const params_entry *e = params_find(p, "parameters", "ks_deg");
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "%s:%d: parameters.ks_deg, kc_deg: the fine-code amplitude %.6g deg must "
                      "be below 1/omega = %.6g deg, else the output is not monotonic and cannot "
                      "be compensated",
                      p->path, e ? e->line : 0, k * DEG_PER_RAD, DEG_PER_RAD / m->omega);
}

/* [design], [fixed] and [derived]: every key known (the sun tilt in
 * [fixed] when measured), eq. 12's d the 1 the model's a, b, c are scaled
 * to, the rest numbers (sun_x and the derived k, t are not read: they
 * follow from the others). */
static int ess_other_keys(const params_file *p, char *err, size_t errlen)
{
    static const char *const design[] = {"theta0_deg"};
    static const char *const fixed[] = {"d", "roll_measured_arcsec", "sun_x_arcsec",
                                        ESS_SUN_Y_MEASURED_KEY};
    static const char *const derived[] = {"k_deg", "t_rad"};
    int st = params_check_keys(p, "design", design, 1, err, errlen);
    if (st == SUNMC_OK)
        st = params_check_keys(p, "fixed", fixed, 4, err, errlen);
    if (st == SUNMC_OK)
        st = params_check_keys(p, "derived", derived, 2, err, errlen);
    double d = 1, v;
    if (st == SUNMC_OK && params_find(p, "fixed", "d"))
        st = params_get_double(p, "fixed", "d", &d, err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, "fixed", "d", d == 1.0,
                            "1 (eq. 12's common scale: a, b and c are relative to it)", err, errlen);
    if (st == SUNMC_OK && params_find(p, "fixed", "sun_x_arcsec"))
        st = params_get_double(p, "fixed", "sun_x_arcsec", &v, err, errlen);
    for (int k = 0; k < 2 && st == SUNMC_OK; k++)
        if (params_find(p, "derived", derived[k]))
            st = params_get_double(p, "derived", derived[k], &v, err, errlen);
    return st;
}

int ess_params_load(const params_file *p, ess_model *m, char *err, size_t errlen)
{
    const char *sensor, *model;
    int st = params_get_text(p, "calibration", "sensor", &sensor, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_text(p, "calibration", "model", &model, err, errlen);
    if (st != SUNMC_OK)
        return st;
    int kind = -1;
    for (int k = 0; k < ESS_N_MODELS; k++)
        if (strcmp(model, calfit_models[k]) == 0)
            kind = k;
    if (strcmp(sensor, "ess") != 0 || kind < 0) {
        const params_entry *e = params_find(p, "calibration", "model");
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: sensor %s model %s: expected sensor ess, model %s, %s, %s, %s "
                          "or %s",
                          p->path, e->line, sensor, model, ESS_CALFIT_MODEL,
                          ESS_CALFIT_MODEL_EXT, ESS_CALFIT_MODEL_SPLINE, ESS_CALFIT_MODEL_HYBRID,
                          ESS_CALFIT_MODEL_TABLE);
    }
    int np = ess_model_np(kind);
    /* a measured sun tilt is in [fixed]; [parameters] then lacks it */
    int fixed = params_find(p, "fixed", ESS_SUN_Y_MEASURED_KEY) != NULL;
    const char *names[ESS_NP_MAX];
    int idx[ESS_NP_MAX], nfit = 0;
    for (int j = 0; j < np; j++)
        if (!(fixed && j == ESS_P_SUN_Y)) {
            idx[nfit] = j;
            names[nfit++] = ess_param_names[j];
        }
    st = params_check_keys(p, "parameters", names, nfit, err, errlen);
    if (st == SUNMC_OK)
        st = ess_other_keys(p, err, errlen);
    double theta0_deg, roll_arcsec, v[ESS_NP_MAX] = {0};
    if (st == SUNMC_OK)
        st = params_get_double(p, "design", "theta0_deg", &theta0_deg, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_double(p, "fixed", "roll_measured_arcsec", &roll_arcsec, err, errlen);
    for (int j = 0; j < nfit && st == SUNMC_OK; j++)
        st = params_get_double(p, "parameters", names[j], &v[idx[j]], err, errlen);
    if (st == SUNMC_OK && fixed)
        st = params_get_double(p, "fixed", ESS_SUN_Y_MEASURED_KEY, &v[ESS_P_SUN_Y], err, errlen);
    if (st != SUNMC_OK)
        return st;
    if ((st = params_check_ranges(p, ess_ranges, (int)(sizeof ess_ranges / sizeof ess_ranges[0]),
                                  err, errlen)) != SUNMC_OK ||
        (st = params_check_ranges(p, &ess_sun_y_ranges[fixed], 1, err, errlen)) != SUNMC_OK)
        return st;
    ess_model_init_kind(m, kind, theta0_deg * RAD_PER_DEG, roll_arcsec * RAD_PER_ARCSEC);
    m->sun_y_fixed = fixed;
    for (int j = 0; j < np; j++)
        m->p[j] = v[j] / par_scale[j];
    if ((st = ess_params_invertible(p, m, err, errlen)) != SUNMC_OK)
        return st;
    ess_model_prepare(m);
    if (kind == ESS_MODEL_TABLE)
        return lab_table_params_load(p, "table", &m->table, err, errlen);
    if (ESS_MODEL_HAS_SPLINE(kind))
        return lab_spline_params_load(p, spline_sections[kind], &m->spline, err, errlen);
    return SUNMC_OK;
}
