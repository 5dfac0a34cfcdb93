/* fold_outliers.h - a cross-validation part unlike the others (issue 39).
 *
 * A calibration's honest estimate pools the held-out errors of its parts
 * (beta lines, sweeps, files).  One part the rest cannot predict -- a
 * campaign whose set-up went wrong, as kenscl's beta sweep of 19.11.2021
 * 16.55, off by up to 2,200 arcsec beyond 40 deg -- dominates the pool and
 * says more about that campaign than about the calibration: held out, it
 * leaves 1,326 arcsec where the other nine leave 405-942.
 *
 * The rule: with at least FOLD_OUTLIER_MIN_FOLDS scored parts, a part
 * whose held-out RMS exceeds FOLD_OUTLIER_RATIO times the median part's is
 * an outlier; when more than a quarter of the parts would be, the spread
 * is the sensor's and none is.  The caller leaves the outliers out of the
 * estimate, gives the estimate with them beside it, and names them. */
#ifndef SUNMC_FOLD_OUTLIERS_H
#define SUNMC_FOLD_OUTLIERS_H

#define FOLD_OUTLIER_RATIO 2.0
#define FOLD_OUTLIER_MIN_FOLDS 5
#define FOLD_OUTLIER_MAX_FOLDS 256

/* rms[n]: each part's held-out RMS (any unit; NaN: not scored, never an
 * outlier).  Sets outlier[f] to 1 or 0 and *median (NaN with fewer than
 * FOLD_OUTLIER_MIN_FOLDS scored parts, or n above FOLD_OUTLIER_MAX_FOLDS:
 * none marked); returns the count marked. */
int fold_outliers_mark(const double *rms, int n, unsigned char *outlier, double *median);

/* The RMS of n parts' sums of squares sum2[f] over cnt[f] values, the
 * parts marked in outlier[] left out (NaN when nothing is left); *rms_all:
 * over every part.  Times scale (the unit: ARCSEC_PER_RAD, say). */
double fold_outliers_pool(const double *sum2, const long *cnt, int n,
                          const unsigned char *outlier, double scale, double *rms_all);

#endif
