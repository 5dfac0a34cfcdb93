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

#include <math.h>

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

/* The cosines and sines of n table angles a, b (rad): a table of a run,
 * the same for every unit (the validation grid's), made once per
 * workspace; arrays of vm_pad(n) doubles.  ess_table_trig_fill computes
 * them in the vector loop the readings use, so a reading from the table
 * is the bits of one computed on the spot. */
typedef struct {
    double *ca, *sa, *cb, *sb;
} ess_table_trig;
void ess_table_trig_fill(size_t n, const double *a_rad, const double *b_rad, ess_table_trig *t);

/* n validation readings at the table angles whose cosines and sines are
 * trig (ess_table_trig_fill) with fresh row noise from r: raw output (0
 * when unseen), the same reading without its noise (raw0_rad, NULL: not
 * wanted; the bits of ess_unit_read without noise), true incidence and
 * status (enum ess_reading_status), vectorised (ess_readings.c). */
void ess_validation_batch(const sunmc_config *c, const ess_unit *u, rng_stream *r, size_t n,
                          const ess_table_trig *trig, double *raw_rad, double *raw0_rad,
                          double *truth_rad, int *status);

/* Number of campaign points of config c (alphas x betas). */
size_t ess_campaign_size(const sunmc_config *c);

/* Half the fine-code period (rad) of c's design. */
double ess_half_period_rad(const sunmc_config *c);

/* The ESS's one gross-error rule: a reading off its reference angle (a
 * campaign point's table alpha, a validation reading's true incidence) by
 * half a fine period or more: the coarse code picked the wrong period.  A
 * lab drops such a reading; `run` counts it and leaves it out of the RMS. */
static inline int ess_is_gross(double raw_rad, double ref_rad, double half_period_rad)
{
    return !(fabs(raw_rad - ref_rad) < half_period_rad);
}

/* Simulate the campaign of unit `unit` into cw (alpha, beta as recorded by
 * the turntable, alphas fastest; raw averaged over campaign.repeats; weight
 * 0 for a point with a gross error or no sun).  *gross counts the dropped
 * points.  truth (n = ess_campaign_size(c) points, or NULL) gets each
 * point's true table angles and incidence and whether the sun was seen. */
void ess_unit_campaign(const sunmc_config *c, const ess_unit *u, long unit,
                       ess_calib_workspace *cw, ess_campaign_point *truth, int *gross);

/* The two halves of ess_unit_campaign: the config's campaign table angles
 * into cw (alphas fastest), and unit u's readings at cw's angles drawn
 * from r, with weight 0 for an unseen reading or a gross error (counted in
 * *gross); truth as above. */
void ess_campaign_angles(const sunmc_config *c, ess_calib_workspace *cw);
void ess_campaign_read(const sunmc_config *c, const ess_unit *u, rng_stream *r,
                       ess_calib_workspace *cw, ess_campaign_point *truth, int *gross);

/* Status of a validation reading. */
enum ess_reading_status { ESS_READING_OK = 0, ESS_READING_UNSEEN = 1, ESS_READING_GROSS = 2 };

/* A unit's validation readings on c's validation grid (alphas fastest):
 * table angles, raw output (0 when unseen), the same reading without its
 * noise (for the systematic part) and true incidence, rad, and each
 * reading's status (enum ess_reading_status).  `run` scores these arrays
 * and `simulate` writes them. */
typedef struct {
    size_t n;
    double *alpha_rad, *beta_rad, *raw_rad, *raw0_rad, *truth_rad;
    int *status;
    ess_table_trig trig; /* of alpha_rad, beta_rad: made once by ess_val_alloc */
} ess_val_readings;

/* Number of validation grid points of config c (alphas x betas). */
size_t ess_validation_size(const sunmc_config *c);

/* Arrays for c's validation grid, its angles and their cosines and sines
 * filled in (they are the same for every unit); SUNMC_ENOMEM.  Free with
 * ess_val_free. */
int ess_val_alloc(const sunmc_config *c, ess_val_readings *v);
void ess_val_free(ess_val_readings *v);

/* The validation readings of unit `unit` with fresh row noise (stream
 * RNG_STREAM_VAL_NOISE of (seed, unit)). */
void ess_unit_read_validation(const sunmc_config *c, const ess_unit *u, long unit,
                         ess_val_readings *v);

/* Draw the 4 fine-row current noises (units of a1) from stream r. */
void ess_row_noise(const sunmc_config *c, rng_stream *r, double noise[ESS_FINE_ROWS]);

/* Fitted parameters in the units of ess_family's par columns: the paper's
 * 8 (k, t for ks, kc), then the extended model's own in degrees. */
#define ESS_N_PAR 8
#define ESS_N_PAR_MAX (ESS_N_PAR + ESS_NP_MAX - ESS_NP)
void ess_model_report(const ess_model *m, double out[ESS_N_PAR_MAX]);

#endif
