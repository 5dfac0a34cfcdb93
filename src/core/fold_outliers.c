/* fold_outliers.c - a cross-validation part unlike the others
 * (fold_outliers.h). */
#include "fold_outliers.h"
#include "stats.h"

#include <math.h>
#include <stddef.h>

int fold_outliers_mark(const double *rms, int n, unsigned char *outlier, double *median)
{
    double v[FOLD_OUTLIER_MAX_FOLDS];
    size_t m = 0;
    *median = NAN;
    for (int f = 0; f < n; f++)
        outlier[f] = 0;
    for (int f = 0; f < n && n <= FOLD_OUTLIER_MAX_FOLDS; f++)
        if (isfinite(rms[f]))
            v[m++] = rms[f];
    if (m < FOLD_OUTLIER_MIN_FOLDS)
        return 0;
    *median = stats_median_inplace(v, m);
    int marked = 0;
    for (int f = 0; f < n; f++)
        if (rms[f] > FOLD_OUTLIER_RATIO * *median) {
            outlier[f] = 1;
            marked++;
        }
    if (4 * marked > (int)m) { /* a quarter or more: the sensor's spread */
        for (int f = 0; f < n; f++)
            outlier[f] = 0;
        marked = 0;
    }
    return marked;
}

double fold_outliers_pool(const double *sum2, const long *cnt, int n,
                          const unsigned char *outlier, double scale, double *rms_all)
{
    double kept = 0, all = 0;
    long n_kept = 0, n_all = 0;
    for (int f = 0; f < n; f++) {
        all += sum2[f];
        n_all += cnt[f];
        if (!outlier[f]) {
            kept += sum2[f];
            n_kept += cnt[f];
        }
    }
    *rms_all = n_all ? sqrt(all / (double)n_all) * scale : NAN;
    return n_kept ? sqrt(kept / (double)n_kept) * scale : NAN;
}
