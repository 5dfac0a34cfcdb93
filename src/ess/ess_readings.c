/* ess_readings.c - a unit's readings on the turntable, many at a time: the
 * sun vector of each table position and the sensor's output for it in
 * vectorised chunks (ess_sensor_output_chunk), with the noise drawn in the
 * Monte Carlo's order.  The one-reading functions are chunks of one, so a
 * reading is the same bits whichever way it is asked for. */
#include "ess_unit.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

#include <math.h>
#include <string.h>

/* Normals drawn per pass of the campaign (at least the 2 + 4 of a point). */
#define ESS_DRAWS_MAX 1024

/* Lanes [k, kp) of a chunk repeat lane 0: every lane holds a valid reading. */
static void pad_lanes(double *x, size_t k)
{
    for (size_t i = k; i < vm_pad(k); i++)
        x[i] = x[0];
}

_Static_assert(ESS_FINE_ROWS == 4, "noise_lanes: four rows a lane");

/* Row noises of k lanes from normals z (lane i's four at z[stride i + m]),
 * scaled by sigma, pads repeating lane 0. */
VM_KERNEL static void noise_lanes(double sigma, const double *restrict z, size_t stride,
                                  size_t k, double nz[restrict ESS_FINE_ROWS][ESS_CHUNK])
{
    /* a lane's four at a time: one pass over z, not four strided ones */
    double *restrict n0 = nz[0], *restrict n1 = nz[1], *restrict n2 = nz[2], *restrict n3 = nz[3];
    for (size_t i = 0; i < k; i++) {
        const double *zi = z + stride * i;
        n0[i] = sigma * zi[0];
        n1[i] = sigma * zi[1];
        n2[i] = sigma * zi[2];
        n3[i] = sigma * zi[3];
    }
    for (int m = 0; m < ESS_FINE_ROWS; m++)
        pad_lanes(nz[m], k);
}

/* n normals of r into z, or n zeros when the caller scales every one of
 * them by 0 (drawn = 0): a stream only that noise draws from then goes
 * unread, and the readings are the bits the scaled draws give. */
static void normals_or_zeros(rng_stream *r, double *z, size_t n, int drawn)
{
    if (drawn)
        rng_normal_fill(r, z, n);
    else
        memset(z, 0, n * sizeof *z);
}

/* k <= ESS_CHUNK readings at true table angles whose cosines and sines
 * are ca, sa (alpha) and cb, sb (beta) (padded arrays): the sun in the
 * sensor frame (R_install rot_x(a) rot_y(-b) v_sun), its true incidence,
 * and the sensor's output with and (raw0 != NULL) without the noise. */
VM_KERNEL static void read_chunk_trig(const ess_unit *u, size_t k, const double *ca,
                                      const double *sa, const double *cb, const double *sb,
                                      const double *const noise[ESS_FINE_ROWS], double *raw,
                                      double *raw0, double *truth, int *status)
{
    _Alignas(VM_ALIGN) double sx[ESS_CHUNK], sy[ESS_CHUNK], sz[ESS_CHUNK];
    const double(*R)[3] = (const double(*)[3])u->R_install, *v = u->v_sun;
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        /* w = rot_x(a) rot_y(-b) v, as mat3_mul and mat3_vec (rotation.h) */
        double w0 = cb[i] * v[0] + 0.0 * v[1] + sb[i] * v[2];
        double w1 = -(sa[i] * sb[i]) * v[0] + ca[i] * v[1] + sa[i] * cb[i] * v[2];
        double w2 = -(ca[i] * sb[i]) * v[0] + -sa[i] * v[1] + ca[i] * cb[i] * v[2];
        sx[i] = R[0][0] * w0 + R[0][1] * w1 + R[0][2] * w2;
        sy[i] = R[1][0] * w0 + R[1][1] * w1 + R[1][2] * w2;
        sz[i] = R[2][0] * w0 + R[2][1] * w1 + R[2][2] * w2;
        truth[i] = atan2(sy[i], sz[i]);
    }
    ess_sensor_output_chunk(&u->sensor, k, sx, sy, sz, noise, raw, raw0, status);
}

