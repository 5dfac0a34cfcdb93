/* stats_blocks.c - a mean's interval from independent blocks (stats_blocks.h). */
#include "stats_blocks.h"
#include "status.h"

#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdlib.h>

void stats_blocks_init(stats_blocks *b)
{
    *b = (stats_blocks){0};
    b->cur = -1;
}

static void close_block(stats_blocks *b)
{
    if (b->cur < 0 || b->cn == 0)
        return;
    b->blocks++;
    b->n += b->cn;
    b->s += b->cs;
    b->ss += b->cs * b->cs;
    b->sn += b->cs * b->cn;
    b->nn += b->cn * b->cn;
    b->cn = b->cs = 0;
}

void stats_blocks_add(stats_blocks *b, long block, double x)
{
    if (b->cur < 0 && b->n == 0 && b->cn == 0)
        b->ref = x;
    if (block != b->cur) {
        close_block(b);
        b->cur = block;
    }
    b->cn += 1;
    b->cs += x - b->ref;
}

double stats_blocks_variance(const stats_blocks *b, long *blocks)
{
    stats_blocks t = *b;
    close_block(&t);
    *blocks = t.blocks;
    if (t.blocks < 2 || t.n <= 0)
        return NAN;
    double r = t.s / t.n; /* the shifted mean */
    double sum = t.ss - 2.0 * r * t.sn + r * r * t.nn;
    return (double)t.blocks / (double)(t.blocks - 1) * fmax(sum, 0.0) / (t.n * t.n);
}

int stats_blocks_t(const stats_blocks *b, double mean, double confidence, stats_interval *ci,
                   char *err, size_t errlen)
{
    ci->lo = ci->hi = NAN;
    if (!(confidence > 0.0 && confidence < 1.0))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "confidence %g is outside (0, 1)",
                          confidence);
    long nb;
    double v = stats_blocks_variance(b, &nb);
    if (isnan(v) || isnan(mean))
        return SUNMC_OK;
    double h = gsl_cdf_tdist_Pinv(0.5 * (1.0 + confidence), (double)(nb - 1)) * sqrt(v);
    ci->lo = mean - h;
    ci->hi = mean + h;
    return SUNMC_OK;
}

int stats_blocks_quantile_ci(const double *sorted, const double *block_of, size_t n, double p,
                             double confidence, stats_interval *ci, char *err, size_t errlen)
{
    ci->lo = ci->hi = NAN;
    if (n < 2 || !(confidence > 0.0 && confidence < 1.0))
        return SUNMC_OK;
    double q = stats_quantile_sorted(sorted, n, p), bmin = block_of[0], bmax = block_of[0];
    for (size_t i = 1; i < n; i++) {
        bmin = fmin(bmin, block_of[i]);
        bmax = fmax(bmax, block_of[i]);
    }
    size_t nb = (size_t)(bmax - bmin) + 1;
    long *cnt = calloc(2 * nb, sizeof *cnt);
    if (!cnt)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "quantile interval: no memory for %zu blocks",
                          nb);
    size_t below = 0;
    for (size_t i = 0; i < n; i++) {
        size_t b = (size_t)(block_of[i] - bmin);
        cnt[2 * b]++;
        cnt[2 * b + 1] += sorted[i] <= q;
        below += sorted[i] <= q;
    }
    stats_blocks acc;
    stats_blocks_init(&acc);
    for (size_t b = 0; b < nb; b++)
        for (long k = 0; k < cnt[2 * b]; k++)
            stats_blocks_add(&acc, (long)b, k < cnt[2 * b + 1] ? 1.0 : 0.0);
    free(cnt);
    long blocks;
    double f = (double)below / (double)n, v = stats_blocks_variance(&acc, &blocks);
    if (isnan(v))
        return SUNMC_OK;
    v = fmax(v, f * (1.0 - f) / (double)n);
    double h = gsl_cdf_tdist_Pinv(0.5 * (1.0 + confidence), (double)(blocks - 1)) * sqrt(v);
    ci->lo = stats_quantile_sorted(sorted, n, fmax(p - h, 0.0));
    ci->hi = stats_quantile_sorted(sorted, n, fmin(p + h, 1.0));
    return SUNMC_OK;
}

double stats_blocks_deff(const stats_blocks *b, double share, long n)
{
    long blocks;
    double v = stats_blocks_variance(b, &blocks);
    double iid = share * (1.0 - share) / (double)n;
    if (isnan(v) || !(iid > 0))
        return 1.0;
    return v / iid;
}

int stats_blocks_ratio_t(const double *x, const double *a, const long *block, size_t n,
                         double confidence, double *ratio, stats_interval *ci, char *err,
                         size_t errlen)
{
    int rc = stats_ratio_t(x, a, n, confidence, ratio, ci, err, errlen);
    if (rc != SUNMC_OK || !block)
        return rc;
    ci->lo = ci->hi = NAN;
    double sa = 0.0, zz = 0.0, z = 0.0;
    long blocks = 0;
    for (size_t i = 0; i < n; i++) {
        sa += a[i];
        z += x[i] - *ratio * a[i];
        if (i + 1 == n || block[i + 1] != block[i]) {
            zz += z * z;
            z = 0.0;
            blocks++;
        }
    }
    if (blocks < 2 || !isfinite(*ratio) || sa == 0.0)
        return SUNMC_OK;
    double v = (double)blocks / (double)(blocks - 1) * zz / (sa * sa);
    double h = gsl_cdf_tdist_Pinv(0.5 * (1.0 + confidence), (double)(blocks - 1)) * sqrt(v);
    ci->lo = *ratio - h;
    ci->hi = *ratio + h;
    return SUNMC_OK;
}
