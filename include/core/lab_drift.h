/* lab_drift.h - campaigns in one lab data file, and how much they differ.
 *
 * A lab file often joins several campaigns: importers write each source
 * file after a comment line "# source: NAME" (scripts/psd-import.py), and a
 * campaign is the rows after one such line.  Two campaigns that sweep the
 * same table line (the same swept angle, the other angle fixed at the same
 * value) should read the same after calibration; what they read
 * differently is drift (a remounted unit, a lamp, a table), not what any
 * calibration can remove.
 *
 * lab_drift_analyse fits, per campaign, the calibrated angle error along
 * its swept angle as a line, e(theta) = zero + scale * theta (theta in rad;
 * scale in % of the angle).  A group is the campaigns of one table line;
 * its profile is, per bin of the swept angle, the median over its
 * campaigns of their mean errors (what the model gets wrong there, common
 * to all).  Each campaign's error minus the profile is fitted by a line
 * (dzero, dscale), and
 *   shift    RMS over its rows of that line (arcsec): what changed in this
 *            campaign against the others of its line;
 *   within   RMS of the difference about that line (arcsec): the
 *            campaign's own scatter (a campaign alone: about its own line).
 * A campaign whose shift exceeds the pooled within is reported as drift
 * (noise alone moves a line of n rows by about within sqrt(2 / n)).  Family-neutral:
 * a family passes its table angles, the fitted calibration's per-row angle
 * errors and the rows' campaigns.
 */
#ifndef SUNMC_LAB_DRIFT_H
#define SUNMC_LAB_DRIFT_H

#include <stddef.h>
#include <stdio.h>

#define LAB_DRIFT_MAX_CAMPAIGNS 64
#define LAB_DRIFT_NAME_MAX 64
#define LAB_DRIFT_NOTE_MAX 800
/* Fewest rows a campaign's line is fitted to. */
#define LAB_DRIFT_MIN_ROWS 8
/* Campaigns sweep the same table line when their fixed angles agree this
 * closely (deg) and their swept ranges overlap by this fraction. */
#define LAB_DRIFT_SAME_LINE_DEG 0.05
#define LAB_DRIFT_MIN_OVERLAP 0.5
/* A campaign has drifted, and is named, when its shift exceeds this many
 * times the pooled within-campaign error. */
#define LAB_DRIFT_NAME_FACTOR 1.0
/* At most this many are named in the note (campaigns.tsv has them all). */
#define LAB_DRIFT_NAMED 4

/* One campaign: rows after one "# source:" line. */
typedef struct {
    char name[LAB_DRIFT_NAME_MAX];
    long n;                   /* rows used (weight > 0, finite error) */
    int axis;                 /* table angle it sweeps (0, 1), -1: none (a point) */
    double fixed_deg;         /* the other table angle's median */
    double lo_deg, hi_deg;    /* swept range */
    int group;                /* campaigns of one table line share it */
    int group_size;
    double zero_arcsec;       /* its line's error at theta = 0 */
    double scale_pct;         /* its line's slope, % of the angle */
    double within_arcsec;     /* its scatter (see above) */
    double shift_arcsec;      /* RMS of its change against its group; NaN: alone */
    double dzero_arcsec, dscale_pct; /* its change's line against its group's profile */
} lab_campaign;

typedef struct {
    int n;                    /* campaigns found (< 2: no report) */
    int truncated;            /* more than LAB_DRIFT_MAX_CAMPAIGNS: the rest in the last */
    lab_campaign c[LAB_DRIFT_MAX_CAMPAIGNS];
    int compared;             /* campaigns with another of their table line */
    double between_arcsec;    /* pooled shift of the compared campaigns (NaN: none) */
    double within_arcsec;     /* pooled within of the compared campaigns */
    int drift;                /* a campaign's shift > within */
    char note[LAB_DRIFT_NOTE_MAX]; /* the finding in words */
} lab_drift;

/* A data file's rows, their campaigns and the calibration's errors. */
typedef struct {
    size_t n;
    const double *angle_deg[2]; /* table angles per row (deg) */
    const double *error_rad[2]; /* the fitted calibration's error per row and angle (rad) */
    size_t error_stride;        /* error_rad[a][i * error_stride] (1: packed) */
    const double *weight;       /* > 0: used (NULL: every row) */
    const int *source;          /* campaign per row, 0 .. n_sources-1 (NULL: one campaign) */
    int n_sources;
    const char *const *source_name;
} lab_drift_input;

/* Fill out from in; returns the number of campaigns (0 or 1: nothing to
 * compare, out->note says why). */
int lab_drift_analyse(const lab_drift_input *in, lab_drift *out);

/* campaigns.tsv: one row per campaign (TSV, header of unique names). */
int lab_drift_write(FILE *f, const lab_drift *d);

#endif
