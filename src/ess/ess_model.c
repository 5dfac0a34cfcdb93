/* ess_model.c - forward ESS calibration model, its gradient and inverse. */
#include "ess_model_lane.h"
#include "root.h"
#include "status.h"
#include "vmath.h"

#include <math.h>
#include <string.h>

#define COMP_MAX_ITER 50
#define COMP_TOL_RAD 1e-15

const char *const ess_param_names[ESS_NP_MAX] = {
    "a", "b", "c", "ks_deg", "kc_deg", "fit_install_y_arcsec", "fit_install_z_arcsec",
    "fit_sun_y_arcsec",
    /* extended */
    "ks_cos4_deg", "kc_cos4_deg", "ks_cos8_deg", "kc_cos8_deg", "k1s_deg", "k1c_deg", "k2s_deg",
    "k2c_deg", "k2s_cos2_deg", "k2c_cos2_deg"};

int ess_model_np(int kind)
{
    return kind == ESS_MODEL_EXTENDED ? ESS_NP_EXT : ESS_NP;
}

/* The paper's fine-code term first: the alias detector keeps it when a
 * later term aliases it. */
static const ess_fine_term fine_terms[] = {
    {4, 0, ESS_P_KS, ESS_P_KC},   {4, 4, ESS_P_KS4, ESS_P_KC4}, {4, 8, ESS_P_KS8, ESS_P_KC8},
    {1, 0, ESS_P_K1S, ESS_P_K1C}, {2, 0, ESS_P_K2S, ESS_P_K2C}, {2, 2, ESS_P_K2S2, ESS_P_K2C2}};

const ess_fine_term *ess_model_fine_terms(int kind, int *n)
{
    *n = kind == ESS_MODEL_EXTENDED ? (int)(sizeof fine_terms / sizeof *fine_terms) : 1;
    return fine_terms;
}

void ess_model_init_kind(ess_model *m, int kind, double theta0_rad, double roll_rad)
{
    memset(m, 0, sizeof *m);
    m->kind = kind;
    m->np = ess_model_np(kind);
    m->p[ESS_P_A] = 1.0;
    m->roll_rad = roll_rad;
    m->omega = 2.0 * M_PI / (theta0_rad / 4.0);
    ess_model_prepare(m);
}

void ess_model_init(ess_model *m, double theta0_rad, double roll_rad)
{
    ess_model_init_kind(m, ESS_MODEL_PAPER, theta0_rad, roll_rad);
}

void ess_model_prepare(ess_model *m)
{
    mat3 rx, ry, rz, dry, drz, t;
    rot_x(m->roll_rad, rx);
    /* install_y turns the sensor (active): rot_y(-y), whose derivative by
     * y is -drot_y(-y) */
    rot_y(-m->p[ESS_P_INST_Y], ry);
    rot_z(m->p[ESS_P_INST_Z], rz);
    drot_y(-m->p[ESS_P_INST_Y], dry);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            dry[i][j] = -dry[i][j];
    drot_z(m->p[ESS_P_INST_Z], drz);
    mat3_mul(rx, ry, t);
    mat3_mul(t, rz, m->R);
    mat3_mul(t, drz, m->dR_z);
    mat3_mul(rx, dry, t);
    mat3_mul(t, rz, m->dR_y);
    double sx = m->sun_x_rad, sy = m->p[ESS_P_SUN_Y];
    sun_direction(sx, sy, m->v);
    m->dv[0] = -sin(sy) * sin(sx);
    m->dv[1] = cos(sy);
    m->dv[2] = -sin(sy) * cos(sx);
    double bound;
    m->invertible = m->kind == ESS_MODEL_EXTENDED && ess_model_ext_invertible(m, &bound);
}

/* Inlined into the scalar and the vectorised forms alike: everything is
 * passed and returned by value (a loop under "omp simd" turns local arrays
 * into per-lane memory, which stops GCC from vectorising it). */
