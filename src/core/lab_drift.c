/* lab_drift.c - campaigns in one lab data file and how much they differ
 * (lab_drift.h). */
#include "lab_drift.h"
#include "stats.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PCT 100.0

static int row_used(const lab_drift_input *in, size_t i)
{
    if (in->weight && !(in->weight[i] > 0))
        return 0;
    return isfinite(in->error_rad[0][i * in->error_stride]) &&
           isfinite(in->error_rad[1][i * in->error_stride]);
}

static int campaign_of(const lab_drift_input *in, size_t i)
{
    int s = in->source ? in->source[i] : 0;
    return s < LAB_DRIFT_MAX_CAMPAIGNS ? s : LAB_DRIFT_MAX_CAMPAIGNS - 1;
}

/* Ranges, then the swept axis and the fixed angle's median. */
static void campaign_shape(const lab_drift_input *in, int s, lab_campaign *c, double *tmp)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < in->n; i++)
        if (campaign_of(in, i) == s && row_used(in, i))
            for (int a = 0; a < 2; a++) {
                lo[a] = fmin(lo[a], in->angle_deg[a][i]);
                hi[a] = fmax(hi[a], in->angle_deg[a][i]);
            }
    c->axis = hi[0] - lo[0] >= hi[1] - lo[1] ? 0 : 1;
    if (!(hi[c->axis] - lo[c->axis] > LAB_DRIFT_SAME_LINE_DEG))
        c->axis = -1;
    int a = c->axis < 0 ? 0 : c->axis, o = 1 - a;
    c->lo_deg = lo[a];
    c->hi_deg = hi[a];
    int k = 0;
    for (size_t i = 0; i < in->n; i++)
        if (campaign_of(in, i) == s && row_used(in, i))
            tmp[k++] = in->angle_deg[o][i];
    c->fixed_deg = k ? stats_median_inplace(tmp, (size_t)k) : NAN;
}

/* The least-squares line of the swept angle's error, and the RMS about it. */
static void campaign_line(const lab_drift_input *in, int s, lab_campaign *c)
{
    int a = c->axis < 0 ? 0 : c->axis;
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (size_t i = 0; i < in->n; i++)
        if (campaign_of(in, i) == s && row_used(in, i)) {
            double x = in->angle_deg[a][i] * RAD_PER_DEG;
            double y = in->error_rad[a][i * in->error_stride];
            sx += x, sy += y, sxx += x * x, sxy += x * y, n++;
        }
    c->n = (long)n;
    double det = n * sxx - sx * sx;
    double slope = c->axis >= 0 && det > 0 ? (n * sxy - sx * sy) / det : 0.0;
    double zero = n > 0 ? (sy - slope * sx) / n : NAN;
    double ss = 0;
    for (size_t i = 0; i < in->n; i++)
        if (campaign_of(in, i) == s && row_used(in, i)) {
            double r = in->error_rad[a][i * in->error_stride] -
                       (zero + slope * in->angle_deg[a][i] * RAD_PER_DEG);
            ss += r * r;
        }
    c->zero_arcsec = zero * ARCSEC_PER_RAD;
    c->scale_pct = slope * PCT;
    c->within_arcsec = n > 0 ? sqrt(ss / n) * ARCSEC_PER_RAD : NAN;
}

static int same_line(const lab_campaign *x, const lab_campaign *y)
{
    if (x->axis < 0 || x->axis != y->axis || !(fabs(x->fixed_deg - y->fixed_deg) <=
                                                LAB_DRIFT_SAME_LINE_DEG))
        return 0;
    double ov = fmin(x->hi_deg, y->hi_deg) - fmax(x->lo_deg, y->lo_deg);
    double span = fmin(x->hi_deg - x->lo_deg, y->hi_deg - y->lo_deg);
    return span > 0 && ov >= LAB_DRIFT_MIN_OVERLAP * span;
}

/* Bins of the swept angle a group's error profile is tabulated on. */
#define LAB_DRIFT_BINS 200

