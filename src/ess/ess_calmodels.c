/* ess_calmodels.c - `sunmc calibrate` of an ESS: the paper's, the
 * extended, the spline, hybrid and table calibration models compared by
 * cross-validation (issue 39).
 *
 * Each beta line is held out in turn; every model is refitted on the
 * other lines (the same data, weights and fit as the report's own fit) and
 * scored on the held-out line in the angle domain (ess_angle_error), point
 * by point.  The pooled held-out RMS is each model's honest accuracy; the
 * paired difference of the squared errors of the best model and the
 * paper's, point by point, says whether they differ beyond the noise: its
 * mean over the points held out by both, with the standard error of that
 * mean (approximate: the points of a fold share that fold's refit).
 * Recommended: the model with the lowest held-out error when the
 * difference exceeds COMPARE_SE_FACTOR standard errors, else the one with
 * fewer parameters (the paper's).  A spline's parameters: its effective
 * degrees of freedom (a table's: its nodes), from the last refit.
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

/* The paper model's held-out error above this many times the best
 * empirical model's (spline or table): its physics does not describe the
 * sensor. */
#define ESS_PHYSICS_FAR 1.5

static const int compared_kinds[ESS_N_MODELS] = {ESS_MODEL_PAPER, ESS_MODEL_EXTENDED,
                                                 ESS_MODEL_SPLINE, ESS_MODEL_HYBRID,
                                                 ESS_MODEL_TABLE};
static const char *const kind_names[ESS_N_MODELS] = {"paper", "extended", "spline", "hybrid",
                                                     "table"};

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
        if (m.kind == ESS_MODEL_TABLE)
            x->np = m.table.nodes;
        else if (ESS_MODEL_HAS_SPLINE(m.kind))
            x->np = (int)lround(m.spline.edf[0]) + (m.kind == ESS_MODEL_HYBRID ? w->np_fit : 0);
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
    x->rms_out_all_arcsec = x->rms_out_arcsec; /* beta lines across the field: not judged */
}

/* The paired difference e_a^2 - e_b^2 over the points both scored: its
 * mean and standard error (arcsec^2); the count. */
static long paired(const double *ea, const double *eb, size_t n, double *mean, double *se)
{
    double sum = 0, sum2 = 0;
    long k = 0;
    for (size_t i = 0; i < n; i++)
        if (isfinite(ea[i]) && isfinite(eb[i])) {
            double d = (ea[i] - eb[i]) * ARCSEC_PER_RAD * ARCSEC_PER_RAD;
            sum += d;
            sum2 += d * d;
            k++;
        }
    *mean = k ? sum / (double)k : NAN;
    double var = k > 1 ? fmax(sum2 / (double)k - *mean * *mean, 0.0) * (double)k / (double)(k - 1)
                       : NAN;
    *se = k > 1 ? sqrt(var / (double)k) : NAN;
    return k;
}

/* The recommendation: the model of the lowest held-out error when its
 * paired difference from the paper's exceeds COMPARE_SE_FACTOR standard
 * errors, else the paper's (the fewest parameters); and, when the paper's
 * error is far above the best empirical model's, that the physics does not
 * describe the sensor. */
static void recommend(calreport_models *cm, const double *const *e2, size_t n)
{
    int best = -1, emp = -1;
    for (int m = 0; m < cm->n; m++) {
        const calreport_model *x = &cm->m[m];
        if (!x->ok)
            continue;
        if (best < 0 || x->rms_out_arcsec < cm->m[best].rms_out_arcsec)
            best = m;
        if (ESS_MODEL_HAS_SPLINE(compared_kinds[m]) && compared_kinds[m] != ESS_MODEL_HYBRID &&
            (emp < 0 || x->rms_out_arcsec < cm->m[emp].rms_out_arcsec))
            emp = m;
    }
    cm->best = 0; /* the paper's: fewer parameters */
    if (best < 0 || !cm->m[0].ok) {
        snprintf(cm->note, sizeof cm->note,
                 "a refit failed or too few points were held out: the paper's model, the "
                 "simpler one, is recommended");
        return;
    }
    double mean, se;
    long k = paired(e2[0], e2[best], n, &mean, &se);
    /* printed: the model used against the best (or, when it is the best,
     * against the paper's; the paper's against the extended) */
    cm->other = best != cm->used ? best : cm->used != 0 ? 0 : 1;
    cm->n_paired = paired(e2[cm->used], e2[cm->other], n, &cm->diff_arcsec2,
                          &cm->diff_se_arcsec2);
    size_t at = 0;
    if (best == 0 || k < 2 || !(mean > COMPARE_SE_FACTOR * se))
        at = (size_t)snprintf(cm->note, sizeof cm->note,
                              "%s: the paper's model, with fewest parameters, is recommended",
                              best == 0 ? "its held-out error is the lowest"
                                        : "the best model's gain is inside the noise");
    else {
        cm->best = best;
        char advice[80] = "";
        if (cm->best != cm->used)
            snprintf(advice, sizeof advice, ": calibrate with --set calibration.model=%s",
                     kind_names[cm->best]);
        at = (size_t)snprintf(cm->note, sizeof cm->note,
                              "the %s model's held-out error is lower than the paper's beyond "
                              "the noise (%.1f standard errors)%s",
                              kind_names[cm->best], mean / se, advice);
    }
    const calreport_model *ph = &cm->m[0];
    if (emp >= 0 && ph->rms_out_arcsec > ESS_PHYSICS_FAR * cm->m[emp].rms_out_arcsec &&
        at < sizeof cm->note)
        snprintf(cm->note + at, sizeof cm->note - at,
                 "; the physics does not describe this sensor: the paper model's held-out "
                 "error is %.1f times the %s model's",
                 ph->rms_out_arcsec / cm->m[emp].rms_out_arcsec, cm->m[emp].name);
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
    double *e2[ESS_N_MODELS] = {NULL};
    int st = SUNMC_OK;
    for (int m = 0; m < ESS_N_MODELS; m++)
        if (!(e2[m] = malloc((cw->n + 1) * sizeof(double))))
            st = SUNMC_ENOMEM;
    for (int m = 0; m < ESS_N_MODELS && st == SUNMC_OK; m++) {
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
        x->np = compared_kinds[m] == ESS_MODEL_SPLINE || compared_kinds[m] == ESS_MODEL_TABLE
                    ? 0 : w->np_fit; /* a spline's: its refits' below */
        score_model(c, cw, betas, nb, w, e2[m], x);
        if (compared_kinds[m] == cw->kind)
            cm->used = m;
        ess_calib_free(w);
    }
    if (st == SUNMC_OK) {
        cm->n = ESS_N_MODELS;
        recommend(cm, (const double *const *)e2, cw->n);
    }
    for (int m = 0; m < ESS_N_MODELS; m++)
        free(e2[m]);
    if (st == SUNMC_ENOMEM)
        return sunmc_fail(err, errlen, st, "out of memory for the model comparison");
    if (st != SUNMC_OK)
        return st;
    return SUNMC_OK;
}
