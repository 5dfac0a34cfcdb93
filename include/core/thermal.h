/* thermal.h - validation at the operating temperatures (docs/temperature.md).
 *
 * A unit is calibrated once, at environment.calibration_temp_c, and
 * validated there (unit_result.rms_before / rms_after: the lab's result) and
 * at each temperature of environment.operating_temp_c
 * (unit_result.rms_before_t / rms_after_t).  A config whose only operating
 * temperature is the lab's has no operating temperatures at all here
 * (thermal_n_temps = 0): its results are the lab's, as without the keys.
 *
 * Over the range a unit's RMS is its worst over the operating temperatures
 * (NaN when it has none at any of them: it then fails), and it passes the
 * spec only when it passes at every one.  budget, sensitivity and sweep use
 * that "primary" figure when there are operating temperatures, else the lab's.
 */
#ifndef SUNMC_THERMAL_H
#define SUNMC_THERMAL_H

#include "config.h"
#include "family.h"

#include <stddef.h>

/* Operating temperatures validated apart from the lab's: 0 when
 * environment.operating_temp_c is calibration_temp_c alone (or empty). */
int thermal_n_temps(const sunmc_config *c);

/* Operating temperature t (C). */
double thermal_temp_c(const sunmc_config *c, int t);

/* Shared checks: at most CONFIG_TEMPS_MAX temperatures, and a family that
 * validates at them (SUNMC_EINPUT naming environment.operating_temp_c). */
int thermal_check(const sunmc_config *c, char *err, size_t errlen);

/* Worst over the operating temperatures of v[t][a][b], t < n: NaN when any
 * is NaN (no reading or a failed compensation there). */
double thermal_worst(const double v[][UNIT_MAX_ANGLES][CONFIG_BANDS_MAX], int n, int a, int b);

/* A unit's RMS before / after for angle a, band b: the worst over the
 * operating temperatures when c has any, else the lab's. */
double unit_primary_before(const sunmc_config *c, const unit_result *r, int a, int b);
double unit_primary_after(const sunmc_config *c, const unit_result *r, int a, int b);

/* Store what `at` (a scratch result validated at temperature t) holds into
 * r's slot t: its RMS before and after, every angle and band. */
void unit_result_store_temp(unit_result *r, int t, const unit_result *at);

/* Validate a calibrated unit at each operating temperature of c into r's
 * per-temperature results: a temperature equal to the lab's takes r's
 * own; any other calls validate_at(c, temp_c, ctx, at) on a zeroed
 * result carrying r's fit status (the family rebuilds its unit at that
 * temperature, reads and scores its validation). */
typedef void (*thermal_validate_fn)(const sunmc_config *c, double temp_c, void *ctx,
                                    unit_result *at);
void thermal_validate_all(const sunmc_config *c, unit_result *r, thermal_validate_fn validate_at,
                          void *ctx);

/* Validations a unit reads: the lab's, then one for each operating
 * temperature other than the lab's, in thermal_validate_all's order (the
 * slots of a family's readings, family.h: unit_read). */
int thermal_n_reads(const sunmc_config *c);

/* The temperature (C) of read k, 1 <= k < thermal_n_reads: the k-th
 * operating temperature other than the lab's, in that order (read 0 is
 * the lab's, at calibration_temp_c).  A family's unit_read fills slot k
 * of its readings at it. */
double thermal_read_temp_c(const sunmc_config *c, int k);

#endif
