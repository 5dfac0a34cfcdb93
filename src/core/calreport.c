/* calreport.c - standard errors, correlations and the printed fit report. */
#include "calreport.h"
#include "fold_outliers.h"
#include "registry.h"
#include "report.h"
#include "status.h"
#include "tsvnum.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdarg.h>
#include <string.h>

void calreport_init(calreport *r, const char *sensor, const char *model)
{
    memset(r, 0, sizeof *r);
    r->sensor = sensor;
    r->model = model;
    r->cv_rms_in_arcsec = NAN;
    r->cv_rms_out_arcsec = NAN;
    r->cv_rms_out_all_arcsec = NAN;
}

void calreport_set_values(calreport *r, const char *const *names, const double *values, int n)
{
    r->np = n;
    for (int i = 0; i < n; i++) {
        snprintf(r->name[i], CALREPORT_NAME_MAX, "%s", names[i]);
        r->value[i] = values[i];
        r->se[i] = NAN;
    }
}

void calreport_warn(calreport *r, const char *action, const char *fmt, ...)
{
    if (r->nw >= CALREPORT_MAX_WARN)
        return;
    calreport_warning *w = &r->w[r->nw++];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->reason, sizeof w->reason, fmt, ap);
    va_end(ap);
    snprintf(w->action, sizeof w->action, "%s", action);
}

int calreport_covariance(calreport *r, const gsl_matrix *cov, double s2, const double *scale)
{
    int p = r->np;
    r->cov_ok = 0;
    for (int i = 0; i < p; i++) {
        double v = gsl_matrix_get(cov, (size_t)i, (size_t)i);
        if (!(v > 0) || !isfinite(v))
            return SUNMC_EFIT;
        r->se[i] = sqrt(s2 * v) * fabs(scale[i]);
    }
    gsl_matrix *c = gsl_matrix_alloc((size_t)p, (size_t)p);
    gsl_vector *ev = gsl_vector_alloc((size_t)p);
    gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc((size_t)p);
    if (!c || !ev || !ws) {
        gsl_matrix_free(c);
        gsl_vector_free(ev);
        gsl_eigen_symm_free(ws);
        return SUNMC_ENOMEM;
    }
    for (int i = 0; i < p; i++)
        for (int j = 0; j < p; j++) {
            double cij = gsl_matrix_get(cov, (size_t)i, (size_t)j) /
                         sqrt(gsl_matrix_get(cov, (size_t)i, (size_t)i) *
                              gsl_matrix_get(cov, (size_t)j, (size_t)j));
            r->corr[i][j] = cij;
            gsl_matrix_set(c, (size_t)i, (size_t)j, cij);
        }
    int st = gsl_eigen_symm(c, ev, ws);
    if (st == GSL_SUCCESS) {
        double lo = gsl_vector_min(ev), hi = gsl_vector_max(ev);
        r->cond_correlation = lo > 0 ? hi / lo : INFINITY;
    }
    gsl_matrix_free(c);
    gsl_vector_free(ev);
    gsl_eigen_symm_free(ws);
    r->cov_ok = st == GSL_SUCCESS;
    return st == GSL_SUCCESS ? SUNMC_OK : SUNMC_EFIT;
}

void calreport_predict(calreport *r, int a, double dof_factor)
{
    for (int b = 0; b < r->bands.n; b++) {
        double noise = r->resid_rms[a][b] * dof_factor, cs = r->cal_sigma_rms[a][b];
        r->predicted_rms[a][b] = sqrt(noise * noise + (isnan(cs) ? 0.0 : cs * cs));
    }
}

/* The generic warning of one pair. */
static void pair_warning(calreport *r, double threshold, int i, int j)
{
    calreport_warn(r,
                               "widen the campaign (a wider angle range, scan lines far apart) so "
                               "the two change the output differently, or fix one of them from "
                               "another measurement; their combination is still determined, "
                               "each alone is not",
                               "parameters %s and %s are nearly unidentifiable: correlation "
                               "%+.4f (|r| > %g): the data barely tell them apart, so their "
                               "standard errors are inflated",
                               r->name[i], r->name[j], r->corr[i][j], threshold);
}

void calreport_check_correlations(calreport *r, double threshold)
{
    calreport_check_correlations_explained(r, threshold, NULL, 0);
}

/* Index of parameter name in r, or -1. */
static int param_index(const calreport *r, const char *name)
{
    for (int i = 0; i < r->np; i++)
        if (strcmp(r->name[i], name) == 0)
            return i;
    return -1;
}

