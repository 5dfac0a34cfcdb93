/* bands.c - the angle grids and the per-band RMS accumulation the
 * families score their units with (bands.h). */
#include "bands.h"
#include "status.h"

#include <math.h>
#include <string.h>

#define GRID_EPS BAND_EPS

long grid_count(double lo, double hi, double step, double offset)
{
    double span = hi - (lo + offset);
    if (span < -GRID_EPS * step)
        return 0;
    return (long)floor(span / step + GRID_EPS) + 1;
}

long grid_values(double lo, double hi, double step, double offset, double *v, long max)
{
    long n = grid_count(lo, hi, step, offset);
    for (long j = 0; j < n && j < max; j++)
        v[j] = lo + offset + (double)j * step;
    return n;
}

long list_values(const double_list *l, double *v, long max)
{
    for (long j = 0; j < l->n && j < max; j++)
        v[j] = l->v[j];
    return l->n;
}

void band_acc_reset(band_acc *b)
{
    memset(b, 0, sizeof *b);
}

int band_check_coverage(const band_list *bands, const band_acc *acc, double max_abs_deg,
                        double fov_deg, const char *fov_key, const char *angle,
                        const char *grid_keys, char *err, size_t errlen)
{
    for (int i = 0; i < bands->n; i++) {
        if (bands->lo[i] >= fov_deg)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "report.bands_deg: band %.10g:%.10g lies outside the field of view "
                              "+-%g deg (%s): no reading can fall in it",
                              bands->lo[i], bands->hi[i], fov_deg, fov_key);
        if (acc->n[i] == 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "report.bands_deg: band %.10g:%.10g holds no point of the validation "
                              "grid (%s; |%s| reaches %g deg): its statistics would be empty; "
                              "change the band or the grid",
                              bands->lo[i], bands->hi[i], grid_keys, angle, max_abs_deg);
    }
    return SUNMC_OK;
}

/* One accumulator's three band sums and counts, in registers. */
typedef struct {
    double s0, s1, s2;
    long n0, n1, n2;
} sums3;

static inline sums3 sums3_load(const band_acc *b)
{
    sums3 a = {b->sum2[0], b->sum2[1], b->sum2[2], 0, 0, 0};
    return a;
}

static inline sums3 sums3_add(sums3 a, unsigned mq, double e2)
{
    a.s0 += vm_keep((int)(mq & 1u), e2);
    a.s1 += vm_keep((int)((mq >> 1) & 1u), e2);
    a.s2 += vm_keep((int)((mq >> 2) & 1u), e2);
    a.n0 += mq & 1u;
    a.n1 += (mq >> 1) & 1u;
    a.n2 += (mq >> 2) & 1u;
    return a;
}

static inline void sums3_store(sums3 a, band_acc *b)
{
    b->sum2[0] = a.s0, b->sum2[1] = a.s1, b->sum2[2] = a.s2;
    b->n[0] += a.n0, b->n[1] += a.n1, b->n[2] += a.n2;
}

void band_acc_add_chunk(band_acc *b, int nb, size_t k, const unsigned *m, const double *e2)
{
    if (nb == 3) {
        sums3 a = sums3_load(b);
        for (size_t q = 0; q < k; q++)
            a = sums3_add(a, m[q], e2[q]);
        sums3_store(a, b);
        return;
    }
    for (int i = 0; i < nb; i++) {
        double s = b->sum2[i];
        long n = 0;
        for (size_t q = 0; q < k; q++) {
            unsigned in = (m[q] >> i) & 1u;
            s += vm_keep((int)in, e2[q]);
            n += in;
        }
        b->sum2[i] = s;
        b->n[i] += n;
    }
}

void band_acc_add_chunks(int na, band_acc *const acc[], int nb, size_t k,
                         const unsigned *const m[], const double *const e2[])
{
    if (nb != 3 || na < 2 || na > 3) {
        for (int j = 0; j < na; j++)
            band_acc_add_chunk(acc[j], nb, k, m[j], e2[j]);
        return;
    }
    sums3 a = sums3_load(acc[0]), b = sums3_load(acc[1]);
    const unsigned *ma = m[0], *mb = m[1];
    const double *ea = e2[0], *eb = e2[1];
    if (na == 2) {
        for (size_t q = 0; q < k; q++) {
            a = sums3_add(a, ma[q], ea[q]);
            b = sums3_add(b, mb[q], eb[q]);
        }
    } else {
        sums3 c = sums3_load(acc[2]);
        const unsigned *mc = m[2];
        const double *ec = e2[2];
        for (size_t q = 0; q < k; q++) {
            a = sums3_add(a, ma[q], ea[q]);
            b = sums3_add(b, mb[q], eb[q]);
            c = sums3_add(c, mc[q], ec[q]);
        }
        sums3_store(c, acc[2]);
    }
    sums3_store(a, acc[0]);
    sums3_store(b, acc[1]);
}

void band_acc_rms(const band_acc *b, const band_list *bands, double scale, double *out)
{
    for (int i = 0; i < bands->n; i++)
        out[i] = b->n[i] ? scale * sqrt(b->sum2[i] / (double)b->n[i]) : NAN;
}

void band_max_add(double *max, const band_list *bands, double abs_deg, double v)
{
    for (int i = 0; i < bands->n; i++)
        if (band_holds(bands, i, abs_deg))
            max[i] = fmax(max[i], v);
}

void band_tail_reset(band_tail *t, int keep)
{
    t->keep = keep < 0 ? 0 : keep > BAND_TAIL_MAX ? BAND_TAIL_MAX : keep;
    for (int i = 0; i < CONFIG_BANDS_MAX; i++)
        for (int j = 0; j < t->keep; j++)
            t->top[i][j] = -1.0;
}

void band_tail_add_chunk(band_tail *t, int nb, size_t k, const unsigned *m, const double *e2)
{
    if (t->keep == 0)
        return;
    for (size_t q = 0; q < k; q++)
        if (m[q])
            band_tail_add_mask(t, nb, m[q], e2[q]);
}

double band_tail_quantile(const band_tail *t, int i, long n, double level)
{
    if (n <= 0 || !(level > 0 && level <= 1))
        return NAN;
    /* nearest rank, ascending and 1-based: ceil(level n) (0.9973 n rounds
     * to no integer above itself for any n up to 30000: checked) */
    long rank = (long)ceil(level * (double)n);
    if (rank < 1)
        rank = 1;
    long k = n - rank + 1; /* the k-th largest */
    if (k > t->keep || t->top[i][k - 1] < 0)
        return NAN;
    return sqrt(t->top[i][k - 1]);
}

void band_count_chunk(long *n, int nb, size_t k, const unsigned *m)
{
    for (size_t q = 0; q < k; q++)
        for (int i = 0; i < nb; i++)
            n[i] += (long)((m[q] >> i) & 1u);
}
