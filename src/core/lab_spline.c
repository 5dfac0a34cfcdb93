/* lab_spline.c - the family-neutral penalised B-spline calibration
 * (lab_spline.h): fit, evaluation, the smoothing by cross-validation. */
#include "lab_spline.h"
#include "status.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Coefficients per input: nbreak + order - 2. */
static int coef_per_input(int nbreak) { return nbreak + LAB_SPLINE_ORDER - 2; }

/* Knot j of input k over nb uniform breakpoints, the ends repeated
 * LAB_SPLINE_ORDER times (gsl_bspline_knots_uniform's). */
static double knot(const lab_spline *s, int k, int nb, int j)
{
    int m = j - (LAB_SPLINE_ORDER - 1);
    if (m <= 0)
        return s->lo[k];
    if (m >= nb - 1)
        return s->hi[k];
    return s->lo[k] + m * (s->hi[k] - s->lo[k]) / (nb - 1);
}

/* The cross term's coefficients of output j start here (after its own). */
static int cross_at(const lab_spline *s) { return coef_per_input(s->nbreak); }

/* The ORDER nonzero basis functions of input k at x, from coefficient
 * *start, by the Cox-de Boor recursion (The NURBS Book, A2.2): no
 * workspace, nothing allocated (the evaluation runs per reading).  x is
 * within the field (in_field, the fit's rows), else NaN-free nonsense: the
 * callers check; a NaN x is refused. */
static int basis_at(const lab_spline *s, int k, int nb, double x, double b[LAB_SPLINE_ORDER],
                    int *start)
{
    if (isnan(x))
        return SUNMC_EDOM;
    int i = (int)((x - s->lo[k]) / (s->hi[k] - s->lo[k]) * (nb - 1));
    i = i > nb - 2 ? nb - 2 : i < 0 ? 0 : i;
    int span = i + LAB_SPLINE_ORDER - 1;
    double left[LAB_SPLINE_ORDER], right[LAB_SPLINE_ORDER];
    b[0] = 1.0;
    for (int j = 1; j < LAB_SPLINE_ORDER; j++) {
        left[j] = x - knot(s, k, nb, span + 1 - j);
        right[j] = knot(s, k, nb, span + j) - x;
        double saved = 0.0;
        for (int r = 0; r < j; r++) {
            double t = b[r] / (right[r + 1] + left[j - r]);
            b[r] = saved + right[r + 1] * t;
            saved = left[j - r] * t;
        }
        b[j] = saved;
    }
    *start = i;
    return SUNMC_OK;
}

/* Is x (dims inputs) inside s's field? */
static int in_field(const lab_spline *s, const double *x)
{
    int n_in = s->dims == 2 ? 2 : s->n_out;
    for (int k = 0; k < n_in; k++)
        if (!(x[k] >= s->lo[k] && x[k] <= s->hi[k]))
            return 0;
    if (s->dims != 2)
        return 1;
    int nc = s->nbreak - 1, c[2];
    for (int k = 0; k < 2; k++) {
        c[k] = (int)((x[k] - s->lo[k]) / (s->hi[k] - s->lo[k]) * nc);
        c[k] = c[k] >= nc ? nc - 1 : c[k];
    }
    return s->cell[c[0] * nc + c[1]];
}

/* dims 1: output j's row, its own input's basis and (cross) the other's
 * coarse one but its pinned first function; the nonzeros' count or -1. */
static int design_row1(const lab_spline *s, int j, const double *x, int *idx, double *val)
{
    double b0[LAB_SPLINE_ORDER], b1[LAB_SPLINE_ORDER];
    int s0, s1, m = 0;
    if (basis_at(s, j, s->nbreak, x[j], b0, &s0) != SUNMC_OK)
        return -1;
    for (int a = 0; a < LAB_SPLINE_ORDER; a++, m++) {
        idx[m] = s0 + a;
        val[m] = b0[a];
    }
    if (!s->cross)
        return m;
    if (basis_at(s, 1 - j, LAB_SPLINE_CROSS_BREAK, x[1 - j], b1, &s1) != SUNMC_OK)
        return -1;
    for (int a = 0; a < LAB_SPLINE_ORDER; a++)
        if (s1 + a > 0) {
            idx[m] = cross_at(s) + s1 + a - 1;
            val[m++] = b1[a];
        }
    return m;
}

