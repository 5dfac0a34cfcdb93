/* bands.h - the angle grids and the report bands (report.bands_deg) a
 * family scores its units in: per-band sums of squared errors, their RMS,
 * and the check that every band holds points of the validation grid. */
#ifndef SUNMC_BANDS_H
#define SUNMC_BANDS_H

#include "config.h"
#include "vmath.h"

#include <stddef.h>

/* Sum of squared errors per report band, for one unit and one angle. */
typedef struct {
    double sum2[CONFIG_BANDS_MAX];
    long n[CONFIG_BANDS_MAX];
} band_acc;

void band_acc_reset(band_acc *b);

/* Slack so that a band or grid end hit exactly in decimal is not lost to
 * rounding. */
#define BAND_EPS 1e-9

/* 1 when band i holds abs_deg: (lo, hi], the first band from 0 [0, hi]. */
static inline int band_holds(const band_list *bands, int i, double abs_deg)
{
    return (abs_deg <= bands->hi[i] + BAND_EPS) &
           ((bands->lo[i] == 0.0) | (abs_deg > bands->lo[i] + BAND_EPS));
}

/* The bands holding abs_deg as bits (bit i: band i), for a reading whose
 * errors go to several accumulators (band_acc_add_mask). */
static inline unsigned band_mask(const band_list *bands, double abs_deg)
{
    unsigned m = 0;
    for (int i = 0; i < bands->n; i++)
        m |= (unsigned)band_holds(bands, i, abs_deg) << i;
    return m;
}

/* band_acc_add to the bands of mask m (band_mask) of a list of n bands. */
static inline void band_acc_add_mask(band_acc *b, int n, unsigned m, double err)
{
    double e2 = err * err;
    for (int i = 0; i < n; i++) {
        int in = (int)((m >> i) & 1u);
        b->sum2[i] += vm_keep(in, e2);
        b->n[i] += in;
    }
}

/* Add error err at |angle| = abs_deg to every band that holds abs_deg,
 * without a branch (a reading's bands are as unpredictable as its angle):
 * the other bands add +0 (vm_keep, so a NaN error there adds nothing),
 * which leaves their sums' bits as they were.  Inline: called for every
 * validation reading. */
static inline void band_acc_add(band_acc *b, const band_list *bands, double abs_deg, double err)
{
    double e2 = err * err;
    for (int i = 0; i < bands->n; i++) {
        int in = band_holds(bands, i, abs_deg);
        b->sum2[i] += vm_keep(in, e2);
        b->n[i] += in;
    }
}

/* band_acc_add_mask for readings q < k at once: squared error e2[q] to the
 * bands of mask m[q] (0: to none), in reading order, so the sums have the
 * bits k calls of band_acc_add_mask give; the sums stay in registers
 * (three bands, the shipped lists, unrolled), not in memory. */
void band_acc_add_chunk(band_acc *b, int nb, size_t k, const unsigned *m, const double *e2);

/* The same for na accumulators at once (acc[j] takes masks m[j] and
 * squared errors e2[j], j < na): the same bits; for two or three
 * accumulators of three bands their chains of adds interleaved. */
void band_acc_add_chunks(int na, band_acc *const acc[], int nb, size_t k,
                         const unsigned *const m[], const double *const e2[]);

/* The largest squared errors per band, for an order statistic of |error|
 * (the spec's p99.7 or max, verdict.h): keep of them (at most
 * BAND_TAIL_MAX) in descending order; keep 0 keeps none (an RMS spec). */
#define BAND_TAIL_MAX 64
typedef struct {
    double top[CONFIG_BANDS_MAX][BAND_TAIL_MAX];
    int keep;
} band_tail;
void band_tail_reset(band_tail *t, int keep);
/* Squared error e2 into the bands of mask m (band_mask) of nb bands. */
static inline void band_tail_add_mask(band_tail *t, int nb, unsigned m, double e2)
{
    if (t->keep == 0 || !(e2 == e2))
        return;
    for (int i = 0; i < nb; i++) {
        double *top = t->top[i];
        if (!((m >> i) & 1u) || !(e2 > top[t->keep - 1]))
            continue;
        int j = t->keep - 1;
        for (; j > 0 && top[j - 1] < e2; j--)
            top[j] = top[j - 1];
        top[j] = e2;
    }
}
/* band_tail_add_mask for readings q < k (mask m[q], squared error e2[q]). */
void band_tail_add_chunk(band_tail *t, int nb, size_t k, const unsigned *m, const double *e2);
/* The nearest-rank quantile at level (0, 1] of |error| over n points of
 * band i: the (n - ceil(level n) + 1)-th largest, sqrt of the kept squared
 * error; NaN when n is 0 or the rank lies past the kept ones. */
double band_tail_quantile(const band_tail *t, int i, long n, double level);
/* Count each reading q < k in the bands of its mask m[q] into n[]. */
void band_count_chunk(long *n, int nb, size_t k, const unsigned *m);

/* RMS per band times scale into out[bands->n]; NaN for an empty band. */
void band_acc_rms(const band_acc *b, const band_list *bands, double scale, double *out);
/* max[i] = fmax(max[i], v) for every band i that holds abs_deg. */
void band_max_add(double *max, const band_list *bands, double abs_deg, double v);

/* Every report band must lie in the field of view (lo < fov_deg) and hold
 * at least one point of the validation grid: acc holds the count per band
 * of the grid's |angle| values (band_acc_add with any error), max_abs_deg
 * the largest of them.  SUNMC_EINPUT otherwise, naming report.bands_deg, the
 * band, fov_key and the grid's keys (grid_keys), since a band without a
 * point would give a row of NaN and a yield of 0 for every unit. */
int band_check_coverage(const band_list *bands, const band_acc *acc, double max_abs_deg,
                        double fov_deg, const char *fov_key, const char *angle,
                        const char *grid_keys, char *err, size_t errlen);

/* Count of alpha grid points from lo to hi in steps (with offset from lo). */
long grid_count(double lo, double hi, double step, double offset);

/* The points of that grid (deg, as the keys give them): v[j] = lo +
 * offset + j step for the first max of them (none when max <= 0);
 * returns grid_count's count, which may exceed max.  For the axes of
 * `sunmc curve` (family_curve.axis). */
long grid_values(double lo, double hi, double step, double offset, double *v, long max);

/* A key's list of angles (deg) into v, the first max of them; returns the
 * list's count, which may exceed max (family_curve.axis). */
long list_values(const double_list *l, double *v, long max);

#endif
