/* lab_table.c - the family-neutral look-up table calibration (lab_table.h):
 * the spline sampled at the nodes, (bi)linear interpolation, the grid step
 * by cross-validation. */
#include "lab_table.h"
#include "status.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int max_log(int dims) { return dims == 2 ? LAB_TABLE_MAX_LOG2 : LAB_TABLE_MAX_LOG1; }
static int n_inputs(int dims, int n_out) { return dims == 2 ? 2 : n_out; }

double lab_table_step(const lab_table *t, int k)
{
    return (t->hi[k] - t->lo[k]) / (t->nodes - 1);
}

size_t lab_table_bytes(const lab_table *t)
{
    size_t per = t->dims == 2 ? (size_t)t->nodes * (size_t)t->nodes : (size_t)t->nodes;
    return per * (size_t)t->n_out * sizeof(float);
}

int lab_table_sample(lab_table *t, const lab_spline *s, int log_nodes, char *err, size_t errlen)
{
    if (s->dims < 1 || s->dims > 2 || log_nodes < LAB_TABLE_MIN_LOG ||
        log_nodes > max_log(s->dims))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "table: %d inputs and 2^%d + 1 nodes per input: 1 or 2 inputs, "
                          "from 2^%d + 1 to 2^%d + 1 nodes", s->dims, log_nodes,
                          LAB_TABLE_MIN_LOG, max_log(s->dims));
    if (s->cross) /* a line per axis has no room for the other input's term */
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "table: a spline with the other input's cross term cannot be "
                          "tabulated one line per input");
    static const lab_table zero;
    *t = zero;
    t->dims = s->dims;
    t->n_out = s->n_out;
    t->nodes = (1 << log_nodes) + 1;
    t->field_cells = s->dims == 2 ? s->nbreak - 1 : 0;
    memcpy(t->lo, s->lo, sizeof t->lo);
    memcpy(t->hi, s->hi, sizeof t->hi);
    memcpy(t->cell, s->cell, sizeof t->cell);
    /* the spline over its whole rectangle: a node on the edge of a cell the
     * data did not visit still has the value the penalty gave it */
    lab_spline open = *s;
    memset(open.cell, 1, sizeof open.cell);
    int n_in = n_inputs(s->dims, s->n_out), n = t->nodes;
    for (int a = 0; a < (s->dims == 2 ? n : 1); a++)
        for (int b = 0; b < n; b++) {
            double x[2], y[LAB_SPLINE_MAX_OUT];
            for (int k = 0; k < n_in; k++) {
                int i = s->dims == 2 ? (k == 0 ? a : b) : b;
                x[k] = i == n - 1 ? s->hi[k] : s->lo[k] + i * (s->hi[k] - s->lo[k]) / (n - 1);
            }
            if (lab_spline_eval(&open, x, y) != SUNMC_OK)
                return sunmc_fail(err, errlen, SUNMC_EFIT,
                                  "table: the spline has no value at node %d, %d", a, b);
            for (int j = 0; j < s->n_out; j++)
                t->v[j][a * n + b] = (float)y[j];
        }
    return SUNMC_OK;
}

/* Is x inside t's field? */
static int in_field(const lab_table *t, const double *x)
{
    int n_in = n_inputs(t->dims, t->n_out);
    for (int k = 0; k < n_in; k++)
        if (!(x[k] >= t->lo[k] && x[k] <= t->hi[k]))
            return 0;
    if (t->dims != 2)
        return 1;
    int nc = t->field_cells, c[2];
    for (int k = 0; k < 2; k++) {
        c[k] = (int)((x[k] - t->lo[k]) / (t->hi[k] - t->lo[k]) * nc);
        c[k] = c[k] >= nc ? nc - 1 : c[k];
    }
    return t->cell[c[0] * nc + c[1]];
}

/* The interval of input k holding x: its index, and x's fraction in it. */
static int interval(const lab_table *t, int k, double x, double *frac)
{
    double u = (x - t->lo[k]) / (t->hi[k] - t->lo[k]) * (t->nodes - 1);
    int i = (int)u;
    i = i > t->nodes - 2 ? t->nodes - 2 : i;
    *frac = u - i;
    return i;
}

int lab_table_eval(const lab_table *t, const double *x, double *y)
{
    for (int j = 0; j < t->n_out; j++)
        y[j] = NAN;
    if (!in_field(t, x))
        return SUNMC_EDOM;
    int n = t->nodes;
    if (t->dims == 1) {
        for (int j = 0; j < t->n_out; j++) {
            double f;
            int i = interval(t, j, x[j], &f);
            y[j] = (1.0 - f) * t->v[j][i] + f * t->v[j][i + 1];
        }
        return SUNMC_OK;
    }
    double f0, f1;
    int a = interval(t, 0, x[0], &f0), b = interval(t, 1, x[1], &f1);
    for (int j = 0; j < t->n_out; j++) {
        const float *v = t->v[j];
        y[j] = (1.0 - f0) * ((1.0 - f1) * v[a * n + b] + f1 * v[a * n + b + 1]) +
               f0 * ((1.0 - f1) * v[(a + 1) * n + b] + f1 * v[(a + 1) * n + b + 1]);
    }
    return SUNMC_OK;
}