/* The design row of output j (dims 1: its input, and the cross term;
 * dims 2: both): idx[], val[] of its nonzeros; their count, or -1 outside. */
static int design_row(const lab_spline *s, int j, const double *x, int *idx,
                      double *val)
{
    double b0[LAB_SPLINE_ORDER], b1[LAB_SPLINE_ORDER];
    int s0, s1;
    if (s->dims == 1)
        return design_row1(s, j, x, idx, val);
    if (basis_at(s, 0, s->nbreak, x[0], b0, &s0) != SUNMC_OK ||
        basis_at(s, 1, s->nbreak, x[1], b1, &s1) != SUNMC_OK)
        return -1;
    int p1 = coef_per_input(s->nbreak), m = 0;
    for (int a = 0; a < LAB_SPLINE_ORDER; a++)
        for (int b = 0; b < LAB_SPLINE_ORDER; b++, m++) {
            idx[m] = (s0 + a) * p1 + s1 + b;
            val[m] = b0[a] * b1[b];
        }
    return m;
}

int lab_spline_eval(const lab_spline *s, const double *x, double *y)
{
    for (int j = 0; j < s->n_out; j++)
        y[j] = NAN;
    if (!in_field(s, x))
        return SUNMC_EDOM;
    int idx[LAB_SPLINE_ORDER * LAB_SPLINE_ORDER], st = SUNMC_OK;
    double val[LAB_SPLINE_ORDER * LAB_SPLINE_ORDER];
    for (int j = 0; j < s->n_out && st == SUNMC_OK; j++) {
        int m = design_row(s, j, x, idx, val);
        if (m < 0) {
            st = SUNMC_EDOM;
            break;
        }
        double v = 0;
        for (int t = 0; t < m; t++)
            v += val[t] * s->coef[j][idx[t]];
        y[j] = v;
    }
    if (st != SUNMC_OK)
        for (int j = 0; j < s->n_out; j++)
            y[j] = NAN;
    return st;
}

/* ---- fit ---- */

static int row_used(const lab_spline_data *d, size_t i)
{
    if (!(d->w ? d->w[i] > 0 : 1))
        return 0;
    int n_in = d->dims == 2 ? 2 : d->n_out;
    for (int k = 0; k < n_in; k++)
        if (!isfinite(d->x[k][i]))
            return 0;
    for (int j = 0; j < d->n_out; j++)
        if (!isfinite(d->y[j][i]))
            return 0;
    return 1;
}

/* The field (ranges, cells) and the knots of the used rows; their count. */
static long set_field(lab_spline *s, const lab_spline_data *d)
{
    int n_in = d->dims == 2 ? 2 : d->n_out;
    long used = 0;
    for (int k = 0; k < n_in; k++) {
        s->lo[k] = INFINITY;
        s->hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < d->n; i++)
        if (row_used(d, i)) {
            used++;
            for (int k = 0; k < n_in; k++) {
                s->lo[k] = fmin(s->lo[k], d->x[k][i]);
                s->hi[k] = fmax(s->hi[k], d->x[k][i]);
            }
        }
    int maxb = d->dims == 2 ? LAB_SPLINE_MAX_BREAK2 : LAB_SPLINE_MAX_BREAK1;
    double per = (double)used / LAB_SPLINE_ROWS_PER_COEF;
    int nb = (int)(d->dims == 2 ? sqrt(per) : per) - (LAB_SPLINE_ORDER - 2);
    s->nbreak = nb > maxb ? maxb : nb < LAB_SPLINE_MIN_BREAK ? LAB_SPLINE_MIN_BREAK : nb;
    int p1 = coef_per_input(s->nbreak);
    s->n_coef = d->dims == 2 ? p1 * p1 : p1 + (s->cross ? LAB_SPLINE_CROSS_COEF : 0);
    memset(s->cell, 0, sizeof s->cell);
    if (d->dims == 2 && used > 0 && s->hi[0] > s->lo[0] && s->hi[1] > s->lo[1]) {
        int nc = s->nbreak - 1;
        for (size_t i = 0; i < d->n; i++)
            if (row_used(d, i)) {
                int c[2];
                for (int k = 0; k < 2; k++) {
                    c[k] = (int)((d->x[k][i] - s->lo[k]) / (s->hi[k] - s->lo[k]) * nc);
                    c[k] = c[k] >= nc ? nc - 1 : c[k];
                }
                s->cell[c[0] * nc + c[1]] = 1;
            }
    }
    return used;
}