#define POINT_INLINE VM_INLINE

/* The structural + fine-code part at one point and its partials. */
typedef struct {
    double raw;
    double G;      /* d raw / d alpha_d */
    double dad_dT; /* d alpha_d / d T */
    double q, N, D;
    double sin_wa, cos_wa;
} structural_eval;

/* alpha_d = atan2(a T + b, c T + 1), the raw output and its partials. */
POINT_INLINE structural_eval structural(const ess_model *m, double T)
{
    const double *p = m->p;
    structural_eval e;
    e.N = p[ESS_P_A] * T + p[ESS_P_B];
    e.D = p[ESS_P_C] * T + 1.0;
    double ad = atan2(e.N, e.D);
    e.sin_wa = sin(m->omega * ad);
    e.cos_wa = cos(m->omega * ad);
    e.raw = ad - p[ESS_P_KS] * e.sin_wa - p[ESS_P_KC] * e.cos_wa;
    e.q = e.N * e.N + e.D * e.D;
    e.G = 1.0 - m->omega * (p[ESS_P_KS] * e.cos_wa - p[ESS_P_KC] * e.sin_wa);
    e.dad_dT = (p[ESS_P_A] * e.D - e.N * p[ESS_P_C]) / e.q;
    return e;
}

VM_NOSAN double ess_model_structural(const ess_model *m, double T)
{
    if (m->kind == ESS_MODEL_EXTENDED) {
        const double *p = m->p;
        double ad = atan2(p[ESS_P_A] * T + p[ESS_P_B], p[ESS_P_C] * T + 1.0);
        return ad - ess_model_ext_fine(m, ad, NULL, NULL);
    }
    return structural(m, T).raw;
}

void ess_turntable_matrix(double alpha_rad, double beta_rad, mat3 M)
{
    mat3 rx, ry;
    rot_x(alpha_rad, rx);
    rot_y(-beta_rad, ry); /* the table turns the sensor: active */
    mat3_mul(rx, ry, M);
}

double ess_model_predict(const ess_model *m, double alpha_rad, double beta_rad,
                         double grad[ESS_NP_MAX])
{
    mat3 M;
    ess_turntable_matrix(alpha_rad, beta_rad, M);
    return ess_model_predict_m(m, (const double(*)[3])M, grad);
}

/* The model at one point and d raw / d p, in enum ess_param order. */
typedef struct {
    double raw;
    double d_a, d_b, d_c, d_ks, d_kc, d_inst_y, d_inst_z, d_sun_y;
} point_eval;

POINT_INLINE point_eval predict_point(const ess_model *m, ess_table_mat M)
{
    ess_lane_geom g = ess_lane_geometry(m, M);
    double T = g.T;
    structural_eval sp = structural(m, T);
    point_eval e;
    e.raw = sp.raw;
    e.d_a = sp.G * (sp.D / sp.q) * T;
    e.d_b = sp.G * (sp.D / sp.q);
    e.d_c = sp.G * (-sp.N / sp.q) * T;
    e.d_ks = -sp.sin_wa;
    e.d_kc = -sp.cos_wa;

    /* d raw / d s through T = s_y / s_z */
    ess_lane_mount d = ess_lane_mount_partials(m, M, g, sp.G * sp.dad_dT);
    e.d_inst_y = d.inst_y;
    e.d_inst_z = d.inst_z;
    e.d_sun_y = d.sun_y;
    return e;
}

VM_NOSAN double ess_model_predict_m(const ess_model *m, const mat3 M, double grad[ESS_NP_MAX])
{
    if (m->kind == ESS_MODEL_EXTENDED)
        return ess_model_ext_predict_m(m, M, grad);
    ess_table_mat t = {M[0][0], M[0][1], M[0][2], M[1][0], M[1][1], M[1][2], M[2][0], M[2][1], M[2][2]};
    point_eval e = predict_point(m, t);
    if (grad) {
        double g[ESS_NP] = {e.d_a, e.d_b, e.d_c, e.d_ks, e.d_kc, e.d_inst_y, e.d_inst_z, e.d_sun_y};
        for (int j = 0; j < ESS_NP; j++)
            grad[j] = g[j];
    }
    return e.raw;
}

