/* dss_score.h - scoring DSS readings against the table's truth, many at a
 * time (vectorised, dss_score.c): the on-board angles of spots, the field
 * angle of the truth and the total angle error.  Arrays hold vm_pad(k)
 * values (vmath.h), the pads any valid numbers. */
#ifndef SUNMC_DSS_SCORE_H
#define SUNMC_DSS_SCORE_H

#include <stddef.h>

/* The table's truth angles (eq. 3-4, table_truth) of k positions. */
void dss_table_truth_batch(size_t k, const double *b1, const double *b2, double *alpha,
                           double *beta);

/* The truth angles (dss_truth_angles, dss_sensor.h) of k table positions
 * under mount mode `mount` and sun simulator v_sun: the angles of R(b)
 * v_sun when mounted, eq. 3-4 when aligned (padded arrays). */
void dss_truth_batch(int mount, const double v_sun[3], size_t k, const double *b1,
                     const double *b2, double *alpha, double *beta);

/* The same with the angles' cosines and sines given (c1 = cos b1, s1 = sin
 * b1, c2 = cos b2, s2 = sin b2; padded arrays): the same bits. */
void dss_truth_batch_trig(int mount, const double v_sun[3], size_t k, const double *b1,
                          const double *b2, const double *c1, const double *s1,
                          const double *c2, const double *s2, double *alpha, double *beta);

/* Field angle (deg) of the directions with angles (alpha0, beta0) rad:
 * atan(hypot(tan alpha0, tan beta0)). */
void dss_field_chunk(size_t k, const double *alpha0, const double *beta0, double *field_deg);

/* The angle (rad) between the directions of (alpha, beta) and of
 * (alpha0, beta0): angle_between of their sun_vector_of. */
void dss_total_error_chunk(size_t k, const double *alpha, const double *beta,
                           const double *alpha0, const double *beta0, double *total);

/* The truth's side of both, made once for several scorings of the same
 * points: the unit vector (vx, vy, vz) of (alpha0, beta0) (sun_vector_of)
 * and its field angle (deg), the same bits as dss_field_chunk; then the
 * total angle error of (alpha, beta) against that vector, the same bits as
 * dss_total_error_chunk. */
void dss_truth_vector_chunk(size_t k, const double *alpha0, const double *beta0, double *vx,
                            double *vy, double *vz, double *field_deg);
void dss_total_error_vec_chunk(size_t k, const double *alpha, const double *beta,
                               const double *vx, const double *vy, const double *vz,
                               double *total);

#endif
