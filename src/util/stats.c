/* stats.c - confidence intervals (Wilson, Clopper-Pearson, Student t,
 * order-statistic quantile, bootstrap percentile) and pick-freeze Sobol
 * indices.  See stats.h for the definitions. */
#include "stats.h"
#include "rng.h"
#include "status.h"

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_sort.h>
#include <math.h>
#include <stdlib.h>

static int check_confidence(double confidence, char *err, size_t errlen)
{
    if (!(confidence > 0.0 && confidence < 1.0))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "confidence %g is outside (0, 1) (0.95 for a 95%% interval)", confidence);
    return SUNMC_OK;
}

static void nan_interval(stats_interval *ci)
{
    ci->lo = ci->hi = NAN;
}

double stats_z(double confidence)
{
    return gsl_cdf_ugaussian_Pinv(0.5 + 0.5 * confidence);
}

/* Wilson bounds for x of n (n > 0). */
static stats_interval wilson_bounds(long x, long trials, double confidence)
{
    double n = (double)trials, p = (double)x / n, z = stats_z(confidence);
    double z2n = z * z / n;
    double centre = (p + 0.5 * z2n) / (1.0 + z2n);
    double half = z / (1.0 + z2n) * sqrt(p * (1.0 - p) / n + 0.25 * z2n / n);
    /* At p = 0 or 1 one bound is exactly 0 or 1; keep it so despite rounding. */
    stats_interval ci = {x == 0 ? 0.0 : fmax(0.0, centre - half),
                         x == trials ? 1.0 : fmin(1.0, centre + half)};
    return ci;
}

/* Beta(a, b) quantile by bisection on the CDF: gsl_cdf_beta_Pinv reports
 * "failed to converge" for ordinary arguments (and through the default
 * handler aborts), so the monotone CDF is inverted here instead. */
static double beta_quantile(double prob, double a, double b)
{
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 200; it++) {
        double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi)
            break;
        if (gsl_cdf_beta_P(mid, a, b) < prob)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* Clopper-Pearson bounds for x of n (n > 0). */
static stats_interval clopper_pearson_bounds(long successes, long trials, double confidence)
{
    double alpha = 1.0 - confidence, x = (double)successes, n = (double)trials;
    stats_interval ci = {
        successes == 0 ? 0.0 : beta_quantile(0.5 * alpha, x, n - x + 1.0),
        successes == trials ? 1.0 : beta_quantile(1.0 - 0.5 * alpha, x + 1.0, n - x)};
    return ci;
}

/* Checks shared by the proportion intervals; no trials gives NaN bounds. */
static int proportion_interval(long successes, long trials, double confidence,
                               stats_interval (*bounds)(long, long, double), stats_interval *ci,
                               char *err, size_t errlen)
{
    int st = check_confidence(confidence, err, errlen);
    if (st != SUNMC_OK)
        return st;
    if (trials < 0 || successes < 0 || successes > trials)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "proportion %ld of %ld: need 0 <= successes <= trials", successes, trials);
    if (trials == 0)
        nan_interval(ci);
    else
        *ci = bounds(successes, trials, confidence);
    return SUNMC_OK;
}

int stats_wilson(long successes, long trials, double confidence, stats_interval *ci, char *err,
                 size_t errlen)
{
    return proportion_interval(successes, trials, confidence, wilson_bounds, ci, err, errlen);
}

int stats_clopper_pearson(long successes, long trials, double confidence, stats_interval *ci,
                          char *err, size_t errlen)
{
    return proportion_interval(successes, trials, confidence, clopper_pearson_bounds, ci, err,
                               errlen);
}

int stats_t_interval(double mean, double sd, long n, double confidence, stats_interval *ci,
                     char *err, size_t errlen)
{
    int st = check_confidence(confidence, err, errlen);
    if (st != SUNMC_OK)
        return st;
    if (n < 0 || sd < 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "t interval: n = %ld and sd = %g must be >= 0",
                          n, sd);
    if (n < 2 || !isfinite(mean) || !isfinite(sd)) {
        nan_interval(ci);
        return SUNMC_OK;
    }
    double t = gsl_cdf_tdist_Pinv(0.5 + 0.5 * confidence, (double)(n - 1));
    double half = t * sd / sqrt((double)n);
    ci->lo = mean - half;
    ci->hi = mean + half;
    return SUNMC_OK;
}