VM_KERNEL void ess_table_fill(ess_table *t, const double *alpha_rad, const double *beta_rad)
{
    size_t np = vm_pad(t->n);
    double *restrict m0 = t->m[0], *restrict m1 = t->m[1], *restrict m2 = t->m[2];
    double *restrict m3 = t->m[3], *restrict m4 = t->m[4], *restrict m5 = t->m[5];
    double *restrict m6 = t->m[6], *restrict m7 = t->m[7], *restrict m8 = t->m[8];
    VM_SIMD for (size_t i = 0; i < np; i++) {
        /* rot_x(alpha) rot_y(-beta), as ess_turntable_matrix */
        double ca = cos(alpha_rad[i]), sa = sin(alpha_rad[i]);
        double cb = cos(beta_rad[i]), sb = sin(beta_rad[i]);
        m0[i] = cb;
        m1[i] = 0.0;
        m2[i] = sb;
        m3[i] = -(sa * sb);
        m4[i] = ca;
        m5[i] = sa * cb;
        m6[i] = -(ca * sb);
        m7[i] = -sa;
        m8[i] = ca * cb;
    }
}

VM_KERNEL void ess_model_batch(const ess_model *m, const ess_table *t, const double *raw_rad,
                               const double *sw, double *f, double *J, size_t ld)
{
    if (m->kind == ESS_MODEL_EXTENDED) {
        ess_model_ext_batch(m, t, raw_rad, sw, f, J, ld);
        return;
    }
    size_t np = vm_pad(t->n);
    ESS_TABLE_POINTERS(t);
    double *restrict j0 = J, *restrict j1 = J + ld, *restrict j2 = J + 2 * ld;
    double *restrict j3 = J + 3 * ld, *restrict j4 = J + 4 * ld, *restrict j5 = J + 5 * ld;
    double *restrict j6 = J + 6 * ld, *restrict j7 = J + 7 * ld, *restrict fo = f;
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
        j3[i] = vm_keep(use, w * e.d_ks);
        j4[i] = vm_keep(use, w * e.d_kc);
        j5[i] = vm_keep(use, w * e.d_inst_y);
        j6[i] = vm_keep(use, w * e.d_inst_z);
        j7[i] = vm_keep(use, w * e.d_sun_y);
    }
}

VM_KERNEL void ess_model_predict_batch(const ess_model *m, const ess_table *t, double *raw_rad)
{
    if (m->kind == ESS_MODEL_EXTENDED) {
        ess_model_ext_predict_batch(m, t, raw_rad);
        return;
    }
    size_t np = vm_pad(t->n);
    ESS_TABLE_POINTERS(t);
    double *restrict out = raw_rad;
    VM_SIMD for (size_t i = 0; i < np; i++) {
        ess_table_mat Mi = ESS_TABLE_POINT(i);
        out[i] = predict_point(m, Mi).raw;
    }
}

/* The fine-code inverse by bisection, for a lane Halley's iteration left
 * unconverged.  g(x) = x - ks sin(w x) - kc cos(w x) - raw rises strictly
 * (g' >= 1 - w k > 0, checked by the caller), and its root lies within
 * k of raw.  Near w k = 1 the slope falls to 1 - w k: the rounding of g
 * (a few ulp of |x|) then moves Halley's step by ulp / (1 - w k), above
 * COMP_TOL_RAD for w k > 0.9 or so, and a lane never meets the step test
 * though its x is as good as the arithmetic allows.  Bisection ends at
 * adjacent doubles whatever the slope. */
typedef struct {
    double ks, kc, w, raw;
} finecode_eq;

