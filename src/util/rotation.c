/* rotation.c - elementary rotations (see rotation.h for the conventions). */
#include "rotation.h"

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
void rot_y(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, c, 0, s, 0, 1, 0, -s, 0, c); }
void rot_z(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, c, s, 0, -s, c, 0, 0, 0, 1); }
void drot_x(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, 0, 0, 0, 0, -s, c, 0, -c, -s); }
void drot_y(double a, mat3 r) { double c = cos(a), s = sin(a); set(r, -s, 0, c, 0, 0, 0, -c, 0, -s); }
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
