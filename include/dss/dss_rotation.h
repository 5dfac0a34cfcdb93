/* dss_rotation.h - the DSS paper's zxy rotations, derived here (the
 * extracted eq. 1 of the DSS paper has sign typos), and the rotary table.
 *
 * Conventions (all angles in radians):
 *  - Elementary rotations are passive (frame) rotations, right-handed:
 *    v_new = R v_old expresses a fixed vector in the frame rotated by +a
 *    about the axis:
 *        Rx(a) = [1 0 0; 0 c s; 0 -s c]
 *        Ry(a) = [c 0 -s; 0 1 0; s 0 c]
 *        Rz(a) = [c s 0; -s c 0; 0 0 1]
 *    (rotation.h's rot_y has the opposite sign of s; the DSS code uses only
 *    these.)
 *  - "Rotated by the order zxy with (tx, ty, tz)" means: first tz about Z,
 *    then tx about the new X, then ty about the newest Y:
 *        C = Ry(ty) Rx(tx) Rz(tz)
 *          = [ cy cz - sy sx sz   cy sz + sy sx cz   -sy cx ]
 *            [ -cx sz             cx cz               sx    ]
 *            [ sy cz + cy sx sz   sy sz - cy sx cz    cy cx ]
 *    The DSS paper's eq. 1 is this matrix with (theta1, theta2, theta3) =
 *    -(tx, ty, tz) (active angles) except for sign typos in elements (1,1),
 *    (3,1) and (3,2); its text names c1, c2 the rotations about X and Y and
 *    c3 the one about the principal axis Z, which is the assignment used here.
 *  - Rotary table: table angles (b1, b2) rotate the table top from its zero
 *    by zxy with (b1 about X, b2 about Y, 0 about Z): R(b) = Ry(b2) Rx(b1).
 *    The sun, along +Z of the table base at zero, is then, in the table top,
 *        u = R(b) (0,0,1) = (-sin b2 cos b1, sin b1, cos b1 cos b2).
 *  - Sun angles of a unit vector u toward the sun: alpha = atan(ux/uz),
 *    beta = atan(uy/uz).  For u above: alpha0 = -b2 and
 *    beta0 = atan(tan b1 / cos b2): the DSS paper's eq. 3-4.  (The paper's
 *    eq. 2 prints the vector with the signs of x and y flipped, the
 *    direction of the image-side ray; eq. 3-4 hold for both.)
 */
#ifndef SUNMC_DSS_ROTATION_H
#define SUNMC_DSS_ROTATION_H

#include "rotation.h" /* mat3, mat3_mul, mat3_vec, mat3_transpose */

/* Elementary passive rotations (above) and their derivatives d/da. */
void dss_rot_x(double a, mat3 r);
void dss_rot_y(double a, mat3 r);
void dss_rot_z(double a, mat3 r);
void dss_drot_x(double a, mat3 r);
void dss_drot_y(double a, mat3 r);
void dss_drot_z(double a, mat3 r);

/* C = Ry(ty) Rx(tx) Rz(tz), from the closed form above. */
void dss_zxy(double tx, double ty, double tz, mat3 c);

/* Partial derivatives of dss_zxy with respect to tx, ty and tz. */
void dss_zxy_deriv(double tx, double ty, double tz, mat3 d_tx, mat3 d_ty, mat3 d_tz);

/* Table rotation R(b) = Ry(b2) Rx(b1). */
void dss_table_rotation(double b1, double b2, mat3 r);

/* Truth angles (rad) of the table at (b1, b2) rad: eq. 3-4. */
void dss_table_truth(double b1, double b2, double *alpha, double *beta);

/* Sun angles (rad) of a vector u toward the sun (u[2] > 0). */
void dss_angles_of(const double u[3], double *alpha, double *beta);

/* Unit vector toward the sun for sun angles (rad). */
void dss_vector_of(double alpha, double beta, double u[3]);

/* Angle (rad) between unit vectors u and v, accurate for small angles. */
double dss_angle_between(const double u[3], const double v[3]);

/* Solve R(b) v = w for the table angles (b1, b2) rad, v and w unit vectors
 * near +Z (|b2| < 90 deg).  SUNMC_EDOM when no such b exists. */
int dss_table_solve(const double v[3], const double w[3], double *b1, double *b2);

#endif