/* 1 when parameters i and j are both in cause's group. */
static int cause_holds(const calreport *r, const calreport_corr_cause *cause, int i, int j)
{
    int has_i = 0, has_j = 0;
    for (int k = 0; k < CALREPORT_CAUSE_PARAMS && cause->params[k]; k++) {
        int x = param_index(r, cause->params[k]);
        has_i |= x == i;
        has_j |= x == j;
    }
    return has_i && has_j;
}

/* One warning for the flagged pairs of cause (listed in pairs), or none. */
static void cause_warning(calreport *r, double threshold, const calreport_corr_cause *cause,
                          unsigned char covered[CALREPORT_MAX_PAR][CALREPORT_MAX_PAR])
{
    char pairs[CALREPORT_TEXT_MAX / 2] = "";
    size_t used = 0;
    int n = 0;
    for (int i = 0; i < r->np; i++)
        for (int j = i + 1; j < r->np; j++)
            if (fabs(r->corr[i][j]) > threshold && !covered[i][j] &&
                cause_holds(r, cause, i, j)) {
                covered[i][j] = 1;
                int w = snprintf(pairs + used, sizeof pairs - used, "%s%s and %s %+.4f",
                                 n ? ", " : "", r->name[i], r->name[j], r->corr[i][j]);
                used = w > 0 && used + (size_t)w < sizeof pairs ? used + (size_t)w : used;
                n++;
            }
    if (n)
        calreport_warn(r, cause->action,
                       "parameters nearly unidentifiable on this campaign (|r| > %g): %s; why: %s",
                       threshold, pairs, cause->why);
}

void calreport_check_correlations_explained(calreport *r, double threshold,
                                            const calreport_corr_cause *causes, int n_causes)
{
    unsigned char covered[CALREPORT_MAX_PAR][CALREPORT_MAX_PAR];
    memset(covered, 0, sizeof covered);
    for (int k = 0; k < n_causes; k++)
        cause_warning(r, threshold, &causes[k], covered);
    for (int i = 0; i < r->np; i++)
        for (int j = i + 1; j < r->np; j++)
            if (fabs(r->corr[i][j]) > threshold && !covered[i][j])
                pair_warning(r, threshold, i, j);
}

void calreport_outlier_text(const calreport *r, const char *verb, char *buf, size_t len)
{
    const calreport_models *cm = &r->models;
    size_t at = cm->judge >= 0
                    ? (size_t)snprintf(buf, len,
                                       "the %s model (the best held out) %s above %g times its "
                                       "median campaign's %.0f arcsec on ",
                                       cm->m[cm->judge].name, verb, FOLD_OUTLIER_RATIO,
                                       cm->judge_median_arcsec)
                    : (size_t)snprintf(buf, len, "held out: ");
    for (int k = 0, first = 1; k < r->n_folds && at < len; k++)
        if (r->fold[k].outlier) {
            at += (size_t)snprintf(buf + at, len - at, "%s%s (%.0f)", first ? "" : ", ",
                                   r->fold[k].label,
                                   cm->judge >= 0 ? cm->judge_fold_arcsec[k]
                                                  : r->fold[k].rms_out_arcsec);
            first = 0;
        }
}

void calreport_check_fold_outliers(calreport *r)
{
    if (r->cv_n_outliers == 0)
        return;
    char text[CALREPORT_TEXT_MAX / 2];
    calreport_outlier_text(r, "leaves", text, sizeof text);
    int one = r->cv_n_outliers == 1;
    calreport_warn(r,
                   "look at the campaign's set-up and data (the light, the mounting, the "
                   "table's zero); the estimate stands for a campaign like the others, the one "
                   "with it for a run that can go as wrong; to calibrate without it, delete its "
                   "rows from the file",
                   "%d of %d held-out repeat campaigns %s unlike the others: %s; the estimate "
                   "leaves %s out: %.2f arcsec (%.2f with %s)",
                   r->cv_n_outliers, r->n_folds, one ? "is" : "are", text, one ? "it" : "them",
                   r->cv_rms_out_arcsec, r->cv_rms_out_all_arcsec, one ? "it" : "them");
}

