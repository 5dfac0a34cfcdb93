/* stats.h - confidence intervals for Monte Carlo estimates and Sobol
 * sensitivity indices.  Every function is deterministic: the bootstrap draws
 * from Philox streams keyed by a caller-given seed, replicate b on its own
 * counter, so results do not depend on threads or order.
 *
 * Conventions: `confidence` is the two-sided coverage, 0 < confidence < 1
 * (0.95 for a 95 % interval).  Invalid arguments (confidence outside (0, 1),
 * negative counts, successes > trials, NULL data with n > 0) return
 * SUNMC_EINPUT with a message naming the argument.  Too little data for an
 * interval (a t interval of one value, a quantile interval whose ranks fall
 * outside 1..n) is not an error: the bound that cannot be had is NaN.
 */
#ifndef SUNMC_STATS_H
#define SUNMC_STATS_H

#include <stddef.h>
#include <stdint.h>

/* Stream id of bootstrap replicates (replicate b draws from unit b of this
 * stream under the bootstrap seed; unit streams use other ids, see rng.h). */
#define STATS_STREAM_BOOTSTRAP 0x300u

typedef struct {
    double lo, hi;
} stats_interval;

/* Two-sided standard normal quantile z with P(|Z| <= z) = confidence. */
double stats_z(double confidence);

/* Wilson score interval for a proportion successes/trials: the p whose
 * score statistic |phat - p| / sqrt(p (1 - p) / n) is at most z.
 *
 * Why Wilson and not Clopper-Pearson: the "exact" Clopper-Pearson interval
 * guarantees at least the nominal coverage at every p and pays for it by
 * being conservative (at 200 units and a nominal 95 % its coverage is
 * 96-98 % for p between 0.5 and 0.99, the interval correspondingly wider).
 * Wilson's coverage oscillates around the nominal value (94.4 % at p = 0.5,
 * 95.6 % at 0.9, 94.4 % at 0.97 for 200 units; exact binomial sums), it is
 * never outside [0, 1], and unlike the textbook Wald interval it stays
 * sensible when the yield is near 100 % (all units pass: [n/(n+z^2), 1],
 * not the degenerate [1, 1]).  Brown, Cai & DasGupta (Stat. Sci. 16, 2001)
 * and Agresti & Coull (Am. Stat. 52, 1998) recommend it on these grounds.
 * Its known weakness is a dip very close to p = 1: with 200 units the
 * coverage falls to about 85 % at p = 0.9992 (one failing unit puts the
 * upper bound just below p; above 89 % for p <= 0.999); with 1000 units it
 * stays above 92 % up to p = 0.999.
 * Clopper-Pearson is provided for callers who need the guarantee.
 * trials == 0 gives NaN bounds. */
int stats_wilson(long successes, long trials, double confidence, stats_interval *ci, char *err,
                 size_t errlen);

/* Clopper-Pearson ("exact") interval from beta quantiles:
 * lo = Beta^-1(alpha/2; x, n-x+1), hi = Beta^-1(1-alpha/2; x+1, n-x), with
 * lo = 0 at x = 0 and hi = 1 at x = n. */
int stats_clopper_pearson(long successes, long trials, double confidence, stats_interval *ci,
                          char *err, size_t errlen);

/* Student-t interval of a mean from its sample moments:
 * mean +- t_{(1+confidence)/2, n-1} * sd / sqrt(n), sd the sample standard
 * deviation (n - 1 divisor).  n < 2 gives NaN bounds. */
int stats_t_interval(double mean, double sd, long n, double confidence, stats_interval *ci,
                     char *err, size_t errlen);

/* The same from data x[n]: *mean gets the sample mean (NaN for n = 0). */
int stats_mean_t(const double *x, size_t n, double confidence, double *mean, stats_interval *ci,
                 char *err, size_t errlen);

/* Running moments of a stream of values, for a mean and its t interval
 * without holding the values: the sum in arrival order (so the mean is
 * bit for bit stats_mean_t's sum / n) and Welford's sum of squared
 * deviations (no cancellation: as accurate as the two-pass formula to a
 * few units in the last place).  Zero-initialise, then add. */
typedef struct {
    long n;
    double sum;   /* sum of the values, in arrival order */
    double mean;  /* Welford's running mean (for m2 only) */
    double m2;    /* sum of squared deviations from the running mean */
} stats_moments;

void stats_moments_add(stats_moments *m, double x);

/* stats_t_interval of the moments: *mean = sum / n (NaN for n = 0), sd from
 * m2 with the n - 1 divisor. */
int stats_moments_t(const stats_moments *m, double confidence, double *mean, stats_interval *ci,
                    char *err, size_t errlen);

/* Ratio of two means R = mean(x) / mean(a) over n paired values (x_i, a_i
 * from the same unit: common random numbers), with the delta-method
 * Student-t interval R +- t_{n-1} sd(z) / (sqrt(n) mean(a)), where
 * z_i = x_i - R a_i (the linearised ratio; its variance carries the pairing,
 * so a difference x_i = y_i - w_i of two correlated runs gets the tight
 * interval of the paired differences).  mean(a) == 0 or n == 0 gives NaN;
 * n < 2 NaN bounds. */
