/* ess_calmodels.c - `sunmc calibrate` of an ESS: the paper's and the
 * extended calibration model compared by cross-validation.
 *
 * Each beta line is held out in turn; both models are refitted on the
 * other lines (the same data, weights and fit as the report's own fit) and
 * scored on the held-out line in the angle domain (ess_angle_error), point
 * by point.  The pooled held-out RMS is each model's honest accuracy; the
 * paired difference of the squared errors, point by point, says whether
 * the two differ beyond the noise: its mean over the points held out by
 * both, with the standard error of that mean (approximate: the points of
 * a fold share that fold's refit).  Recommended: the model with the lower
 * held-out error when the difference exceeds COMPARE_SE_FACTOR standard
 * errors, else the one with fewer parameters (the paper's).
 */
#include "ess_labfit.h"
#include "ess_prior.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Standard errors a held-out difference must exceed to decide. */
#define COMPARE_SE_FACTOR 2.0

static const int compared_kinds[2] = {ESS_MODEL_PAPER, ESS_MODEL_EXTENDED};
static const char *const kind_names[2] = {"paper", "extended"};

/* One model over every fold: held-out squared error of each point (rad^2,
 * NaN where not scored) into e2, its summary into x. */
static void score_model(const sunmc_config *c, const ess_calib_workspace *cw, const double *betas, int nb, ess_calib_workspace *w, double *e2,
                        calreport_model *x)
{
    const ess_config *ec = ess_cfg(c);
    double theta0 = ec->design.theta0_deg * RAD_PER_DEG;
    double roll = ec->roll_measured_arcsec * RAD_PER_ARCSEC;
    double sum_in = 0, sum_out = 0;
    long n_in = 0;
    x->ok = 1;
    for (size_t i = 0; i < cw->n; i++)
        e2[i] = NAN;
    for (int k = 0; k < nb; k++) {
        for (size_t i = 0; i < cw->n; i++) {
            int held = ess_beta_line_of(betas, nb, cw->beta_rad[i]) == k;
            w->weight[i] = held ? 0.0 : cw->weight[i];
        }
        ess_model m;
        fit_result fr;
        if (ess_calibrate(w, theta0, roll, ec->alias_threshold, c->max_iterations, &m, &fr) !=
            SUNMC_OK) {
            x->ok = 0;
            continue;
        }
        x->aliased |= w->alias.n_weak > 0;
        for (size_t i = 0; i < cw->n; i++) {
            double e;
            if (!(cw->weight[i] > 0) ||
                ess_angle_error(&m, cw->alpha_rad[i], cw->beta_rad[i], cw->raw_rad[i], &e) !=
                    SUNMC_OK)
                continue;
            if (w->weight[i] > 0) {
                sum_in += e * e;
                n_in++;
            } else {
                e2[i] = e * e;
                sum_out += e * e;
                x->n_out++;
            }
        }
    }
    x->rms_in_arcsec = n_in ? sqrt(sum_in / (double)n_in) * ARCSEC_PER_RAD : NAN;
    x->rms_out_arcsec = x->n_out ? sqrt(sum_out / (double)x->n_out) * ARCSEC_PER_RAD : NAN;
}

/* The paired difference e_used^2 - e_other^2 over the points both scored,
 * and the recommendation. */
static void recommend(calreport_models *cm, const double *const e2[2], size_t n)
{
    int u = cm->used, o = 1 - u;
    double sum = 0, sum2 = 0;
    long k = 0;
    for (size_t i = 0; i < n; i++)
        if (isfinite(e2[u][i]) && isfinite(e2[o][i])) {
            double d = (e2[u][i] - e2[o][i]) * ARCSEC_PER_RAD * ARCSEC_PER_RAD;
            sum += d;
            sum2 += d * d;
            k++;
        }
    cm->n_paired = k;
    cm->best = 0; /* the paper's: fewer parameters */
    if (k < 2 || !cm->m[0].ok || !cm->m[1].ok) {
        snprintf(cm->note, sizeof cm->note,
                 "a refit failed or too few points were held out: the paper's model, the "
                 "simpler one, is recommended");
        return;
    }
    double mean = sum / (double)k;
    double var = fmax(sum2 / (double)k - mean * mean, 0.0) * (double)k / (double)(k - 1);
    cm->diff_arcsec2 = mean;
    cm->diff_se_arcsec2 = sqrt(var / (double)k);
    if (fabs(mean) <= COMPARE_SE_FACTOR * cm->diff_se_arcsec2) {
        snprintf(cm->note, sizeof cm->note,
                 "the difference is inside the noise (within %g standard errors): the paper's "
                 "model, with fewer parameters, is recommended",
                 COMPARE_SE_FACTOR);
        return;
    }
    cm->best = mean > 0 ? o : u;
    char advice[64] = "";
    if (cm->best != u)
        snprintf(advice, sizeof advice, ": calibrate with --set calibration.model=%s",
                 kind_names[cm->best]);
    snprintf(cm->note, sizeof cm->note,
             "the %s model's held-out error is lower beyond the noise (%.1f standard errors)%s",
             kind_names[cm->best], fabs(mean) / cm->diff_se_arcsec2, advice);
}

int ess_labfit_compare(const sunmc_config *c, const ess_calib_workspace *cw, calreport *rep,
                       char *err, size_t errlen)
{
    calreport_models *cm = &rep->models;
    memset(cm, 0, sizeof *cm);
    double betas[CALREPORT_MAX_FOLDS];
    int nb = ess_beta_lines(cw, betas, CALREPORT_MAX_FOLDS);
    if (nb < 2) {
        snprintf(cm->note, sizeof cm->note,
                 "no model comparison: it holds out beta lines, the data have %s",
                 nb < 0 ? "too many" : "fewer than two");
        return SUNMC_OK;
    }
    double *e2[2] = {malloc(cw->n * sizeof(double)), malloc(cw->n * sizeof(double))};
    int st = e2[0] && e2[1] ? SUNMC_OK : SUNMC_ENOMEM;
    for (int m = 0; m < 2 && st == SUNMC_OK; m++) {
        ess_calib_workspace *w = ess_calib_alloc_fix(cw->n, compared_kinds[m], cw->fix_sun_y);
        if (!w) {
            st = SUNMC_ENOMEM;
            break;
        }
        w->sun_y_rad = cw->sun_y_rad;
        memcpy(w->alpha_rad, cw->alpha_rad, cw->n * sizeof(double));
        memcpy(w->beta_rad, cw->beta_rad, cw->n * sizeof(double));
        memcpy(w->raw_rad, cw->raw_rad, cw->n * sizeof(double));
        calib_prior prior; /* each model its own priors, as the fit uses */
        st = ess_prior_apply(c, w, &prior, err, errlen);
        if (st != SUNMC_OK) {
            ess_calib_free(w);
            break;
        }
        calreport_model *x = &cm->m[m];
        snprintf(x->name, sizeof x->name, "%s", kind_names[m]);
        x->np = w->np_fit;
        score_model(c, cw, betas, nb, w, e2[m], x);
        if (compared_kinds[m] == cw->kind)
            cm->used = m;
        ess_calib_free(w);
    }
    if (st == SUNMC_OK) {
        cm->n = 2;
        recommend(cm, (const double *const *)e2, cw->n);
    }
    free(e2[0]);
    free(e2[1]);
    if (st == SUNMC_ENOMEM)
        return sunmc_fail(err, errlen, st, "out of memory for the model comparison");
    if (st != SUNMC_OK)
        return st;
    return SUNMC_OK;
}