void calreport_check_crossval(calreport *r, double ratio)
{
    if (!(r->cv_rms_out_arcsec > ratio * r->cv_rms_in_arcsec))
        return;
    int worst = -1;
    for (int k = 0; k < r->n_folds; k++)
        if (r->fold[k].ok && r->fold[k].rms_out_arcsec > 0 &&
            (worst < 0 || r->fold[k].rms_out_arcsec / r->fold[k].rms_in_arcsec >
                              r->fold[worst].rms_out_arcsec / r->fold[worst].rms_in_arcsec))
            worst = k;
    calreport_warn(r,
                   "do not trust the in-sample residual: calibrate over the angles the sensor "
                   "will be used at (both signs of each table angle, lines spanning the field), "
                   "or fit a model with fewer free parameters; take the held-out error as the "
                   "accuracy",
                   "the held-out error %.2f arcsec is %.1f times the in-sample %.2f (above %gx): "
                   "the fit does not carry over to data it did not see (worst: %s held out, "
                   "%.2f against %.2f in-sample)",
                   r->cv_rms_out_arcsec, r->cv_rms_out_arcsec / r->cv_rms_in_arcsec,
                   r->cv_rms_in_arcsec, ratio, worst >= 0 ? r->fold[worst].label : "-",
                   worst >= 0 ? r->fold[worst].rms_out_arcsec : NAN,
                   worst >= 0 ? r->fold[worst].rms_in_arcsec : NAN);
}

void calreport_check_fold_condition(calreport *r, double factor)
{
    char names[CALREPORT_TEXT_MAX / 2] = "";
    double worst = 0;
    int n = 0;
    for (int k = 0; k < r->n_folds; k++) {
        const calreport_fold *fo = &r->fold[k];
        double q = fo->cond / r->cond_jacobian;
        if (!fo->ok || !(r->cond_jacobian > 0) || !(q > factor))
            continue;
        size_t used = strlen(names);
        snprintf(names + used, sizeof names - used, "%s%s (%.2g)", n ? ", " : "", fo->label,
                 fo->cond);
        worst = fmax(worst, q);
        n++;
    }
    if (n == 0)
        return;
    calreport_warn(r,
                   "read the held-out error of the other folds; a campaign whose remaining "
                   "parts still determine the model (more lines or angles) makes every fold "
                   "count",
                   "refit without %s nearly singular: condition number of its Jacobian up to "
                   "%.2g times the fit on all the data's (%.3g): the rest of the data barely "
                   "determine some parameter combination, so %s held-out error reflects where "
                   "the refit started along it, not the calibration",
                   names, worst, r->cond_jacobian, n == 1 ? "that fold's" : "those folds'");
}

static void print_value(FILE *f, double v)
{
    if (isnan(v))
        fprintf(f, "  %9s", "-");
    else
        fprintf(f, "  %9.2f", v);
}

/* The model comparison block (nothing for a family with one model). */
static void print_models(FILE *f, const calreport_models *m)
{
    if (m->n == 0 && !m->note[0])
        return;
    fprintf(f, "\nmodel comparison (the same folds, each model refitted on the rest, error on "
               "the held-out part, arcsec):\n");
    for (int k = 0; k < m->n; k++) {
        const calreport_model *x = &m->m[k];
        fprintf(f, "  %-10s %3d parameters: ", x->name, x->np);
        if (x->ok && x->per_point > 1)
            fprintf(f, "in-sample %8.2f  held-out %8.2f, mean of %.3g readings %8.2f\n",
                    x->rms_in_arcsec, x->rms_out_arcsec, x->per_point, x->rms_out_mean_arcsec);
        else if (x->ok)
            fprintf(f, "in-sample %8.2f  held-out %8.2f%s\n", x->rms_in_arcsec,
                    x->rms_out_arcsec,
                    x->aliased ? "  (terms aliased by the campaign, held at 0)" : "");
        else
            fprintf(f, "a refit failed\n");
    }
    int other = m->n == 2 && m->other == 0 ? 1 - m->used : m->other;
    if (m->n >= 2 && m->n_paired > 0 && other != m->used)
        fprintf(f, "  held-out squared error, %s - %s: %+.4g arcsec^2 +- %.2g (standard error "
                   "over %ld points)\n",
                m->m[m->used].name, m->m[other].name, m->diff_arcsec2, m->diff_se_arcsec2,
                m->n_paired);
    if (m->n > 0)
        fprintf(f, "  used: %s; recommended: %s\n", m->m[m->used].name, m->m[m->best].name);
    if (m->note[0])
        fprintf(f, "  %s\n", m->note);
}