/* The cosines and sines of n <= ESS_CHUNK padded angles. */
VM_KERNEL static void trig_chunk(size_t n, const double *a, const double *b, double *ca,
                                 double *sa, double *cb, double *sb)
{
    VM_SIMD for (size_t i = 0; i < vm_pad(n); i++) {
        ca[i] = cos(a[i]);
        sa[i] = sin(a[i]);
        cb[i] = cos(b[i]);
        sb[i] = sin(b[i]);
    }
}

/* read_chunk_trig at true table angles a, b (padded arrays). */
static void read_chunk(const ess_unit *u, size_t k, const double *a, const double *b,
                       const double *const noise[ESS_FINE_ROWS], double *raw, double *raw0,
                       double *truth, int *status)
{
    _Alignas(VM_ALIGN) double ca[ESS_CHUNK], sa[ESS_CHUNK], cb[ESS_CHUNK], sb[ESS_CHUNK];
    trig_chunk(k, a, b, ca, sa, cb, sb);
    read_chunk_trig(u, k, ca, sa, cb, sb, noise, raw, raw0, truth, status);
}

void ess_table_trig_fill(size_t n, const double *a_rad, const double *b_rad, ess_table_trig *t)
{
    for (size_t i0 = 0; i0 < n; i0 += ESS_CHUNK) {
        size_t k = n - i0 < ESS_CHUNK ? n - i0 : ESS_CHUNK;
        _Alignas(VM_ALIGN) double a[ESS_CHUNK], b[ESS_CHUNK], ca[ESS_CHUNK], sa[ESS_CHUNK];
        _Alignas(VM_ALIGN) double cb[ESS_CHUNK], sb[ESS_CHUNK];
        memcpy(a, a_rad + i0, k * sizeof *a);
        memcpy(b, b_rad + i0, k * sizeof *b);
        pad_lanes(a, k);
        pad_lanes(b, k);
        trig_chunk(k, a, b, ca, sa, cb, sb);
        memcpy(t->ca + i0, ca, k * sizeof *ca);
        memcpy(t->sa + i0, sa, k * sizeof *sa);
        memcpy(t->cb + i0, cb, k * sizeof *cb);
        memcpy(t->sb + i0, sb, k * sizeof *sb);
    }
}

int ess_unit_read(const ess_unit *u, double alpha_rad, double beta_rad,
                  const double row_noise[ESS_FINE_ROWS], double *raw_rad, double *truth_rad)
{
    _Alignas(VM_ALIGN) double a[VM_PAD], b[VM_PAD], raw[VM_PAD], truth[VM_PAD];
    _Alignas(VM_ALIGN) double nz[ESS_FINE_ROWS][VM_PAD] = {{0}};
    const double *noise[ESS_FINE_ROWS] = {nz[0], nz[1], nz[2], nz[3]};
    int status[VM_PAD];
    a[0] = alpha_rad;
    b[0] = beta_rad;
    pad_lanes(a, 1);
    pad_lanes(b, 1);
    for (int m = 0; m < ESS_FINE_ROWS && row_noise; m++)
        nz[m][0] = row_noise[m];
    read_chunk(u, 1, a, b, noise, raw, NULL, truth, status);
    *truth_rad = truth[0];
    if (status[0] == SUNMC_OK)
        *raw_rad = raw[0];
    return status[0];
}

/* The campaign's draws of points [0, np) (np (2 + 4 R) <= ESS_DRAWS_MAX
 * normals, in the Monte Carlo's order: per point the two encoder errors,
 * then per repeat the four row noises) and their readings. */
