/* report.h - aggregating unit results in unit order: Table 1 of the ESS
 * paper (per band: RMS after compensation max/min, times of accuracy
 * improvement mean/max/min) plus mean RMS before/after and its systematic
 * part, the 95th percentile, yield against the spec, fit failures and gross
 * errors, each estimate with its confidence interval.  Writers for
 * summary.tsv and units.tsv (tab-separated, one header line). */
#ifndef SUNMC_REPORT_H
#define SUNMC_REPORT_H

#include "config.h"
#include "family.h"
#include "stats.h"

#include <stdio.h>

/* The fewest units (with a fit in every run, for the paired studies) that
 * budget, sensitivity and allocate estimate from: below it the shares,
 * indices and their t or bootstrap intervals are not numbers sunmc can
 * stand behind (sensitivity at 2 units gave ST = 2.449 [2.449, 127.7]),
 * so the study is refused and says how many it had. */
#define STUDY_MIN_UNITS 10

/* Which validation a row summarises (thermal.h): the lab's temperature,
 * one operating temperature, or the worst over the operating temperatures
 * (a unit's worst RMS; it passes only when it passes at every one). */
enum report_condition { REPORT_LAB = 0, REPORT_OPERATING = 1, REPORT_WORST = 2 };

typedef struct {
    int condition;          /* enum report_condition */
    double temp_c;          /* its temperature (C); NaN for the worst over the range */
    int angle;              /* index into the family's angle names */
    int band;               /* index into c->bands_deg */
    long units;             /* units in the run */
    long stat_units;        /* units in the means, max/min and p95: fit ok, band not empty */
    long no_reading_units;  /* units with a fit but no usable reading in the band (all gross
                               errors, or the sun never seen there): not in the statistics,
                               failing in the yield */
    long fit_failures;      /* units whose fit failed (excluded from the statistics) */
    long gross_errors;      /* validation readings with a gross error, all units */
    long alias_units;       /* units whose campaign could not resolve the fine-code term */
    double rms_before_mean, rms_after_mean, rms_after_max, rms_after_min, rms_after_p95;
    double rms_after_sys_mean; /* systematic part: noise-free validation readings */
    /* The model-form part (modelform.h): the mean of rms_after_mf over the
     * mf_units units of the stat_units that had the pass, and the after
     * mean square of those units split in three (fractions, summing to 1):
     * the validation reading's noise (after^2 - sys^2), the calibration's
     * estimation error (sys^2 - mf^2) and model form (mf^2); each a ratio
     * of means with its delta-method interval (stats_ratio_t).  NaN and 0
     * units without the pass (report.model_form_every = 0, or a set at an
     * operating temperature). */
    double rms_after_mf_mean;
    long mf_units;
    double share_noise, share_estimation, share_model_form;
    double improvement_mean, improvement_max, improvement_min;
    double yield;           /* fraction of all units meeting the spec in this band alone
                               (verdict_band: its statistic and coverage) */
    /* The yield under the spec (verdict_unit: every band it names), the
     * same on every band row of this angle and condition: the one a
     * unit's pass means, the one the studies use. */
    double spec_yield;
    stats_interval spec_yield_ci;
    long band_points;       /* validation points in the band (the most any unit had) */
    double worse;           /* fraction of the stat_units whose RMS after exceeds their RMS
                               before: calibration made them worse (Wilson interval) */
    /* Confidence intervals at level `confidence` (report.confidence):
     * Student t over the per-unit values for the means (improvement: mean
     * of the per-unit ratios), the distribution-free order-statistic
     * interval for p95, Wilson's score interval for the yield (stats.h).
     * NaN bounds when the units are too few. */
    double confidence;
    /* The campaign (campaign.h): table positions, estimated turntable hours
     * and how far (deg) validation angles lie beyond its span (0: none);
     * 0, NaN, NaN for a family without table grids. */
    long campaign_points;
    double campaign_hours;
    double extrapolation_deg;
    stats_interval rms_before_mean_ci, rms_after_mean_ci, rms_after_sys_mean_ci;
    stats_interval rms_after_mf_mean_ci, share_noise_ci, share_estimation_ci,
        share_model_form_ci;
    stats_interval rms_after_p95_ci, improvement_mean_ci, yield_ci, worse_ci;
} summary_row;

/* Decimals a family's RMS values are shown with in tables: its
 * rms_decimals (ESS 4: 0.0001 deg = 0.36 arcsec); when it sets none, 4
 * for degrees and 2 for any other unit. */
int report_decimals(const struct sensor_family *fam);

/* The confidence label of c's intervals, "[95% CI]", into buf. */
void report_ci_label(const sunmc_config *c, char *buf, size_t len);