int stats_ratio_t(const double *x, const double *a, size_t n, double confidence, double *ratio,
                  stats_interval *ci, char *err, size_t errlen);

/* stats_ratio_t of a stream of pairs, without holding them: sums of x, a
 * and their squares and products (the residual sum of squares
 * sum (x - R a)^2 expanded, clamped at 0).  Zero-initialise, then add. */
typedef struct {
    long n;
    double sx, sa, sxx, sxa, saa;
} stats_ratio_acc;

void stats_ratio_acc_add(stats_ratio_acc *r, double x, double a);

int stats_ratio_acc_t(const stats_ratio_acc *r, double confidence, double *ratio,
                      stats_interval *ci, char *err, size_t errlen);

/* Point estimate of the p-quantile of sorted[n] (ascending): Hyndman & Fan
 * (1996) definition 7, the linear interpolation between order statistics at
 * h = (n - 1) p (0-based), as R's default and numpy's "linear"; bit for bit
 * gsl_stats_quantile_from_sorted_data.  NaN for n = 0. */
double stats_quantile_sorted(const double *sorted, size_t n, double p);
/* The median of v[0..n-1] (n > 0), v sorted in place. */
double stats_median_inplace(double *v, size_t n);

/* Distribution-free confidence interval for the population p-quantile
 * x_p = F^-1(p) from order statistics of sorted[n] (ascending; any
 * continuous F).  With K = #{X_i <= x_p} ~ Binomial(n, p),
 * P(X_(l) <= x_p <= X_(u)) = P(l <= K <= u - 1); the ranks are
 * l = max{l : P(K <= l - 1) <= alpha/2} and
 * u = min{u : P(K <= u - 1) >= 1 - alpha/2}, alpha = 1 - confidence, so
 * each tail holds at most alpha/2 and the coverage is at least `confidence`.
 * A rank outside 1..n (too few units: for p = 0.95 at 95 % the upper
 * bound needs 0.95^n <= 0.025, n >= 72) leaves that bound NaN.  The
 * interval is for x_p itself and so does not depend on the point
 * estimate's definition.  Ranks (1-based, 0 when
 * unavailable) are stored in *rank_lo, *rank_hi when those are non-NULL. */
int stats_quantile_ci(const double *sorted, size_t n, double p, double confidence,
                      stats_interval *ci, size_t *rank_lo, size_t *rank_hi, char *err,
                      size_t errlen);

/* A statistic for the bootstrap: evaluate k values on the resample whose
 * members are the rows idx[0..n-1] of the caller's data (rows may repeat),
 * writing out[0..k-1].  Return 0, or nonzero to abort the bootstrap. */
typedef int (*stats_resample_fn)(const size_t *idx, size_t n, void *ctx, double *out);

/* Bootstrap percentile intervals of k statistics of n rows: n_boot resamples
 * of n rows with replacement (replicate b draws from Philox stream
 * (seed, b, STATS_STREAM_BOOTSTRAP)), ci[j] the alpha/2 and 1 - alpha/2
 * empirical quantiles (definition 7) of replicate j's values.  Replicates
 * whose statistic is NaN are dropped per statistic; none left gives NaN.
 * Returns SUNMC_ENOMEM, SUNMC_EINPUT (n == 0, n_boot < 2, k < 1) or the
 * callback's failure as SUNMC_EDOM. */
int stats_bootstrap(size_t n, size_t k, stats_resample_fn fn, void *ctx, size_t n_boot,
                    uint64_t seed, double confidence, stats_interval *ci, char *err,
                    size_t errlen);

/* Sobol indices of input i of a model Y = f(X_1..X_d) with independent
 * inputs, by pick-freeze: A and B are two independent samples of n input
 * rows, A_B^i is A with column i taken from B.  Given fA[n], fB[n] and
 * fAB[i * n + j] = f(row j of A_B^i):
 *   V   = variance of the 2n values fA, fB (divisor 2n)
 *   S1_i = (1/n) sum_j (fB_j - f0) (fAB_ij - fA_j) / V (Saltelli et al. 2010)
 *   ST_i = (1/2n) sum_j (fA_j - fAB_ij)^2 / V         (Jansen 1999)
 * with f0 the mean of the 2n values.  Centring fB by f0 leaves the estimator
 * unbiased (E[fAB - fA] = 0) but removes a term of variance f0^2 Var(fAB -
 * fA) / n: uncentred, an output whose mean is large against its spread (a
 * sensor's RMS) gives S1 intervals many times wider than the index (a
 * single-input model: [-17, 23] for 40 rows against [0.9, 1.1] centred).
 * With bootstrap percentile intervals over the n rows (n_boot resamples,
 * fixed seed).  Estimates are not clipped to [0, 1]: a small negative S1 is
 * the estimator's noise and its interval says so.  V == 0 gives NaN. */
typedef struct {
    double s1, s1_lo, s1_hi;
    double st, st_lo, st_hi;
} stats_sobol_index;

int stats_sobol(const double *fA, const double *fB, const double *fAB, size_t n, size_t d,
                size_t n_boot, uint64_t seed, double confidence, stats_sobol_index *out,
                char *err, size_t errlen);

#endif
