/* lab_accuracy.h - what `compensate` achieved, when the readings carry
 * their truth: each compensated angle (compensated_X) against the truth of
 * the same row (truth_X: a column of the input, e.g. simulate's
 * validation.csv, or one the family adds from the table angles), in the
 * family's RMS unit, per band: the points, the RMS, the 99.73 % quantile of
 * |error| (nearest rank, as the verdict's p99.7) and the largest |error|.
 *
 * Two compensated angles are alpha and beta of a direction (tan alpha,
 * tan beta, 1) (rotation.h: sun_vector_of); their total error is the angle
 * between the compensated and the true direction, and a row's band is the
 * truth's field angle.  One compensated angle is banded by |truth|.  The
 * bands, the spec and its statistic are the config's (report.bands_deg,
 * report.spec_arcsec, report.spec_statistic), or without one a single band
 * over the data and no spec.
 */
#ifndef SUNMC_LAB_ACCURACY_H
#define SUNMC_LAB_ACCURACY_H

#include "config.h"
#include "family.h"
#include "output.h"

#include <stdio.h>

#define LAB_ACC_ANGLES 3 /* alpha, beta, total */
#define LAB_ACC_FILE "accuracy.tsv"

typedef struct lab_accuracy_s {
    int n_comp;          /* compensated angles: 1 or 2 */
    int n_angles;        /* reported: 1, or 3 for two (alpha, beta, total) */
    const char *angle[LAB_ACC_ANGLES];
    const char *unit;    /* the family's rms_unit */
    double per_deg;      /* rms units per degree */
    band_list bands;
    int have_spec;       /* 1: spec_statistic / spec from a config */
    int statistic;       /* enum verdict_statistic */
    double spec;         /* rms unit */
    int required;        /* set by the caller: refuse a file without truth columns */
    int found;           /* set by lab_compensate_csv: the truth columns were there */
    char truth[2][64];   /* their names */
    long rows, missing;  /* rows seen; of them without a compensated angle or truth */
    long n[LAB_ACC_ANGLES][CONFIG_BANDS_MAX];
    double rms[LAB_ACC_ANGLES][CONFIG_BANDS_MAX];
    double p997[LAB_ACC_ANGLES][CONFIG_BANDS_MAX];
    double max[LAB_ACC_ANGLES][CONFIG_BANDS_MAX];
    /* collected rows: n_angles errors (rms unit) and the band value (deg) */
    double *err, *band_deg;
    size_t used, cap;
} lab_accuracy;

/* For n_comp compensated angles of family fam; c (or NULL) gives the
 * bands and the spec.  SUNMC_EINPUT when n_comp is neither 1 nor 2. */
int lab_accuracy_init(lab_accuracy *a, const sensor_family *fam, const sunmc_config *c,
                      int n_comp, char *err, size_t errlen);
/* One row: compensated and true angles (rad); a NaN in either counts the
 * row as missing.  SUNMC_ENOMEM when out of memory. */
int lab_accuracy_add(lab_accuracy *a, const double *comp_rad, const double *truth_rad);
/* The statistics per angle and band (the one band over the data spans
 * 0 to the largest band value when no config gave bands); NaN and 0
 * points in a band without rows.  SUNMC_ENOMEM when out of memory. */
int lab_accuracy_finish(lab_accuracy *a);
/* Angle k, band b: the spec's statistic (rms without a config), its name,
 * and whether it meets the spec ("yes", "no", "-": no spec or no points). */
double lab_accuracy_stat(const lab_accuracy *a, int k, int b);
const char *lab_accuracy_stat_name(const lab_accuracy *a);
const char *lab_accuracy_meets(const lab_accuracy *a, int k, int b);
void lab_accuracy_free(lab_accuracy *a);
/* accuracy.tsv: angle, band, band_lo_deg, band_hi_deg, points, unit, rms,
 * p99_7, max, spec_statistic, spec, meets_spec ("-" without a spec). */
void lab_accuracy_write(const lab_accuracy *a, FILE *f);
/* accuracy.tsv into the output set os (out_begin'ed: DIR checked before
 * any work), committed, or aborted on an error (output.h). */
int lab_accuracy_save(const lab_accuracy *a, out_set *os, char *err, size_t errlen);

#endif