static double finecode_g(double x, const void *ctx)
{
    const finecode_eq *e = ctx;
    return x - e->ks * sin(e->w * x) - e->kc * cos(e->w * x) - e->raw;
}

static double finecode_bisect(double ks, double kc, double w, double raw)
{
    double k = hypot(ks, kc);
    finecode_eq e = {ks, kc, w, raw};
    return root_bisect_increasing(finecode_g, &e, raw - 2.0 * k, raw + 2.0 * k);
}

/* Halley's error after a step dx is about K dx^3, K = |g'''| / (6 g') +
 * (g'' / (2 g'))^2 <= w^3 k / (6 (1 - w k)) + (w^2 k / (2 (1 - w k)))^2
 * (g' >= 1 - w k, |g''| <= w^2 k, |g'''| <= w^3 k): a lane whose last step
 * makes that bound (times COMP_SAFETY) smaller than COMP_TOL_RAD is done,
 * with no further step to show it.  Infinite when w k >= 1 (the caller
 * refuses that). */
#define COMP_SAFETY 1e3
static double halley_bound(double w, double k)
{
    double slope = 1.0 - w * k;
    if (!(slope > 0.0))
        return HUGE_VAL;
    double b = w * w * k / (2.0 * slope);
    return COMP_SAFETY * (w * w * w * k / (6.0 * slope) + b * b);
}

/* The step below which a lane is done: |dx| < COMP_TOL_RAD or bound
 * |dx|^3 < COMP_TOL_RAD, i.e. |dx| < the larger of COMP_TOL_RAD and
 * (COMP_TOL_RAD / bound)^(1/3), one comparison a lane and step. */
static double halley_done_step(double w, double k)
{
    return fmax(COMP_TOL_RAD, cbrt(COMP_TOL_RAD / halley_bound(w, k)));
}

/* One pass's lanes, kept for a pass over the same readings without their
 * noise (compensate_pair): its raws, alpha_d and g' at the last iterate,
 * where sin(w x) and cos(w x) were last taken (xe, sn, cs), tan alpha_d
 * (td) and eq. 13's result. */
typedef struct {
    _Alignas(VM_ALIGN) double r[ESS_COMP_CHUNK], x[ESS_COMP_CHUNK], slope[ESS_COMP_CHUNK];
    _Alignas(VM_ALIGN) double xe[ESS_COMP_CHUNK], sn[ESS_COMP_CHUNK], cs[ESS_COMP_CHUNK];
    _Alignas(VM_ALIGN) double td[ESS_COMP_CHUNK], alpha[ESS_COMP_CHUNK];
} comp_lanes;

/* A turn of w (x - xe) the series take: ess_lane_turn_wide on a pass's
 * first turn, ess_lane_turn_near on the later ones (each Halley step a
 * cube shorter: the noisy pass's second turn is below 0.011, the
 * noise-free pass's below 0.08 for the shipped configs); a lane turned
 * further takes libm's sine and cosine on its own. */
#define COMP_TURN_MAX 1.0
#define COMP_TURN_NEAR_MAX 0.1
/* The tangent's and arctangent's steps eq. 13 takes by series from a
 * nearby pass (comp_eq13_near); a lane beyond them, libm on its own. */
#define COMP_NEAR_MAX 1e-2

enum { COMP_TRIG_FRESH, COMP_TRIG_WIDE, COMP_TRIG_NEAR };

/* sin(w x), cos(w x) of kp lanes into sn, cs: fresh from libmvec, else
 * turned from their values at xe (how: COMP_TRIG_*); xe = x after.
 * Each lane's bits depend on its own values only; the lanes beyond the
 * series' range are looked for only when the vector loop saw one. */
