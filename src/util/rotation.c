/* rotation.c - elementary rotations, zxy, the two-axis table and sun angles
 * (see rotation.h for the one convention). */
#include "rotation.h"
#include "status.h"

#include <math.h>
#include <string.h>

static void set(mat3 r, double a0, double a1, double a2, double b0, double b1, double b2,
                double c0, double c1, double c2)
{
    r[0][0] = a0; r[0][1] = a1; r[0][2] = a2;
    r[1][0] = b0; r[1][1] = b1; r[1][2] = b2;
    r[2][0] = c0; r[2][1] = c1; r[2][2] = c2;
}

void rot_x(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, 1, 0, 0, 0, c, s, 0, -s, c); }
void rot_y(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, c, 0, -s, 0, 1, 0, s, 0, c); }
void rot_z(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, c, s, 0, -s, c, 0, 0, 0, 1); }
void drot_x(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, 0, 0, 0, 0, -s, c, 0, -c, -s); }
void drot_y(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, -s, 0, -c, 0, 0, 0, c, 0, -s); }
void drot_z(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, -s, c, 0, -c, -s, 0, 0, 0, 0); }

void mat3_mul(const mat3 a, const mat3 b, mat3 out)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
}

void mat3_vec(const mat3 a, const double v[3], double out[3])
{
    double t[3];
    for (int i = 0; i < 3; i++)
        t[i] = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2];
    memcpy(out, t, sizeof t);
}

void mat3_transpose(const mat3 a, mat3 out)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[i][j] = a[j][i];
}

void sun_direction(double sun_x, double sun_y, double v[3])
{
    v[0] = cos(sun_y) * sin(sun_x);
    v[1] = sin(sun_y);
    v[2] = cos(sun_y) * cos(sun_x);
}

void rot_zxy(double tx, double ty, double tz, mat3 c)
{
    double cx = cos(tx), sx = sin(tx), cy = cos(ty), sy = sin(ty), cz = cos(tz), sz = sin(tz);
    set(c, cy * cz - sy * sx * sz, cy * sz + sy * sx * cz, -sy * cx,
        -cx * sz, cx * cz, sx,
        sy * cz + cy * sx * sz, sy * sz - cy * sx * cz, cy * cx);
}

void rot_zxy_deriv(double tx, double ty, double tz, mat3 d_tx, mat3 d_ty, mat3 d_tz)
{
    mat3 rx, ry, rz, drx, dry, drz, t;
    rot_x(tx, rx);
    rot_y(ty, ry);
    rot_z(tz, rz);
    drot_x(tx, drx);
    drot_y(ty, dry);
    drot_z(tz, drz);
    mat3_mul(ry, drx, t);
    mat3_mul(t, rz, d_tx);
    mat3_mul(dry, rx, t);
    mat3_mul(t, rz, d_ty);
    mat3_mul(ry, rx, t);
    mat3_mul(t, drz, d_tz);
}

void table_rotation(double b1, double b2, mat3 r) { rot_zxy(b1, b2, 0.0, r); }

void table_truth(double b1, double b2, double *alpha, double *beta)
{
    *alpha = -b2;
    *beta = atan(tan(b1) / cos(b2));
}

void sun_angles_of(const double u[3], double *alpha, double *beta)
{
    *alpha = atan2(u[0], u[2]);
    *beta = atan2(u[1], u[2]);
}

void sun_vector_of(double alpha, double beta, double u[3])
{
    double tx = tan(alpha), ty = tan(beta), n = sqrt(1.0 + tx * tx + ty * ty);
    u[0] = tx / n;
    u[1] = ty / n;
    u[2] = 1.0 / n;
}

int table_solve(const double v[3], const double w[3], double *b1, double *b2)
{
    /* rot_x(b1) v = rot_y(-b2) w.  rot_x keeps the x component: with w_x =
     * rho sin phi, w_z = rho cos phi, (rot_y(-b2) w)_x = rho sin(phi + b2) = v_x. */
    double rho = hypot(w[0], w[2]);
    if (!(rho > fabs(v[0])))
        return SUNMC_EDOM;
    double phi = atan2(w[0], w[2]);
    *b2 = asin(v[0] / rho) - phi;
    mat3 ry;
    rot_y(-*b2, ry);
    double q[3];
    mat3_vec(ry, w, q);
    /* rot_x(b1) turns the (y, z) angle atan2(y, z) by +b1. */
    *b1 = atan2(q[1], q[2]) - atan2(v[1], v[2]);
    return SUNMC_OK;
}

double angle_between(const double u[3], const double v[3])
{
    double cx = u[1] * v[2] - u[2] * v[1];
    double cy = u[2] * v[0] - u[0] * v[2];
    double cz = u[0] * v[1] - u[1] * v[0];
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), u[0] * v[0] + u[1] * v[1] + u[2] * v[2]);
}
