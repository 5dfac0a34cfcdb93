/* psd_overlap.c - area and first moments of a disc within a rectangle,
 * in closed form (psd_sensor.h): the quadrant photodiode's four overlaps
 * and the light's centroid on a lateral PSD.
 *
 * For the disc x^2 + y^2 <= R^2 and the region x > a, y > b, with
 * h(x) = sqrt(R^2 - x^2): the chord above b is h - b where |x| < xb =
 * sqrt(R^2 - b^2), and, when b < 0, the whole 2h where |x| >= xb.  Its
 * integrals use H0 = int h dx = (x h + R^2 asin(x/R))/2, H1 = int x h dx =
 * -h^3/3 and, for the y moment, int (h^2 - b^2)/2 dx. */
#include "psd_sensor.h"

#include <math.h>

static double h0(double R, double x)
{
    double t = x / R;
    t = t > 1 ? 1 : t < -1 ? -1 : t;
    double h = sqrt(fmax(R * R - x * x, 0.0));
    return 0.5 * (x * h + R * R * asin(t));
}

static double h1(double R, double x)
{
    double h = sqrt(fmax(R * R - x * x, 0.0));
    return -h * h * h / 3.0;
}

/* Add the piece on [x1, x2] (clipped to x > a) with chord h - b (full = 0)
 * or 2h (full = 1). */
static void piece(double R, double a, double b, double x1, double x2, int full, double s[3])
{
    if (x1 < a)
        x1 = a;
    if (!(x2 > x1))
        return;
    if (full) {
        s[0] += 2.0 * (h0(R, x2) - h0(R, x1));
        s[1] += 2.0 * (h1(R, x2) - h1(R, x1));
        return;
    }
    s[0] += h0(R, x2) - h0(R, x1) - b * (x2 - x1);
    s[1] += h1(R, x2) - h1(R, x1) - 0.5 * b * (x2 * x2 - x1 * x1);
    double k = R * R - b * b;
    s[2] += 0.5 * (k * (x2 - x1) - (x2 * x2 * x2 - x1 * x1 * x1) / 3.0);
}

/* Area s[0], x moment s[1], y moment s[2] of the disc in x > a, y > b. */
static void corner(double R, double a, double b, double s[3])
{
    s[0] = s[1] = s[2] = 0.0;
    if (b >= R || a >= R)
        return;
    if (b <= -R) {
        piece(R, a, b, -R, R, 1, s);
        return;
    }
    double xb = sqrt(R * R - b * b);
    piece(R, a, b, -xb, xb, 0, s);
    if (b < 0) {
        piece(R, a, b, -R, -xb, 1, s);
        piece(R, a, b, xb, R, 1, s);
    }
}

void psd_disc_rect(double R, double x1, double x2, double y1, double y2, double *area,
                   double *mx, double *my)
{
    double s11[3], s21[3], s12[3], s22[3];
    corner(R, x1, y1, s11);
    corner(R, x2, y1, s21);
    corner(R, x1, y2, s12);
    corner(R, x2, y2, s22);
    *area = s11[0] - s21[0] - s12[0] + s22[0];
    *mx = s11[1] - s21[1] - s12[1] + s22[1];
    *my = s11[2] - s21[2] - s12[2] + s22[2];
}
