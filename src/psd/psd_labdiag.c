/* psd_labdiag.c - what is wrong with lab data the physics does not fit,
 * in terms of the data (psd_lab.h): the measured ratios against the
 * design's nominal ones, mapped linearly over the inner half of the
 * field.  A pinhole over a lateral detector gives a map near a scaled
 * identity; the data's may be mirrored, turned, or compress towards the
 * field's edge (a saturating or non-pinhole response), and rows may lie
 * far off it (outliers). */
#include "psd_lab.h"
#include "stats.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Fewest inner rows the map is fitted to. */
#define PSD_DIAG_MIN_ROWS 6
/* Bins of the total angle the compression is tabulated in (deg). */
#define PSD_DIAG_BIN_DEG 5.0
#define PSD_DIAG_BINS 18
/* The spot's travel is "compressed" below this fraction of the map's. */
#define PSD_DIAG_COMPRESSED 0.8
/* A row is an outlier beyond this many times the median residual. */
#define PSD_DIAG_OUTLIER 5.0
/* A map scaled outside [1 / this, this] is named. */
#define PSD_DIAG_SCALE 1.4
/* A map turned by more than this (deg) is named. */
#define PSD_DIAG_TURN_DEG 5.0

/* Every row's measured raw ratios q, the design's nominal ones p and its
 * total angle t (rad), computed once; t NaN where one is missing (a row
 * of weight 0, a reading without ratios, a sun the design cannot see). */
typedef struct {
    size_t n;
    double *q[2], *p[2], *t;
} diag_rows;

static int rows_fill(const psd_labcal *k, const psd_phys *nom, diag_rows *r)
{
    size_t n = k->d->n;
    double *buf = malloc((5 * n + 1) * sizeof *buf);
    if (!buf)
        return SUNMC_ENOMEM;
    *r = (diag_rows){.n = n, .q = {buf, buf + n}, .p = {buf + 2 * n, buf + 3 * n}, .t = buf + 4 * n};
    const double z[3] = {0, 0, 1};
    for (size_t i = 0; i < n; i++) {
        const double *ut = k->ut + 3 * i;
        double m[4] = {k->d->v[2][i], k->d->v[3][i], k->d->v[4][i], k->d->v[5][i]};
        int ok = k->d->v[6][i] > 0 &&
                 psd_poly_ratios(&psd_cfg(k->c)->design, m, &r->q[0][i], &r->q[1][i]) ==
                     SUNMC_OK &&
                 psd_phys_predicted(nom, ut, &r->p[0][i], &r->p[1][i]) == SUNMC_OK &&
                 isfinite(r->p[0][i]) && isfinite(r->p[1][i]);
        r->t[i] = ok ? angle_between(ut, z) : NAN;
    }
    return SUNMC_OK;
}

/* Row i's residual about the map a (ratio units). */
static double map_residual(const diag_rows *r, size_t i, const double a[6])
{
    return hypot(r->q[0][i] - a[0] * r->p[0][i] - a[1] * r->p[1][i] - a[2],
                 r->q[1][i] - a[3] * r->p[0][i] - a[4] * r->p[1][i] - a[5]);
}

/* Least squares of q = Q p + c over the rows within theta_max: out a[6] =
 * Q00 Q01 c0 Q10 Q11 c1.  Non-OK when singular. */
