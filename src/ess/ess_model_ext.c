/* ess_model_ext.c - the extended ESS calibration model (calibration.model =
 * extended): the paper's eq. 12 and installation, with the fine-code terms
 * the physical sensor (ess_finecode.c, ess_slit.c) makes.
 *
 * Derivation.  Row m (m = 0..3) reads the dial angle psi_m and gives
 *     I_m = illum g_m [DC - sum_n c_n cos(n (x_m - m pi/2) + phi_n)],
 * x_m = 2 pi psi_m / theta0; the chopper's phase is arg Z with
 * Z = -sum_m I_m e^{i m pi/2}.  For ideal rows Z = 2 c1 e^{ix}
 * [1 + r3 e^{-4ix} + r5 e^{4ix}], r_n = c_n / c1 (complex with the
 * harmonic's phase), so the phase error is arg(1 + r3 e^{-4ix} + ...):
 *  - the third and fifth photocell harmonics give the 4th harmonic of the
 *    fine period x (the paper's k sin(4x + t), period theta0/4) and, at
 *    second order, the 8th (r3^2 / 2 sin(8x - 2 phi3): about 7-12" for
 *    type A's r3 = 0.11-0.15).  The slit's angular width w cos^2(psi)/H
 *    shrinks toward grazing incidence, so r3 = R3 sinc(3 pi z)/sinc(pi z)
 *    and r5 (sinc(5 pi z)) change with psi, z = w cos^2(psi) / (H theta0):
 *    even functions of z, i.e. series in cos^4 psi, cos^8 psi (type A: r3
 *    changes by ~30 % over the field, type B ~80 %).  Model: rho(psi) =
 *    rho0 + rho4 cos^4 + rho8 cos^8 (complex: the 5th harmonic's phase
 *    differs from the 3rd's) inside the exact arg(1 + rho e^{4ix}), which
 *    carries the 8th harmonic with no parameter of its own.  (The 8th
 *    cannot be fitted freely: a 0.2- or 0.8-deg step samples it exactly as
 *    the 2nd harmonic.)
 *  - per-row gain errors g_m = 1 + gamma_m (tolerance.gain_pct): the DC
 *    parts no longer cancel, Z gains -DC sum gamma_m e^{i m pi/2}: the
 *    fine period's fundamental (1x, amplitude ~DC Gamma1 / 2 c1, 5-12"),
 *    with an incidence dependence through 1/c1 of 3 % (A) to 7 % (B):
 *    not fitted.  The fundamental's alternating part sum (-1)^m gamma_m
 *    gives the 2nd harmonic (2x), constant over the field (1-4").
 *  - per-row etching errors (tolerance.etch_um) and the slit tilt's row
 *    offsets x_m tan dphi shift row m by delta_m = e_m cos^2(psi) / H
 *    (d atan(eta/H) / d eta): their mean is eq. 12's offset b exactly (it
 *    is a shift in tan space), their alternating part the 2nd harmonic
 *    times cos^2 psi.
 *  - the tilt's common part (x_r + Hr u) tan dphi, u = s_x/s_z, is a
 *    rotation about Z: the fitted fit_install_z absorbs it (and so
 *    measures install_z + dphi together); dH and dd are eq. 12's a and b.
 *  - second-order cross terms (gain x third harmonic: 2x, 6x; DC x 4x: 3x,
 *    5x) stay below 2": not fitted.
 * So: raw = alpha_d - arg(1 + rho e^{4ix}) / w1 - L(alpha_d) with
 *     L = k1s sin x + k1c cos x + (k2s + k2s2 c^2) sin 2x + (k2c + k2c2 c^2) cos 2x,
 * c = cos alpha_d, rho = w1 [(ks + i kc) + (ks4 + i kc4) c^4 + (ks8 + i kc8) c^8]
 * (ess_model.h), 18 parameters; alpha_d stands for psi (eq. 12 maps the
 * incidence to the dial angle).
 */
#include "ess_model_lane.h"
#include "root.h"
#include "status.h"

#include <math.h>

#define COMP_MAX_ITER 50
#define COMP_TOL_RAD 1e-15

/* The fine-code terms at one alpha_d: F = alpha_d - raw, dF/dalpha_d and
 * dF/dp of the twelve fine-code parameters. */
typedef struct {
    double F, dF;
    double ks, kc, ks4, kc4, ks8, kc8, k1s, k1c, k2s, k2c, k2s2, k2c2;
} fine_eval;

