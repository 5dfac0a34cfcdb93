/* rotation.h - 3x3 frame rotations, the zxy rotation order, the two-axis
 * turntable and sun angles: the geometry every family shares.
 *
 * One convention (all angles in radians):
 *  - Elementary rotations are passive (frame) rotations, right-handed:
 *    v_new = R v_old expresses a fixed vector in the frame rotated by +a
 *    about the axis:
 *        rot_x(a) = [1 0 0; 0 c s; 0 -s c]
 *        rot_y(a) = [c 0 -s; 0 1 0; s 0 c]
 *        rot_z(a) = [c s 0; -s c 0; 0 0 1]
 *    The d* variants are the derivatives with respect to the angle.  A
 *    family whose own angle turns the sensor (an active rotation, as the
 *    ESS's table beta and install_y) passes its negative: rot_y(-b).
 *  - "Rotated by the order zxy with (tx, ty, tz)" means: first tz about Z,
 *    then tx about the new X, then ty about the newest Y:
 *        C = rot_y(ty) rot_x(tx) rot_z(tz)
 *          = [ cy cz - sy sx sz   cy sz + sy sx cz   -sy cx ]
 *            [ -cx sz             cx cz               sx    ]
 *            [ sy cz + cy sx sz   sy sz - cy sx cz    cy cx ]
 *    The DSS paper's eq. 1 is this matrix with (theta1, theta2, theta3) =
 *    -(tx, ty, tz) (active angles) except for sign typos in elements (1,1),
 *    (3,1) and (3,2); its text names c1, c2 the rotations about X and Y and
 *    c3 the one about the principal axis Z, which is the assignment used here.
 *  - Two-axis table: table angles (b1, b2) rotate the table top from its
 *    zero by zxy with (b1 about X, b2 about Y, 0 about Z): R(b) = rot_y(b2)
 *    rot_x(b1).  The sun, along +Z of the table base at zero, is then, in
 *    the table top, u = R(b) (0,0,1) = (-sin b2 cos b1, sin b1, cos b1 cos b2).
 *  - Sun angles of a unit vector u toward the sun: alpha = atan(ux/uz),
 *    beta = atan(uy/uz).  For u above: alpha0 = -b2 and
 *    beta0 = atan(tan b1 / cos b2): the DSS paper's eq. 3-4.  (The paper's
 *    eq. 2 prints the vector with the signs of x and y flipped, the
 *    direction of the image-side ray; eq. 3-4 hold for both.)
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
 * (radians): rot_y(-sun_x) rot_x(sun_y) (0,0,1)
 * = (cos sun_y sin sun_x, sin sun_y, cos sun_y cos sun_x). */
void sun_direction(double sun_x, double sun_y, double v[3]);

/* C = rot_y(ty) rot_x(tx) rot_z(tz), from the closed form above. */
void rot_zxy(double tx, double ty, double tz, mat3 c);

/* Partial derivatives of rot_zxy with respect to tx, ty and tz. */
void rot_zxy_deriv(double tx, double ty, double tz, mat3 d_tx, mat3 d_ty, mat3 d_tz);

/* Table rotation R(b) = rot_y(b2) rot_x(b1). */
void table_rotation(double b1, double b2, mat3 r);

/* Truth angles (rad) of the table at (b1, b2) rad: eq. 3-4. */
void table_truth(double b1, double b2, double *alpha, double *beta);

/* Solve R(b) v = w for the table angles (b1, b2) rad, v and w unit vectors
 * near +Z (|b2| < 90 deg).  SUNMC_EDOM when no such b exists. */
int table_solve(const double v[3], const double w[3], double *b1, double *b2);

/* Sun angles (rad) of a vector u toward the sun (u[2] > 0). */
void sun_angles_of(const double u[3], double *alpha, double *beta);

/* Unit vector toward the sun for sun angles (rad). */
void sun_vector_of(double alpha, double beta, double u[3]);

/* Angle (rad) between unit vectors u and v, accurate for small angles. */
double angle_between(const double u[3], const double v[3]);

#endif
