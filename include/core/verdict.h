/* verdict.h - whether a unit meets the spec: the one rule every command
 * judges by (run, sweep, budget, sensitivity, design, allocate, the
 * temperature rows, merge).
 *
 * A unit passes for a measured angle when its calibration converged and, in
 * every band the spec names (report.spec_bands: all of report.bands_deg, or
 * a list of them), it read at least report.min_coverage of the band's
 * validation points (default all: a unit blind over part of its field
 * fails) and report.spec_statistic of its error after calibration over the
 * points it read is at most report.spec_arcsec.  The statistic is the RMS
 * (rms), the nearest-rank 99.73 % quantile of |error| (p99.7: the
 * ceil(0.9973 n)-th smallest of n, which is the largest below 371 points),
 * or the largest |error| (max).  At operating temperatures a unit passes
 * only when it passes at every one.
 */
#ifndef SUNMC_VERDICT_H
#define SUNMC_VERDICT_H

#include "config.h"
#include "family.h"

#include <stddef.h>

enum verdict_statistic { VERDICT_RMS = 0, VERDICT_P997 = 1, VERDICT_MAX = 2 };
#define VERDICT_P997_LEVEL 0.9973

/* Why a unit passed or failed (units.tsv's verdict column). */
enum verdict_why { VERDICT_PASS = 0, VERDICT_NO_FIT, VERDICT_COVERAGE, VERDICT_OVER_SPEC };

/* Which validation the verdict judges: the lab's, an operating
 * temperature t >= 0 (thermal.h), or the worst over them. */
#define VERDICT_LAB (-1)
#define VERDICT_WORST (-2)

typedef struct {
    int pass;        /* 1: meets the spec */
    int why;         /* enum verdict_why */
    int band;        /* the band that decided: the first failing one, else the one
                        closest to the spec; -1 without a fit */
    double stat;     /* its statistic (rms unit; NaN when nothing was read) */
    double coverage; /* its share of validation points read */
} verdict;

/* Checks report.spec_bands against report.bands_deg (SUNMC_EINPUT naming
 * the band that is not one of them) and the statistic's reach. */
int verdict_check(const sunmc_config *c, char *err, size_t errlen);
/* The spec's bands as bits (bit b: band b); every band for "all". */
unsigned verdict_band_mask(const sunmc_config *c);
/* The measured angle studies judge: the last (the total angle of a
 * two-axis family, the only one of the ESS). */
int verdict_angle(const sunmc_config *c);
/* How many of the largest errors a band_tail keeps for the statistic. */
int verdict_tail_keep(const sunmc_config *c);
/* The statistic's quantile level (1 for max; unused for rms). */
double verdict_level(const sunmc_config *c);

/* Unit r's verdict for angle `angle` over the spec's bands, at `set`
 * (VERDICT_LAB, a temperature index, or VERDICT_WORST). */
void verdict_unit(const sunmc_config *c, const unit_result *r, int angle, int set, verdict *v);
/* The same rule in one band only (a band row's yield). */
void verdict_band(const sunmc_config *c, const unit_result *r, int angle, int band, int set,
                  verdict *v);
/* 1 when r passes for the studies' angle at the worst of its conditions
 * (the yield budget, design, allocate and sensitivity count). */
int verdict_pass(const sunmc_config *c, const unit_result *r);

/* "p99.7 of |total| <= 20\" in every band (0:25, 25:50), every point read" */
void verdict_rule_text(const sunmc_config *c, char *buf, size_t len);
/* "pass", "no_fit", "coverage", "over_spec" */
const char *verdict_why_name(int why);
/* "rms", "p99.7", "max" */
const char *verdict_statistic_name(const sunmc_config *c);

#endif