/* What the fit was given and how it ended. */
static void print_header(FILE *f, const calreport *r)
{
    fprintf(f, "calibration: sensor family %s, model %s\n", r->sensor, r->model);
    if (r->n_set_aside)
        fprintf(f, "data: %zu rows, %zu used (%zu of campaigns unlike the others set aside), %d "
                   "degrees of freedom\n",
                r->n_rows, r->n_used, r->n_set_aside, r->dof);
    else
        fprintf(f, "data: %zu rows, %zu used, %d degrees of freedom\n", r->n_rows, r->n_used,
                r->dof);
    if (r->campaign.known)
        fprintf(f,
                "campaign: %ld points on %ld lines, %ld readings: %.2f turntable hours (the "
                "rows' table angles in file order, the config's campaign.* cost keys)\n",
                r->campaign.points, r->campaign.lines, r->campaign.readings, r->campaign.hours);
    if (r->refused[0])
        fprintf(f, "fit: REFUSED after %zu iterations: %s\n", r->fit.iterations, r->refused);
    else
        fprintf(f, "fit: %s after %zu iterations (%s)\n", r->fit_ok ? "converged" : "FAILED",
                r->fit.iterations, fit_reason(&r->fit));
    /* the weights are scaled to a median of 1 (lab_check_data): sigma is a
     * typical row's */
    fprintf(f, "residual standard deviation: %.3f arcsec\n", r->sigma_arcsec);
}

/* Parameters with standard errors (and priors), the correlation matrix. */
static void print_parameters(FILE *f, const calreport *r)
{
    fprintf(f, "\nparameters (standard errors from the covariance at the solution, "
               "scaled by the residual variance):\n");
    for (int i = 0; i < r->np; i++) {
        if (r->prior_on && r->undetermined[i])
            fprintf(f, "  %-24s %+.9e  not determined (held: the campaign does not see it)\n",
                    r->name[i], r->value[i]);
        else
            fprintf(f, "  %-24s %+.9e  +- %.3e\n", r->name[i], r->value[i], r->se[i]);
    }
    if (r->prior_on) {
        fprintf(f, "\npriors (calibration.priors = tolerances: mean and sigma over a pilot of %ld "
                   "units drawn from the config's tolerances, fitted without noise); moved = "
                   "(fitted - prior mean) / prior sigma, se/prior = what the data left of the "
                   "prior's uncertainty:\n",
                r->prior_units);
        for (int i = 0; i < r->np; i++)
            fprintf(f, "  %-24s prior %+.6e +- %.3e  moved %+7.2f  se/prior %6.3f\n", r->name[i],
                    r->prior_mean[i], r->prior_sigma[i],
                    (r->value[i] - r->prior_mean[i]) / r->prior_sigma[i],
                    r->se[i] / r->prior_sigma[i]);
    }
    if (!r->cov_ok) {
        fprintf(f, "\ncorrelation matrix: not available (the parameter covariance could not be "
                   "formed: the Jacobian is rank-deficient or the residual is not finite)\n");
    } else {
        fprintf(f, "\ncorrelation matrix:\n%-24s", "");
        for (int j = 0; j < r->np; j++)
            fprintf(f, " %7d", j + 1);
        fputc('\n', f);
        for (int i = 0; i < r->np; i++) {
            fprintf(f, "  %2d %-20s", i + 1, r->name[i]);
            for (int j = 0; j < r->np; j++)
                fprintf(f, " %+7.3f", r->corr[i][j]);
            fputc('\n', f);
        }
    }
    fprintf(f, "condition number: %.3g of the Jacobian (parameters in internal units), "
               "%.3g of the correlation matrix\n",
            r->cond_jacobian, r->cond_correlation);
}

/* Residual, propagated and predicted accuracy per angle and band. */
static void print_bands(FILE *f, const calreport *r)
{
    fprintf(f, "\nper band (arcsec; predicted = sqrt(noise^2 + calibration^2), calibration = "
               "parameter covariance\npropagated to the compensated angle):\n");
    char head[64];
    report_band_head(sensor_family_find(r->sensor), head, sizeof head);
    int wb = (int)strlen(head) > 12 ? (int)strlen(head) : 12;
    fprintf(f, "  angle  %-*s %7s  residual  cal.sigma(rms)  cal.sigma(max)  predicted\n", wb, head,
            "points");
    for (int a = 0; a < r->n_angles; a++)
        for (int b = 0; b < r->bands.n; b++) {
            char band[32];
            snprintf(band, sizeof band, "%g:%g", r->bands.lo[b], r->bands.hi[b]);
            fprintf(f, "  %-6s %-*s %7ld", r->angle_name[a], wb, band, r->band_n[a][b]);
            print_value(f, r->resid_rms[a][b]);
            fprintf(f, "     ");
            print_value(f, r->cal_sigma_rms[a][b]);
            fprintf(f, "     ");
            print_value(f, r->cal_sigma_max[a][b]);
            fprintf(f, "  ");
            print_value(f, r->predicted_rms[a][b]);
            fputc('\n', f);
        }
}

