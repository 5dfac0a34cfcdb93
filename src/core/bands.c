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