static void campaign_chunk(const sunmc_config *c, const ess_unit *u, rng_stream *r, size_t np,
                           const double *a_rad, const double *b_rad, ess_campaign_point *out)
{
    const ess_config *ec = ess_cfg(c);
    size_t per = 2 + (size_t)ESS_FINE_ROWS * (size_t)c->cal_repeats;
    double enc = c->encoder_arcsec * RAD_PER_ARCSEC;
    double sigma = ec->noise.row_current_pct * FRACTION_PER_PCT;
    double z[ESS_DRAWS_MAX];
    _Alignas(VM_ALIGN) double at[ESS_CHUNK], bt[ESS_CHUNK], raw[ESS_CHUNK], truth[ESS_CHUNK];
    _Alignas(VM_ALIGN) double nz[ESS_FINE_ROWS][ESS_CHUNK];
    const double *noise[ESS_FINE_ROWS] = {nz[0], nz[1], nz[2], nz[3]};
    int status[ESS_CHUNK];
    normals_or_zeros(r, z, np * per, enc > 0 || sigma > 0);
    for (size_t i = 0; i < np; i++) {
        at[i] = out[i].a_true_rad = a_rad[i] + enc * z[i * per];
        bt[i] = out[i].b_true_rad = b_rad[i] + enc * z[i * per + 1];
        out[i].sum_rad = 0.0;
        out[i].seen = 1;
    }
    pad_lanes(at, np);
    pad_lanes(bt, np);
    for (int rep = 0; rep < c->cal_repeats; rep++) {
        noise_lanes(sigma, z + 2 + ESS_FINE_ROWS * rep, per, np, nz);
        read_chunk(u, np, at, bt, noise, raw, NULL, truth, status);
        for (size_t i = 0; i < np; i++) {
            out[i].incidence_rad = truth[i];
            if (status[i] != SUNMC_OK)
                out[i].seen = 0;
            else
                out[i].sum_rad += raw[i];
        }
    }
}

/* One point of a campaign whose repeats do not fit one pass: its encoder
 * errors, then its repeats a chunk at a time (drawn as campaign_chunk
 * draws them, so a point's bits do not depend on the pass size). */
static void campaign_long(const sunmc_config *c, const ess_unit *u, rng_stream *r, double a_rad,
                          double b_rad, ess_campaign_point *out)
{
    const ess_config *ec = ess_cfg(c);
    double enc = c->encoder_arcsec * RAD_PER_ARCSEC;
    double sigma = ec->noise.row_current_pct * FRACTION_PER_PCT;
    double z[ESS_FINE_ROWS * ESS_CHUNK];
    _Alignas(VM_ALIGN) double at[ESS_CHUNK], bt[ESS_CHUNK], raw[ESS_CHUNK], truth[ESS_CHUNK];
    _Alignas(VM_ALIGN) double nz[ESS_FINE_ROWS][ESS_CHUNK];
    const double *noise[ESS_FINE_ROWS] = {nz[0], nz[1], nz[2], nz[3]};
    int status[ESS_CHUNK];
    normals_or_zeros(r, z, 2, enc > 0 || sigma > 0);
    out->a_true_rad = a_rad + enc * z[0];
    out->b_true_rad = b_rad + enc * z[1];
    out->sum_rad = 0.0;
    out->seen = 1;
    for (size_t i = 0; i < ESS_CHUNK; i++) {
        at[i] = out->a_true_rad;
        bt[i] = out->b_true_rad;
    }
    for (int rep0 = 0; rep0 < c->cal_repeats; rep0 += ESS_CHUNK) {
        size_t g = (size_t)(c->cal_repeats - rep0) < ESS_CHUNK ? (size_t)(c->cal_repeats - rep0)
                                                                 : ESS_CHUNK;
        normals_or_zeros(r, z, ESS_FINE_ROWS * g, enc > 0 || sigma > 0);
        noise_lanes(sigma, z, ESS_FINE_ROWS, g, nz);
        read_chunk(u, g, at, bt, noise, raw, NULL, truth, status);
        for (size_t i = 0; i < g; i++) {
            out->incidence_rad = truth[i];
            if (status[i] != SUNMC_OK)
                out->seen = 0;
            else
                out->sum_rad += raw[i];
        }
    }
}