/* Second divided differences of neighbouring coefficients at their
 * Greville abscissae g (the clamped end knots space them unevenly), scaled
 * by the knot spacing squared: {1, -2, 1} inside, and exactly zero for
 * coefficients of a straight line, whose spline is that line. */
static void second_difference(const double g[3], double h, double d2[3])
{
    double a = g[1] - g[0], b = g[2] - g[1];
    d2[0] = 2.0 * h * h / (a * (a + b));
    d2[1] = -2.0 * h * h / (a * b);
    d2[2] = 2.0 * h * h / (b * (a + b));
}

/* P = sum over the inputs of D^T D (p x p). */
/* Greville abscissa of coefficient j of input k: the mean of its
 * ORDER - 1 inner knots. */
static double greville(const lab_spline *s, int k, int nb, int j)
{
    double g = 0;
    for (int t = 1; t < LAB_SPLINE_ORDER; t++)
        g += knot(s, k, nb, j + t);
    return g / (LAB_SPLINE_ORDER - 1);
}

/* The cross term's second differences (dims 1): its coefficients from
 * cross_at, the pinned first one left out (the differences that would
 * take it are not penalised), on input k's coarse knots. */
static void penalty_cross(const lab_spline *s, int k, gsl_matrix *P)
{
    int pc = LAB_SPLINE_CROSS_COEF + 1, at0 = cross_at(s) - 1;
    double h = (s->hi[k] - s->lo[k]) / (LAB_SPLINE_CROSS_BREAK - 1);
    for (int r = 1; r + 2 < pc; r++) {
        double g[3], d2[3];
        for (int t = 0; t < 3; t++)
            g[t] = greville(s, k, LAB_SPLINE_CROSS_BREAK, r + t);
        second_difference(g, h, d2);
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                *gsl_matrix_ptr(P, (size_t)(at0 + r + a), (size_t)(at0 + r + b)) += d2[a] * d2[b];
    }
}

static void penalty(const lab_spline *s, gsl_matrix *P)
{
    gsl_matrix_set_zero(P);
    int p1 = coef_per_input(s->nbreak), nd = s->dims == 2 ? 2 : 1;
    for (int dir = 0; dir < nd; dir++) {
        double h = (s->hi[dir] - s->lo[dir]) / (s->nbreak - 1);
        for (int r = 0; r + 2 < p1; r++) {
            double g[3], d2[3];
            for (int t = 0; t < 3; t++)
                g[t] = greville(s, dir, s->nbreak, r + t);
            second_difference(g, h, d2);
            for (int o = 0; o < (nd == 2 ? p1 : 1); o++) {
                int at[3];
                for (int t = 0; t < 3; t++)
                    at[t] = nd == 1 ? r + t : dir == 0 ? (r + t) * p1 + o : o * p1 + r + t;
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++)
                        *gsl_matrix_ptr(P, (size_t)at[a], (size_t)at[b]) += d2[a] * d2[b];
            }
        }
    }
    if (s->cross)
        penalty_cross(s, 0, P);
}

typedef struct {
    gsl_matrix *A, *P, *M;
    gsl_vector *r[LAB_SPLINE_MAX_OUT], *c;
    gsl_matrix_view av, pv, mv;
    gsl_vector_view rv[LAB_SPLINE_MAX_OUT], cv;
} fit_ws;

