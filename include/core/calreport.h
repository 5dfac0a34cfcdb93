/* calreport.h - what `sunmc calibrate` reports about a fit, for any sensor
 * family: parameters with standard errors, correlation matrix, condition
 * numbers, warnings (each with its reason and what to do), residual RMS and
 * predicted after-calibration accuracy per band, and cross-validation.
 *
 * The family's calibration code (ess_labfit.h, ...) fills a calreport;
 * calreport_print writes it for a person.
 *
 * Units: parameter values and standard errors are in the unit of the
 * parameter's name (name[i]); every RMS and sigma is in arcsec.
 */
#ifndef SUNMC_CALREPORT_H
#define SUNMC_CALREPORT_H

#include "campaign.h"
#include "config.h"
#include "fit.h"
#include "lab_drift.h"
#include "prior.h"

#include <gsl/gsl_matrix.h>
#include <stddef.h>
#include <stdio.h>

#define CALREPORT_MAX_PAR 72 /* e.g. the DSS polynomial of order 7: 2 x 36 terms */
#define CALREPORT_MAX_WARN 24
#define CALREPORT_MAX_FOLDS 64
#define CALREPORT_MAX_ANGLES 2
#define CALREPORT_TEXT_MAX 800
#define CALREPORT_NAME_MAX 40

/* |correlation| above which a parameter pair is named as near-unidentifiable. */
#define CALREPORT_CORR_WARN 0.98

typedef struct {
    char reason[CALREPORT_TEXT_MAX];  /* what was found and why it matters */
    char action[CALREPORT_TEXT_MAX];  /* what to do about it */
} calreport_warning;

/* One cross-validation fold: a part of the data held out, the rest refitted. */
typedef struct {
    char label[CALREPORT_NAME_MAX];   /* e.g. "beta = 20 deg" */
    size_t n_out;                     /* points held out */
    int ok;                           /* refit converged */
    double rms_in_arcsec;             /* refit's residual on the points it used */
    double rms_out_arcsec;            /* its error on the held-out points */
    double cond;                      /* condition number of the refit's Jacobian (NaN: none) */
    int outlier;                      /* unlike the others: out of the estimate (fold_outliers.h) */
} calreport_fold;

/* ---- model comparison (a family with several calibration models) ----
 * Each model refitted on the same cross-validation folds and scored on the
 * held-out points; the recommendation follows the paired difference of
 * the held-out squared errors, point by point. */
#define CALREPORT_MAX_MODELS 6

typedef struct {
    char name[CALREPORT_NAME_MAX];    /* as calibration.model names it */
    int np;                           /* parameters */
    int ok;                           /* every fold's refit converged */
    int aliased;                      /* the campaign aliased some of its terms (held at 0) */
    long n_out;                       /* held-out points scored */
    double rms_in_arcsec, rms_out_arcsec; /* pooled over the folds (held out: the folds
                                             unlike the others left out, fold_outliers.h) */
    double rms_out_all_arcsec;        /* held out, every fold */
    int n_outliers;                   /* folds left out of rms_out_arcsec and the means */
    /* A flight reading averaged over per_point repeats (the data's rows
     * per point; 0: not estimated): the held-out RMS of the points' mean
     * errors, each point's held-out rows averaged first. */
    double per_point, rms_out_mean_arcsec;
    /* parameters' worth (effective degrees of freedom of a spline), or NaN */
    double edf;
} calreport_model;

typedef struct {
    int n;                            /* models compared; 0: none (note says why) */
    calreport_model m[CALREPORT_MAX_MODELS];
    int used, best;                   /* the model fitted, the one recommended */
    /* mean over the held-out points of e_used^2 - e_other^2 (arcsec^2), its
     * standard error and the points (n_paired 0: not printed); other: the
     * model compared with (0 stands for 1 - used when n == 2) */
    double diff_arcsec2, diff_se_arcsec2;
    long n_paired;
    int other;
    char note[CALREPORT_TEXT_MAX];    /* the recommendation in words, or why there is none */
    /* Repeat campaigns unlike the others (fold_outliers.h), judged on the
     * folds of the model that describes the data best (the lowest held-out
     * error over every fold: a model that does not describe them makes
     * any campaign look odd); every model's estimate, and the
     * calibration's, leave them out.  judge: that model (-1: none judged). */
    int judge, n_fold_outliers;
    unsigned char fold_outlier[CALREPORT_MAX_FOLDS];
    double judge_fold_arcsec[CALREPORT_MAX_FOLDS], judge_median_arcsec;
} calreport_models;