VM_INLINE void comp_trig(size_t kp, double w, const double *x, double *xe, double *sn,
                         double *cs, int how)
{
    _Alignas(VM_ALIGN) double d[ESS_COMP_CHUNK];
    if (how == COMP_TRIG_FRESH) {
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            double wa = w * x[i];
            sn[i] = sin(wa);
            cs[i] = cos(wa);
            xe[i] = x[i];
        }
        return;
    }
    double lim = how == COMP_TRIG_NEAR ? COMP_TURN_NEAR_MAX : COMP_TURN_MAX;
    long far = 0;
    if (how == COMP_TRIG_NEAR)
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            d[i] = w * (x[i] - xe[i]);
            ess_lane_cs t = ess_lane_turn_near(cs[i], sn[i], d[i]);
            sn[i] = t.s;
            cs[i] = t.c;
            xe[i] = x[i];
            far |= fabs(d[i]) > lim ? 1 : 0;
        }
    else
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            d[i] = w * (x[i] - xe[i]);
            ess_lane_cs t = ess_lane_turn_wide(cs[i], sn[i], d[i]);
            sn[i] = t.s;
            cs[i] = t.c;
            xe[i] = x[i];
            far |= fabs(d[i]) > lim ? 1 : 0;
        }
    if (far)
        for (size_t i = 0; i < kp; i++)
            if (fabs(d[i]) > lim) {
                sn[i] = sin(w * x[i]);
                cs[i] = cos(w * x[i]);
            }
}

/* Halley's method on kp lanes from x (lanes with active set): every lane
 * iterates until its own step is below done (halley_done_step), exactly
 * as one reading alone would.  The first sine and cosine from libmvec unless near (the lanes'
 * values at xe then), the rest turned from the last (comp_trig).  fpl gets
 * each lane's g' at its last iterate.  Returns the lanes still active. */
VM_INLINE long halley_steps(const ess_model *m, double done, size_t kp, const double *r,
                            double *x, long *active, double *xe, double *sn, double *cs,
                            double *fpl, int near)
{
    double ks = m->p[ESS_P_KS], kc = m->p[ESS_P_KC], w = m->omega;
    long left = (long)kp;
    for (int it = 0; it < COMP_MAX_ITER && left > 0; it++) {
        left = 0;
        int first = near ? 0 : 1;
        comp_trig(kp, w, x, xe, sn, cs,
                  it < first ? COMP_TRIG_FRESH : it == first ? COMP_TRIG_WIDE : COMP_TRIG_NEAR);
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            double f = x[i] - ks * sn[i] - kc * cs[i] - r[i];
            double fp = 1.0 - w * (ks * cs[i] - kc * sn[i]);
            double fpp = w * w * (ks * sn[i] + kc * cs[i]);
            /* Halley's step: cubic convergence from the same sin and cos */
            double dx = 2.0 * f * fp / (2.0 * fp * fp - f * fpp), adx = fabs(dx);
            x[i] = vm_select(active[i] != 0, x[i] - dx, x[i]);
            fpl[i] = vm_select(active[i] != 0, fp, fpl[i]);
            active[i] = adx < done ? 0 : active[i];
            left += active[i];
        }
    }
    return left;
}

/* Eq. 13 on kp lanes near a pass's (near): tan alpha_d = (td' + tan h) /
 * (1 - td' tan h) by the addition formula from near's td' with tan(h), h
 * = alpha_d - near's, by its series (|h| <= COMP_NEAR_MAX: to h^9, the
 * rest below 1e-23), into ess_lane_eq13_turn; a lane beyond either range
 * (or with 1 - td' tan h <= 0, across alpha_d = 90 deg) by libm's tangent
 * on its own. */