int stats_mean_t(const double *x, size_t n, double confidence, double *mean, stats_interval *ci,
                 char *err, size_t errlen)
{
    if (n > 0 && x == NULL)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "t interval: no data for %zu values", n);
    /* Two passes: the mean, then the squared deviations (no cancellation). */
    double s = 0.0;
    for (size_t i = 0; i < n; i++)
        s += x[i];
    double m = n > 0 ? s / (double)n : NAN, ss = 0.0;
    for (size_t i = 0; i < n; i++)
        ss += (x[i] - m) * (x[i] - m);
    double sd = n > 1 ? sqrt(ss / (double)(n - 1)) : 0.0;
    *mean = m;
    return stats_t_interval(m, sd, (long)n, confidence, ci, err, errlen);
}

void stats_moments_add(stats_moments *m, double x)
{
    m->n++;
    m->sum += x;
    double d = x - m->mean;
    m->mean += d / (double)m->n;
    m->m2 += d * (x - m->mean);
}

int stats_moments_t(const stats_moments *m, double confidence, double *mean, stats_interval *ci,
                    char *err, size_t errlen)
{
    *mean = m->n > 0 ? m->sum / (double)m->n : NAN;
    double sd = m->n > 1 ? sqrt(fmax(m->m2, 0.0) / (double)(m->n - 1)) : 0.0;
    return stats_t_interval(*mean, sd, m->n, confidence, ci, err, errlen);
}

int stats_ratio_t(const double *x, const double *a, size_t n, double confidence, double *ratio,
                  stats_interval *ci, char *err, size_t errlen)
{
    if (n > 0 && (x == NULL || a == NULL))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "ratio interval: no data for %zu values", n);
    double sx = 0.0, sa = 0.0;
    for (size_t i = 0; i < n; i++) {
        sx += x[i];
        sa += a[i];
    }
    double r = n > 0 && sa != 0.0 ? sx / sa : NAN, ss = 0.0;
    for (size_t i = 0; i < n && isfinite(r); i++) {
        double z = x[i] - r * a[i];
        ss += z * z;
    }
    double abar = n > 0 ? sa / (double)n : NAN;
    double sd = n > 1 && isfinite(r) ? sqrt(ss / (double)(n - 1)) / fabs(abar) : 0.0;
    *ratio = r;
    return stats_t_interval(r, sd, (long)n, confidence, ci, err, errlen);
}

void stats_ratio_acc_add(stats_ratio_acc *r, double x, double a)
{
    r->n++;
    r->sx += x;
    r->sa += a;
    r->sxx += x * x;
    r->sxa += x * a;
    r->saa += a * a;
}

int stats_ratio_acc_t(const stats_ratio_acc *r, double confidence, double *ratio,
                      stats_interval *ci, char *err, size_t errlen)
{
    double R = r->n > 0 && r->sa != 0.0 ? r->sx / r->sa : NAN;
    double ss = isfinite(R) ? fmax(r->sxx - 2.0 * R * r->sxa + R * R * r->saa, 0.0) : 0.0;
    double abar = r->n > 0 ? r->sa / (double)r->n : NAN;
    double sd = r->n > 1 && isfinite(R) ? sqrt(ss / (double)(r->n - 1)) / fabs(abar) : 0.0;
    *ratio = R;
    return stats_t_interval(R, sd, r->n, confidence, ci, err, errlen);
}

double stats_quantile_sorted(const double *sorted, size_t n, double p)
{
    if (n == 0)
        return NAN;
    double h = (double)(n - 1) * p;
    size_t i = (size_t)floor(h);
    if (i + 1 >= n)
        return sorted[n - 1];
    double frac = h - (double)i;
    /* GSL's arithmetic, so the value is the same to the last bit. */
    return (1.0 - frac) * sorted[i] + frac * sorted[i + 1];
}