static int bin_of(const lab_campaign *g, double angle_deg)
{
    double span = g->hi_deg - g->lo_deg;
    int b = (int)floor((angle_deg - g->lo_deg) / span * LAB_DRIFT_BINS);
    return b < 0 ? -1 : b > LAB_DRIFT_BINS ? -1 : b == LAB_DRIFT_BINS ? b - 1 : b;
}

/* The group's error profile along its swept angle: per bin, the median over
 * its campaigns of each campaign's mean error there (NaN: fewer than two
 * campaigns read the bin).  A common error of the model cancels in the
 * difference from it; what is left is the campaign's own. */
static void group_profile(const lab_drift_input *in, const lab_drift *d, int grp,
                          const lab_campaign *range, double *profile, double *sum, double *cnt)
{
    int a = range->axis;
    double vals[LAB_DRIFT_MAX_CAMPAIGNS];
    for (int b = 0; b < LAB_DRIFT_BINS; b++)
        profile[b] = NAN;
    for (int s = 0, m = 0; s < d->n; s++) {
        if (d->c[s].group != grp)
            continue;
        double *su = sum + (size_t)m * LAB_DRIFT_BINS, *cn = cnt + (size_t)m * LAB_DRIFT_BINS;
        for (int b = 0; b < LAB_DRIFT_BINS; b++)
            su[b] = cn[b] = 0.0;
        for (size_t i = 0; i < in->n; i++) {
            int b = campaign_of(in, i) == s && row_used(in, i) ? bin_of(range, in->angle_deg[a][i])
                                                                : -1;
            if (b >= 0)
                su[b] += in->error_rad[a][i * in->error_stride], cn[b] += 1.0;
        }
        m++;
    }
    int m = range->group_size;
    for (int b = 0; b < LAB_DRIFT_BINS; b++) {
        int k = 0;
        for (int j = 0; j < m; j++)
            if (cnt[(size_t)j * LAB_DRIFT_BINS + b] > 0)
                vals[k++] = sum[(size_t)j * LAB_DRIFT_BINS + b] / cnt[(size_t)j * LAB_DRIFT_BINS + b];
        if (k >= 2)
            profile[b] = stats_median_inplace(vals, (size_t)k);
    }
}

/* Campaign s against its group's profile: the line of its difference
 * (dzero, dscale), the RMS of that line over its rows (shift) and of the
 * difference about it (within). */
static void against_profile(const lab_drift_input *in, int s, lab_campaign *c,
                            const lab_campaign *range, const double *profile)
{
    int a = c->axis;
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (int pass = 0; pass < 2; pass++) {
        double slope = 0, zero = 0, ss_line = 0, ss_res = 0;
        if (pass == 1) {
            double det = n * sxx - sx * sx;
            slope = det > 0 ? (n * sxy - sx * sy) / det : 0.0;
            zero = n > 0 ? (sy - slope * sx) / n : NAN;
        }
        for (size_t i = 0; i < in->n; i++) {
            int b = campaign_of(in, i) == s && row_used(in, i) ? bin_of(range, in->angle_deg[a][i])
                                                                : -1;
            if (b < 0 || !isfinite(profile[b]))
                continue;
            double x = in->angle_deg[a][i] * RAD_PER_DEG;
            double y = in->error_rad[a][i * in->error_stride] - profile[b];
            if (pass == 0) {
                sx += x, sy += y, sxx += x * x, sxy += x * y, n++;
            } else {
                double l = zero + slope * x;
                ss_line += l * l;
                ss_res += (y - l) * (y - l);
            }
        }
        if (pass == 1 && n > 0) {
            c->dzero_arcsec = zero * ARCSEC_PER_RAD;
            c->dscale_pct = slope * PCT;
            c->shift_arcsec = sqrt(ss_line / n) * ARCSEC_PER_RAD;
            c->within_arcsec = sqrt(ss_res / n) * ARCSEC_PER_RAD;
        }
    }
}

/* Groups of campaigns of one table line; each campaign of a group of two
 * or more is compared with the group's profile. */
