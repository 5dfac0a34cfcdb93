/* stats_blocks.h - the interval of a mean over units that come in
 * independent blocks (a randomised sampling design, sampling.h): within a
 * block the units are not independent, across blocks they are, so the
 * variance of the mean comes from the block totals.
 *
 * With block b holding n_b values of total S_b, the mean is
 * R = sum S_b / sum n_b (a ratio estimator: blocks may differ in size, the
 * last of a run being partial) and its variance
 *   v = B / (B - 1) * sum_b (S_b - R n_b)^2 / (sum n_b)^2,
 * B the number of blocks (Cochran, Sampling Techniques, 3rd ed., 6.9 and
 * 11.8: cluster sampling with a ratio estimate); the interval is
 * R +- t_{(1+confidence)/2, B-1} sqrt(v).  Values are added in block order
 * (nondecreasing block ids, as units arrive in unit order); the sums are
 * kept of values minus the first value (the formula does not change under
 * a shift; the sums then do not cancel).
 */
#ifndef SUNMC_STATS_BLOCKS_H
#define SUNMC_STATS_BLOCKS_H

#include "stats.h"

typedef struct {
    long blocks;       /* blocks closed */
    long cur;          /* id of the block being filled; -1 before the first value */
    double ref;        /* the first value (the shift) */
    double cn, cs;     /* the open block's count and shifted total */
    double n, s, ss, sn, nn; /* sums over closed blocks: n_b, S_b, S_b^2, S_b n_b, n_b^2 */
} stats_blocks;

/* A fresh accumulator (cur = -1). */
void stats_blocks_init(stats_blocks *b);

/* Value x of a unit of block `block` (>= the previous call's). */
void stats_blocks_add(stats_blocks *b, long block, double x);

/* The mean's variance v above (closing the open block in a copy), and the
 * number of blocks B in *blocks; NaN when B < 2. */
double stats_blocks_variance(const stats_blocks *b, long *blocks);

/* The interval of the mean `mean` (the caller's point estimate) with the
 * block variance: mean +- t_{B-1} sqrt(v); NaN bounds when B < 2. */
int stats_blocks_t(const stats_blocks *b, double mean, double confidence, stats_interval *ci,
                   char *err, size_t errlen);

/* The interval of the p-quantile of sorted[n] (ascending) whose values
 * came from blocks block_of[n] (the block id of each sorted value, as
 * doubles: gsl_sort2's companion) by Woodruff's method (J. Am. Stat. Assoc.
 * 47, 1952): the share F = #{x <= q} / n at the estimate q gets the block
 * variance v above (floored at F (1 - F) / n, never narrower than for
 * independent units), and the interval is the quantiles at
 * p -+ t_{B-1} sqrt(v), clipped to [0, 1].  NaN bounds when B < 2.
 * Returns SUNMC_ENOMEM or SUNMC_OK. */
int stats_blocks_quantile_ci(const double *sorted, const double *block_of, size_t n, double p,
                             double confidence, stats_interval *ci, char *err, size_t errlen);

/* stats_ratio_t's ratio R = sum x / sum a of n paired values, its interval
 * from blocks: block[i] the block of pair i (nondecreasing), the variance
 * B / (B - 1) sum_b (X_b - R A_b)^2 / (sum a)^2 over the block totals,
 * t_{B-1}; NaN bounds when B < 2.  block NULL: stats_ratio_t itself. */
int stats_blocks_ratio_t(const double *x, const double *a, const long *block, size_t n,
                         double confidence, double *ratio, stats_interval *ci, char *err,
                         size_t errlen);

/* The design effect of a share (the mean of 0/1 values in b, n of them,
 * share their mean): the block variance over the independent units'
 * share (1 - share) / n; 1 when the share is 0 or 1 or there are fewer
 * than 2 blocks. */
double stats_blocks_deff(const stats_blocks *b, double share, long n);

#endif
