/* ess_spline.c - the spline, table and hybrid models of the ESS (ess_model.h):
 * the family's side of core's lab_spline and lab_table, one input (the raw
 * angle of its code) and one output (the true angle, or the paper model's
 * error in it). */
#include "ess_calib.h"
#include "status.h"

#include <math.h>
#include <string.h>

double ess_model_truth(const ess_model *m, double alpha_rad, double beta_rad)
{
    mat3 rx, ry, M;
    rot_x(alpha_rad, rx);
    rot_y(-beta_rad, ry); /* the table turns the sensor: active */
    mat3_mul(rx, ry, M);
    double w[3], s[3];
    mat3_vec(M, m->v, w);
    mat3_vec(m->R, w, s);
    return atan2(s[1], s[2]);
}

int ess_spline_compensate_batch(const ess_model *m, size_t n, const double *raw_rad,
                                double *alpha_rad, int *status)
{
    int st = SUNMC_OK, hyb = m->kind == ESS_MODEL_HYBRID;
    if (hyb)
        st = ess_model_phys_compensate_batch(m, n, raw_rad, alpha_rad, status);
    for (size_t i = 0; i < n; i++) {
        if (!hyb) {
            alpha_rad[i] = 0.0;
            status[i] = SUNMC_OK;
        }
        double t;
        if (status[i] != SUNMC_OK ||
            (m->kind == ESS_MODEL_TABLE ? lab_table_eval(&m->table, &raw_rad[i], &t)
                                        : lab_spline_eval(&m->spline, &raw_rad[i], &t)) !=
                SUNMC_OK) {
            status[i] = SUNMC_EDOM;
            alpha_rad[i] = NAN;
            st = SUNMC_EDOM;
            continue;
        }
        alpha_rad[i] += t;
    }
    return st;
}

int ess_spline_fit(ess_calib_workspace *cw, ess_model *m)
{
    size_t n = cw->n;
    double *y = cw->scratch[0], *phys = cw->scratch[1];
    int *ok = cw->fold; /* the physical model's status first, then the folds */
    int hyb = m->kind == ESS_MODEL_HYBRID;
    if (hyb)
        ess_model_phys_compensate_batch(m, n, cw->raw_rad, phys, ok);
    long used = 0;
    for (size_t i = 0; i < n; i++) {
        y[i] = NAN;
        if (!(cw->weight[i] > 0) || (hyb && ok[i] != SUNMC_OK))
            continue;
        y[i] = ess_model_truth(m, cw->alpha_rad[i], cw->beta_rad[i]) - (hyb ? phys[i] : 0.0);
        used++;
    }
    if (used < ESS_SPLINE_MIN_ROWS)
        return SUNMC_EINPUT;
    for (size_t i = 0; i < n; i++)
        cw->fold[i] = (int)((i / ESS_SPLINE_FOLD_BLOCK) % ESS_SPLINE_FOLDS);
    lab_spline_data sd = {.n = n, .dims = 1, .n_out = 1, .x = {cw->raw_rad}, .y = {y},
                          .w = cw->weight};
    char err[SUNMC_ERRLEN];
    double rms;
    long outside;
    int st = lab_spline_choose_ws(&m->spline, &sd, cw->fold, ESS_SPLINE_FOLDS, cw->sws, &rms,
                                  &outside, err, sizeof err);
    if (st == SUNMC_OK && m->kind == ESS_MODEL_TABLE)
        st = lab_table_choose_ws(&m->table, &m->spline, &sd, cw->fold, ESS_SPLINE_FOLDS, cw->sws,
                                 &rms, &outside, err, sizeof err);
    return st == SUNMC_OK ? SUNMC_OK : st == SUNMC_EINPUT ? SUNMC_EINPUT : SUNMC_EFIT;
}