static void print_crossval(FILE *f, const calreport *r)
{
    fprintf(f, "\ncross-validation (hold out each part, refit the rest, error on the held-out "
               "part, arcsec):\n");
    if (r->n_folds == 0)
        fprintf(f, "  none: %s\n", r->cv_note);
    for (int k = 0; k < r->n_folds; k++) {
        const calreport_fold *fo = &r->fold[k];
        if (fo->ok)
            fprintf(f, "  held out %-20s %6zu points: in-sample %8.2f  held-out %8.2f%s\n",
                    fo->label, fo->n_out, fo->rms_in_arcsec, fo->rms_out_arcsec,
                    fo->outlier ? "  (unlike the others: not in the estimate)" : "");
        else
            fprintf(f, "  held out %-20s %6zu points: refit failed\n", fo->label, fo->n_out);
    }
    if (r->n_folds > 0 && r->cv_n_outliers > 0)
        fprintf(f, "  pooled: in-sample %.2f, held-out %.2f (the honest accuracy estimate, "
                   "%d part%s unlike the others left out; %.2f with %s)\n",
                r->cv_rms_in_arcsec, r->cv_rms_out_arcsec, r->cv_n_outliers,
                r->cv_n_outliers > 1 ? "s" : "", r->cv_rms_out_all_arcsec,
                r->cv_n_outliers > 1 ? "them" : "it");
    else if (r->n_folds > 0)
        fprintf(f, "  pooled: in-sample %.2f, held-out %.2f (the honest accuracy estimate)\n",
                r->cv_rms_in_arcsec, r->cv_rms_out_arcsec);
}

static void print_drift(FILE *f, const lab_drift *d)
{
    if (d->n < 2)
        return;
    fprintf(f, "\ncampaigns (the file's \"# source:\" blocks; campaigns.tsv):\n");
    fprintf(f, "  %-34s %6s %5s %9s %9s %9s %9s %9s\n", "campaign", "rows", "swept", "zero\"",
            "scale %", "within\"", "d zero\"", "d scale %");
    for (int s = 0; s < d->n; s++) {
        const lab_campaign *c = &d->c[s];
        static const char *const ax[] = {"-", "alpha", "beta"};
        if (c->n == 0) {
            fprintf(f, "  %-34.34s %6ld  (no row the calibration reads)\n", c->name, c->n);
            continue;
        }
        fprintf(f, "  %-34.34s %6ld %5s %9.0f %9.3f %9.0f", c->name, c->n, ax[c->axis + 1],
                c->zero_arcsec, c->scale_pct, c->within_arcsec);
        if (isfinite(c->shift_arcsec))
            fprintf(f, " %9.0f %9.3f\n", c->dzero_arcsec, c->dscale_pct);
        else
            fprintf(f, " %9s %9s\n", "alone", "-");
    }
    fprintf(f, "  %s\n", d->note);
}

