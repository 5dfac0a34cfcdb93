/* unit_result.c - what every family's unit pipeline shares: its random
 * streams, filling a unit_result from its band accumulators, and the
 * phase clock of --profile (family.h). */
#include "family.h"
#include "verdict.h"
#include "status.h"
#include "thermal.h"

#include <math.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

uint64_t unit_stream_seed(const sunmc_config *c, uint64_t seed, uint32_t stream)
{
    for (int i = 0; i < c->pick.n; i++)
        if (c->pick.stream[i] == stream)
            return (uint64_t)c->pick.seed;
    return seed;
}

void unit_stream_init(rng_stream *r, const sunmc_config *c, long unit, uint32_t stream)
{
    rng_stream_init(r, unit_stream_seed(c, (uint64_t)c->seed, stream), (uint64_t)unit, stream);
}

void unit_result_set_rms(unit_result *r, int angle, const band_acc *before, const band_acc *after,
                         const band_list *bands, double scale)
{
    band_acc_rms(before, bands, scale, r->rms_before[angle]);
    if (r->fit_status == UNIT_FIT_OK)
        band_acc_rms(after, bands, scale, r->rms_after[angle]);
    else
        for (int i = 0; i < bands->n; i++)
            r->rms_after[angle][i] = NAN;
}

void unit_result_set_stat(unit_result *r, const sunmc_config *c, int angle, const band_acc *after,
                          const band_tail *tail, const long *points, double scale)
{
    int ok = r->fit_status == UNIT_FIT_OK, rms = c->spec_statistic == VERDICT_RMS;
    double level = verdict_level(c);
    for (int b = 0; b < c->bands_deg.n; b++) {
        r->points[b] = (int)points[b];
        r->read_after[angle][b] = ok ? (int)after->n[b] : 0;
        if (!ok || after->n[b] == 0)
            r->stat_after[angle][b] = NAN;
        else
            r->stat_after[angle][b] =
                rms ? r->rms_after[angle][b]
                    : band_tail_quantile(tail, b, after->n[b], level) * scale;
    }
}

void unit_result_set_sys(unit_result *r, int angle, const band_acc *after_sys,
                         const band_list *bands, double scale)
{
    if (r->fit_status == UNIT_FIT_OK && after_sys)
        band_acc_rms(after_sys, bands, scale, r->rms_after_sys[angle]);
    else
        for (int i = 0; i < bands->n; i++)
            r->rms_after_sys[angle][i] = NAN;
    for (int i = 0; i < CONFIG_BANDS_MAX; i++)
        r->rms_after_mf[angle][i] = NAN;
}

/* Set once by the command before any unit runs, only read afterwards. */
static int profile_on;

void unit_profile_enable(int on)
{
    profile_on = on;
}

double unit_clock(void)
{
    if (!profile_on)
        return 0.0;
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void unit_phase_end(unit_result *r, int phase, double *t)
{
    if (!profile_on)
        return;
    double now = unit_clock();
    r->phase_s[phase] += now - *t;
    *t = now;
}

static size_t unit_rd_block_bytes(size_t n, int n_arrays)
{
    size_t flags = (n * sizeof(int) + sizeof(double) - 1) / sizeof(double) * sizeof(double);
    return (size_t)n_arrays * n * sizeof(double) + flags;
}

size_t unit_rd_bytes(const sunmc_config *c, size_t n, int n_arrays)
{
    return (size_t)thermal_n_reads(c) * unit_rd_block_bytes(n, n_arrays);
}

double *unit_rd_block(const void *rd, size_t n, int n_arrays, int k)
{
    return (double *)(uintptr_t)rd + (size_t)k * (unit_rd_block_bytes(n, n_arrays) / sizeof(double));
}

int *unit_rd_flags(double *block, size_t n, int n_arrays)
{
    return (int *)(void *)(block + (size_t)n_arrays * n);
}

int unit_read_finish(const sunmc_config *c, long unit, void *ws, void *rd, int held,
                     unit_result *r)
{
    double t = unit_clock();
    int rs = held ? SUNMC_OK : c->family->unit_read(c, unit, ws, rd);
    double read_s = unit_clock() - t;
    if (rs == SUNMC_OK)
        rs = c->family->unit_finish(c, unit, ws, rd, r);
    r->phase_s[UNIT_PHASE_VALIDATION] += read_s;
    return rs;
}
