/* dss_readings.c - a DSS unit's readings on the rotary table, many at a
 * time: the sun vector of each table position and the spot it throws, in
 * vectorised chunks (one reading per vector lane, dss_lane.h), with the
 * noise drawn in the Monte Carlo's order.  The one-reading functions are
 * chunks of one, so a reading is the same bits whichever way it is asked
 * for. */
#include "dss_lane.h"
#include "dss_score.h"
#include "dss_unit.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

#include <math.h>
#include <string.h>

/* Normals drawn per pass of the campaign (at least the 2 + 2 of a point). */
#define DSS_DRAWS_MAX 1024

/* Lanes [k, vm_pad(k)) of a chunk repeat lane 0: every lane holds a valid
 * table position. */
static void pad_lanes(double *x, size_t k)
{
    for (size_t i = k; i < vm_pad(k); i++)
        x[i] = x[0];
}

/* The cosines and sines of a chunk's table angles b1, b2 (padded arrays):
 * what read_chunk and the truth take. */
typedef struct {
    _Alignas(VM_ALIGN) double c1[DSS_CHUNK];
    _Alignas(VM_ALIGN) double s1[DSS_CHUNK];
    _Alignas(VM_ALIGN) double c2[DSS_CHUNK];
    _Alignas(VM_ALIGN) double s2[DSS_CHUNK];
} dss_trig;

/* The cosines and sines of k <= DSS_CHUNK table angle pairs. */
VM_KERNEL static void trig_chunk(size_t k, const double *b1, const double *b2, dss_trig *t)
{
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        t->c1[i] = cos(b1[i]);
        t->s1[i] = sin(b1[i]);
        t->c2[i] = cos(b2[i]);
        t->s2[i] = sin(b2[i]);
    }
}

VM_KERNEL void dss_trig_fill(size_t n, const double *b1_rad, const double *b2_rad,
                             double *const trig[4])
{
    double *restrict c1 = trig[0], *restrict s1 = trig[1];
    double *restrict c2 = trig[2], *restrict s2 = trig[3];
    VM_SIMD for (size_t i = 0; i < vm_pad(n); i++) {
        c1[i] = cos(b1_rad[i]);
        s1[i] = sin(b1_rad[i]);
        c2[i] = cos(b2_rad[i]);
        s2[i] = sin(b2_rad[i]);
    }
}

/* Noiseless spots (px) and whether each is seen, for k <= DSS_CHUNK true
 * table positions given by their cosines and sines (padded arrays);
 * seen[i] is 1.0 or 0.0. */
VM_KERNEL static void read_chunk(const dss_sensor *s, size_t k, const dss_trig *t, double *x_px,
                                 double *y_px, double *seen)
{
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        geo_table R = geo_table_trig(t->c1[i], t->s1[i], t->c2[i], t->s2[i]);
        dss_lane_spot sp = dss_lane_sensor_spot(s, dss_lane_sun_at(s, R));
        x_px[i] = sp.x;
        y_px[i] = sp.y;
        seen[i] = vm_select(sp.ok, 1.0, 0.0);
    }
}

/* The fixed pattern and the ghost (dss_pattern.h) of the seen spots of a
 * chunk: a loop per spot, outside the vectorised kernel. */
static void read_extras(const dss_sensor *s, size_t k, const dss_trig *t, double *x_px,
                        double *y_px, const double *seen)
{
    if (!dss_sensor_extras_on(s))
        return;
    for (size_t i = 0; i < k; i++) {
        if (seen[i] == 0.0)
            continue;
        double u[3];
        geo_v3 v = dss_lane_sun_at(s, geo_table_trig(t->c1[i], t->s1[i], t->c2[i], t->s2[i]));
        u[0] = v.x;
        u[1] = v.y;
        u[2] = v.z;
        dss_sensor_extras(s, u, &x_px[i], &y_px[i]);
    }
}