VM_INLINE void comp_eq13_near(const ess_model *m, size_t kp, const double *x, long *active,
                              const comp_lanes *near, double *alpha)
{
    const double *p = m->p;
    _Alignas(VM_ALIGN) long far[ESS_COMP_CHUNK];
    long any_far = 0;
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        double h = x[i] - near->x[i], th = ess_lane_tan_small(h);
        double q = 1.0 - near->td[i] * th, tn = near->td[i] + th;
        ess_lane_eq13 e = ess_lane_eq13_turn(p, x[i], tn, q);
        alpha[i] = e.alpha;
        long in = q > 0.0 ? 1 - e.far : 0;
        far[i] = fabs(h) <= COMP_NEAR_MAX ? 1 - in : 1;
        any_far |= far[i];
        active[i] = p[ESS_P_C] * tn == p[ESS_P_A] * q ? 1 : active[i];
    }
    for (size_t i = 0; any_far && i < kp; i++)
        if (far[i]) {
            double td = tan(x[i]);
            ess_lane_eq13 e = ess_lane_eq13_turn(p, x[i], td, 1.0);
            alpha[i] = e.far ? ess_lane_eq13_atan(p, td) : e.alpha;
        }
}

/* The lanes' start near a pass over the same readings with noise: near's
 * solution moved by (raw - near's raw) / g' (one Newton step; the raw
 * where that is not a number).  The iteration then turns near's sines
 * and cosines in place (near's pass needs them no more). */
VM_INLINE void comp_warm_start(size_t kp, const comp_lanes *near, comp_lanes *l)
{
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        double x0 = near->x[i] + (l->r[i] - near->r[i]) / near->slope[i];
        l->x[i] = vm_select(isfinite(x0), x0, l->r[i]);
    }
}

/* Halley's method on k <= ESS_COMP_CHUNK raws at once (padded lanes),
 * done = halley_done_step of the model: from each raw, or (near != NULL)
 * from near's solution (comp_warm_start); a lane still moving after
 * COMP_MAX_ITER steps is solved by bisection (finecode_bisect); then eq.
 * 13 (near: comp_eq13_near).  status[i]: SUNMC_OK or SUNMC_EDOM (a raw
 * that is not a number, or eq. 13 undefined).  keep (NULL: not wanted)
 * gets the lanes for a pass near this one; the iteration works in it.
 * Returns 1 when a lane failed. */
VM_KERNEL ESS_CONTRACT static int compensate_chunk(const ess_model *m, double done, size_t k,
                                                   const double *raw, comp_lanes *near,
                                                   comp_lanes *keep, double *alpha, int *status)
{
    comp_lanes own;
    comp_lanes *l = keep ? keep : &own;
    double *x = l->x, *r = l->r;
    _Alignas(VM_ALIGN) long active[ESS_COMP_CHUNK];
    size_t kp = vm_pad(k);
    ess_lane_comp_start(k, raw, x, r, active);
    comp_lanes *trig = l;
    if (near) {
        comp_warm_start(kp, near, l);
        trig = near;
    }
    long left = halley_steps(m, done, kp, r, x, active, trig->xe, trig->sn, trig->cs, l->slope,
                             near != NULL);
    for (size_t i = 0; left && i < k; i++)
        if (active[i] && isfinite(r[i])) {
            x[i] = finecode_bisect(m->p[ESS_P_KS], m->p[ESS_P_KC], m->omega, r[i]);
            active[i] = 0;
        }
    /* one call of each form, so that a raw alone and in a pair's noisy
     * pass run the same instructions (FMA contraction is decided per
     * inlined copy) */
    if (near)
        comp_eq13_near(m, kp, x, active, near, own.alpha);
    else
        ess_lane_eq13_lanes(m, kp, x, active, l->td, l->alpha);
    long bad = 0;
    VM_SIMD for (size_t i = 0; i < k; i++) {
        status[i] = active[i] ? SUNMC_EDOM : SUNMC_OK;
        alpha[i] = l->alpha[i];
        bad |= active[i];
    }
    return bad != 0;
}

int ess_model_compensate_batch(const ess_model *m, size_t n, const double *raw_rad,
                               double *alpha_rad, int *status)
{
    if (ESS_MODEL_HAS_SPLINE(m->kind))
        return ess_spline_compensate_batch(m, n, raw_rad, alpha_rad, status);
    return ess_model_phys_compensate_batch(m, n, raw_rad, alpha_rad, status);
}

