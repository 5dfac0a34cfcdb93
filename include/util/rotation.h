/* rotation.h - 3x3 frame rotations and the turntable's sun vector.
 *
 * All matrices are passive (frame) rotations: v_new = R v_old expresses a
 * fixed vector in a frame rotated by the angle (radians) about the axis.
 *   rot_x(a) = [1 0 0; 0 c s; 0 -s c]
 *   rot_y(a) = [c 0 s; 0 1 0; -s 0 c]     (so rot_x(alpha) rot_y(beta) (0,0,1)
 *   rot_z(a) = [c s 0; -s c 0; 0 0 1]      = (sin b, cos b sin a, cos b cos a))
 * The d* variants are the derivatives with respect to the angle.
 */
#ifndef SUNMC_ROTATION_H
#define SUNMC_ROTATION_H

typedef double mat3[3][3];

void rot_x(double a, mat3 r);
void rot_y(double a, mat3 r);
void rot_z(double a, mat3 r);
void drot_x(double a, mat3 r);
void drot_y(double a, mat3 r);
void drot_z(double a, mat3 r);

void mat3_mul(const mat3 a, const mat3 b, mat3 out);   /* out = a b (out may not alias) */
void mat3_vec(const mat3 a, const double v[3], double out[3]);
void mat3_transpose(const mat3 a, mat3 out);

/* Sun direction of a simulator tilted by sun_x toward +X and sun_y toward +Y
 * (radians): rot_y(sun_x) rot_x(sun_y) (0,0,1). */
void sun_direction(double sun_x, double sun_y, double v[3]);

#endif