int dss_sensor_read(const dss_sensor *s, double b1, double b2, const double noise_px[2],
                    double *x_px, double *y_px)
{
    _Alignas(VM_ALIGN) double a[VM_PAD], b[VM_PAD], x[VM_PAD], y[VM_PAD], seen[VM_PAD];
    dss_trig t;
    a[0] = b1;
    b[0] = b2;
    pad_lanes(a, 1);
    pad_lanes(b, 1);
    trig_chunk(1, a, b, &t);
    read_chunk(s, 1, &t, x, y, seen);
    read_extras(s, 1, &t, x, y, seen);
    if (seen[0] == 0.0)
        return SUNMC_EDOM;
    *x_px = noise_px ? x[0] + noise_px[0] : x[0];
    *y_px = noise_px ? y[0] + noise_px[1] : y[0];
    return SUNMC_OK;
}

/* Points [0, np) of a campaign whose draws fit one pass (np (2 + 2 R) <=
 * DSS_DRAWS_MAX normals, in the Monte Carlo's order: per point the two
 * encoder errors, then per repeat the two centroid noises).  The repeats
 * of a point see the same spot: it is traced once and each repeat adds
 * its noise, summed in repeat order as one reading at a time would. */
static void campaign_chunk(const sunmc_config *c, const dss_unit *u, rng_stream *r, size_t np,
                           const double *b1_rad, const double *b2_rad, dss_campaign_point *out)
{
    size_t reps = (size_t)c->cal_repeats, per = 2 + 2 * reps;
    double enc = c->encoder_arcsec * RAD_PER_ARCSEC, sigma = dss_cfg(c)->noise.centroid_px;
    double z[DSS_DRAWS_MAX];
    _Alignas(VM_ALIGN) double bt1[DSS_CHUNK], bt2[DSS_CHUNK], x[DSS_CHUNK], y[DSS_CHUNK];
    _Alignas(VM_ALIGN) double seen[DSS_CHUNK];
    dss_trig t;
    rng_normal_fill(r, z, np * per);
    for (size_t i = 0; i < np; i++) {
        bt1[i] = out[i].b1_true_rad = b1_rad[i] + enc * z[i * per];
        bt2[i] = out[i].b2_true_rad = b2_rad[i] + enc * z[i * per + 1];
    }
    pad_lanes(bt1, np);
    pad_lanes(bt2, np);
    trig_chunk(np, bt1, bt2, &t);
    read_chunk(&u->sensor, np, &t, x, y, seen);
    read_extras(&u->sensor, np, &t, x, y, seen);
    for (size_t i = 0; i < np; i++) {
        double sx = 0.0, sy = 0.0;
        for (size_t rep = 0; rep < reps; rep++) {
            sx += x[i] + sigma * z[i * per + 2 + 2 * rep];
            sy += y[i] + sigma * z[i * per + 3 + 2 * rep];
        }
        out[i].seen = seen[i] != 0.0;
        out[i].x_px = out[i].seen ? sx / (double)reps : NAN;
        out[i].y_px = out[i].seen ? sy / (double)reps : NAN;
    }
}

/* One point of a campaign whose repeats do not fit one pass: the same
 * draws in the same order, a pass of repeats at a time. */
static void campaign_long(const sunmc_config *c, const dss_unit *u, rng_stream *r, double b1_rad,
                          double b2_rad, dss_campaign_point *out)
{
    size_t reps = (size_t)c->cal_repeats;
    double enc = c->encoder_arcsec * RAD_PER_ARCSEC, sigma = dss_cfg(c)->noise.centroid_px;
    double z[DSS_DRAWS_MAX], x = 0.0, y = 0.0;
    rng_normal_fill(r, z, 2);
    out->b1_true_rad = b1_rad + enc * z[0];
    out->b2_true_rad = b2_rad + enc * z[1];
    out->seen = dss_sensor_read(&u->sensor, out->b1_true_rad, out->b2_true_rad, NULL, &x, &y) ==
                SUNMC_OK;
    double sx = 0.0, sy = 0.0;
    for (size_t rep0 = 0; rep0 < reps; rep0 += DSS_DRAWS_MAX / 2) {
        size_t g = reps - rep0 < DSS_DRAWS_MAX / 2 ? reps - rep0 : DSS_DRAWS_MAX / 2;
        rng_normal_fill(r, z, 2 * g);
        for (size_t rep = 0; rep < g; rep++) {
            sx += x + sigma * z[2 * rep];
            sy += y + sigma * z[2 * rep + 1];
        }
    }
    out->x_px = out->seen ? sx / (double)reps : NAN;
    out->y_px = out->seen ? sy / (double)reps : NAN;
}