int calreport_print(FILE *f, const calreport *r)
{
    print_header(f, r);
    print_parameters(f, r);
    print_bands(f, r);
    print_crossval(f, r);
    print_models(f, &r->models);
    print_drift(f, &r->drift);
    fprintf(f, "\nwarnings: %d\n", r->nw);
    for (int i = 0; i < r->nw; i++)
        fprintf(f, "  %d. %s\n     what to do: %s\n", i + 1, r->w[i].reason, r->w[i].action);
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

void calreport_set_priors(calreport *r, const calib_prior *p, const double *offset,
                          const double *scale)
{
    r->prior_on = p->np > 0;
    r->prior_units = p->units;
    for (int j = 0; j < p->np && j < CALREPORT_MAX_PAR; j++) {
        r->prior_mean[j] = (p->mean[j] - (offset ? offset[j] : 0.0)) * scale[j];
        r->prior_sigma[j] = p->sigma[j] * fabs(scale[j]);
        r->undetermined[j] = p->unseen[j];
    }
}

void calreport_check_priors(calreport *r)
{
    if (!r->prior_on || !r->cov_ok)
        return;
    char names[CALREPORT_TEXT_MAX / 2] = "";
    size_t len = 0;
    int n = 0;
    char unseen[CALREPORT_TEXT_MAX / 2] = "";
    size_t lu = 0;
    int nu = 0;
    for (int j = 0; j < r->np; j++)
        if (r->undetermined[j] && lu < sizeof unseen) {
            lu += (size_t)snprintf(unseen + lu, sizeof unseen - lu, "%s%s", nu ? ", " : "",
                                   r->name[j]);
            nu++;
        }
    if (nu)
        calreport_warn(r,
                       "add table positions that move them (for the ESS: beta lines other than "
                       "0 for the installation about Y and Z), or measure them and fix them",
                       "%d parameter%s not determined: no unit of the pilot's moved %s from "
                       "%s starting value on these table angles, so the fit holds %s there and "
                       "the propagated accuracy does not include %s",
                       nu, nu == 1 ? "" : "s", unseen, nu == 1 ? "its" : "their",
                       nu == 1 ? "it" : "them", nu == 1 ? "it" : "them");
    for (int j = 0; j < r->np; j++)
        if (!r->undetermined[j] && r->se[j] >= CALREPORT_PRIOR_NOT_BEATEN * r->prior_sigma[j] &&
            len < sizeof names) {
            len += (size_t)snprintf(names + len, sizeof names - len, "%s%s (%.2f)",
                                    n ? ", " : "", r->name[j], r->se[j] / r->prior_sigma[j]);
            n++;
        }
    if (n)
        calreport_warn(r,
                       "these parameters are what the tolerances say, not what this campaign "
                       "measured: widen the campaign (more lines, a wider alpha span, more "
                       "repeats) if they matter, or tighten the tolerance behind them",
                       "the campaign cannot beat the prior for %d parameter%s: standard error "
                       "over prior sigma >= %.2f for %s",
                       n, n == 1 ? "" : "s", CALREPORT_PRIOR_NOT_BEATEN, names);
}

int calreport_write_bands(FILE *f, const calreport *r)
{
    fprintf(f, "angle\tband_lo_deg\tband_hi_deg\tpoints\tresidual_rms_arcsec\t"
               "cal_sigma_rms_arcsec\tcal_sigma_max_arcsec\tpredicted_rms_arcsec\n");
    for (int a = 0; a < r->n_angles; a++)
        for (int b = 0; b < r->bands.n; b++)
            tsv_printf(f, "%s\t%g\t%g\t%ld\t%.6g\t%.6g\t%.6g\t%.6g\n", r->angle_name[a],
                    r->bands.lo[b], r->bands.hi[b], r->band_n[a][b], r->resid_rms[a][b],
                    r->cal_sigma_rms[a][b], r->cal_sigma_max[a][b], r->predicted_rms[a][b]);
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

int calreport_write_folds(FILE *f, const calreport *r)
{
    fprintf(f, "fold\theld_out\tpoints\tok\trms_in_arcsec\trms_out_arcsec\trefit_condition\t"
               "outlier\n");
    for (int k = 0; k < r->n_folds; k++) {
        const calreport_fold *fo = &r->fold[k];
        char label[CALREPORT_NAME_MAX];
        snprintf(label, sizeof label, "%s", fo->label);
        for (char *s = label; *s; s++)
            if (*s == ' ' || *s == '\t')
                *s = '_';
        tsv_printf(f, "%d\t%s\t%zu\t%d\t%.6g\t%.6g\t%.6g\t%d\n", k + 1, label, fo->n_out,
                   fo->ok, fo->rms_in_arcsec, fo->rms_out_arcsec, fo->cond, fo->outlier);
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

int calreport_write_models(FILE *f, const calreport_models *m)
{
    fprintf(f, "model\tparameters\tok\taliased\theld_out_points\trms_in_arcsec\t"
               "rms_out_arcsec\tused\trecommended\treadings_per_point\t"
               "rms_out_mean_arcsec\toutlier_folds\trms_out_all_arcsec\n");
    for (int k = 0; k < m->n; k++) {
        const calreport_model *x = &m->m[k];
        tsv_printf(f, "%s\t%d\t%d\t%d\t%ld\t%.6g\t%.6g\t%d\t%d\t%.6g\t%.6g\t%d\t%.6g\n", x->name,
                   x->np, x->ok, x->aliased, x->n_out, x->rms_in_arcsec, x->rms_out_arcsec,
                   k == m->used, k == m->best, x->per_point > 0 ? x->per_point : NAN,
                   x->per_point > 0 ? x->rms_out_mean_arcsec : NAN, x->n_outliers,
                   x->rms_out_all_arcsec);
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}