static int compare_groups(const lab_drift_input *in, lab_drift *d)
{
    for (int s = 0; s < d->n; s++)
        d->c[s].group = -1;
    int g = 0;
    for (int s = 0; s < d->n; s++) {
        if (d->c[s].group >= 0 || d->c[s].n < LAB_DRIFT_MIN_ROWS || d->c[s].axis < 0)
            continue;
        d->c[s].group = g;
        for (int t = s + 1; t < d->n; t++)
            if (d->c[t].group < 0 && d->c[t].n >= LAB_DRIFT_MIN_ROWS &&
                same_line(&d->c[s], &d->c[t]))
                d->c[t].group = g;
        g++;
    }
    double *buf = malloc((size_t)(2 * LAB_DRIFT_MAX_CAMPAIGNS + 1) * LAB_DRIFT_BINS * sizeof *buf);
    if (!buf)
        return SUNMC_ENOMEM;
    double profile[LAB_DRIFT_BINS];
    for (int grp = 0; grp < g; grp++) {
        lab_campaign range = {.axis = -1, .lo_deg = INFINITY, .hi_deg = -INFINITY};
        for (int s = 0; s < d->n; s++)
            if (d->c[s].group == grp) {
                range.axis = d->c[s].axis;
                range.lo_deg = fmin(range.lo_deg, d->c[s].lo_deg);
                range.hi_deg = fmax(range.hi_deg, d->c[s].hi_deg);
                range.group_size++;
            }
        for (int s = 0; s < d->n; s++)
            if (d->c[s].group == grp)
                d->c[s].group_size = range.group_size;
        if (range.group_size < 2)
            continue;
        group_profile(in, d, grp, &range, profile, buf,
                      buf + (size_t)LAB_DRIFT_MAX_CAMPAIGNS * LAB_DRIFT_BINS);
        for (int s = 0; s < d->n; s++)
            if (d->c[s].group == grp)
                against_profile(in, s, &d->c[s], &range, profile);
    }
    free(buf);
    return SUNMC_OK;
}

static void pool(lab_drift *d)
{
    double sb = 0, sw = 0, n = 0;
    d->compared = 0;
    for (int s = 0; s < d->n; s++)
        if (isfinite(d->c[s].shift_arcsec)) {
            const lab_campaign *c = &d->c[s];
            sb += (double)c->n * c->shift_arcsec * c->shift_arcsec;
            sw += (double)c->n * c->within_arcsec * c->within_arcsec;
            n += (double)c->n;
            d->compared++;
        }
    d->between_arcsec = n > 0 ? sqrt(sb / n) : NAN;
    d->within_arcsec = n > 0 ? sqrt(sw / n) : NAN;
    /* drift: a campaign changed by more than a campaign scatters (the
     * noise alone moves a line of n rows by about within sqrt(2 / n)) */
    d->drift = 0;
    for (int s = 0; s < d->n; s++)
        d->drift |= d->c[s].shift_arcsec > LAB_DRIFT_NAME_FACTOR * d->within_arcsec;
}

/* The finding in words, naming the campaigns that differ most. */
static void describe(lab_drift *d)
{
    char *p = d->note;
    size_t left = sizeof d->note;
    int w;
    if (d->compared == 0) {
        snprintf(p, left,
                 "%d campaigns (\"# source:\" blocks), none sweeping the same table line as "
                 "another: a change between them cannot be told from the model's error",
                 d->n);
        return;
    }
    w = snprintf(p, left,
                 "%d of %d campaigns repeat another's table line; the change between them "
                 "(each campaign's line against the median of its table line's campaigns) is "
                 "%.0f arcsec RMS against %.0f within a campaign%s",
                 d->compared, d->n, d->between_arcsec, d->within_arcsec,
                 d->drift ? ": the sensor or its set-up drifted between campaigns" : "");
    /* the campaigns whose change exceeds the scatter, largest first */
    int used[LAB_DRIFT_MAX_CAMPAIGNS] = {0};
    for (int named = 0; named < LAB_DRIFT_NAMED && d->drift && w > 0 && (size_t)w < left;
         named++) {
        int best = -1;
        for (int s = 0; s < d->n; s++)
            if (!used[s] && d->c[s].shift_arcsec > LAB_DRIFT_NAME_FACTOR * d->within_arcsec &&
                (best < 0 || d->c[s].shift_arcsec > d->c[best].shift_arcsec))
                best = s;
        if (best < 0)
            break;
        used[best] = 1;
        const lab_campaign *c = &d->c[best];
        int k = snprintf(p + w, left - (size_t)w, "; %s: zero %+.0f arcsec, scale %+.2f %%",
                         c->name, c->dzero_arcsec, c->dscale_pct);
        if (k < 0)
            break;
        w += k;
    }
}

