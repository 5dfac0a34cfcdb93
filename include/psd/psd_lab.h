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

/* The data under other table conventions (psd_labconv.c): the physical
 * model fitted in-sample on a subsample under the configured convention,
 * every other sign of the two axes, the axes swapped and the other two
 * orders; better when the best fits PSD_CONV_BETTER times better. */
typedef struct {
    long rows;                        /* rows of the subsample fitted */
    int tried;                        /* other conventions tried */
    double rms_configured_arcsec;     /* in-sample RMS total angle (+inf: fails) */
    double rms_best_arcsec;
    int better;
    char configured[240], best[240]; /* the conventions in config-key words */
} psd_conv_check;
int psd_labcal_conventions(const psd_labcal *k, psd_conv_check *out);
/* What is wrong with data the physics does not fit, in the data's terms
 * (psd_labdiag.c): the measured raw ratios mapped linearly (q = Q p + c)
 * on the design's nominal ones over the inner half of the data's field. */
#define PSD_DIAG_LINES 3
typedef struct {
    long rows;                 /* inner rows the map is fitted to */
    double inner_deg;          /* the inner field's total angle */
    int mirrored;              /* det Q < 0: the spot moves as the design's mirror image */
    double scale;              /* sqrt |det Q| */
    double turn_deg;           /* Q's rotation; mirrored: its mirror line's angle to X */
    double compressed_from_deg; /* first 5-deg bin whose travel is < 0.8 of the map's (NaN) */
    double outer_ratio, outer_deg; /* the outermost bin's travel over the map's, its start */
    long outliers;             /* inner rows beyond 5 times the median residual */
    int outlier_line[PSD_DIAG_LINES];
    double resid_median;       /* the map's median residual (ratio units) */
    int defects;               /* mirrored, turned, compressed, outliers: how many */
} psd_data_diag;
int psd_labcal_diagnose(const psd_labcal *k, psd_data_diag *g);
/* A warning in rep naming the data's defects (psd_labcal_diagnose). */
void psd_labcal_report_defects(const psd_labcal *k, calreport *rep);

/* A warning in rep when another convention fits markedly better (also
 * after a fit that failed: it may be why). */
void psd_labcal_report_conventions(const psd_labcal *k, calreport *rep);

#endif