/* Decimals that show a fraction frac in percent (at least min_decimals, at
 * most 6) so that a failure is never rounded away: 0.9995 is "99.95", not
 * "100.0"; a yield above 0 never shows as "0.0". */
int report_percent_decimals(double frac, int min_decimals);

/* v with d decimals into buf, or "-" where there is no number (no unit
 * with a fit, no point): no table prints nan.  Returns snprintf's count. */
int report_format_number(char *buf, size_t len, double v, int d);

/* The yield interval of pass of n independent units by c's method
 * (report.yield_interval) at report.confidence. */
void report_yield_ci(const sunmc_config *c, long pass, long n, stats_interval *ci);

/* The yield interval's method of c (report.yield_interval), in words. */
const char *report_yield_interval_name(const sunmc_config *c);

/* Number of rows = angles x bands, times (operating temperatures + 2) when
 * the config has operating temperatures (thermal.h): the lab's rows first
 * (angle-major, as without them), then each temperature's, then the worst
 * over them. */
int report_n_rows(const sunmc_config *c);
/* The lab's rows: angles x bands. */
int report_n_lab_rows(const sunmc_config *c);
/* Index of the row that budget, sensitivity and sweep judge by for angle
 * and band: the worst over the operating temperatures when there are any,
 * else the lab's. */
int report_primary_row(const sunmc_config *c, int angle, int band);

/* The statistics of a stream of units, added in unit order a block at a
 * time: running moments for the means, counts, max/min, and per angle and
 * band the RMS after of each unit (the p95 and its interval need them all:
 * 8 bytes per unit per angle and band, the only memory that grows with the
 * run).  report_acc_rows may be called after any block and adding go on. */
typedef struct report_acc report_acc;

/* NULL when out of memory; c (and its family) must outlive the accumulator. */
report_acc *report_acc_new(const sunmc_config *c);
/* Add results[n], the next units in unit order.  SUNMC_ENOMEM. */
int report_acc_add(report_acc *acc, const unit_result *results, long n);
/* Units added so far. */
long report_acc_units(const report_acc *acc);
/* The summary of the units so far into rows[report_n_rows]. */
void report_acc_rows(report_acc *acc, summary_row *rows);
void report_acc_free(report_acc *acc);

/* `run --until STAT:HALFWIDTH`: the estimates with an interval by their
 * summary.tsv name (index, or -1 when unknown), the list of names for
 * messages, the band of the widest |angle| range (the last of equal ones),
 * and the half-width (hi - lo) / 2 of stat's interval in band `band`, the
 * largest over the measured angles: NaN while any is missing (too few
 * units).  Only rms_after_p95 sorts (its cost grows with the units). */
int report_stat_find(const char *name);
void report_stat_list(char *buf, size_t len);
int report_widest_band(const sunmc_config *c);
double report_acc_halfwidth(report_acc *acc, int stat, int band);

/* Fill rows[report_n_rows] from results[n] (in unit order), intervals at
 * c->confidence (an accumulator over one array).  SUNMC_ENOMEM. */
int report_summarize(const sunmc_config *c, const unit_result *results,
                     long n, summary_row *rows);

/* summary.tsv: header then one row per angle and band; each estimate S with
 * an interval is followed by S_ci_lo and S_ci_hi.  `lead` (may be NULL)
 * prefixes extra columns: lead_names in the header, lead_values (as text,
 * without tabs) on every row (for sweeps). */
void report_write_summary_header(FILE *f, int n_lead, const char *const *lead_names);
/* The same, with the columns condition (lab, operating, worst) and temp_c
 * after the others when c has operating temperatures (thermal.h). */
void report_write_summary_header_of(FILE *f, const sunmc_config *c, int n_lead,
                                    const char *const *lead_names);
void report_write_summary_rows(FILE *f, const sunmc_config *c,
                               const summary_row *rows, int n_lead, const char *const *lead_values);

/* units.tsv: header then one row per unit; the header and the rows apart,
 * for writing the rows a block at a time. */
void report_write_units(FILE *f, const sunmc_config *c,
                        const unit_result *results, long n);
void report_write_units_header(FILE *f, const sunmc_config *c);
void report_write_unit_rows(FILE *f, const sunmc_config *c,
                            const unit_result *results, long n);

/* Band label "0:30" of band i. */
void report_band_label(const sunmc_config *c, int i, char *buf, size_t len);
/* The band column's header: "|alpha| deg", "field angle deg" (the
 * family's band_name). */
void report_band_head(const sensor_family *fam, char *buf, size_t len);

#endif
