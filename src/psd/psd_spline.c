/* psd_spline.c - the spline, table and hybrid models of the four-channel sensor
 * (psd_model.h): the family's side of core's lab_spline, its inputs and
 * outputs. */
#include "psd_model.h"
#include "status.h"

#include <math.h>
#include <stdlib.h>

/* A row on an axis: its other table angle this close to 0 (a single-axis sweep). */
#define PSD_SPLINE_AXIS_TOL 1e-12
/* Rows per block of the interleaved folds (a point's repeats stay together). */
#define PSD_SPLINE_FOLD_BLOCK 8

const char *const psd_model_names[PSD_N_MODELS] = {"physical", "polynomial", "spline", "hybrid",
                                                   "table"};

int psd_spline_inputs(const psd_cal *k, const double r[4], double x[2])
{
    if (k->model != PSD_MODEL_HYBRID)
        return psd_poly_ratios(k->design, r, &x[0], &x[1]);
    double xr, yr, ut[3];
    if (psd_phys_observed(&k->phys, r, &xr, &yr) != SUNMC_OK ||
        psd_phys_invert(&k->phys, xr, yr, ut) != SUNMC_OK || !(ut[2] > 0))
        return SUNMC_EDOM;
    x[0] = ut[0] / ut[2];
    x[1] = ut[1] / ut[2];
    return SUNMC_OK;
}

int psd_spline_eval(const psd_cal *k, const double x[2], double t[2])
{
    return k->model == PSD_MODEL_TABLE ? lab_table_eval(&k->table, x, t)
                                       : lab_spline_eval(&k->spline, x, t);
}

int psd_table_log(const lab_table *t)
{
    int lg = 0;
    while ((1 << lg) + 1 < t->nodes)
        lg++;
    return lg;
}

/* Inputs and targets of every row into x[2], y[2] (NaN where the row is
 * not used); returns 1 when every used row lies on an axis. */
static int spline_rows(const psd_cal *k, const psd_rows *d, double *x[2], double *y[2])
{
    int on_axis = 1;
    for (size_t i = 0; i < d->n; i++) {
        double r[4] = {d->m[0][i], d->m[1][i], d->m[2][i], d->m[3][i]}, in[2];
        const double *u = d->ut + 3 * i;
        x[0][i] = x[1][i] = y[0][i] = y[1][i] = NAN;
        if ((d->w && !(d->w[i] > 0)) || psd_spline_inputs(k, r, in) != SUNMC_OK)
            continue;
        double ta = u[0] / u[2], tb = u[1] / u[2];
        int hyb = k->model == PSD_MODEL_HYBRID;
        x[0][i] = in[0];
        x[1][i] = in[1];
        y[0][i] = hyb ? ta - in[0] : ta;
        y[1][i] = hyb ? tb - in[1] : tb;
        on_axis &= fabs(u[0]) < PSD_SPLINE_AXIS_TOL || fabs(u[1]) < PSD_SPLINE_AXIS_TOL;
    }
    return on_axis;
}

int psd_spline_fit(psd_cal *k, const psd_rows *d, double *work)
{
    size_t n = d->n;
    double *x[2] = {work, work + n}, *y[2] = {work + 2 * n, work + 3 * n};
    int on_axis = spline_rows(k, d, x, y);
    char err[SUNMC_ERRLEN];
    int tab = k->model == PSD_MODEL_TABLE;
    /* single-axis sweeps: each angle of its ratio plus the other ratio's
     * cross-talk (lab_spline.h), but for the table, one line per axis */
    lab_spline_data sd = {.n = n, .dims = on_axis ? 1 : 2, .n_out = 2, .cross = on_axis && !tab,
                          .x = {x[0], x[1]}, .y = {y[0], y[1]}, .w = d->w};
    /* the Monte Carlo's thread workspace, or one for this fit */
    lab_spline_ws *w = d->sws ? d->sws : lab_spline_ws_alloc(n);
    int *fold = d->fold || d->fold_buf ? d->fold_buf : malloc((n + 1) * sizeof *fold);
    if (!w || (!d->fold && !fold)) {
        if (!d->sws)
            lab_spline_ws_free(w);
        if (!d->fold_buf)
            free(fold);
        return SUNMC_ENOMEM;
    }
    for (size_t i = 0; !d->fold && i < n; i++)
        fold[i] = (int)((i / PSD_SPLINE_FOLD_BLOCK) % PSD_SPLINE_AUTO_FOLDS);
    const int *use = d->fold ? d->fold : fold;
    int nf = d->fold ? d->n_folds : PSD_SPLINE_AUTO_FOLDS;
    double rms;
    long outside;
    int st;
    if (d->smooth > 0)
        st = lab_spline_fit_ws(&k->spline, &sd, d->smooth, 1, w, err, sizeof err);
    else
        st = lab_spline_choose_ws(&k->spline, &sd, use, nf, w, &rms, &outside, err, sizeof err);
    if (st == SUNMC_OK && tab && d->smooth > 0 && d->table_log > 0)
        st = lab_table_sample(&k->table, &k->spline, d->table_log, err, sizeof err);
    else if (st == SUNMC_OK && tab)
        st = lab_table_choose_ws(&k->table, &k->spline, &sd, use, nf, w, &rms, &outside, err,
                                 sizeof err);
    if (!d->sws)
        lab_spline_ws_free(w);
    if (!d->fold_buf)
        free(fold);
    return st == SUNMC_OK ? SUNMC_OK : SUNMC_EFIT;
}