int ess_model_phys_compensate_batch(const ess_model *m, size_t n, const double *raw_rad,
                                    double *alpha_rad, int *status)
{
    int ext = m->kind == ESS_MODEL_EXTENDED;
    if (ext ? !m->invertible : m->omega * hypot(m->p[ESS_P_KS], m->p[ESS_P_KC]) >= 1.0) {
        for (size_t i = 0; i < n; i++)
            status[i] = SUNMC_EDOM;
        return SUNMC_EDOM;
    }
    double done = ext ? 0.0 : halley_done_step(m->omega, hypot(m->p[ESS_P_KS], m->p[ESS_P_KC]));
    int st = SUNMC_OK;
    for (size_t i0 = 0; i0 < n; i0 += ESS_COMP_CHUNK) {
        size_t k = n - i0 < ESS_COMP_CHUNK ? n - i0 : ESS_COMP_CHUNK;
        if (!ext) {
            if (compensate_chunk(m, done, k, raw_rad + i0, NULL, NULL, alpha_rad + i0,
                                 status + i0))
                st = SUNMC_EDOM;
            continue;
        }
        ess_model_ext_compensate_chunk(m, k, raw_rad + i0, alpha_rad + i0, status + i0);
        for (size_t i = 0; i < k; i++)
            if (status[i0 + i] != SUNMC_OK)
                st = SUNMC_EDOM;
    }
    return st;
}

int ess_model_compensate_pair_batch(const ess_model *m, size_t n, const double *raw_rad,
                                    const double *raw0_rad, double *alpha_rad,
                                    double *alpha0_rad, int *status, int *status0)
{
    if (m->kind == ESS_MODEL_EXTENDED || ESS_MODEL_HAS_SPLINE(m->kind)) {
        int st = ess_model_compensate_batch(m, n, raw_rad, alpha_rad, status);
        int st0 = ess_model_compensate_batch(m, n, raw0_rad, alpha0_rad, status0);
        return st != SUNMC_OK ? st : st0;
    }
    double k_rad = hypot(m->p[ESS_P_KS], m->p[ESS_P_KC]);
    if (m->omega * k_rad >= 1.0) {
        for (size_t i = 0; i < n; i++)
            status[i] = status0[i] = SUNMC_EDOM;
        return SUNMC_EDOM;
    }
    double done = halley_done_step(m->omega, k_rad);
    int st = SUNMC_OK;
    comp_lanes lanes;
    for (size_t i0 = 0; i0 < n; i0 += ESS_COMP_CHUNK) {
        size_t k = n - i0 < ESS_COMP_CHUNK ? n - i0 : ESS_COMP_CHUNK;
        int bad = compensate_chunk(m, done, k, raw_rad + i0, NULL, &lanes, alpha_rad + i0,
                                   status + i0);
        bad |= compensate_chunk(m, done, k, raw0_rad + i0, &lanes, NULL, alpha0_rad + i0,
                                status0 + i0);
        if (bad)
            st = SUNMC_EDOM;
    }
    return st;
}

int ess_model_compensate(const ess_model *m, double raw_rad, double *alpha_rad)
{
    /* one lane of the batch, so a single reading is the same bits */
    double a;
    int status;
    if (ess_model_compensate_batch(m, 1, &raw_rad, &a, &status) != SUNMC_OK)
        return SUNMC_EDOM;
    *alpha_rad = a;
    return SUNMC_OK;
}

void ess_model_kt(const ess_model *m, double *k_rad, double *t_rad)
{
    *k_rad = hypot(m->p[ESS_P_KS], m->p[ESS_P_KC]);
    *t_rad = atan2(m->p[ESS_P_KC], m->p[ESS_P_KS]);
}
