/* dss_pattern.c - the detector's fixed pattern and the cover glass's ghost
 * in the spot's centroid (see dss_pattern.h). */
#include "dss_pattern.h"

#include <math.h>

/* A pixel's two values: from 16 bits k of its hash, the odd integer
 * z = 2 k - 65535 (zero mean), times DSS_Z_SCALE a uniform of unit variance
 * (the discrete uniform's variance (65536^2 - 1) / 3 / 65536^2, ~1). */
#define DSS_Z_SCALE (1.7320508075688772 / 65536.0)
/* The window's weights as integers of DSS_G_ONE (2^23 = 1): the pattern's
 * sums are then exact integers, the same in any order and on any vector
 * width; the rounding moves a weight by < 6e-8 of the peak. */
#define DSS_G_ONE 8388608.0
/* A ghost this many sigmas beyond the window holds < 1e-15 of its light. */
#define DSS_GHOST_FAR_SIGMAS 8.0

int dss_window_half_px(double sigma_px)
{
    double m = ceil(DSS_WINDOW_SIGMAS * sigma_px);
    return m < 1.0 ? 1 : m > DSS_WINDOW_HALF_MAX ? DSS_WINDOW_HALF_MAX : (int)m;
}

void dss_pattern_init(dss_pattern *p, double sigma_px, double phase_px)
{
    p->key = 0;
    p->prnu = p->dsnu = p->ghost = 0.0;
    p->sigma_px = sigma_px;
    p->half_px = dss_window_half_px(sigma_px);
    p->phase_px = phase_px;
}

/* A 32-bit finaliser (lowbias32, C. Wellons' hash prospector). */
static inline uint32_t mix32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

static inline uint32_t row_key(uint32_t key, int32_t j)
{
    return mix32(key ^ ((uint32_t)j * 0x9e3779b9U));
}

uint32_t dss_pattern_hash(uint32_t key, int32_t i, int32_t j)
{
    return mix32(row_key(key, j) + (uint32_t)i);
}

void dss_pattern_pixel(const dss_pattern *p, int32_t i, int32_t j, double *gain, double *dark)
{
    uint32_t h = dss_pattern_hash(p->key, i, j);
    *gain = p->prnu * (2.0 * (double)(h & 0xffffU) - 65535.0) * DSS_Z_SCALE;
    *dark = p->dsnu * (2.0 * (double)(h >> 16) - 65535.0) * DSS_Z_SCALE;
}

/* One row of the window, n pixels from column i0 of row key rk: the sums
 * of g z1, k g z1, z2, k z2 (k = 0 .. n-1), integers (gq = g DSS_G_ONE,
 * kgq = k gq). */
static void
row_sums(uint32_t rk, int32_t i0, int n, const int32_t *gq, const int32_t *kgq, int64_t out[4])
{
    int64_t s0 = 0, s1 = 0, d0 = 0, d1 = 0;
    /* integer sums: any order gives the same bits */
#pragma omp simd reduction(+ : s0, s1, d0, d1)
    for (int k = 0; k < n; k++) {
        uint32_t h = mix32(rk + (uint32_t)(i0 + k));
        int32_t z1 = 2 * (int32_t)(h & 0xffffU) - 65535;
        int32_t z2 = 2 * (int32_t)(h >> 16) - 65535;
        s0 += (int64_t)gq[k] * z1;
        s1 += (int64_t)kgq[k] * z1;
        d0 += z2;
        d1 += (int64_t)k * z2;
    }
    out[0] = s0;
    out[1] = s1;
    out[2] = d0;
    out[3] = d1;
}

/* The Gaussian weights g[k] of the window's 2 m + 1 pixel centres
 * c + k (c = the first centre) about x, by the recurrence
 * g[k+1] = g[k] q[k], q[k+1] = q[k] exp(-1 / sigma^2); their sum and first
 * moment about x. */
static void window_weights(double c, double x, double sigma, int m, double *g, double *sum,
                           double *mom)
{
    double is2 = 1.0 / (2.0 * sigma * sigma), t = c - x;
    double gk = exp(-t * t * is2), q = exp(-(2.0 * t + 1.0) * is2), qq = exp(-2.0 * is2);
    double s = 0.0, s1 = 0.0;
    for (int k = 0; k <= 2 * m; k++) {
        g[k] = gk;
        s += gk;
        s1 += (t + k) * gk;
        gk *= q;
        q *= qq;
    }
    *sum = s;
    *mom = s1;
}