/* The recommendation (calreport_models.c), m[0] the physical model: the
 * lowest held-out error, keeping the simpler of two (fewer parameters)
 * unless the other is lower by more than the fraction gain; "the physics
 * does not describe this sensor" when m[0]'s held-out error is more than
 * far times the best other model's.  Sets best and note. */
void calreport_models_recommend(calreport_models *cm, double gain, double far);

typedef struct {
    const char *sensor;               /* "ess", "dss" */
    const char *model;                /* model name as in params.ini */

    /* data */
    size_t n_rows;                    /* rows in the file */
    size_t n_used;                    /* rows with weight > 0 after gross-error checks */
    size_t n_set_aside;               /* rows of campaigns dropped as unlike the others
                                         (calibration.outlier_campaigns): not gross errors */
    int dof;                          /* degrees of freedom of the residual variance */
    campaign_info campaign;           /* the data's table angles in file order: cost, span */

    /* fit */
    fit_result fit;
    int fit_ok;
    char refused[CALREPORT_TEXT_MAX]; /* why a converged fit is refused (lab_check_fit), else "" */
    double sigma_arcsec;              /* residual standard deviation, sqrt(chi2 / dof) */
    double sigma_typical_arcsec;      /* the same for a row of the median weight (lab_check_fit;
                                         0: not computed) */

    /* parameters, in the units of their names */
    int np;
    char name[CALREPORT_MAX_PAR][CALREPORT_NAME_MAX];
    double value[CALREPORT_MAX_PAR];
    double se[CALREPORT_MAX_PAR];     /* standard error (scaled covariance) */
    double corr[CALREPORT_MAX_PAR][CALREPORT_MAX_PAR];
    int cov_ok;                       /* se and corr formed (calreport_covariance) */
    /* priors (calibration.priors = tolerances, prior.h; prior_on 0: none),
     * per parameter in the units of its name */
    int prior_on;
    long prior_units;                 /* pilot units they come from */
    double prior_mean[CALREPORT_MAX_PAR];
    double prior_sigma[CALREPORT_MAX_PAR];
    int undetermined[CALREPORT_MAX_PAR]; /* the campaign does not see it (prior.h unseen) */
    double cond_jacobian;             /* 1 / rcond of J at the solution (fit.h) */
    double cond_correlation;          /* largest / smallest eigenvalue of corr */

    int nw;
    calreport_warning w[CALREPORT_MAX_WARN];

    /* per measured angle and band (config report.bands_deg) */
    int n_angles;
    const char *angle_name[CALREPORT_MAX_ANGLES];
    band_list bands;
    long band_n[CALREPORT_MAX_ANGLES][CONFIG_BANDS_MAX];            /* data points */
    double resid_rms[CALREPORT_MAX_ANGLES][CONFIG_BANDS_MAX];       /* in-sample, arcsec */
    double cal_sigma_rms[CALREPORT_MAX_ANGLES][CONFIG_BANDS_MAX];   /* propagated, arcsec */
    double cal_sigma_max[CALREPORT_MAX_ANGLES][CONFIG_BANDS_MAX];
    double predicted_rms[CALREPORT_MAX_ANGLES][CONFIG_BANDS_MAX];   /* sqrt(noise^2 + cal^2) */

    /* cross-validation */
    int n_folds;
    calreport_fold fold[CALREPORT_MAX_FOLDS];
    double cv_rms_in_arcsec;          /* pooled over folds */
    double cv_rms_out_arcsec;         /* held out, the outlying folds left out: the estimate */
    double cv_rms_out_all_arcsec;     /* held out, every fold */
    int cv_n_outliers;                /* folds left out of the estimate */
    char cv_note[CALREPORT_TEXT_MAX]; /* why there is no cross-validation, else "" */

    calreport_models models;          /* model comparison (models.n = 0: none) */
    lab_drift drift;                  /* campaigns of the file (drift.n < 2: none) */
} calreport;

/* Zero r and set its family names. */
void calreport_init(calreport *r, const char *sensor, const char *model);

/* r's parameter rows: the n (at most CALREPORT_MAX_PAR) named values
 * with no standard error (se NaN), replacing any; for the figures of an
 * empirical model (a spline's smoothing and effective degrees of freedom,
 * a table's nodes), in the units of their names. */
void calreport_set_values(calreport *r, const char *const *names, const double *values, int n);