static int fit_map(const diag_rows *d, double theta_max, double a[6], long *n_used)
{
    double ata[3][3] = {{0}}, atb[2][3] = {{0}};
    long n = 0;
    for (size_t i = 0; i < d->n; i++) {
        if (!(d->t[i] <= theta_max))
            continue;
        const double row[3] = {d->p[0][i], d->p[1][i], 1.0};
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                ata[r][c] += row[r] * row[c];
            atb[0][r] += row[r] * d->q[0][i];
            atb[1][r] += row[r] * d->q[1][i];
        }
        n++;
    }
    *n_used = n;
    if (n < PSD_DIAG_MIN_ROWS)
        return SUNMC_EFIT;
    /* Cramer's rule on the 3 x 3 normal equations */
    double det = ata[0][0] * (ata[1][1] * ata[2][2] - ata[1][2] * ata[2][1]) -
                 ata[0][1] * (ata[1][0] * ata[2][2] - ata[1][2] * ata[2][0]) +
                 ata[0][2] * (ata[1][0] * ata[2][1] - ata[1][1] * ata[2][0]);
    if (!(fabs(det) > 0))
        return SUNMC_EFIT;
    for (int o = 0; o < 2; o++)
        for (int j = 0; j < 3; j++) {
            double m[3][3];
            memcpy(m, ata, sizeof m);
            for (int r = 0; r < 3; r++)
                m[r][j] = atb[o][r];
            double dj = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                        m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                        m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
            a[3 * o + j] = dj / det;
        }
    return SUNMC_OK;
}

/* Per bin of the total angle from the inner field's edge outwards, the
 * median of the measured travel over the map's; the first bin below
 * PSD_DIAG_COMPRESSED. */
static void compression(const diag_rows *d, const double a[6], double theta_max,
                        psd_data_diag *g, double *tmp)
{
    g->compressed_from_deg = g->outer_ratio = g->outer_deg = NAN;
    for (int b = 0; b < PSD_DIAG_BINS; b++) {
        double lo = b * PSD_DIAG_BIN_DEG * RAD_PER_DEG, hi = lo + PSD_DIAG_BIN_DEG * RAD_PER_DEG;
        if (lo < 0.5 * theta_max)
            continue;
        size_t m = 0;
        for (size_t i = 0; i < d->n; i++) {
            if (!(d->t[i] >= lo && d->t[i] < hi))
                continue;
            double mx = a[0] * d->p[0][i] + a[1] * d->p[1][i];
            double my = a[3] * d->p[0][i] + a[4] * d->p[1][i];
            double den = hypot(mx, my);
            if (den > 0)
                tmp[m++] = hypot(d->q[0][i] - a[2], d->q[1][i] - a[5]) / den;
        }
        if (m < 3)
            continue;
        double r = stats_median_inplace(tmp, m);
        g->outer_ratio = r;
        g->outer_deg = b * PSD_DIAG_BIN_DEG;
        if (r < PSD_DIAG_COMPRESSED && !isfinite(g->compressed_from_deg))
            g->compressed_from_deg = b * PSD_DIAG_BIN_DEG;
    }
}

/* Rows of the inner field far off the map. */
static void outliers(const psd_labcal *k, const diag_rows *d, const double a[6],
                     double theta_max, psd_data_diag *g, double *tmp)
{
    size_t m = 0;
    for (size_t i = 0; i < d->n; i++)
        if (d->t[i] <= theta_max)
            tmp[m++] = map_residual(d, i, a);
    g->outliers = 0;
    if (m < PSD_DIAG_MIN_ROWS)
        return;
    double med = stats_median_inplace(tmp, m);
    g->resid_median = med;
    for (size_t i = 0; i < d->n; i++) {
        if (!(d->t[i] <= theta_max))
            continue;
        if (map_residual(d, i, a) > PSD_DIAG_OUTLIER * med) {
            if (g->outliers < PSD_DIAG_LINES)
                g->outlier_line[g->outliers] = k->d->line[i];
            g->outliers++;
        }
    }
}

/* The map's shape: mirror, scale and turn (or, mirrored, its line). */
static void map_shape(const double a[6], psd_data_diag *g)
{
    double det = a[0] * a[4] - a[1] * a[3];
    g->mirrored = det < 0;
    g->scale = sqrt(fabs(det));
    /* the map's rotation (or, mirrored, twice its mirror line's angle) */
    double phi = det >= 0 ? atan2(a[3] - a[1], a[0] + a[4]) : atan2(a[3] + a[1], a[0] - a[4]);
    g->turn_deg = (det >= 0 ? phi : 0.5 * phi) * DEG_PER_RAD;
}

