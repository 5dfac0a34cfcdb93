/* ess_unit.h - one simulated ESS unit on the turntable: its deviations, its
 * physical sensor and installation, its calibration campaign and its
 * validation.  The ESS family of the Monte Carlo (ess_family) is built from
 * these; `simulate` and `curve` use them directly. */
#ifndef SUNMC_ESS_UNIT_H
#define SUNMC_ESS_UNIT_H

#include "ess_config.h"
#include "ess_calib.h"
#include "ess_model.h"
#include "ess_sensor.h"
#include "rng.h"

typedef struct {
    ess_deviations dev;
    ess_sensor sensor;
    mat3 R_install;        /* true ESS-to-turntable rotation */
    double v_sun[3];       /* true sun-simulator direction */
} ess_unit;

/* Build a unit from given deviations. */
void ess_unit_build(const sunmc_config *c, const ess_deviations *dev, ess_unit *u);

/* Turntable at (alpha, beta) rad: the sun vector in the sensor frame, the true
 * incidence (rad) and the raw output (rad) with row noise (NULL: none).
 * SUNMC_EDOM when the sun is not seen.  (ess_readings.c, as the batches.) */
int ess_unit_read(const ess_unit *u, double alpha_rad, double beta_rad,
                  const double row_noise[ESS_FINE_ROWS], double *raw_rad, double *truth_rad);

/* One campaign point: the true table angles (encoder error added), the
 * true incidence, the raw output averaged over campaign.repeats (0 when
 * not seen) and seen = 1 when the sun was seen at every repeat. */
typedef struct {
    double a_true_rad, b_true_rad, incidence_rad, raw_rad;
    double sum_rad; /* work: sum of the seen repeats */
    int seen;
} ess_campaign_point;

/* The campaign readings of n points at recorded table angles a, b (rad),
 * drawing from r in the Monte Carlo's order (per point: the two encoder
 * errors, then the four row noises of each repeat), vectorised
 * (ess_readings.c).  Splitting the points over calls gives the same bits. */
void ess_campaign_batch(const sunmc_config *c, const ess_unit *u, rng_stream *r, size_t n,
                           const double *a_rad, const double *b_rad, ess_campaign_point *out);

/* n validation readings at table angles a, b (rad) with fresh row noise
 * from r: raw output (0 when unseen), the same reading without its noise
 * (raw0_rad, NULL: not wanted; the bits of ess_unit_read without noise),
 * true incidence and status (enum ess_reading_status), vectorised
 * (ess_readings.c). */
void ess_validation_batch(const sunmc_config *c, const ess_unit *u, rng_stream *r, size_t n,
                          const double *a_rad, const double *b_rad, double *raw_rad,
                          double *raw0_rad, double *truth_rad, int *status);

/* Number of campaign points of config c (alphas x betas). */
size_t ess_campaign_size(const sunmc_config *c);

/* Simulate the campaign of unit `unit` into cw (alpha, beta as recorded by
 * the turntable; raw averaged over campaign.repeats; weight 0 for a point
 * with a gross error or no sun).  *gross counts the dropped points. */
void ess_unit_campaign(const sunmc_config *c, const ess_unit *u, long unit,
                       ess_calib_workspace *cw, int *gross);

/* One campaign reading at recorded table angles (a, b) rad, drawing from r
 * in the Monte Carlo's order: the true table angles (encoder error added),
 * the true incidence and the raw output averaged over campaign.repeats.
 * Returns 1 when the sun was seen at every repeat, else 0. */
int ess_campaign_reading(const sunmc_config *c, const ess_unit *u, rng_stream *r, double a_rad,
                         double b_rad, double *a_true_rad, double *b_true_rad,
                         double *incidence_rad, double *raw_rad);

/* Status of a validation reading. */
enum ess_reading_status { ESS_READING_OK = 0, ESS_READING_UNSEEN = 1, ESS_READING_GROSS = 2 };

/* One validation reading at table angles (a, b) rad with fresh row noise
 * from r: raw output and true incidence (rad); ESS_READING_GROSS when they
 * differ by more than half a fine period (the wrong period was picked). */
int ess_validation_reading(const sunmc_config *c, const ess_unit *u, rng_stream *r, double a_rad,
                           double b_rad, double *raw_rad, double *truth_rad);

/* Draw the 4 fine-row current noises (units of a1) from stream r. */
void ess_row_noise(const sunmc_config *c, rng_stream *r, double noise[ESS_FINE_ROWS]);

/* Fitted parameters in the units of ess_family's par columns. */
#define ESS_N_PAR 8
void ess_model_report(const ess_model *m, double out[ESS_N_PAR]);

#endif