/* P(K <= k) for K ~ Binomial(n, p); k < 0 gives 0. */
static double binom_cdf(long k, double p, size_t n)
{
    return k < 0 ? 0.0 : gsl_cdf_binomial_P((unsigned)k, p, (unsigned)n);
}

/* Largest rank l in 1..n with P(K <= l - 1) <= tail, or 0 if none
 * (binary search: the CDF is monotone in l). */
static size_t lower_rank(size_t n, double p, double tail)
{
    if (binom_cdf(0, p, n) > tail)
        return 0;
    size_t lo = 1, hi = n; /* invariant: cdf(lo - 1) <= tail */
    while (lo < hi) {
        size_t mid = lo + (hi - lo + 1) / 2;
        if (binom_cdf((long)mid - 1, p, n) <= tail)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* Smallest rank u in 1..n with P(K <= u - 1) >= 1 - tail, or 0 if none. */
static size_t upper_rank(size_t n, double p, double tail)
{
    if (binom_cdf((long)n - 1, p, n) < 1.0 - tail)
        return 0;
    size_t lo = 1, hi = n; /* invariant: cdf(hi - 1) >= 1 - tail */
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (binom_cdf((long)mid - 1, p, n) >= 1.0 - tail)
            hi = mid;
        else
            lo = mid + 1;
    }
    return hi;
}

int stats_quantile_ci(const double *sorted, size_t n, double p, double confidence,
                      stats_interval *ci, size_t *rank_lo, size_t *rank_hi, char *err,
                      size_t errlen)
{
    int st = check_confidence(confidence, err, errlen);
    if (st != SUNMC_OK)
        return st;
    if (!(p > 0.0 && p < 1.0))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "quantile level %g is outside (0, 1)", p);
    if (n > 0 && sorted == NULL)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "quantile interval: no data for %zu values",
                          n);
    double tail = 0.5 * (1.0 - confidence);
    size_t l = n > 0 ? lower_rank(n, p, tail) : 0, u = n > 0 ? upper_rank(n, p, tail) : 0;
    ci->lo = l > 0 ? sorted[l - 1] : NAN;
    ci->hi = u > 0 ? sorted[u - 1] : NAN;
    if (rank_lo)
        *rank_lo = l;
    if (rank_hi)
        *rank_hi = u;
    return SUNMC_OK;
}

/* Percentile interval of one statistic's replicates (NaNs dropped; sorts). */
static stats_interval percentile_interval(double *rep, size_t n_boot, double confidence)
{
    size_t m = 0;
    for (size_t b = 0; b < n_boot; b++)
        if (!isnan(rep[b]))
            rep[m++] = rep[b];
    gsl_sort(rep, 1, m);
    double tail = 0.5 * (1.0 - confidence);
    stats_interval ci = {stats_quantile_sorted(rep, m, tail),
                         stats_quantile_sorted(rep, m, 1.0 - tail)};
    return ci;
}