/* ---- the grid step by cross-validation ---- */

/* The coarser table of 2^log + 1 nodes from the finest one's nodes. */
static void subsample(lab_table *dst, const lab_table *fine, int log_nodes)
{
    *dst = *fine;
    int n = (1 << log_nodes) + 1, nf = fine->nodes, stride = (nf - 1) / (n - 1);
    dst->nodes = n;
    for (int j = 0; j < fine->n_out; j++)
        for (int a = 0; a < (fine->dims == 2 ? n : 1); a++)
            for (int b = 0; b < n; b++)
                dst->v[j][a * n + b] = fine->v[j][a * stride * nf + b * stride];
}

static int row_used(const lab_spline_data *d, size_t i)
{
    if (d->w && !(d->w[i] > 0))
        return 0;
    for (int k = 0; k < n_inputs(d->dims, d->n_out); k++)
        if (!isfinite(d->x[k][i]))
            return 0;
    for (int j = 0; j < d->n_out; j++)
        if (!isfinite(d->y[j][i]))
            return 0;
    return 1;
}

typedef struct {
    double sum2[LAB_TABLE_MAX_LOG1 + 1];
    long cnt, outside;
    lab_table fine, coarse;
    lab_spline s;
} step_scores;

/* Every table's held-out sum of squares over fold f (wk: the weights). */
static void score_fold(const lab_spline_data *d, const int *fold, int f, double smooth,
                       lab_spline_ws *w, step_scores *sc)
{
    char e[SUNMC_ERRLEN];
    lab_spline_data dk = *d;
    double *wk = lab_spline_ws_weights(w, d->n);
    dk.w = wk;
    for (size_t i = 0; i < d->n; i++)
        wk[i] = fold[i] == f ? 0.0 : (d->w ? d->w[i] : 1.0);
    int top = max_log(d->dims);
    if (lab_spline_fit_ws(&sc->s, &dk, smooth, 0, w, e, sizeof e) != SUNMC_OK ||
        lab_table_sample(&sc->fine, &sc->s, top, e, sizeof e) != SUNMC_OK)
        return;
    for (size_t i = 0; i < d->n; i++) {
        if (fold[i] != f || !row_used(d, i))
            continue;
        double x[2], y[LAB_TABLE_MAX_OUT];
        for (int k = 0; k < n_inputs(d->dims, d->n_out); k++)
            x[k] = d->x[k][i];
        if (!in_field(&sc->fine, x)) {
            sc->outside++;
            continue;
        }
        sc->cnt++;
        for (int lg = LAB_TABLE_MIN_LOG; lg <= top; lg++) {
            subsample(&sc->coarse, &sc->fine, lg);
            lab_table_eval(&sc->coarse, x, y);
            for (int j = 0; j < d->n_out; j++)
                sc->sum2[lg] += (y[j] - d->y[j][i]) * (y[j] - d->y[j][i]);
        }
    }
}

/* The coarsest step within LAB_TABLE_STEP_TOL of the best; its RMS. */
static int pick_step(const step_scores *sc, int top, int n_out, double *rms)
{
    double best = INFINITY;
    for (int lg = LAB_TABLE_MIN_LOG; lg <= top; lg++)
        best = fmin(best, sc->sum2[lg]);
    for (int lg = LAB_TABLE_MIN_LOG; lg <= top; lg++)
        if (sqrt(sc->sum2[lg]) <= (1.0 + LAB_TABLE_STEP_TOL) * sqrt(best)) {
            *rms = sqrt(sc->sum2[lg] / (double)(sc->cnt * n_out));
            return lg;
        }
    *rms = NAN;
    return top;
}

int lab_table_choose_ws(lab_table *t, const lab_spline *s, const lab_spline_data *d,
                        const int *fold, int n_folds, lab_spline_ws *w, double *cv_rms,
                        long *n_outside, char *err, size_t errlen)
{
    int top = max_log(s->dims), lg = top;
    *cv_rms = NAN;
    *n_outside = 0;
    if (!lab_spline_ws_weights(w, d->n))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "table: %zu rows, more than the workspace",
                          d->n);
    if (n_folds >= 2) {
        step_scores sc; /* on the stack: nothing allocated per fit */
        memset(sc.sum2, 0, sizeof sc.sum2);
        sc.cnt = sc.outside = 0;
        for (int f = 0; f < n_folds; f++)
            score_fold(d, fold, f, s->smooth, w, &sc);
        if (sc.cnt > 0)
            lg = pick_step(&sc, top, d->n_out, cv_rms);
        *n_outside = sc.outside;
    }
    return lab_table_sample(t, s, lg, err, errlen);
}

int lab_table_choose(lab_table *t, const lab_spline *s, const lab_spline_data *d,
                     const int *fold, int n_folds, double *cv_rms, long *n_outside, char *err,
                     size_t errlen)
{
    lab_spline_ws *w = lab_spline_ws_alloc(d->n);
    if (!w)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "table: out of memory");
    int st = lab_table_choose_ws(t, s, d, fold, n_folds, w, cv_rms, n_outside, err, errlen);
    lab_spline_ws_free(w);
    return st;
}
