/* psd_lab.h - the four-channel sensor's lab commands (psd_lab.c: the
 * family_lab hooks; psd_labfit.c: the calibration of a lab's data). */
#ifndef SUNMC_PSD_LAB_H
#define SUNMC_PSD_LAB_H

#include "lab.h"
#include "psd_unit.h"

/* Rows further back than this are not searched for a repeat of a row's
 * table angles (a lab records a point's repeats together). */
#define PSD_REPEAT_LOOKBACK 64
/* params.ini's [calibration] model line of each model. */
#define PSD_CALFIT_MODEL_PHYSICAL "psd_physical"
#define PSD_CALFIT_MODEL_POLYNOMIAL "psd_polynomial"
#define PSD_CALFIT_MODEL_SPLINE "psd_spline"
#define PSD_CALFIT_MODEL_HYBRID "psd_hybrid"
#define PSD_CALFIT_MODEL_TABLE "psd_table"
#define PSD_LAB_POLY_WORK (PSD_POLY_MAX_TERMS * (PSD_POLY_MAX_TERMS + 2))

/* What compensate reads from a params.ini (family_lab.model_size). */
typedef struct {
    psd_config cfg;      /* design and table convention, from params.ini */
    psd_cal cal;
} psd_model_file;

/* The polynomial's terms are fitted on ratios up to poly.scale (the
 * campaign's largest): a ratio this fraction beyond is an extrapolation
 * the calibration cannot stand behind (a spot off the calibrated field). */
#define PSD_POLY_RANGE_MARGIN 0.1

/* Data columns: alpha_deg, beta_deg, i1..i4, weight (v[0..6]). */
typedef struct {
    const sunmc_config *c;
    const lab_columns *d;
    double *ut;          /* 3 n: the table top's sun vectors */
    double *w;           /* n: weights (0: not used) */
    double *err;         /* 3 n: alpha, beta, total error (rad) of the fitted calibration */
    double *scratch;     /* 8 n */
    double *poly_work;
    long *point;         /* n: the point (equal table angles) of each row */
    long n_points;
    fit_workspace *fw;   /* physical model only */
    fit_workspace *fw_channels; /* its first stage (psd_phys_fit_channels) */
    psd_cal cal;
    psd_rows rows;       /* the fit's view of the data (and its variable scales) */
    fit_result fr;
    size_t dropped;      /* rows the fitted model could not read (weight set 0) */
    /* spline and hybrid: the smoothing once chosen (0: choose it by the
     * cross-validation's folds, spline_fold, at the next fit) */
    double spline_smooth;
    int table_log;              /* table: its nodes once chosen (log2 of the steps; 0: choose) */
    int *spline_fold;
    int spline_n_folds;
    calreport_models models; /* for models.tsv */
} psd_labcal;

psd_labcal *psd_labcal_alloc(const sunmc_config *c, const lab_columns *d, char *err,
                             size_t errlen);
void psd_labcal_free(psd_labcal *k);
void psd_labcal_rows(psd_labcal *k, psd_rows *r);
/* Fit c's model to the rows with weight > 0 into k->cal. */
int psd_labcal_fit(psd_labcal *k, fit_result *fr);
/* Errors (rad) of row i under k->cal. */
int psd_labcal_row_error(const psd_labcal *k, size_t i, double e[3]);
/* Every row's errors into k->err; the count of used rows it cannot read. */
size_t psd_labcal_errors(psd_labcal *k);

/* Per-point statistics of k->err over rows with w > 0. */
typedef struct {
    long points, rows;
    double per_point;        /* rows per point */
    double repeat_rad;       /* repeatability: rows about their point's mean, per axis */
    double mean_rms_rad[2];  /* RMS of the points' mean errors, alpha and beta */
} psd_point_stats;
void psd_labcal_point_stats(const psd_labcal *k, const double *w, psd_point_stats *s);

/* The cross-validation's folds: fold[i] of each row (-1: never held out),
 * by beta line (*by_line = 1; line[f] the fold's beta, deg) or by sweep.
 * Returns their count. */
int psd_labcal_folds(const psd_labcal *k, int *fold, double line[CALREPORT_MAX_FOLDS],
                     int *by_line);

/* The model comparison (psd_labmodels.c): every model refitted on the
 * folds of psd_labcal_folds, into rep->models with the recommendation. */
void psd_labcal_compare(const psd_labcal *k, calreport *rep);

/* Fill rep for the fitted k (parameters, covariance, bands, prediction,
 * cross-validation). */
void psd_labcal_report(psd_labcal *k, calreport *rep);

#endif
