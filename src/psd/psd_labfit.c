/* psd_labfit.c - `sunmc calibrate` for the four-channel sensor: a lab's
 * readings fitted by the physical or the polynomial model, with standard
 * errors, identifiability warnings, repeatability and cross-validation
 * (psd_lab.h).
 *
 * Repeated readings: rows at the same table angles form a point.  The fit
 * uses every row (a point's mean carries its rows' weight), but the
 * parameters' standard errors and the accuracy estimate treat each point,
 * not each row, as one observation: the residual variance is that of the
 * points' mean residuals, and the spread of the rows about their point's
 * mean is reported as the repeatability.  Repeats thus lower the noise of
 * a point, never the count of what the calibration was shown. */
#include "psd_lab.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void psd_labcal_free(psd_labcal *k)
{
    if (!k)
        return;
    free(k->ut);
    free(k->spline_fold);
    free(k->aside);
    fit_workspace_free(k->fw);
    fit_workspace_free(k->fw_channels);
    free(k);
}

/* Point index of each row: rows with equal table angles share one. */
static void group_points(psd_labcal *k)
{
    size_t n = k->d->n;
    k->n_points = 0;
    for (size_t i = 0; i < n; i++) {
        k->point[i] = -1;
        for (size_t j = i; j-- > 0 && i - j <= PSD_REPEAT_LOOKBACK;)
            if (k->d->v[0][j] == k->d->v[0][i] && k->d->v[1][j] == k->d->v[1][i]) {
                k->point[i] = k->point[j];
                break;
            }
        if (k->point[i] < 0)
            k->point[i] = k->n_points++;
    }
}

psd_labcal *psd_labcal_alloc(const sunmc_config *c, const lab_columns *d, char *err,
                             size_t errlen)
{
    psd_labcal *k = calloc(1, sizeof *k);
    size_t n = d->n;
    int fr[PSD_NP];
    int nfree = psd_phys_free(&psd_cfg(c)->design, psd_cfg(c)->fit_tilt, fr);
    if (k) {
        k->ut = malloc((n * 16 + PSD_LAB_POLY_WORK) * sizeof(double) + n * sizeof(long));
        k->fw = PSD_MODEL_HAS_PHYSICS(psd_cfg(c)->cal_model)
                    ? fit_workspace_alloc(2 * n, (size_t)nfree) : NULL;
        k->fw_channels = k->fw ? fit_workspace_alloc(PSD_RESIDUALS_PER_ROW * n,
                                                     (size_t)psd_phys_free_channels(
                                                         psd_cfg(c)->fit_tilt))
                               : NULL;
    }
    if (!k || !k->ut ||
        (PSD_MODEL_HAS_PHYSICS(psd_cfg(c)->cal_model) && (!k->fw || !k->fw_channels))) {
        psd_labcal_free(k);
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for %zu rows", n);
        return NULL;
    }
    k->c = c;
    k->d = d;
    k->w = k->ut + 3 * n;
    k->err = k->w + n;          /* 3 n: alpha, beta, total errors (rad) */
    k->scratch = k->err + 3 * n; /* 8 n */
    k->poly_work = k->scratch + 8 * n;
    k->point = (long *)(k->poly_work + PSD_LAB_POLY_WORK);
    const psd_config *p = psd_cfg(c);
    for (size_t i = 0; i < n; i++) {
        psd_table_sun(p, d->v[0][i] * RAD_PER_DEG, d->v[1][i] * RAD_PER_DEG, k->ut + 3 * i);
        k->w[i] = d->v[6][i];
    }
    group_points(k);
    return k;
}

void psd_labcal_rows(psd_labcal *k, psd_rows *r)
{
    memset(r, 0, sizeof *r);
    r->n = k->d->n;
    for (int c = 0; c < PSD_CHANNELS; c++)
        r->m[c] = k->d->v[2 + c];
    r->ut = k->ut;
    r->w = k->w;
    r->design = &psd_cfg(k->c)->design;
    r->scratch = k->scratch;
    r->fw_channels = k->fw_channels;
}

int psd_labcal_fit(psd_labcal *k, fit_result *fr)
{
    psd_labcal_rows(k, &k->rows);
    k->rows.smooth = k->spline_smooth;
    k->rows.table_log = k->table_log;
    k->rows.fold = k->spline_fold;
    k->rows.n_folds = k->spline_n_folds;
    return psd_unit_fit(k->c, k->fw, &k->rows, k->poly_work, &k->cal, fr);
}

int psd_labcal_row_error(const psd_labcal *k, size_t i, double e[3])
{
    double m[4] = {k->d->v[2][i], k->d->v[3][i], k->d->v[4][i], k->d->v[5][i]};
    double a, b, ta, tb, uc[3];
    const double *ut = k->ut + 3 * i;
    if (psd_cal_angles(&k->cal, m, &a, &b) != SUNMC_OK)
        return SUNMC_EDOM;
    sun_angles_of(ut, &ta, &tb);
    sun_vector_of(a, b, uc);
    e[0] = a - ta;
    e[1] = b - tb;
    e[2] = angle_between(uc, ut);
    return SUNMC_OK;
}

/* Errors of every row (NaN where it cannot be compensated); returns the
 * count of rows with weight > 0 that cannot. */
size_t psd_labcal_errors(psd_labcal *k)
{
    size_t bad = 0;
    for (size_t i = 0; i < k->d->n; i++) {
        double *e = k->err + 3 * i;
        if (psd_labcal_row_error(k, i, e) != SUNMC_OK) {
            e[0] = e[1] = e[2] = NAN;
            bad += k->w[i] > 0;
        }
    }
    return bad;
}

void psd_labcal_point_stats(const psd_labcal *k, const double *w, psd_point_stats *s)
{
    memset(s, 0, sizeof *s);
    double *mean = k->scratch, *cnt = k->scratch + 2 * k->n_points; /* 2 n_points + n_points */
    memset(mean, 0, 3 * (size_t)k->n_points * sizeof *mean);
    for (size_t i = 0; i < k->d->n; i++)
        if (w[i] > 0 && isfinite(k->err[3 * i])) {
            long g = k->point[i];
            mean[2 * g] += k->err[3 * i];
            mean[2 * g + 1] += k->err[3 * i + 1];
            cnt[g] += 1.0;
        }
    double within = 0.0, between[2] = {0, 0};
    long n_within = 0;
    for (long g = 0; g < k->n_points; g++)
        if (cnt[g] > 0) {
            mean[2 * g] /= cnt[g];
            mean[2 * g + 1] /= cnt[g];
            between[0] += mean[2 * g] * mean[2 * g];
            between[1] += mean[2 * g + 1] * mean[2 * g + 1];
            s->points++;
            n_within += (long)cnt[g] - 1;
        }
    for (size_t i = 0; i < k->d->n; i++)
        if (w[i] > 0 && isfinite(k->err[3 * i])) {
            long g = k->point[i];
            double dx = k->err[3 * i] - mean[2 * g], dy = k->err[3 * i + 1] - mean[2 * g + 1];
            within += dx * dx + dy * dy;
            s->rows++;
        }
    s->repeat_rad = n_within > 0 ? sqrt(within / (2.0 * (double)n_within)) : NAN;
    s->mean_rms_rad[0] = s->points ? sqrt(between[0] / (double)s->points) : NAN;
    s->mean_rms_rad[1] = s->points ? sqrt(between[1] / (double)s->points) : NAN;
    s->per_point = s->points ? (double)s->rows / (double)s->points : 1.0;
}
