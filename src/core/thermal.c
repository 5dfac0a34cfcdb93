/* thermal.c - the operating temperatures of a config (see thermal.h). */
#include "thermal.h"
#include "status.h"

#include <math.h>
#include <string.h>

int thermal_n_temps(const sunmc_config *c)
{
    const double_list *l = &c->op_temps_c;
    if (l->n == 0 || (l->n == 1 && l->v[0] == c->cal_temp_c))
        return 0;
    return l->n < CONFIG_TEMPS_MAX ? l->n : CONFIG_TEMPS_MAX;
}

double thermal_temp_c(const sunmc_config *c, int t)
{
    return c->op_temps_c.v[t];
}

int thermal_check(const sunmc_config *c, char *err, size_t errlen)
{
    if (c->op_temps_c.n > CONFIG_TEMPS_MAX)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "environment.operating_temp_c lists %d temperatures; at most %d",
                          c->op_temps_c.n, CONFIG_TEMPS_MAX);
    if (thermal_n_temps(c) > 0 && c->family && !c->family->thermal)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "environment.operating_temp_c: sensor family %s has no thermal model; "
                          "the operating temperature must be calibration_temp_c",
                          c->family->name);
    return SUNMC_OK;
}

double thermal_worst(const double v[][UNIT_MAX_ANGLES][CONFIG_BANDS_MAX], int n, int a, int b)
{
    double w = -INFINITY;
    for (int t = 0; t < n; t++) {
        if (isnan(v[t][a][b]))
            return NAN;
        w = fmax(w, v[t][a][b]);
    }
    return n > 0 ? w : NAN;
}

double unit_primary_before(const sunmc_config *c, const unit_result *r, int a, int b)
{
    int n = thermal_n_temps(c);
    return n > 0 ? thermal_worst(r->rms_before_t, n, a, b) : r->rms_before[a][b];
}

double unit_primary_after(const sunmc_config *c, const unit_result *r, int a, int b)
{
    int n = thermal_n_temps(c);
    return n > 0 ? thermal_worst(r->rms_after_t, n, a, b) : r->rms_after[a][b];
}

void unit_result_store_temp(unit_result *r, int t, const unit_result *at)
{
    memcpy(r->rms_before_t[t], at->rms_before, sizeof r->rms_before_t[t]);
    memcpy(r->rms_after_t[t], at->rms_after, sizeof r->rms_after_t[t]);
    memcpy(r->stat_after_t[t], at->stat_after, sizeof r->stat_after_t[t]);
    memcpy(r->read_after_t[t], at->read_after, sizeof r->read_after_t[t]);
}

void thermal_validate_all(const sunmc_config *c, unit_result *r, thermal_validate_fn validate_at,
                          void *ctx)
{
    int n = thermal_n_temps(c);
    for (int t = 0; t < n; t++) {
        double T = thermal_temp_c(c, t);
        if (T == c->cal_temp_c) {
            unit_result_store_temp(r, t, r);
            continue;
        }
        unit_result at;
        memset(&at, 0, sizeof at);
        at.fit_status = r->fit_status;
        validate_at(c, T, ctx, &at);
        unit_result_store_temp(r, t, &at);
    }
}

int thermal_n_reads(const sunmc_config *c)
{
    int n = 1;
    for (int t = 0; t < thermal_n_temps(c); t++)
        n += thermal_temp_c(c, t) != c->cal_temp_c;
    return n;
}

double thermal_read_temp_c(const sunmc_config *c, int k)
{
    for (int t = 0, j = 0; t < thermal_n_temps(c); t++)
        if (thermal_temp_c(c, t) != c->cal_temp_c && ++j == k)
            return thermal_temp_c(c, t);
    return c->cal_temp_c; /* read 0, or none: the lab's */
}