int lab_drift_analyse(const lab_drift_input *in, lab_drift *out)
{
    memset(out, 0, sizeof *out);
    out->between_arcsec = out->within_arcsec = NAN;
    int ns = in->source ? in->n_sources : 1;
    out->truncated = ns > LAB_DRIFT_MAX_CAMPAIGNS;
    out->n = ns < LAB_DRIFT_MAX_CAMPAIGNS ? ns : LAB_DRIFT_MAX_CAMPAIGNS;
    if (out->n < 2) {
        snprintf(out->note, sizeof out->note,
                 "one campaign (no \"# source:\" lines dividing the file): no drift to measure");
        return out->n;
    }
    double *tmp = malloc((in->n + 1) * sizeof *tmp);
    if (!tmp) {
        out->n = 0;
        snprintf(out->note, sizeof out->note, "out of memory");
        return 0;
    }
    for (int s = 0; s < out->n; s++) {
        lab_campaign *c = &out->c[s];
        const char *nm = in->source_name ? in->source_name[s] : "";
        if (out->truncated && s == out->n - 1) /* the rest, together: said so */
            snprintf(c->name, sizeof c->name, "(campaigns %d to %d together)", s + 1, ns);
        else
            snprintf(c->name, sizeof c->name, "%s", nm ? nm : "");
        c->shift_arcsec = c->dzero_arcsec = c->dscale_pct = NAN;
        campaign_shape(in, s, c, tmp);
        campaign_line(in, s, c);
    }
    free(tmp);
    if (compare_groups(in, out) != SUNMC_OK) {
        out->n = 0;
        snprintf(out->note, sizeof out->note, "out of memory");
        return 0;
    }
    pool(out);
    describe(out);
    return out->n;
}

static void put_num(FILE *f, double v, const char *fmt)
{
    if (isfinite(v))
        fprintf(f, fmt, v);
    else
        fputc('-', f);
}

int lab_drift_write(FILE *f, const lab_drift *d)
{
    fprintf(f, "campaign\tname\trows\tswept_angle\tfixed_deg\tfrom_deg\tto_deg\tline_group\t"
               "group_campaigns\tzero_arcsec\tscale_pct\twithin_arcsec\tzero_change_arcsec\t"
               "scale_change_pct\tshift_arcsec\n");
    static const char *const axis_name[] = {"none", "alpha", "beta"};
    for (int s = 0; s < d->n; s++) {
        const lab_campaign *c = &d->c[s];
        fprintf(f, "%d\t%s\t%ld\t%s\t", s + 1, c->name[0] ? c->name : "-", c->n,
                axis_name[c->axis + 1]);
        const double v[] = {c->fixed_deg, c->lo_deg, c->hi_deg};
        for (int k = 0; k < 3; k++) {
            put_num(f, v[k], "%.6g");
            fputc('\t', f);
        }
        fprintf(f, "%d\t%d\t", c->group + 1, c->group_size);
        const double w[] = {c->zero_arcsec, c->scale_pct, c->within_arcsec, c->dzero_arcsec,
                            c->dscale_pct, c->shift_arcsec};
        for (int k = 0; k < 6; k++) {
            put_num(f, w[k], "%.6g");
            fputc(k < 5 ? '\t' : '\n', f);
        }
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}