int stats_bootstrap(size_t n, size_t k, stats_resample_fn fn, void *ctx, size_t n_boot,
                    uint64_t seed, double confidence, stats_interval *ci, char *err,
                    size_t errlen)
{
    int st = check_confidence(confidence, err, errlen);
    if (st != SUNMC_OK)
        return st;
    if (n == 0 || k == 0 || n_boot < 2 || fn == NULL)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "bootstrap: need rows (%zu), statistics (%zu) and >= 2 resamples (%zu)",
                          n, k, n_boot);
    size_t *idx = malloc(n * sizeof *idx);
    double *rep = malloc(n_boot * k * sizeof *rep); /* statistic j's replicates contiguous */
    double *out = malloc(k * sizeof *out);
    if (!idx || !rep || !out) {
        free(idx);
        free(rep);
        free(out);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "bootstrap: out of memory (%zu x %zu)",
                          n_boot, k);
    }
    st = SUNMC_OK;
    for (size_t b = 0; b < n_boot && st == SUNMC_OK; b++) {
        rng_stream r;
        rng_stream_init(&r, seed, (uint64_t)b, STATS_STREAM_BOOTSTRAP);
        for (size_t i = 0; i < n; i++) {
            size_t j = (size_t)(rng_uniform(&r) * (double)n);
            idx[i] = j < n ? j : n - 1;
        }
        if (fn(idx, n, ctx, out) != 0)
            st = sunmc_fail(err, errlen, SUNMC_EDOM, "bootstrap: statistic failed on resample %zu",
                            b);
        for (size_t j = 0; j < k; j++)
            rep[j * n_boot + b] = out[j];
    }
    for (size_t j = 0; j < k && st == SUNMC_OK; j++)
        ci[j] = percentile_interval(rep + j * n_boot, n_boot, confidence);
    free(idx);
    free(rep);
    free(out);
    return st;
}

typedef struct {
    const double *fA, *fB, *fAB;
    size_t n, d;
} sobol_data;

/* S1 and ST of every input over rows idx[0..m-1]: out[2i] = S1_i,
 * out[2i + 1] = ST_i. */
static int sobol_estimate(const size_t *idx, size_t m, void *ctx, double *out)
{
    const sobol_data *s = ctx;
    double sum = 0.0, ss = 0.0;
    for (size_t j = 0; j < m; j++)
        sum += s->fA[idx[j]] + s->fB[idx[j]];
    double mean = sum / (double)(2 * m);
    for (size_t j = 0; j < m; j++) {
        double a = s->fA[idx[j]] - mean, b = s->fB[idx[j]] - mean;
        ss += a * a + b * b;
    }
    double var = ss / (double)(2 * m);
    for (size_t i = 0; i < s->d; i++) {
        const double *fab = s->fAB + i * s->n;
        double v1 = 0.0, vt = 0.0;
        for (size_t j = 0; j < m; j++) {
            size_t r = idx[j];
            double diff = fab[r] - s->fA[r];
            v1 += (s->fB[r] - mean) * diff; /* centred: see stats.h */
            vt += diff * diff;
        }
        out[2 * i] = var > 0 ? v1 / (double)m / var : NAN;
        out[2 * i + 1] = var > 0 ? 0.5 * vt / (double)m / var : NAN;
    }
    return 0;
}

int stats_sobol(const double *fA, const double *fB, const double *fAB, size_t n, size_t d,
                size_t n_boot, uint64_t seed, double confidence, stats_sobol_index *out,
                char *err, size_t errlen)
{
    if (n < 2 || d == 0 || !fA || !fB || !fAB || !out)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "Sobol indices: need >= 2 rows (%zu) and >= 1 input (%zu)", n, d);
    sobol_data s = {fA, fB, fAB, n, d};
    size_t *idx = malloc(n * sizeof *idx);
    double *est = malloc(2 * d * sizeof *est);
    stats_interval *ci = malloc(2 * d * sizeof *ci);
    int st = SUNMC_OK;
    if (!idx || !est || !ci)
        st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "Sobol indices: out of memory (%zu inputs)", d);
    if (st == SUNMC_OK) {
        for (size_t j = 0; j < n; j++)
            idx[j] = j;
        sobol_estimate(idx, n, &s, est);
        st = stats_bootstrap(n, 2 * d, sobol_estimate, &s, n_boot, seed, confidence, ci, err,
                             errlen);
    }
    for (size_t i = 0; i < d && st == SUNMC_OK; i++) {
        out[i] = (stats_sobol_index){est[2 * i], ci[2 * i].lo, ci[2 * i].hi,
                                     est[2 * i + 1], ci[2 * i + 1].lo, ci[2 * i + 1].hi};
    }
    free(idx);
    free(est);
    free(ci);
    return st;
}

double stats_median_inplace(double *v, size_t n)
{
    gsl_sort(v, 1, n);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
