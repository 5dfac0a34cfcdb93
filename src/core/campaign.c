/* campaign.c - a campaign's turntable time and the table angles it covers. */
#include "campaign.h"
#include "family.h"
#include "status.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SECONDS_PER_HOUR 3600.0
/* A validation angle this close to the campaign's span is inside it. */
#define CAMPAIGN_SPAN_EPS_DEG 1e-9

void campaign_cost(const sunmc_config *c, const double *a0, const double *a1, long n,
                   double to_deg, campaign_info *out)
{
    memset(out, 0, sizeof *out);
    out->known = 1;
    out->points = n;
    out->readings = n * c->cal_repeats;
    for (int k = 0; k < CAMPAIGN_AXES; k++) {
        out->cal_lo[k] = out->val_lo[k] = n > 0 ? INFINITY : NAN;
        out->cal_hi[k] = out->val_hi[k] = n > 0 ? -INFINITY : NAN;
    }
    double move_s = 0;
    for (long i = 0; i < n; i++) {
        double p[CAMPAIGN_AXES] = {a0[i] * to_deg, a1[i] * to_deg};
        for (int k = 0; k < CAMPAIGN_AXES; k++) {
            out->cal_lo[k] = fmin(out->cal_lo[k], p[k]);
            out->cal_hi[k] = fmax(out->cal_hi[k], p[k]);
        }
        if (i == 0 || a1[i] != a1[i - 1])
            out->lines++;
        if (i > 0) {
            double travel = fmax(fabs(p[0] - a0[i - 1] * to_deg), fabs(p[1] - a1[i - 1] * to_deg));
            out->slew_deg += travel;
        }
    }
    move_s = out->slew_deg / c->slew_deg_per_s;
    double settle_s = (double)out->lines * c->line_settle_s +
                      (double)(out->points - out->lines) * c->point_settle_s;
    double read_s = (double)out->readings * c->dwell_s;
    out->hours = (move_s + settle_s + read_s) / SECONDS_PER_HOUR;
}

/* The family's grid `which` into freshly allocated arrays (*a0, *a1). */
static int grid_alloc(const sunmc_config *c, int which, double **a0, double **a1, long *n)
{
    const sensor_family *fam = c->family;
    *n = fam->grid->points(c, which, NULL, NULL, 0);
    size_t len = (size_t)(*n > 0 ? *n : 1);
    *a0 = malloc(len * sizeof **a0);
    *a1 = malloc(len * sizeof **a1);
    if (!*a0 || !*a1) {
        free(*a0);
        free(*a1);
        return SUNMC_ENOMEM;
    }
    fam->grid->points(c, which, *a0, *a1, *n);
    return SUNMC_OK;
}

int campaign_describe(const sunmc_config *c, campaign_info *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (!c->family || !c->family->grid)
        return SUNMC_OK;
    double *a0, *a1;
    long n;
    if (grid_alloc(c, FAMILY_GRID_CAMPAIGN, &a0, &a1, &n) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the campaign grid");
    campaign_cost(c, a0, a1, n, 1.0, out);
    free(a0);
    free(a1);
    if (grid_alloc(c, FAMILY_GRID_VALIDATION, &a0, &a1, &n) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the validation grid");
    for (long i = 0; i < n; i++) {
        const double p[CAMPAIGN_AXES] = {a0[i], a1[i]};
        for (int k = 0; k < CAMPAIGN_AXES; k++) {
            out->val_lo[k] = i ? fmin(out->val_lo[k], p[k]) : p[k];
            out->val_hi[k] = i ? fmax(out->val_hi[k], p[k]) : p[k];
        }
    }
    free(a0);
    free(a1);
    for (int k = 0; k < CAMPAIGN_AXES && n > 0 && out->points > 0; k++) {
        double d = fmax(out->cal_lo[k] - out->val_lo[k], out->val_hi[k] - out->cal_hi[k]);
        out->outside_deg[k] = d > CAMPAIGN_SPAN_EPS_DEG ? d : 0.0;
        out->extrapolation_deg = fmax(out->extrapolation_deg, out->outside_deg[k]);
    }
    return SUNMC_OK;
}

void campaign_extrapolation_text(const campaign_info *ci, const char *const *axis_names,
                                 char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < CAMPAIGN_AXES && ci->known; k++) {
        if (!(ci->outside_deg[k] > 0) || used >= len)
            continue;
        used += (size_t)snprintf(buf + used, len - used,
                                 "%svalidation %s reaches %g..%g deg, beyond the campaign's "
                                 "%g..%g deg (extrapolated by up to %g deg)",
                                 used ? "; " : "", axis_names[k], ci->val_lo[k], ci->val_hi[k],
                                 ci->cal_lo[k], ci->cal_hi[k], ci->outside_deg[k]);
    }
}