VM_INLINE fine_eval fine(const ess_model *m, double ad)
{
    const double *p = m->p;
    double w1 = 0.25 * m->omega; /* the fine period's angular frequency */
    double s1 = sin(w1 * ad), c1 = cos(w1 * ad);
    double s2 = 2.0 * s1 * c1, c2 = c1 * c1 - s1 * s1;  /* 2x */
    double s4 = 2.0 * s2 * c2, c4 = c2 * c2 - s2 * s2;  /* 4x */
    double ca = cos(ad), sa = sin(ad);
    double ca2 = ca * ca, ca4 = ca2 * ca2, ca8 = ca4 * ca4;
    double dca4 = -4.0 * ca2 * ca * sa, dca8 = 2.0 * ca4 * dca4; /* d/dalpha_d */

    /* 4x: arg(1 + w) / w1, w = rho e^{4ix} */
    double rr = w1 * (p[ESS_P_KS] + p[ESS_P_KS4] * ca4 + p[ESS_P_KS8] * ca8);
    double ri = w1 * (p[ESS_P_KC] + p[ESS_P_KC4] * ca4 + p[ESS_P_KC8] * ca8);
    double wr = rr * c4 - ri * s4, wi = rr * s4 + ri * c4;
    double Dr = 1.0 + wr, q = Dr * Dr + wi * wi;
    /* e^{4ix} conj(1 + w): d arg / d rho_r = Ei / q, d arg / d rho_i = Er / q */
    double Er = c4 * Dr + s4 * wi, Ei = s4 * Dr - c4 * wi;
    double drr = w1 * (p[ESS_P_KS4] * dca4 + p[ESS_P_KS8] * dca8);
    double dri = w1 * (p[ESS_P_KC4] * dca4 + p[ESS_P_KC8] * dca8);
    double Xr = drr - m->omega * ri, Xi = dri + m->omega * rr;
    fine_eval e;
    double gs = Ei / q, gc = Er / q;
    e.ks = gs;
    e.kc = gc;
    e.ks4 = gs * ca4;
    e.kc4 = gc * ca4;
    e.ks8 = gs * ca8;
    e.kc8 = gc * ca8;
    double F4 = atan2(wi, Dr) / w1, dF4 = (Xr * Ei + Xi * Er) / (q * w1);

    /* 1x, 2x and 2x cos^2 */
    double a2s = p[ESS_P_K2S] + p[ESS_P_K2S2] * ca2, a2c = p[ESS_P_K2C] + p[ESS_P_K2C2] * ca2;
    double L = p[ESS_P_K1S] * s1 + p[ESS_P_K1C] * c1 + a2s * s2 + a2c * c2;
    double dL = w1 * (p[ESS_P_K1S] * c1 - p[ESS_P_K1C] * s1) +
                2.0 * w1 * (a2s * c2 - a2c * s2) -
                2.0 * ca * sa * (p[ESS_P_K2S2] * s2 + p[ESS_P_K2C2] * c2);
    e.k1s = s1;
    e.k1c = c1;
    e.k2s = s2;
    e.k2c = c2;
    e.k2s2 = s2 * ca2;
    e.k2c2 = c2 * ca2;
    e.F = F4 + L;
    e.dF = dF4 + dL;
    return e;
}

/* The model at one point: raw and d raw / d p (ESS_NP_EXT of them). */
typedef struct {
    double raw;
    double d_a, d_b, d_c, d_inst_y, d_inst_z, d_sun_y;
    fine_eval f;
} point_eval;

VM_INLINE point_eval predict_point(const ess_model *m, ess_table_mat M)
{
    const double *p = m->p;
    ess_lane_geom g = ess_lane_geometry(m, M);
    double T = g.T;
    double N = p[ESS_P_A] * T + p[ESS_P_B], D = p[ESS_P_C] * T + 1.0, q = N * N + D * D;
    double ad = atan2(N, D);
    point_eval e;
    e.f = fine(m, ad);
    double G = 1.0 - e.f.dF; /* d raw / d alpha_d */
    e.raw = ad - e.f.F;
    e.d_a = G * (D / q) * T;
    e.d_b = G * (D / q);
    e.d_c = G * (-N / q) * T;
    ess_lane_mount d =
        ess_lane_mount_partials(m, M, g, G * (p[ESS_P_A] * D - N * p[ESS_P_C]) / q);
    e.d_inst_y = d.inst_y;
    e.d_inst_z = d.inst_z;
    e.d_sun_y = d.sun_y;
    return e;
}

/* d raw / d p in enum ess_param order. */
static void point_grad(point_eval e, double grad[ESS_NP_MAX])
{
    const double g[ESS_NP_EXT] = {
        e.d_a,     e.d_b,      e.d_c,      -e.f.ks,    -e.f.kc,    e.d_inst_y,
        e.d_inst_z, e.d_sun_y, -e.f.ks4,   -e.f.kc4,   -e.f.ks8,   -e.f.kc8,
        -e.f.k1s,  -e.f.k1c,   -e.f.k2s,   -e.f.k2c,   -e.f.k2s2,  -e.f.k2c2};
    for (int j = 0; j < ESS_NP_EXT; j++)
        grad[j] = g[j];
}