void dss_campaign_batch(const sunmc_config *c, const dss_unit *u, rng_stream *r, size_t n,
                        const double *b1_rad, const double *b2_rad, dss_campaign_point *out)
{
    size_t per = 2 + 2 * (size_t)c->cal_repeats;
    size_t chunk = DSS_DRAWS_MAX / per < DSS_CHUNK ? DSS_DRAWS_MAX / per : DSS_CHUNK;
    if (chunk == 0) {
        for (size_t i = 0; i < n; i++)
            campaign_long(c, u, r, b1_rad[i], b2_rad[i], &out[i]);
        return;
    }
    for (size_t i0 = 0; i0 < n; i0 += chunk)
        campaign_chunk(c, u, r, n - i0 < chunk ? n - i0 : chunk, b1_rad + i0, b2_rad + i0,
                       out + i0);
}

/* Validation points [0, k) of one chunk, k <= DSS_CHUNK, their table
 * angles' cosines and sines in t (padded). */
static void validation_chunk(const sunmc_config *c, const dss_unit *u, rng_stream *r, size_t k,
                             const double *b1_rad, const double *b2_rad, const dss_trig *t,
                             dss_validation_point *out)
{
    double sigma = dss_cfg(c)->noise.centroid_px;
    double z[2 * DSS_CHUNK];
    _Alignas(VM_ALIGN) double p[DSS_CHUNK], q[DSS_CHUNK], x[DSS_CHUNK], y[DSS_CHUNK];
    _Alignas(VM_ALIGN) double seen[DSS_CHUNK], a0[DSS_CHUNK], b0[DSS_CHUNK];
    rng_normal_fill(r, z, 2 * k);
    memcpy(p, b1_rad, k * sizeof *p);
    memcpy(q, b2_rad, k * sizeof *q);
    pad_lanes(p, k);
    pad_lanes(q, k);
    read_chunk(&u->sensor, k, t, x, y, seen);
    read_extras(&u->sensor, k, t, x, y, seen);
    dss_truth_batch_trig(u->sensor.mount, u->sensor.v0, k, p, q, t->c1, t->s1, t->c2, t->s2, a0,
                         b0);
    for (size_t i = 0; i < k; i++) {
        dss_validation_point *o = &out[i];
        o->seen = seen[i] != 0.0;
        o->x0_px = x[i];
        o->y0_px = y[i];
        o->x_px = x[i] + sigma * z[2 * i];
        o->y_px = y[i] + sigma * z[2 * i + 1];
        o->alpha0_rad = a0[i];
        o->beta0_rad = b0[i];
    }
}

void dss_validation_batch(const sunmc_config *c, const dss_unit *u, rng_stream *r, size_t n,
                          const double *b1_rad, const double *b2_rad, dss_validation_point *out)
{
    _Alignas(VM_ALIGN) double p[DSS_CHUNK], q[DSS_CHUNK];
    dss_trig t;
    for (size_t i0 = 0; i0 < n; i0 += DSS_CHUNK) {
        size_t k = n - i0 < DSS_CHUNK ? n - i0 : DSS_CHUNK;
        memcpy(p, b1_rad + i0, k * sizeof *p);
        memcpy(q, b2_rad + i0, k * sizeof *q);
        pad_lanes(p, k);
        pad_lanes(q, k);
        trig_chunk(k, p, q, &t);
        validation_chunk(c, u, r, k, b1_rad + i0, b2_rad + i0, &t, out + i0);
    }
}

void dss_validation_batch_trig(const sunmc_config *c, const dss_unit *u, rng_stream *r, size_t n,
                               const double *b1_rad, const double *b2_rad,
                               const double *const trig[4], dss_validation_point *out)
{
    dss_trig t;
    double *const dst[4] = {t.c1, t.s1, t.c2, t.s2};
    const double *const *src = trig;
    for (size_t i0 = 0; i0 < n; i0 += DSS_CHUNK) {
        size_t k = n - i0 < DSS_CHUNK ? n - i0 : DSS_CHUNK;
        for (int a = 0; a < 4; a++) {
            memcpy(dst[a], src[a] + i0, k * sizeof *dst[a]);
            pad_lanes(dst[a], k);
        }
        validation_chunk(c, u, r, k, b1_rad + i0, b2_rad + i0, &t, out + i0);
    }
}