struct lab_spline_ws {
    size_t n;                                /* rows it takes */
    double *a, *p, *m;                       /* LAB_SPLINE_MAX_COEF^2 each */
    double *r[LAB_SPLINE_MAX_OUT], *c;       /* LAB_SPLINE_MAX_COEF each */
    double *wk;                              /* n + 1: the folds' weights */
};

lab_spline_ws *lab_spline_ws_alloc(size_t n)
{
    lab_spline_ws *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    size_t p = LAB_SPLINE_MAX_COEF;
    w->n = n;
    w->a = malloc(p * p * sizeof *w->a);
    w->p = malloc(p * p * sizeof *w->p);
    w->m = malloc(p * p * sizeof *w->m);
    w->c = malloc(p * sizeof *w->c);
    w->wk = malloc((n + 1) * sizeof *w->wk);
    int ok = w->a && w->p && w->m && w->c && w->wk;
    for (int j = 0; j < LAB_SPLINE_MAX_OUT; j++)
        ok &= (w->r[j] = malloc(p * sizeof *w->r[j])) != NULL;
    if (!ok) {
        lab_spline_ws_free(w);
        return NULL;
    }
    return w;
}

void lab_spline_ws_free(lab_spline_ws *w)
{
    if (!w)
        return;
    free(w->a);
    free(w->p);
    free(w->m);
    free(w->c);
    free(w->wk);
    for (int j = 0; j < LAB_SPLINE_MAX_OUT; j++)
        free(w->r[j]);
    free(w);
}

double lab_spline_ws_bytes(size_t n)
{
    return sizeof(double) * (3.0 * LAB_SPLINE_MAX_COEF * LAB_SPLINE_MAX_COEF +
                             (LAB_SPLINE_MAX_OUT + 1.0) * LAB_SPLINE_MAX_COEF + (double)n + 1.0);
}

double *lab_spline_ws_weights(lab_spline_ws *w, size_t n)
{
    return n <= w->n ? w->wk : NULL;
}

/* The system of p coefficients on w's buffers. */
static void fit_ws_views(fit_ws *f, lab_spline_ws *w, size_t p)
{
    f->av = gsl_matrix_view_array(w->a, p, p);
    f->pv = gsl_matrix_view_array(w->p, p, p);
    f->mv = gsl_matrix_view_array(w->m, p, p);
    f->cv = gsl_vector_view_array(w->c, p);
    f->A = &f->av.matrix;
    f->P = &f->pv.matrix;
    f->M = &f->mv.matrix;
    f->c = &f->cv.vector;
    for (int j = 0; j < LAB_SPLINE_MAX_OUT; j++) {
        f->rv[j] = gsl_vector_view_array(w->r[j], p);
        f->r[j] = &f->rv[j].vector;
    }
}

/* X^T W X (of output j's rows; dims 2: any output) into A, X^T W y_j into r[j]. */
static int accumulate(const lab_spline *s, const lab_spline_data *d, int j, fit_ws *f)
{
    int idx[LAB_SPLINE_ORDER * LAB_SPLINE_ORDER];
    double val[LAB_SPLINE_ORDER * LAB_SPLINE_ORDER], x[2];
    int n_in = d->dims == 2 ? 2 : d->n_out;
    gsl_matrix_set_zero(f->A);
    for (int o = 0; o < d->n_out; o++)
        gsl_vector_set_zero(f->r[o]);
    for (size_t i = 0; i < d->n; i++) {
        if (!row_used(d, i))
            continue;
        for (int k = 0; k < n_in; k++)
            x[k] = d->x[k][i];
        int m = design_row(s, j, x, idx, val);
        if (m < 0)
            return SUNMC_EFIT;
        double w = d->w ? d->w[i] : 1.0;
        for (int a = 0; a < m; a++) {
            for (int b = 0; b < m; b++)
                *gsl_matrix_ptr(f->A, (size_t)idx[a], (size_t)idx[b]) += w * val[a] * val[b];
            for (int o = 0; o < d->n_out; o++)
                if (d->dims == 2 || o == j)
                    *gsl_vector_ptr(f->r[o], (size_t)idx[a]) += w * val[a] * d->y[o][i];
        }
    }
    return SUNMC_OK;
}

