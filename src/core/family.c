/* family.c - grids and per-band RMS accumulation for the families. */
#include "family.h"
#include "status.h"

#include <math.h>
#include <string.h>
#include <time.h>

/* Slack so that a grid end hit exactly in decimal is not lost to rounding. */
#define GRID_EPS 1e-9

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

long grid_count(double lo, double hi, double step, double offset)
{
    double span = hi - (lo + offset);
    if (span < -GRID_EPS * step)
        return 0;
    return (long)floor(span / step + GRID_EPS) + 1;
}

void band_acc_reset(band_acc *b)
{
    memset(b, 0, sizeof *b);
}

static int in_band(const band_list *bands, int i, double abs_deg)
{
    if (bands->lo[i] == 0.0)
        return abs_deg <= bands->hi[i] + GRID_EPS;
    return abs_deg > bands->lo[i] + GRID_EPS && abs_deg <= bands->hi[i] + GRID_EPS;
}

void band_acc_add(band_acc *b, const band_list *bands, double abs_deg, double err)
{
    for (int i = 0; i < bands->n; i++)
        if (in_band(bands, i, abs_deg)) {
            b->sum2[i] += err * err;
            b->n[i]++;
        }
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

void band_acc_rms(const band_acc *b, const band_list *bands, double scale, double *out)
{
    for (int i = 0; i < bands->n; i++)
        out[i] = b->n[i] ? scale * sqrt(b->sum2[i] / (double)b->n[i]) : NAN;
}

void band_max_add(double *max, const band_list *bands, double abs_deg, double v)
{
    for (int i = 0; i < bands->n; i++)
        if (in_band(bands, i, abs_deg))
            max[i] = fmax(max[i], v);
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

void unit_result_set_sys(unit_result *r, int angle, const band_acc *after_sys,
                         const band_list *bands, double scale)
{
    if (r->fit_status == UNIT_FIT_OK)
        band_acc_rms(after_sys, bands, scale, r->rms_after_sys[angle]);
    else
        for (int i = 0; i < bands->n; i++)
            r->rms_after_sys[angle][i] = NAN;
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