VM_NOSAN double ess_model_ext_fine(const ess_model *m, double ad_rad, double *dF_dad,
                                   double dF_dp[ESS_NP_MAX])
{
    fine_eval e = fine(m, ad_rad);
    if (dF_dad)
        *dF_dad = e.dF;
    if (dF_dp) {
        point_eval pe = {0};
        pe.f = e;
        point_grad(pe, dF_dp);
        for (int j = 0; j < ESS_NP_EXT; j++)
            dF_dp[j] = -dF_dp[j];
    }
    return e.F;
}

VM_NOSAN double ess_model_ext_predict_m(const ess_model *m, const mat3 M, double grad[ESS_NP_MAX])
{
    ess_table_mat t = {M[0][0], M[0][1], M[0][2], M[1][0], M[1][1],
                       M[1][2], M[2][0], M[2][1], M[2][2]};
    point_eval e = predict_point(m, t);
    if (grad)
        point_grad(e, grad);
    return e.raw;
}

/* Samples of u = cos^2 alpha_d in [0, 1] for the invertibility bound. */
#define INV_SAMPLES 64

int ess_model_ext_invertible(const ess_model *m, double *bound)
{
    const double *p = m->p;
    double w1 = 0.25 * m->omega;
    /* rho(u) = rho0 + rho4 u^2 + rho8 u^4 and d rho / d alpha_d = (2 u rho4 +
     * 4 u^3 rho8) du/dalpha_d, |du/dalpha_d| = |sin 2 alpha_d| <= 1: their
     * largest moduli over u, sampled, plus what they can gain between samples */
    double r4 = w1 * hypot(p[ESS_P_KS4], p[ESS_P_KC4]), r8 = w1 * hypot(p[ESS_P_KS8], p[ESS_P_KC8]);
    double rho = 0, drho = 0;
    for (int k = 0; k <= INV_SAMPLES; k++) {
        double u = (double)k / INV_SAMPLES, u2 = u * u;
        double rr = w1 * (p[ESS_P_KS] + (p[ESS_P_KS4] + p[ESS_P_KS8] * u2) * u2);
        double ri = w1 * (p[ESS_P_KC] + (p[ESS_P_KC4] + p[ESS_P_KC8] * u2) * u2);
        double dr = w1 * (2.0 * p[ESS_P_KS4] + 4.0 * p[ESS_P_KS8] * u2) * u;
        double di = w1 * (2.0 * p[ESS_P_KC4] + 4.0 * p[ESS_P_KC8] * u2) * u;
        rho = fmax(rho, hypot(rr, ri));
        drho = fmax(drho, hypot(dr, di));
    }
    double half_step = 0.5 / INV_SAMPLES;
    rho += (2.0 * r4 + 4.0 * r8) * half_step;
    drho += (2.0 * r4 + 12.0 * r8) * half_step;
    /* d arg(1 + rho e^{i theta}) / d theta <= rho / (1 + rho) (at theta = 0),
     * theta = 4 x: the 4x term's slope is at most 4 rho / (1 + rho) */
    double b4 = rho < 1.0 ? 4.0 * rho / (1.0 + rho) + drho / ((1.0 - rho) * w1) : INFINITY;
    double k22 = hypot(p[ESS_P_K2S2], p[ESS_P_K2C2]);
    double k2 = fmax(hypot(p[ESS_P_K2S], p[ESS_P_K2C]),
                     hypot(p[ESS_P_K2S] + p[ESS_P_K2S2], p[ESS_P_K2C] + p[ESS_P_K2C2]));
    double bl = w1 * hypot(p[ESS_P_K1S], p[ESS_P_K1C]) + 2.0 * w1 * k2 + k22;
    *bound = b4 + bl;
    return *bound < 1.0;
}

