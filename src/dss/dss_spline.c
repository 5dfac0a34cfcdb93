/* dss_spline.c - the spline, table and hybrid models of the pinhole DSS
 * (dss_calib.h): the family's side of core's lab_spline and lab_table, its
 * inputs (the spot, px) and outputs (the angles, rad). */
#include "dss_calib.h"
#include "dss_score.h"
#include "status.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <string.h>

const char *const dss_model_names[DSS_N_MODELS] = {"physical", "polynomial", "spline", "hybrid",
                                                   "table"};

/* Targets of every reading into y[2] (NaN where not used): the truth, or
 * for the hybrid the truth minus its physical angles.  Returns the count. */
static long spline_rows(const dss_calib_workspace *cw, const dss_calibration *cal, double *y[2])
{
    long used = 0;
    int hyb = cal->kind == DSS_MODEL_HYBRID;
    for (size_t i = 0; i < cw->n; i++) {
        double a0, b0, a = 0, b = 0;
        y[0][i] = y[1][i] = NAN;
        if (!(cw->weight[i] > 0) || !isfinite(cw->x_px[i]) || !isfinite(cw->y_px[i]))
            continue;
        if (hyb && dss_model_compensate(&cal->phys, cw->x_px[i], cw->y_px[i], &a, &b) != SUNMC_OK)
            continue;
        dss_calib_truth(cal, cw->b1_rad[i], cw->b2_rad[i], &a0, &b0);
        y[0][i] = a0 - a;
        y[1][i] = b0 - b;
        used++;
    }
    return used;
}

int dss_spline_fit(dss_calib_workspace *cw, dss_calibration *cal, fit_result *res)
{
    size_t n = cw->n;
    double *y[2] = {cw->sx, cw->sx + n};
    long used = spline_rows(cw, cal, y);
    memset(res, 0, sizeof *res);
    /* no Jacobian: the penalised normal equations are solved by Cholesky,
     * which fails (SUNMC_EFIT) when they are singular; the penalty keeps
     * them well conditioned otherwise */
    res->rcond = 1.0;
    if (used < DSS_SPLINE_MIN_ROWS) {
        res->status = GSL_EINVAL;
        return SUNMC_EINPUT;
    }
    for (size_t i = 0; i < n; i++)
        cw->fold[i] = (int)((i / DSS_SPLINE_FOLD_BLOCK) % DSS_SPLINE_FOLDS);
    lab_spline_data sd = {.n = n, .dims = 2, .n_out = 2, .x = {cw->x_px, cw->y_px},
                          .y = {y[0], y[1]}, .w = cw->weight};
    char err[SUNMC_ERRLEN];
    double rms;
    long outside;
    int st = lab_spline_choose_ws(&cal->spline, &sd, cw->fold, DSS_SPLINE_FOLDS, cw->sws, &rms,
                                  &outside, err, sizeof err);
    if (st == SUNMC_OK && cal->kind == DSS_MODEL_TABLE)
        st = lab_table_choose_ws(&cal->table, &cal->spline, &sd, cw->fold, DSS_SPLINE_FOLDS,
                                 cw->sws, &rms, &outside, err, sizeof err);
    res->status = st == SUNMC_OK ? GSL_SUCCESS : GSL_EFAILED;
    return st == SUNMC_OK ? SUNMC_OK : st == SUNMC_ENOMEM ? SUNMC_ENOMEM : SUNMC_EFIT;
}

int dss_spline_compensate(const dss_calibration *cal, double x_px, double y_px, double *alpha,
                          double *beta)
{
    double x[2] = {x_px, y_px}, t[2], a = 0, b = 0;
    *alpha = *beta = NAN;
    if (cal->kind == DSS_MODEL_HYBRID &&
        dss_model_compensate(&cal->phys, x_px, y_px, &a, &b) != SUNMC_OK)
        return SUNMC_EDOM;
    int st = cal->kind == DSS_MODEL_TABLE ? lab_table_eval(&cal->table, x, t)
                                          : lab_spline_eval(&cal->spline, x, t);
    if (st != SUNMC_OK)
        return SUNMC_EDOM;
    *alpha = a + t[0];
    *beta = b + t[1];
    return SUNMC_OK;
}
