/* dss_unit.h - one simulated DSS unit on the rotary table: its deviations,
 * its calibration campaign as a lab records it, and the DSS family of the
 * Monte Carlo (dss_family: sample -> campaign -> fit -> validate).
 *
 * For `sunmc simulate / calibrate / compensate` and `curve`:
 *   dss_deviations_sample + dss_unit_build     a unit (or fill the deviations)
 *   dss_unit_campaign, dss_unit_read_validation     its readings and the truth
 *   dss_calib_alloc + dss_calibrate            the fit (dss_calib.h)
 *   dss_compensate                             spot -> (alpha, beta)
 *   dss_sensor_read + dss_sensor_angles        one raw reading anywhere
 */
#ifndef SUNMC_DSS_UNIT_H
#define SUNMC_DSS_UNIT_H

#include "dss_config.h"
#include "rng.h"
#include "dss_calib.h"
#include "dss_sensor.h"

#include <stddef.h>

typedef struct {
    dss_deviations dev;
    dss_sensor sensor;
} dss_unit;

/* Build a unit of config c with deviations dev. */
void dss_unit_build(const sunmc_config *c, const dss_deviations *dev, dss_unit *u);
/* The same with the S-curve amplitudes given (dss_sensor_init_amp). */
void dss_unit_build_amp(const sunmc_config *c, const dss_deviations *dev, const double *amp_px,
                        dss_unit *u);

/* Give unit u the fixed pattern of unit `unit` for seed (dss_pattern_key);
 * a unit built without it has key 0's pattern.  Call after each build. */
void dss_unit_set_pattern(const sunmc_config *c, uint64_t seed, long unit, dss_unit *u);

/* Readings in c's campaign: the b1 x b2 grid (campaign.b_min_deg ..
 * b_max_deg, step b_step_deg, both axes), b1 varying slowest. */
size_t dss_campaign_size(const sunmc_config *c);

/* Simulate unit `unit`'s campaign as a lab records it, one reading per grid
 * point (arrays of dss_campaign_size(c)):
 *   b1_rad, b2_rad   the table angles as recorded (the table is really at
 *                    recorded + encoder error, noise.encoder_arcsec);
 *   x_px, y_px       the spot centroid averaged over campaign.repeats
 *                    readings, each with centroid noise (noise.centroid_px)
 *                    and the S-curve bias if on; NaN when the spot is not on
 *                    the detector;
 *   weight           1, or 0 for a reading with no spot;
 *   truth_alpha_rad, truth_beta_rad (may be NULL): eq. 3-4 at the table's
 *                    true angles.
 * Draws come from stream RNG_STREAM_CAL_NOISE of (seed, unit).  Returns the
 * number of readings with a spot. */
size_t dss_unit_campaign(const sunmc_config *c, const dss_unit *u, long unit, double *b1_rad,
                         double *b2_rad, double *x_px, double *y_px, double *weight,
                         double *truth_alpha_rad, double *truth_beta_rad);

/* The parameter columns of units.tsv for c's model, and their values from a
 * calibration (cal) with its largest correlation (corr, pair i < j) and the
 * fit's reciprocal condition number. */
#define DSS_N_PAR_PHYSICAL (DSS_NP + 3)
#define DSS_N_PAR_POLYNOMIAL 5
#define DSS_N_PAR_SPLINE 5             /* spline and table (the hybrid: the physical's) */
/* A unit's validation readings on c's validation grid (b1 varying
 * slowest; the table at exactly these angles): table angles rad, the
 * measured spot (px from the detector centre, one reading with centroid
 * noise; meaningless with seen[i] = 0 when there is no spot), the same
 * spot without the noise (for the systematic part) and the truth angles of
 * eq. 3-4, rad.  `run` scores these arrays and `simulate` writes them. */
typedef struct {
    size_t n;
    double *b1_rad, *b2_rad, *x_px, *y_px, *x0_px, *y0_px, *truth_alpha_rad, *truth_beta_rad;
    int *seen;
    double *trig[4]; /* cos b1, sin b1, cos b2, sin b2 of the grid, made once (dss_val_alloc) */
} dss_val_readings;

/* Number of validation grid points of config c (b1 x b2). */
size_t dss_validation_size(const sunmc_config *c);

/* Arrays for c's validation grid, its table angles and their cosines and
 * sines filled (the same for every unit); SUNMC_ENOMEM.  Free with
 * dss_val_free. */
int dss_val_alloc(const sunmc_config *c, dss_val_readings *v);
void dss_val_free(dss_val_readings *v);

/* The validation readings of unit `unit`, fresh centroid noise from stream
 * RNG_STREAM_VAL_NOISE of (seed, unit) (two normals per point, spot or not). */
void dss_unit_read_validation(const sunmc_config *c, const dss_unit *u, long unit,
                         dss_val_readings *v);

/* One campaign point as the lab records it (dss_campaign_batch). */
typedef struct {
    double b1_true_rad, b2_true_rad; /* where the table really stood */
    double x_px, y_px;               /* mean over the repeats; NaN if not seen */
    int seen;
} dss_campaign_point;

/* The readings of n campaign points at recorded table angles (b1, b2) rad,
 * their draws taken from r in the order of dss_unit_campaign (per point the
 * two encoder errors, then per repeat the two centroid noises), computed in
 * vectorised chunks (dss_readings.c). */
void dss_campaign_batch(const sunmc_config *c, const dss_unit *u, rng_stream *r, size_t n,
                        const double *b1_rad, const double *b2_rad, dss_campaign_point *out);

/* One validation point (dss_validation_batch). */
typedef struct {
    double x_px, y_px;             /* with centroid noise */
    double x0_px, y0_px;           /* the same reading without noise */
    double alpha0_rad, beta0_rad;  /* the table's truth, eq. 3-4 */
    int seen;                      /* 0: spot off the detector (x, y meaningless) */
} dss_validation_point;

/* n validation readings with fresh centroid noise from r (two normals per
 * point, spot or not), plus each reading without its noise, in vectorised
 * chunks (dss_readings.c); splitting the points over calls gives the same
 * bits. */
void dss_validation_batch(const sunmc_config *c, const dss_unit *u, rng_stream *r, size_t n,
                          const double *b1_rad, const double *b2_rad, dss_validation_point *out);

/* trig = {cos b1, sin b1, cos b2, sin b2} of n table angle pairs, the
 * arrays of vm_pad(n) values (vmath.h) as the kernels make them. */
void dss_trig_fill(size_t n, const double *b1_rad, const double *b2_rad, double *const trig[4]);

/* The same with the table angles' cosines and sines given: trig = {cos
 * b1, sin b1, cos b2, sin b2}, arrays of n (a per-run table, as
 * dss_val_alloc keeps); the same bits as dss_validation_batch. */
void dss_validation_batch_trig(const sunmc_config *c, const dss_unit *u, rng_stream *r, size_t n,
                               const double *b1_rad, const double *b2_rad,
                               const double *const trig[4], dss_validation_point *out);

/* The field angle (deg) of sun angles alpha, beta (rad): the angle from the
 * boresight, atan(hypot(tan alpha, tan beta)); the report's bands bin on it. */
double dss_field_angle_deg(double alpha, double beta);

int dss_par_names(const sunmc_config *c, const char **names, int max);
int dss_par_values(const sunmc_config *c, const dss_calibration *cal, double corr, int i, int j,
                   double rcond, double *out, int max);

#endif