void dss_pattern_error(const dss_pattern *p, double x_px, double y_px, double *ex, double *ey)
{
    *ex = *ey = 0.0;
    if ((p->prnu == 0.0 && p->dsnu == 0.0) || !isfinite(x_px) || !isfinite(y_px))
        return;
    int m = p->half_px, n = 2 * m + 1;
    double gx[2 * DSS_WINDOW_HALF_MAX + 1], gy[2 * DSS_WINDOW_HALF_MAX + 1];
    int32_t gq[2 * DSS_WINDOW_HALF_MAX + 1], kgq[2 * DSS_WINDOW_HALF_MAX + 1];
    int32_t i0 = (int32_t)lround(x_px - p->phase_px) - m;
    int32_t j0 = (int32_t)lround(y_px - p->phase_px) - m;
    double cx = p->phase_px + i0, cy = p->phase_px + j0;
    double wx, wx1, wy, wy1;
    window_weights(cx, x_px, p->sigma_px, m, gx, &wx, &wx1);
    window_weights(cy, y_px, p->sigma_px, m, gy, &wy, &wy1);
    /* the pattern-free x moment is (cx - x) + gksum / gsum, which (cx - x)
     * of both terms cancels */
    double gsum = 0.0, gksum = 0.0;
    for (int k = 0; k < n; k++) {
        gq[k] = (int32_t)(gx[k] * DSS_G_ONE + 0.5); /* g >= 0: rounded */
        kgq[k] = k * gq[k];
        gsum += gq[k];
        gksum += kgq[k];
    }
    double a = p->prnu * DSS_Z_SCALE, b = p->dsnu * DSS_Z_SCALE * DSS_G_ONE;
    double S = 0.0, Sk = 0.0, Sy = 0.0;
    for (int l = 0; l < n; l++) {
        int64_t r[4];
        row_sums(row_key(p->key, j0 + l), i0, n, gq, kgq, r);
        /* the row's light and its moment in k, in units of 1 / DSS_G_ONE */
        double s0 = gy[l] * (gsum + a * (double)r[0]) + b * (double)r[2];
        double s1 = gy[l] * (gksum + a * (double)r[1]) + b * (double)r[3];
        S += s0;
        Sk += s1;
        Sy += (cy - y_px + l) * s0;
    }
    *ex = Sk / S - gksum / gsum; /* the same sums without the pattern: exactly 0 */
    *ey = Sy / S - wy1 / wy;
}

double dss_ghost_intensity(double cos_th, double n)
{
    double s2 = 1.0 - cos_th * cos_th;
    double ct = sqrt(n * n - s2) / n; /* cos of the refraction angle */
    double rs = (cos_th - n * ct) / (cos_th + n * ct);
    double rp = (n * cos_th - ct) / (n * cos_th + ct);
    double Rs = rs * rs, Rp = rp * rp;
    return 0.5 * (Rs * Rs + Rp * Rp);
}

/* Mass and first moment about x of a unit Gaussian spot centred at c in
 * the window [lo, hi] (one axis). */
static void window_share(double lo, double hi, double c, double x, double sigma, double *mass,
                         double *mom)
{
    double a = (lo - c) / sigma, b = (hi - c) / sigma;
    *mass = 0.5 * (erfc(-b * M_SQRT1_2) - erfc(-a * M_SQRT1_2));
    double phi_a = exp(-0.5 * a * a), phi_b = exp(-0.5 * b * b);
    *mom = (c - x) * *mass + sigma * (phi_a - phi_b) * (0.5 * M_2_SQRTPI * M_SQRT1_2);
}

void dss_ghost_pull(const dss_pattern *p, double a, double x_px, double y_px, double dx_px,
                    double dy_px, double *ex, double *ey)
{
    *ex = *ey = 0.0;
    double reach = p->half_px + 1.0 + DSS_GHOST_FAR_SIGMAS * p->sigma_px;
    if (a == 0.0 || !(fabs(dx_px) < reach) || !(fabs(dy_px) < reach) || !isfinite(x_px) ||
        !isfinite(y_px))
        return;
    double half = p->half_px + 0.5;
    double nx = p->phase_px + (double)lround(x_px - p->phase_px);
    double ny = p->phase_px + (double)lround(y_px - p->phase_px);
    double Mx, Sx, My, Sy, Gx, Tx, Gy, Ty;
    window_share(nx - half, nx + half, x_px, x_px, p->sigma_px, &Mx, &Sx);
    window_share(ny - half, ny + half, y_px, y_px, p->sigma_px, &My, &Sy);
    window_share(nx - half, nx + half, x_px + dx_px, x_px, p->sigma_px, &Gx, &Tx);
    window_share(ny - half, ny + half, y_px + dy_px, y_px, p->sigma_px, &Gy, &Ty);
    double den = Mx * My + a * Gx * Gy;
    *ex = (Sx * My + a * Tx * Gy) / den - Sx / Mx;
    *ey = (Sy * Mx + a * Ty * Gx) / den - Sy / My;
}
