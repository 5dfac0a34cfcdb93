/* psd_labconv.c - does the lab's data fit markedly better under another
 * table convention?  A table whose alpha turns the other way, axes
 * recorded crossed (the board's X channel pair on the table's beta), or
 * another order of the two axes gives data that no calibration of the
 * configured convention fits well; the physical model, which knows which
 * way the spot moves, tells them apart where an empirical model (a
 * spline is as happy mirrored) cannot.  (psd_lab.h) */
#include "psd_lab.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rows the check fits at most (every k-th row of the data). */
#define PSD_CONV_MAX_ROWS 1500
/* "Markedly better": an in-sample RMS this many times smaller. */
#define PSD_CONV_BETTER 1.5
/* A convention under which more than this fraction of rows cannot be
 * compensated does not describe the data. */
#define PSD_CONV_MAX_UNREAD 0.1

typedef struct {
    int order, a_minus, b_minus, swap;
} psd_conv;

static const char *const order_name[] = {"projected", "alpha_outer", "beta_outer"};

/* A subsample of d (weight > 0 rows, every stride-th), its arrays in *buf. */
static int subsample(const lab_columns *d, const double *w, lab_columns *s, double **buf)
{
    size_t used = 0;
    for (size_t i = 0; i < d->n; i++)
        used += w[i] > 0;
    size_t stride = used / PSD_CONV_MAX_ROWS + 1, m = used / stride + 1;
    *buf = malloc((7 * m + 1) * sizeof **buf + (m + 1) * sizeof(int));
    if (!*buf)
        return SUNMC_ENOMEM;
    memset(s, 0, sizeof *s);
    s->path = d->path;
    s->n_cols = 7;
    for (int k = 0; k < 7; k++)
        s->v[k] = *buf + (size_t)k * m;
    s->line = (int *)(void *)(*buf + 7 * m);
    size_t j = 0, seen = 0;
    for (size_t i = 0; i < d->n && j < m; i++) {
        if (!(w[i] > 0) || seen++ % stride)
            continue;
        for (int k = 0; k < 6; k++)
            s->v[k][j] = d->v[k][i];
        s->v[6][j] = w[i];
        s->line[j++] = d->line[i];
    }
    s->n = j;
    return SUNMC_OK;
}

/* The physical model's in-sample RMS of the total angle (arcsec) on s
 * under convention v; +inf when it fails or leaves rows unread. */
static double try_convention(const sunmc_config *c0, const lab_columns *s, psd_conv v)
{
    sunmc_config *c = malloc(sizeof *c);
    if (!c)
        return NAN;
    *c = *c0;
    psd_config *p = (psd_config *)(void *)c->fam.bytes;
    p->cal_model = PSD_MODEL_PHYSICAL;
    p->table_order = v.order;
    p->table_alpha_sign = v.a_minus;
    p->table_beta_sign = v.b_minus;
    lab_columns d = *s;
    if (v.swap) {
        d.v[0] = s->v[1];
        d.v[1] = s->v[0];
    }
    char err[SUNMC_ERRLEN];
    psd_labcal *k = psd_labcal_alloc(c, &d, err, sizeof err);
    double rms = INFINITY;
    fit_result fr;
    if (k && psd_labcal_fit(k, &fr) == SUNMC_OK) {
        size_t bad = psd_labcal_errors(k), n = 0;
        double ss = 0;
        for (size_t i = 0; i < d.n; i++)
            if (isfinite(k->err[3 * i + 2]))
                ss += k->err[3 * i + 2] * k->err[3 * i + 2], n++;
        if (n > 0 && (double)bad <= PSD_CONV_MAX_UNREAD * (double)d.n)
            rms = sqrt(ss / (double)n) * ARCSEC_PER_RAD;
    }
    psd_labcal_free(k);
    free(c);
    return rms;
}

static void describe(const psd_conv *v, char *buf, size_t len)
{
    snprintf(buf, len, "table_order = %s, table_alpha_sign = %s, table_beta_sign = %s%s",
             order_name[v->order], v->a_minus ? "minus" : "plus", v->b_minus ? "minus" : "plus",
             v->swap ? ", with the alpha_deg and beta_deg columns swapped (the axes recorded "
                       "crossed)"
                     : "");
}

int psd_labcal_conventions(const psd_labcal *k, psd_conv_check *out)
{
    memset(out, 0, sizeof *out);
    const psd_config *p = psd_cfg(k->c);
    lab_columns s;
    double *buf;
    if (subsample(k->d, k->d->v[6], &s, &buf) != SUNMC_OK)
        return SUNMC_ENOMEM;
    psd_conv now = {p->table_order, p->table_alpha_sign, p->table_beta_sign, 0}, best = now;
    out->rms_configured_arcsec = try_convention(k->c, &s, now);
    out->rms_best_arcsec = out->rms_configured_arcsec;
    out->rows = (long)s.n;
    /* the configured order with every sign and the axes swapped, then the
     * other orders with the configured signs */
    for (int t = 0; t < 10; t++) {
        psd_conv v = now;
        if (t < 8) {
            v.a_minus = t & 1 ? !now.a_minus : now.a_minus;
            v.b_minus = t & 2 ? !now.b_minus : now.b_minus;
            v.swap = (t & 4) != 0;
            if (t == 0)
                continue;
        } else {
            v.order = (now.order + t - 7) % 3;
        }
        double r = try_convention(k->c, &s, v);
        out->tried++;
        if (r < out->rms_best_arcsec)
            out->rms_best_arcsec = r, best = v;
    }
    free(buf);
    out->better = out->rms_best_arcsec * PSD_CONV_BETTER < out->rms_configured_arcsec;
    describe(&best, out->best, sizeof out->best);
    describe(&now, out->configured, sizeof out->configured);
    return SUNMC_OK;
}
