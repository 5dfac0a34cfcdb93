/* psd_sensor.h - the physics of the four-channel analog sun sensor.
 *
 * Frames and conventions (rotation.h, optics.h): the sensor frame has the
 * detector in the plane z = 0, its centre at the origin, edges along X and
 * Y; the aperture is at (x0, y0, h); a cover glass of thickness t and index
 * n may lie between them.  u is the unit vector toward the sun in the
 * sensor frame; the spot's centre is spot = (x0, y0) - (ux, uy) q with q of
 * optics_q.  The mount (detector rotations about X, Y, Z in zxy order,
 * rotation.h's rot_zxy) takes the table top's vector to the sensor frame:
 * u = M u_top.
 *
 * The spot is modelled as a uniform disc of radius
 *     R = aperture/2 + h tan(PSD_SUN_HALF_ANGLE_DEG)
 * (the aperture's shadow widened by the sun's 0.53 deg disc; a uniform disc
 * in place of their convolution).  The light on the detector is
 * P = u_z * (the disc's area on the active area) / (pi R^2), 1 for the sun
 * at the normal with the whole spot on the detector.
 *
 * Channels, by design.detector:
 *  - lateral, duo (electrode pairs): x = (i2 - i1)/(i1 + i2) and y = (i4 -
 *    i3)/(i3 + i4); each face collects the whole photocurrent: i1,2 = P (1
 *    -+ X)/2, i3,4 = P (1 -+ Y)/2, with X = 2 cx/L, Y = 2 cy/L and (cx, cy)
 *    the centroid of the light on the active area (L the side): linear,
 *    clipped at the edges (a spot partly off the area: the centroid of
 *    what remains).
 *  - lateral, tetra (corner electrodes, the pincushion-improved form):
 *    i_k = P/4 (1 + sx_k X')(1 + sy_k Y') with corner signs 1 (-,-), 2
 *    (+,+), 3 (+,-), 4 (-,+), so x = (i2 + i3 - i1 - i4)/sum = X' and y =
 *    (i2 + i4 - i1 - i3)/sum = Y', with the tetra-lateral's pincushion
 *    X' = X (1 + k Y^2), Y' = Y (1 + k X^2) (k = design.pincushion).
 *  - quadrant: i_k = u_z A_k / (pi R^2), A_k the disc's area on quadrant k
 *    (same corner signs; the quadrants are the active square less a gap g
 *    along both axes); x and y as for tetra: linear within the spot's
 *    size, saturated (+-1) beyond.
 * Measured channel k (fractions of the ADC's full scale): signal_fs (1 +
 * gain_k) (i_k + b/4) + dark_k, b the uniform background; inverted
 * polarity (an inverting amplifier): dark_k - signal_fs (...).  Then
 * Gaussian noise and the ADC's quantisation (psd_adc).
 */
#ifndef SUNMC_PSD_SENSOR_H
#define SUNMC_PSD_SENSOR_H

#include "psd_config.h"
#include "rotation.h"

#define PSD_SUN_HALF_ANGLE_DEG 0.2665

typedef struct {
    int detector, lateral;
    double x0_mm, y0_mm, h_mm;
    double glass_t_mm, glass_n;
    double R_mm, half_mm, gap_half_mm, pincushion;
    mat3 M;                          /* table top -> sensor */
    double gain[PSD_CHANNELS];       /* signal_fs (1 + gain_k), signed by the polarity */
    double dark[PSD_CHANNELS];       /* fraction of full scale */
    double background;               /* fraction of the sun's normal signal */
} psd_sensor;

/* The nominal sensor of design d (no deviation). */
void psd_sensor_nominal(const psd_design *d, psd_sensor *s);
/* The sensor of design d with deviations dev. */
void psd_sensor_build(const psd_design *d, const psd_deviations *dev, psd_sensor *s);

/* Spot centre (mm) for sun direction u (sensor frame).  SUNMC_EDOM when
 * the sun is not in front or is totally reflected. */
int psd_sensor_spot(const psd_sensor *s, const double u[3], double spot[2]);

/* Photocurrents i[4] (P units above) of a spot centred at spot[2] with
 * light u_z (lateral: the centroid's clipping; quadrant: the overlaps). */
void psd_sensor_currents(const psd_sensor *s, const double spot[2], double uz, double i[4]);

/* The two ratios x, y of channel signals sig[4] (see above). */
void psd_ratios(int detector, int lateral, const double sig[4], double *x, double *y);

/* Noiseless measured channels m[4] for sun direction u.  SUNMC_EDOM as
 * psd_sensor_spot, or when no light reaches the detector. */
int psd_sensor_read(const psd_sensor *s, const double u[3], double m[4]);
/* The same with the sun's light scaled by `light` (the lab's lamp at this
 * reading, noise.lamp_pct): m_k = dark_k + gain_k (light i_k + b share). */
int psd_sensor_read_lit(const psd_sensor *s, const double u[3], double light, double m[4]);

/* Quantise m (fraction of full scale) to `bits` bits: clipped to [0, 1]. */
double psd_adc(double m, int bits);

/* Area and first moments of a disc of radius R centred at the origin
 * within the rectangle [x1, x2] x [y1, y2] (closed forms, psd_overlap.c). */
void psd_disc_rect(double R, double x1, double x2, double y1, double y2, double *area,
                   double *mx, double *my);

/* The table top's sun vector for table angles (rad) under c's convention
 * (psd_config.h, enum psd_table). */
void psd_table_sun(const psd_config *pc, double alpha, double beta, double u[3]);

#endif