void ess_campaign_batch(const sunmc_config *c, const ess_unit *u, rng_stream *r, size_t n,
                           const double *a_rad, const double *b_rad, ess_campaign_point *out)
{
    size_t per = 2 + (size_t)ESS_FINE_ROWS * (size_t)c->cal_repeats;
    size_t chunk = ESS_DRAWS_MAX / per < ESS_CHUNK ? ESS_DRAWS_MAX / per : ESS_CHUNK;
    if (chunk == 0) {
        /* more repeats than one pass holds: one point at a time */
        for (size_t i = 0; i < n; i++)
            campaign_long(c, u, r, a_rad[i], b_rad[i], &out[i]);
    } else {
        for (size_t i0 = 0; i0 < n; i0 += chunk)
            campaign_chunk(c, u, r, n - i0 < chunk ? n - i0 : chunk, a_rad + i0, b_rad + i0,
                           out + i0);
    }
    for (size_t i = 0; i < n; i++)
        out[i].raw_rad = out[i].seen ? out[i].sum_rad / c->cal_repeats : 0.0;
}

/* A validation chunk's k readings into the unit's arrays: 0 where the
 * sun is not seen, and each reading's status (branch-free: the status is
 * as unpredictable as the readings). */
VM_KERNEL static void chunk_out(size_t k, const int *st, const double *raw, const double *raw0,
                                const double *truth, double half_period, double *restrict raw_rad,
                                double *restrict raw0_rad, double *restrict truth_rad,
                                int *restrict status)
{
    VM_SIMD for (size_t i = 0; i < k; i++) {
        int seen = st[i] == SUNMC_OK;
        raw_rad[i] = vm_keep(seen, raw[i]);
        truth_rad[i] = truth[i];
        status[i] = !seen ? ESS_READING_UNSEEN
                    : ess_is_gross(raw[i], truth[i], half_period) ? ESS_READING_GROSS
                                                                  : ESS_READING_OK;
    }
    if (raw0_rad)
        VM_SIMD for (size_t i = 0; i < k; i++)
            raw0_rad[i] = vm_keep(st[i] == SUNMC_OK, raw0[i]);
}

void ess_validation_batch(const sunmc_config *c, const ess_unit *u, rng_stream *r, size_t n,
                          const ess_table_trig *trig, double *raw_rad, double *raw0_rad,
                          double *truth_rad, int *status)
{
    const ess_config *ec = ess_cfg(c);
    double sigma = ec->noise.row_current_pct * FRACTION_PER_PCT;
    double half_period = ess_half_period_rad(c);
    double z[ESS_FINE_ROWS * ESS_CHUNK];
    _Alignas(VM_ALIGN) double ca[ESS_CHUNK], sa[ESS_CHUNK], cb[ESS_CHUNK], sb[ESS_CHUNK];
    _Alignas(VM_ALIGN) double raw[ESS_CHUNK], truth[ESS_CHUNK];
    _Alignas(VM_ALIGN) double raw0[ESS_CHUNK], nz[ESS_FINE_ROWS][ESS_CHUNK];
    const double *noise[ESS_FINE_ROWS] = {nz[0], nz[1], nz[2], nz[3]};
    int st[ESS_CHUNK];
    for (size_t i0 = 0; i0 < n; i0 += ESS_CHUNK) {
        size_t k = n - i0 < ESS_CHUNK ? n - i0 : ESS_CHUNK;
        normals_or_zeros(r, z, ESS_FINE_ROWS * k, sigma > 0);
        /* a whole chunk reads the table in place; the last one, padded */
        const double *tca = trig->ca + i0, *tsa = trig->sa + i0, *tcb = trig->cb + i0,
                     *tsb = trig->sb + i0;
        if (k < ESS_CHUNK) {
            memcpy(ca, tca, k * sizeof *ca);
            memcpy(sa, tsa, k * sizeof *sa);
            memcpy(cb, tcb, k * sizeof *cb);
            memcpy(sb, tsb, k * sizeof *sb);
            pad_lanes(ca, k);
            pad_lanes(sa, k);
            pad_lanes(cb, k);
            pad_lanes(sb, k);
            tca = ca, tsa = sa, tcb = cb, tsb = sb;
        }
        noise_lanes(sigma, z, ESS_FINE_ROWS, k, nz);
        read_chunk_trig(u, k, tca, tsa, tcb, tsb, noise, raw, raw0_rad ? raw0 : NULL, truth, st);
        chunk_out(k, st, raw, raw0_rad ? raw0 : NULL, truth, half_period, raw_rad + i0,
                  raw0_rad ? raw0_rad + i0 : NULL, truth_rad + i0, status + i0);
    }
}
