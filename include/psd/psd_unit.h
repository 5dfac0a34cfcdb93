/* psd_unit.h - one Monte Carlo unit of the four-channel sensor: sample ->
 * sensor -> the lab's campaign -> fit -> validation (psd_unit.c), and the
 * pieces the lab commands share (psd_lab.c). */
#ifndef SUNMC_PSD_UNIT_H
#define SUNMC_PSD_UNIT_H

#include "family.h"
#include "psd_model.h"
#include "rng.h"

/* Campaign rows of c: alphas x beta lines x repeats. */
long psd_campaign_rows(const sunmc_config *c);
/* Validation points of c. */
long psd_validation_points(const sunmc_config *c);
/* Table angles (rad) of campaign row i / validation point i. */
void psd_campaign_angles(const sunmc_config *c, long i, double *alpha, double *beta);
void psd_validation_angles(const sunmc_config *c, long i, double *alpha, double *beta);

/* The table's setting error of every line (noise.table_line_arcsec) of
 * the campaign (which = FAMILY_GRID_CAMPAIGN) or the validation
 * (FAMILY_GRID_VALIDATION) of unit `unit`, rad: off[line][0] in alpha,
 * off[line][1] in beta, from the unit's line stream; all 0 when the key
 * is 0 (no draw). */
void psd_line_offsets(const sunmc_config *c, long unit, int which,
                      double off[CONFIG_LIST_MAX][2]);
/* The line (index into the beta list) of campaign row i / validation point i. */
long psd_campaign_line(const sunmc_config *c, long i);
long psd_validation_line(const sunmc_config *c, long i);

/* Unit `unit`'s deviations (drawn as unit_run draws them, times dev_sign). */
void psd_unit_sample(const sunmc_config *c, long unit, double dev_sign, psd_deviations *dev);

/* One reading of sensor s at table angles (rad): channels m[4] (fractions
 * of full scale, ADC-quantised) with noise from r (none when r is NULL).
 * SUNMC_EDOM where the sensor sees no sun. */
int psd_unit_read(const sunmc_config *c, const psd_sensor *s, double alpha, double beta,
                  rng_stream *r, double m[4]);

/* Fit c's model to rows d into k (k->design set). */
int psd_unit_fit(const sunmc_config *c, fit_workspace *fw, psd_rows *d, double *poly_work,
                 psd_cal *k, fit_result *fr);

extern const sensor_family psd_family;
extern const struct family_lab psd_lab;

#endif