int psd_labcal_diagnose(const psd_labcal *k, psd_data_diag *g)
{
    memset(g, 0, sizeof *g);
    double p0[PSD_NP] = {0};
    psd_phys nom;
    psd_phys_set(&nom, &psd_cfg(k->c)->design, p0);
    const double z[3] = {0, 0, 1};
    double tmax = 0;
    for (size_t i = 0; i < k->d->n; i++)
        if (k->d->v[6][i] > 0)
            tmax = fmax(tmax, angle_between(k->ut + 3 * i, z));
    double inner = 0.5 * tmax, a[6];
    g->inner_deg = inner * DEG_PER_RAD;
    diag_rows d;
    if (rows_fill(k, &nom, &d) != SUNMC_OK)
        return SUNMC_ENOMEM;
    double *tmp = malloc((d.n + 1) * sizeof *tmp);
    int st = !tmp ? SUNMC_ENOMEM : fit_map(&d, inner, a, &g->rows);
    if (st == SUNMC_OK) {
        map_shape(a, g);
        compression(&d, a, inner, g, tmp);
        outliers(k, &d, a, inner, g, tmp);
        g->defects = g->mirrored + (!g->mirrored && fabs(g->turn_deg) > PSD_DIAG_TURN_DEG) +
                     (g->scale > PSD_DIAG_SCALE || g->scale * PSD_DIAG_SCALE < 1.0) +
                     isfinite(g->compressed_from_deg) + (g->outliers > 0);
    }
    free(tmp);
    free(d.q[0]);
    return st;
}

void psd_labcal_report_defects(const psd_labcal *k, calreport *rep)
{
    psd_data_diag g;
    if (psd_labcal_diagnose(k, &g) != SUNMC_OK || g.defects == 0)
        return;
    char what[CALREPORT_TEXT_MAX] = "";
    size_t w = 0;
#define ADD(...) w += (size_t)snprintf(what + w, w < sizeof what ? sizeof what - w : 0, __VA_ARGS__)
    if (g.mirrored)
        ADD("; mirrored: the spot moves as the design's mirror image, across a line %.1f deg "
            "from X (0: beta's sign, 90: alpha's, +-45: the axes crossed)",
            g.turn_deg);
    else if (fabs(g.turn_deg) > PSD_DIAG_TURN_DEG)
        ADD("; turned by %.1f deg about the optical axis", g.turn_deg);
    if (g.scale > PSD_DIAG_SCALE || g.scale * PSD_DIAG_SCALE < 1.0)
        ADD("; the spot travels %.2f times as far as the design's (design.h_mm, active_mm, the "
            "aperture's size)",
            g.scale);
    if (isfinite(g.compressed_from_deg))
        ADD("; the spot's travel falls below %.0f %% of the inner field's map from %.0f deg "
            "(%.2f of it at %.0f-%.0f deg): a saturating or non-pinhole response",
            100 * PSD_DIAG_COMPRESSED, g.compressed_from_deg, g.outer_ratio, g.outer_deg,
            g.outer_deg + PSD_DIAG_BIN_DEG);
    if (g.outliers > 0) {
        ADD("; %ld inner rows lie beyond %.0f times the map's median residual (lines", g.outliers,
            PSD_DIAG_OUTLIER);
        for (long j = 0; j < g.outliers && j < PSD_DIAG_LINES; j++)
            ADD(" %d", g.outlier_line[j]);
        ADD("%s)", g.outliers > PSD_DIAG_LINES ? " ..." : "");
    }
#undef ADD
    calreport_warn(rep,
                   "fix what can be fixed in the set-up or the convention keys (a mirror or a "
                   "turn), keep the data within the field that responds, or calibrate with an "
                   "empirical model (calibration.model = spline)",
                   "the data against the design (the measured ratios mapped linearly on the "
                   "design's, %ld rows within %.1f deg)%s",
                   g.rows, g.inner_deg, what);
}
