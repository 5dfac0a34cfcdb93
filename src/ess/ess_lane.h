/* ess_lane.h - the ESS sensor's physics for one reading, as inline
 * functions: the scalar API (ess_slit.c, ess_finecode.c) and the vectorised
 * batch (ess_sensor_output_chunk, one reading per vector lane) are the same
 * code.  The formulas are documented in ess_sensor.h, ess_slit.c and
 * ess_finecode.c.  Everything is passed and returned by value so that GCC
 * vectorises a loop calling these (vmath.h). */
#ifndef SUNMC_ESS_LANE_H
#define SUNMC_ESS_LANE_H

#include "ess_sensor.h"
#include "ess_series.h"
#include "vmath.h"

/* Below this |z|, sinc(z) = 1 to double precision. */
#define ESS_SINC_SMALL 1e-8

/* The dial coordinate (mm) where the slit image crosses the row at x_mm
 * (ess_slit.c). */
VM_INLINE double ess_lane_eta(const ess_sensor *s, double x_mm, double u, double v)
{
    double h = s->Hp_mm + x_mm * s->tan_tau; /* the row's height: the dial's tilt */
    return h * v - s->dd_mm - (x_mm + h * u) * s->tan_dphi;
}

/* sin(n pi z) / (n pi z) for n = 1, 3, 5 from one sine: sin 3t = sin t
 * (3 - 4 sin^2 t), sin 5t = sin t (16 sin^4 t - 20 sin^2 t + 5). */
typedef struct {
    double s1, s3, s5;
} ess_lane_sinc135;

VM_INLINE ess_lane_sinc135 ess_lane_sinc_pi135(double z)
{
    double s = sin(M_PI * z), s2 = s * s;
    double t = M_PI * z;
    ess_lane_sinc135 o;
    o.s1 = vm_select(fabs(z) < ESS_SINC_SMALL, 1.0, s / t);
    o.s3 = vm_select(fabs(3 * z) < ESS_SINC_SMALL, 1.0, s * (3.0 - 4.0 * s2) / (3 * t));
    o.s5 = vm_select(fabs(5 * z) < ESS_SINC_SMALL, 1.0,
                     s * ((16.0 * s2 - 20.0) * s2 + 5.0) / (5 * t));
    return o;
}

/* Relative harmonic amplitudes c_n (n = 1, 3, 5) at dial angle psi. */
typedef struct {
    double c1, c3, c5;
} ess_lane_harm;

/* The same from cos^2(psi) (the batch has it as 1 / (1 + tan^2 psi)). */
VM_INLINE ess_lane_harm ess_lane_harmonics_cos2(const ess_sensor *s, double cos2_psi)
{
    double slit_ang = s->slit_width_mm * cos2_psi / s->H_mm;
    int given = s->harmonics_given;
    ess_lane_sinc135 q = ess_lane_sinc_pi135(slit_ang / s->theta0_rad);
    ess_lane_harm h;
    h.c1 = vm_select(given, s->given_ratio[0], s->dial_sun[0] * q.s1 / s->norm1);
    h.c3 = vm_select(given, s->given_ratio[1], s->dial_sun[1] * q.s3 / s->norm1);
    h.c5 = vm_select(given, s->given_ratio[2], s->dial_sun[2] * q.s5 / s->norm1);
    return h;
}

/* The same from q = cos^2(psi) with the sensor's scales (inv_H,
 * slit_z_per_cos2, harm_scale, harm_scale_n: ess_sensor_init): one
 * division (1 / (pi z)) instead of nine; within a few ulps of
 * ess_lane_harmonics_cos2. */
VM_INLINE ess_lane_harm ess_lane_harmonics_q(const ess_sensor *s, double q)
{
    double z = s->slit_z_per_cos2 * q, t = M_PI * z, r = 1.0 / t;
    double sn = sin(t), s2 = sn * sn;
    int given = s->harmonics_given;
    const double *k = s->harm_scale, *kn = s->harm_scale_n;
    double s1 = vm_select(fabs(z) < ESS_SINC_SMALL, k[0], kn[0] * (sn * r));
    double s3 = vm_select(fabs(3 * z) < ESS_SINC_SMALL, k[1], kn[1] * (sn * (3.0 - 4.0 * s2) * r));
    double s5 = vm_select(fabs(5 * z) < ESS_SINC_SMALL, k[2],
                          kn[2] * (sn * ((16.0 * s2 - 20.0) * s2 + 5.0) * r));
    ess_lane_harm h;
    h.c1 = vm_select(given, s->given_ratio[0], s1);
    h.c3 = vm_select(given, s->given_ratio[1], s3);
    h.c5 = vm_select(given, s->given_ratio[2], s5);
    return h;
}

VM_INLINE ess_lane_harm ess_lane_harmonics(const ess_sensor *s, double psi_rad)
{
    double cos_psi = cos(psi_rad);
    return ess_lane_harmonics_cos2(s, cos_psi * cos_psi);
}