/* trace((A + lambda P)^-1 A) from the Cholesky factor in M. */
static int edf_of(fit_ws *f, double *edf)
{
    size_t p = f->A->size1;
    double t = 0;
    for (size_t q = 0; q < p; q++) {
        gsl_vector_const_view col = gsl_matrix_const_column(f->A, q);
        if (gsl_linalg_cholesky_solve(f->M, &col.vector, f->c) != GSL_SUCCESS)
            return SUNMC_EFIT;
        t += gsl_vector_get(f->c, q);
    }
    *edf = t;
    return SUNMC_OK;
}

/* Solve for the outputs of group j (dims 1: output j; dims 2: all). */
static int solve_group(lab_spline *s, const lab_spline_data *d, int j, fit_ws *f, int want_edf)
{
    int st = accumulate(s, d, j, f);
    double ta = 0, tp = 0;
    for (size_t q = 0; q < f->A->size1; q++) {
        ta += gsl_matrix_get(f->A, q, q);
        tp += gsl_matrix_get(f->P, q, q);
    }
    double lambda = s->smooth * ta / tp;
    if (st == SUNMC_OK && (gsl_matrix_memcpy(f->M, f->A) != GSL_SUCCESS ||
                           gsl_matrix_scale(f->P, lambda) != GSL_SUCCESS ||
                           gsl_matrix_add(f->M, f->P) != GSL_SUCCESS ||
                           gsl_matrix_scale(f->P, 1.0 / lambda) != GSL_SUCCESS))
        st = SUNMC_EFIT;
    if (st == SUNMC_OK && gsl_linalg_cholesky_decomp1(f->M) != GSL_SUCCESS)
        st = SUNMC_EFIT;
    for (int o = 0; o < d->n_out && st == SUNMC_OK; o++) {
        if (d->dims == 1 && o != j)
            continue;
        if (gsl_linalg_cholesky_solve(f->M, f->r[o], f->c) != GSL_SUCCESS)
            st = SUNMC_EFIT;
        for (int q = 0; q < s->n_coef && st == SUNMC_OK; q++)
            if (!isfinite(s->coef[o][q] = gsl_vector_get(f->c, (size_t)q)))
                st = SUNMC_EFIT;
    }
    double edf = NAN;
    if (st == SUNMC_OK && want_edf)
        st = edf_of(f, &edf);
    for (int o = 0; o < d->n_out; o++)
        if (d->dims == 2 || o == j)
            s->edf[o] = edf;
    return st;
}

static int check_data(const lab_spline_data *d, char *err, size_t errlen)
{
    if (d->dims < 1 || d->dims > 2 || d->n_out < 1 || d->n_out > LAB_SPLINE_MAX_OUT ||
        (d->dims == 1 && d->n_out > 2) || (d->cross && (d->dims != 1 || d->n_out != 2)))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "spline: %d inputs and %d outputs%s: 1 or 2 inputs, 1 or 2 outputs "
                          "(the cross term: 1 input per output, 2 outputs)",
                          d->dims, d->n_out, d->cross ? " with the cross term" : "");
    return SUNMC_OK;
}

int lab_spline_fit_ws(lab_spline *s, const lab_spline_data *d, double smooth, int want_edf,
                      lab_spline_ws *w, char *err, size_t errlen)
{
    int st = check_data(d, err, errlen);
    if (st != SUNMC_OK)
        return st;
    memset(s, 0, sizeof *s);
    s->dims = d->dims;
    s->n_out = d->n_out;
    s->cross = d->cross;
    s->smooth = smooth;
    long used = set_field(s, d);
    int n_in = d->dims == 2 ? 2 : d->n_out;
    for (int k = 0; k < n_in; k++)
        if (!(s->hi[k] > s->lo[k]))
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "spline: input %d does not vary over the %ld rows used: nothing "
                              "to fit a curve to", k + 1, used);
    if (used < (long)(d->dims == 2 ? 3 : 2) * LAB_SPLINE_MIN_BREAK)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "spline: %ld rows used: too few", used);
    fit_ws f;
    fit_ws_views(&f, w, (size_t)s->n_coef);
    penalty(s, f.P);
    int groups = d->dims == 2 ? 1 : d->n_out;
    for (int j = 0; j < groups && st == SUNMC_OK; j++)
        st = solve_group(s, d, j, &f, want_edf);
    if (st != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_EFIT,
                          "spline: the penalised normal equations are singular (%ld rows, %d "
                          "coefficients)", used, s->n_coef);
    return SUNMC_OK;
}