/* Add a warning (formatted reason, formatted action); dropped when full. */
void calreport_warn(calreport *r, const char *action, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* From the unscaled covariance cov (p x p, (J^T J)^-1 in the fit's internal
 * units) and the residual variance s2: standard errors se[i] = sqrt(s2
 * cov_ii) * scale[i] (scale converts internal units to those of name[i]),
 * the correlation matrix and its condition number.  r->np must be set.
 * SUNMC_EFIT when a variance is not positive or the eigen-solve fails. */
int calreport_covariance(calreport *r, const gsl_matrix *cov, double s2, const double *scale);

/* Record priors p (fit-vector order, internal units; np = 0: none) in
 * the parameters' reported units: (internal - offset[j]) x scale[j]
 * (offset NULL: 0). */
void calreport_set_priors(calreport *r, const calib_prior *p, const double *offset,
                          const double *scale);

/* Posterior over prior standard deviation at or above which the campaign
 * is said not to beat the prior for a parameter. */
#define CALREPORT_PRIOR_NOT_BEATEN 0.9
/* One warning naming every parameter whose standard error is at least
 * CALREPORT_PRIOR_NOT_BEATEN of its prior's sigma: the data add little to
 * what the lab knew (needs se: after calreport_covariance). */
void calreport_check_priors(calreport *r);

/* Add one warning for each pair with |corr| > threshold, naming both. */
void calreport_check_correlations(calreport *r, double threshold);

/* A known reason why some of a family's parameters correlate on a
 * campaign: the group's names (NULL-terminated), why the campaign cannot
 * tell them apart and what would (both for a person, in full). */
#define CALREPORT_CAUSE_PARAMS 4
typedef struct {
    const char *params[CALREPORT_CAUSE_PARAMS + 1];
    const char *why;
    const char *action;
} calreport_corr_cause;

/* calreport_check_correlations with causes: the flagged pairs inside one
 * cause's group make one warning, every pair with its correlation, and the
 * cause's reason and action; a flagged pair no cause covers gets the
 * generic warning of its own. */
void calreport_check_correlations_explained(calreport *r, double threshold,
                                            const calreport_corr_cause *causes, int n_causes);

/* Warn, naming them, when folds were left out of the estimate as unlike
 * the others (fold_outliers.h): each one's held-out error against the
 * median fold's, and the estimate with them. */
void calreport_check_fold_outliers(calreport *r);
/* Which folds are unlike the others and by whose judgement, into
 * buf[len]: "the MODEL model (the best held out) VERB above R times its
 * median campaign's M arcsec on NAME (RMS), ..." (each fold with the
 * judging model's held-out error; "held out: NAME (RMS), ..." with the
 * fold's own when no compared model judged). */
void calreport_outlier_text(const calreport *r, const char *verb, char *buf, size_t len);

/* Held-out error above this multiple of the in-sample one is flagged. */
#define CALREPORT_CV_RATIO_WARN 3.0

/* Warn when the pooled held-out error exceeds ratio times the pooled
 * in-sample one, naming the worst fold: the fit does not carry over to
 * data it did not see. */
void calreport_check_crossval(calreport *r, double ratio);

/* A fold's refit whose Jacobian condition number exceeds this multiple of
 * the fit on all the data's is flagged. */
#define CALREPORT_FOLD_COND_WARN 1e3

/* Warn, naming the folds, when a fold's refit is much worse conditioned
 * than the fit on all the data (its condition number above factor times
 * r->cond_jacobian): without those rows some parameter combination is
 * barely determined, the refit stays near where it started along it, and
 * that fold's held-out error says more about the start than about the
 * calibration. */
void calreport_check_fold_condition(calreport *r, double factor);

/* predicted_rms of angle a in every band: the in-sample residual RMS times
 * dof_factor (sqrt(n / dof): the noise it underestimates) added in
 * quadrature to the propagated calibration sigma (when there is one). */
void calreport_predict(calreport *r, int a, double dof_factor);

/* Print the report for a person. */
int calreport_print(FILE *f, const calreport *r);

/* Write the band table (one row per angle and band) as TSV with a header. */
int calreport_write_bands(FILE *f, const calreport *r);

/* Write the cross-validation folds as TSV with a header: fold, held_out
 * (label), points, ok, rms_in_arcsec, rms_out_arcsec, refit_condition (the
 * refit's Jacobian condition number; NaN for a model without one). */
int calreport_write_folds(FILE *f, const calreport *r);

/* The model comparison as TSV with a header: model, parameters, ok,
 * aliased, held-out points, RMS in-sample and held-out, used, recommended. */
int calreport_write_models(FILE *f, const calreport_models *m);

#endif