/* Current of fine row m with harmonics h, illumination illum and additive
 * noise, from the cosine c and sine sn of its phase x = 2 pi psi / theta0
 * - m pi / 2: cos 3x and cos 5x from them (Chebyshev: cos 3x = cos x (4
 * cos^2 x - 3), sin 3x = sin x (3 - 4 sin^2 x), cos 5x = cos x (16 cos^4 x
 * - 20 cos^2 x + 5)), the third harmonic's phase as its cosine and sine
 * (ess_sensor). */
VM_INLINE double ess_lane_current_cs(const ess_sensor *s, int m, ess_lane_harm h, double c,
                                     double sn, double illum, double noise)
{
    double c2 = c * c;
    double c3 = c * (4.0 * c2 - 3.0), s3 = sn * (3.0 - 4.0 * sn * sn);
    double c5 = c * ((16.0 * c2 - 20.0) * c2 + 5.0);
    double sum = h.c1 * c + h.c3 * (c3 * s->harmonic_cos - s3 * s->harmonic_sin) + h.c5 * c5;
    return illum * s->gain[m] * (s->dc_ratio - sum) + noise;
}

/* Current of fine row m (0..3) at dial angle psi_rad. */
VM_INLINE double ess_lane_current(const ess_sensor *s, int m, ess_lane_harm h, double psi_rad,
                                  double illum, double noise)
{
    double x = 2.0 * M_PI * psi_rad / s->theta0_rad - m * M_PI / 2.0;
    return ess_lane_current_cs(s, m, h, cos(x), sin(x), illum, noise);
}

/* Fine row m's current (m = 1..3) from row 0's dial tangent t0, q = 1 /
 * (1 + t0^2), w = v - u tan(dphi) and the cosine and sine of row 0's
 * phase: row m's tangent is t0 + dt (dt = s->fine_dt[m] + s->fine_dt_w[m]
 * w: ess_lane_eta is linear in x, and only the dial tilt's share depends
 * on the sun direction), so its dial angle is psi0 + atan(e), e =
 * dt / (1 + t0 (t0 + dt)) = a / (1 + t0 a) with a = dt q (|t0 a| <= |dt|
 * / 2 <= 5e-3: 1 / (1 + t0 a) by its series to the 7th power, the rest
 * below 4e-19), and its phase row 0's turned by 2 pi / theta0 times
 * that, less m quarter turns (exact: the cosine and sine swap and change
 * sign).  No division: they are the loop's dearest operations. */
VM_INLINE double ess_lane_current_from0(const ess_sensor *s, int m, ess_lane_harm h, double t0,
                                        double q, double w, double c0, double s0, double illum)
{
    double a = (s->fine_dt[m] + s->fine_dt_w[m] * w) * q, nb = -t0 * a;
    double g = 1.0 + nb * (1.0 + nb * (1.0 + nb * (1.0 + nb * (1.0 + nb * (1.0 + nb *
               (1.0 + nb))))));
    double d = s->fine_turn * ess_lane_atan_small(a * g);
    ess_lane_cs r = ess_lane_turn(c0, s0, d);
    double c = m == 1 ? r.s : m == 2 ? -r.c : -r.s;
    double sn = m == 1 ? -r.c : m == 2 ? -r.s : r.c;
    return ess_lane_current_cs(s, m, h, c, sn, illum, 0.0);
}

/* The phase in [0, 2 pi) of the phasor (x, y) = (i2 - i0, i3 - i1). */
VM_INLINE double ess_lane_phase_xy(double x, double y)
{
    double ph = atan2(y, x);
    return vm_select(ph < 0, ph + 2.0 * M_PI, ph);
}

/* Fine-code phase in [0, 2 pi) from the four currents (ESS paper Fig. 8). */
VM_INLINE double ess_lane_demodulate(double i0, double i1, double i2, double i3)
{
    return ess_lane_phase_xy(i2 - i0, i3 - i1);
}

/* The phase of (x0, y0) from ph in [0, 2 pi), that of a nearby phasor
 * (x, y): turned by the angle between them, atan(e), e = (x y0 - y x0) /
 * (x x0 + y y0), by its series (ess_lane_atan_quarter), back into [0, 2
 * pi).  far = 1 where |e| > ESS_PHASE0_SERIES_TAN or the phasors are a
 * quarter turn or more apart (ph is then meaningless: the caller takes
 * atan2), else 0. */
typedef struct {
    double ph, far;
} ess_lane_phase;

VM_INLINE ess_lane_phase ess_lane_phase_near(double ph, double x, double y, double x0, double y0)
{
    double cross = x * y0 - y * x0, dot = x * x0 + y * y0;
    double e = cross / dot;
    int ok = dot > 0 && fabs(e) <= ESS_PHASE0_SERIES_TAN;
    double p = ph + ess_lane_atan_quarter(vm_keep(ok, e));
    p = vm_select(p < 0, p + 2.0 * M_PI, p);
    ess_lane_phase o = {vm_select(p >= 2.0 * M_PI, p - 2.0 * M_PI, p), vm_select(ok, 0.0, 1.0)};
    return o;
}