VM_KERNEL void ess_model_ext_batch(const ess_model *m, const ess_table *t, const double *raw_rad,
                                   const double *sw, double *f, double *J, size_t ld)
{
    size_t np = vm_pad(t->n);
    ESS_TABLE_POINTERS(t);
    double *restrict j0 = J, *restrict j1 = J + ld, *restrict j2 = J + 2 * ld;
    double *restrict j3 = J + 3 * ld, *restrict j4 = J + 4 * ld, *restrict j5 = J + 5 * ld;
    double *restrict j6 = J + 6 * ld, *restrict j7 = J + 7 * ld, *restrict j8 = J + 8 * ld;
    double *restrict j9 = J + 9 * ld, *restrict j10 = J + 10 * ld, *restrict j11 = J + 11 * ld;
    double *restrict j12 = J + 12 * ld, *restrict j13 = J + 13 * ld, *restrict j14 = J + 14 * ld;
    double *restrict j15 = J + 15 * ld, *restrict j16 = J + 16 * ld, *restrict j17 = J + 17 * ld;
    double *restrict fo = f;
    VM_SIMD for (size_t i = 0; i < np; i++) {
        ess_table_mat Mi = ESS_TABLE_POINT(i);
        point_eval e = predict_point(m, Mi);
        /* a dropped point (sw = 0) gives 0, whatever the model says there */
        double w = sw[i];
        int use = w > 0.0;
        fo[i] = vm_keep(use, w * (e.raw - raw_rad[i]));
        j0[i] = vm_keep(use, w * e.d_a);
        j1[i] = vm_keep(use, w * e.d_b);
        j2[i] = vm_keep(use, w * e.d_c);
        j3[i] = vm_keep(use, -w * e.f.ks);
        j4[i] = vm_keep(use, -w * e.f.kc);
        j5[i] = vm_keep(use, w * e.d_inst_y);
        j6[i] = vm_keep(use, w * e.d_inst_z);
        j7[i] = vm_keep(use, w * e.d_sun_y);
        j8[i] = vm_keep(use, -w * e.f.ks4);
        j9[i] = vm_keep(use, -w * e.f.kc4);
        j10[i] = vm_keep(use, -w * e.f.ks8);
        j11[i] = vm_keep(use, -w * e.f.kc8);
        j12[i] = vm_keep(use, -w * e.f.k1s);
        j13[i] = vm_keep(use, -w * e.f.k1c);
        j14[i] = vm_keep(use, -w * e.f.k2s);
        j15[i] = vm_keep(use, -w * e.f.k2c);
        j16[i] = vm_keep(use, -w * e.f.k2s2);
        j17[i] = vm_keep(use, -w * e.f.k2c2);
    }
}

VM_KERNEL void ess_model_ext_predict_batch(const ess_model *m, const ess_table *t,
                                           double *raw_rad)
{
    size_t np = vm_pad(t->n);
    ESS_TABLE_POINTERS(t);
    double *restrict out = raw_rad;
    VM_SIMD for (size_t i = 0; i < np; i++) {
        ess_table_mat Mi = ESS_TABLE_POINT(i);
        out[i] = predict_point(m, Mi).raw;
    }
}

/* The inverse by bisection for a lane Newton left unconverged (a slope
 * near 0 makes rounding keep its step above COMP_TOL_RAD, as for the
 * paper's model): g(x) = x - F(x) - raw rises strictly (the caller checked
 * ess_model_ext_invertible), and |F| < asin(|rho|) / w1 + |L| < 2 / w1
 * (|rho| < 1/3, w1 (k1 + 2 k2) < 1), so the root lies within raw +- 2 / w1. */
typedef struct {
    const ess_model *m;
    double raw;
} ext_eq;

static double ext_g(double x, const void *ctx)
{
    const ext_eq *e = ctx;
    return x - ess_model_ext_fine(e->m, x, NULL, NULL) - e->raw;
}

static double ext_bisect(const ess_model *m, double raw)
{
    double half = 2.0 / (0.25 * m->omega);
    ext_eq e = {m, raw};
    return root_bisect_increasing(ext_g, &e, raw - half, raw + half);
}

/* Newton on alpha_d - F(alpha_d) = raw for k <= ESS_COMP_CHUNK raws
 * (padded lanes), each lane until its own step is below COMP_TOL_RAD (a
 * lane still moving after COMP_MAX_ITER: ext_bisect), then eq. 13, as the
 * paper's model (ess_model.c). */
VM_KERNEL void ess_model_ext_compensate_chunk(const ess_model *m, size_t k, const double *raw,
                                              double *alpha, int *status)
{
    _Alignas(VM_ALIGN) double x[ESS_COMP_CHUNK], r[ESS_COMP_CHUNK];
    _Alignas(VM_ALIGN) long active[ESS_COMP_CHUNK];
    size_t kp = vm_pad(k);
    ess_lane_comp_start(k, raw, x, r, active);
    long left = (long)kp;
    for (int it = 0; it < COMP_MAX_ITER && left > 0; it++) {
        left = 0;
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            fine_eval e = fine(m, x[i]);
            double dx = (x[i] - e.F - r[i]) / (1.0 - e.dF);
            x[i] = vm_select(active[i] != 0, x[i] - dx, x[i]);
            active[i] = active[i] & (long)!(fabs(dx) < COMP_TOL_RAD);
        }
        for (size_t i = 0; i < kp; i++)
            left += active[i];
    }
    for (size_t i = 0; i < k; i++)
        if (active[i] && isfinite(r[i])) {
            x[i] = ext_bisect(m, r[i]);
            active[i] = 0;
        }
    ess_lane_comp_eq13(m, k, x, active, alpha, status);
}