int lab_spline_fit(lab_spline *s, const lab_spline_data *d, double smooth, int want_edf,
                   char *err, size_t errlen)
{
    lab_spline_ws *w = lab_spline_ws_alloc(d->n);
    if (!w)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "spline: out of memory");
    int st = lab_spline_fit_ws(s, d, smooth, want_edf, w, err, errlen);
    lab_spline_ws_free(w);
    return st;
}

/* ---- the smoothing by cross-validation ---- */

static double grid_smooth(int k) { return pow(10.0, LAB_SPLINE_LOG_SMOOTH_MIN + 0.5 * k); }

/* Pooled held-out sum of squares of smoothing grid value k over the folds. */
static int score_smooth(const lab_spline_data *d, const int *fold, int n_folds, lab_spline_ws *w,
                        double smooth, double *sum2, long *cnt, long *outside)
{
    lab_spline_data dk = *d;
    dk.w = w->wk;
    char e[SUNMC_ERRLEN];
    *sum2 = 0;
    *cnt = *outside = 0;
    int n_in = d->dims == 2 ? 2 : d->n_out;
    for (int f = 0; f < n_folds; f++) {
        for (size_t i = 0; i < d->n; i++)
            w->wk[i] = fold[i] == f ? 0.0 : (d->w ? d->w[i] : 1.0);
        lab_spline s;
        if (lab_spline_fit_ws(&s, &dk, smooth, 0, w, e, sizeof e) != SUNMC_OK)
            continue;
        for (size_t i = 0; i < d->n; i++) {
            if (fold[i] != f || !row_used(d, i))
                continue;
            double x[2], y[LAB_SPLINE_MAX_OUT];
            for (int k = 0; k < n_in; k++)
                x[k] = d->x[k][i];
            if (lab_spline_eval(&s, x, y) != SUNMC_OK) {
                (*outside)++;
                continue;
            }
            for (int j = 0; j < d->n_out; j++)
                *sum2 += (y[j] - d->y[j][i]) * (y[j] - d->y[j][i]);
            (*cnt)++;
        }
    }
    return SUNMC_OK;
}

int lab_spline_choose_ws(lab_spline *s, const lab_spline_data *d, const int *fold, int n_folds,
                         lab_spline_ws *w, double *cv_rms, long *n_outside, char *err,
                         size_t errlen)
{
    if (d->n > w->n)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "spline: %zu rows, the workspace takes %zu",
                          d->n, w->n);
    int best = LAB_SPLINE_N_SMOOTH / 2;
    double best_rms = NAN;
    *n_outside = 0;
    for (int k = 0; k < LAB_SPLINE_N_SMOOTH && n_folds >= 2; k++) {
        double sum2;
        long cnt, out;
        score_smooth(d, fold, n_folds, w, grid_smooth(k), &sum2, &cnt, &out);
        double rms = cnt ? sqrt(sum2 / (double)(cnt * d->n_out)) : NAN;
        if (isfinite(rms) && !(rms >= best_rms)) {
            best_rms = rms;
            best = k;
            *n_outside = out;
        }
    }
    *cv_rms = best_rms;
    return lab_spline_fit_ws(s, d, grid_smooth(best), 1, w, err, errlen);
}

int lab_spline_choose(lab_spline *s, const lab_spline_data *d, const int *fold, int n_folds,
                      double *cv_rms, long *n_outside, char *err, size_t errlen)
{
    lab_spline_ws *w = lab_spline_ws_alloc(d->n);
    if (!w)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "spline: out of memory");
    int st = lab_spline_choose_ws(s, d, fold, n_folds, w, cv_rms, n_outside, err, errlen);
    lab_spline_ws_free(w);
    return st;
}