/* The Gray-coded coarse rows (ess_coarse.c) in exact double arithmetic (a
 * vector lane has no cheap 64-bit integers): a running decode over rows
 * j = 0 .. n-1, the most significant bit first. */
typedef struct {
    double parity; /* XOR of the Gray bits so far: the current binary bit */
    double cell;   /* decoded cell index so far */
} ess_lane_coarse;

/* Bit m (0 or 1) of a whole number 0 <= k < 2^53. */
VM_INLINE double ess_lane_bit(double k, double scale_m /* 2^-m */)
{
    double q = floor(k * scale_m);
    return q - 2.0 * floor(0.5 * q);
}

/* The cell (clamped to the dial) holding dial angle psi. */
VM_INLINE double ess_lane_coarse_cell(const ess_sensor *s, double psi_rad)
{
    double ncell = s->coarse_cells;
    double k = floor((psi_rad - s->coarse_origin_rad) / s->coarse_res_rad);
    k = vm_select(k < 0.0, 0.0, k);
    return vm_select(k > ncell - 1.0, ncell - 1.0, k);
}

/* Row j reads cell k: the bit m = n-1-j of k's Gray code is this row's
 * bit; two_m = 2^m. */
VM_INLINE ess_lane_coarse ess_lane_coarse_bit(double two_m, double k, ess_lane_coarse acc)
{
    double g = fabs(ess_lane_bit(k, 1.0 / two_m) - ess_lane_bit(k, 0.5 / two_m));
    acc.parity = fabs(acc.parity - g);
    acc.cell += acc.parity * two_m;
    return acc;
}

/* Row j reads dial angle psi: its cell (ess_lane_coarse_cell) and bit. */
VM_INLINE ess_lane_coarse ess_lane_coarse_row(const ess_sensor *s, double two_m, double psi_rad,
                                              ess_lane_coarse acc)
{
    return ess_lane_coarse_bit(two_m, ess_lane_coarse_cell(s, psi_rad), acc);
}

/* The cell of a row whose dial tangent is t, given a cell k0 within one
 * of it and the tangents lo, hi of k0's edges (-inf, +inf at the dial's
 * ends): the row's angle against the cell edges, compared as tangents
 * (atan rises), so no arctangent. */
VM_INLINE double ess_lane_coarse_near(double k0, double lo, double hi, double t)
{
    return k0 - vm_select(t < lo, 1.0, 0.0) + vm_select(t >= hi, 1.0, 0.0);
}

/* The tangents of cell k's lower and upper edges (the upper one by the
 * addition formula from tan_res = tan(s->coarse_res_rad)), -inf and +inf
 * at the dial's ends and beyond a quarter turn. */
typedef struct {
    double lo, hi;
} ess_lane_edges;

VM_INLINE ess_lane_edges ess_lane_coarse_edges(const ess_sensor *s, double k, double tan_res)
{
    double a = s->coarse_origin_rad + k * s->coarse_res_rad, b = a + s->coarse_res_rad;
    double ta = tan(a), tb = (ta + tan_res) / (1.0 - ta * tan_res); /* tan(a + res) */
    ess_lane_edges e;
    e.lo = vm_select(k < 0.5 || a <= -M_PI_2, -HUGE_VAL, ta);
    e.hi = vm_select(k > s->coarse_cells - 1.5 || b >= M_PI_2, HUGE_VAL, tb);
    return e;
}

/* 2^(n-1-j) for coarse row j. */
VM_INLINE double ess_lane_row_bit(const ess_sensor *s, int j)
{
    return (double)(1ULL << (s->n_coarse - 1 - j));
}

/* The cell centre (rad) of a decoded coarse reading. */
VM_INLINE double ess_lane_coarse_angle(const ess_sensor *s, ess_lane_coarse acc)
{
    return s->coarse_origin_rad + (acc.cell + 0.5) * s->coarse_res_rad;
}

/* round(x), half away from zero, for |x| < 2^52, as a vector lane does it. */
VM_INLINE double ess_lane_round(double x)
{
    double t = trunc(x), d = x - t;
    return t + vm_select(d >= 0.5, 1.0, 0.0) - vm_select(d <= -0.5, 1.0, 0.0);
}

/* The output angle: the fine period nearest the coarse estimate. */
VM_INLINE double ess_lane_combine(double coarse_rad, double fine_phase, double theta0_rad)
{
    double fine = fine_phase / (2.0 * M_PI) * theta0_rad;
    return fine + theta0_rad * ess_lane_round((coarse_rad - fine) / theta0_rad);
}

/* The same with the sensor's period per turn (theta0 / (2 pi)) and 1 /
 * theta0 (ess_sensor_init): two multiplications instead of two divisions;
 * within an ulp of ess_lane_combine (the nearest period the same unless
 * the coarse estimate lies within an ulp of half a period from the fine
 * one, a gross error either way). */
VM_INLINE double ess_lane_combine_s(const ess_sensor *s, double coarse_rad, double fine_phase)
{
    double fine = fine_phase * s->period_per_turn;
    return fine + s->theta0_rad * ess_lane_round((coarse_rad - fine) * s->inv_theta0);
}

#endif
