/* ess_sensor.c - one ESS unit: its sampled deviations, its construction and
 * its raw output for a sun direction (the pieces are in ess_slit.c,
 * ess_finecode.c and ess_coarse.c). */
#include "ess_lane.h"
#include "ess_sensor.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

/* Sun closer to grazing than this is not seen by the sensor. */
#define ESS_MIN_COS_INCIDENCE 0.0175 /* cos(89 deg) */

_Static_assert(sizeof(ess_deviations) == ESS_N_DEV * sizeof(double),
               "ess_deviations: one double per column of ESS_DEVIATIONS, then the roll");

ESS_DEVIATIONS(DEVIATION_X_COLUMNS)

const deviation_spec ess_deviation_list[ESS_N_TOL] = {
#define ESS_X_SPEC(name, unit, count, stream, ...)                                                \
    DEVIATION_SPEC(ess_config, ess_deviations, name, count, stream),
    ESS_DEVIATIONS(ESS_X_SPEC)
#undef ESS_X_SPEC
};

const char *const ess_deviation_names[ESS_N_DEV] = {
    ESS_DEVIATIONS(DEVIATION_X_NAMES)
    "roll_measured_arcsec"};

void ess_deviations_values(const ess_deviations *d, double out[ESS_N_DEV])
{
    int k = deviations_values(ess_deviation_list, ESS_N_TOL, d, out, ESS_N_DEV);
    out[k] = d->roll_measured_arcsec;
}

void ess_deviations_sample(const sunmc_config *c, uint64_t seed, long unit, ess_deviations *d)
{
    memset(d, 0, sizeof *d);
    deviations_sample(ess_deviation_list, ESS_N_TOL, c, seed, unit, d);
    rng_stream r;
    rng_stream_init(&r, unit_stream_seed(c, seed, RNG_STREAM_ALIGNMENT), (uint64_t)unit,
                    RNG_STREAM_ALIGNMENT);
    d->roll_measured_arcsec =
        d->install_x_arcsec + ess_cfg(c)->roll_sigma_arcsec * rng_normal(&r);
}

double ess_sun_y_measured_arcsec(const sunmc_config *c, uint64_t seed, long unit,
                                 const ess_deviations *d)
{
    const ess_config *ec = ess_cfg(c);
    if (ec->sun_y_mode != ESS_SUN_Y_MEASURED)
        return 0.0;
    rng_stream r;
    rng_stream_init(&r, unit_stream_seed(c, seed, RNG_STREAM_SUN_Y), (uint64_t)unit,
                    RNG_STREAM_SUN_Y);
    return d->sun_y_arcsec + ec->sun_y_sigma_arcsec * rng_normal(&r);
}

/* The largest distance across the rows between a coarse row and fine row 0. */
static double coarse_dx(const ess_sensor *s)
{
    double dx = 0.0;
    for (int j = 0; j < s->n_coarse; j++)
        dx = fmax(dx, fabs(s->fine_x_mm[0] - s->coarse_x_mm[j]));
    return dx;
}

/* The largest difference between a coarse row's dial tangent and fine row
 * 0's (ess_lane_eta: the tilt's share and fine row 0's etching) at w = 0,
 * a bound on the difference of their dial angles (atan' <= 1); the dial
 * tilt adds dx tan(tau) |w| / H (eta is linear in x with slope tan(tau) w
 * - tan(dphi), w = v - u tan(dphi)). */
static double coarse_spread(const ess_sensor *s)
{
    return (coarse_dx(s) * fabs(s->tan_dphi) + fabs(s->etch_mm[0])) / s->H_mm;
}

/* Margin on the bounds of |w| (w_safe): below the limits' last digits. */
#define ESS_W_SAFE_MARGIN (1.0 - 1e-9)

/* The largest |w| within which the shortcuts taken at w = 0 hold with the
 * dial tilt's share: the fine rows' series (|fine_dt| + |fine_dt_w| |w|
 * within both limits) and the coarse comparison (the spread within half
 * a cell); +inf without a dial tilt. */
static double w_safe_of(const ess_sensor *s)
{
    double w = HUGE_VAL;
    if (s->tan_tau == 0.0)
        return w;
    if (s->fine_by_series) {
        double lim = fmin(ESS_FINE_SERIES_TAN, ESS_FINE_SERIES_PHASE / s->fine_turn) / (1.0 + 1e-4);
        for (int m = 1; m < ESS_FINE_ROWS; m++)
            if (s->fine_dt_w[m] != 0.0)
                w = fmin(w, (lim - fabs(s->fine_dt[m])) / fabs(s->fine_dt_w[m]));
    }
    double dx = coarse_dx(s);
    if (s->coarse_by_compare && dx > 0.0)
        w = fmin(w, (0.5 * s->coarse_res_rad - coarse_spread(s)) * s->H_mm / (dx * fabs(s->tan_tau)));
    return w * ESS_W_SAFE_MARGIN;
}

/* The tangents of every cell's edges, as coarse_by_compare makes them a
 * reading (the same expressions, the same vector tan of this clone: the
 * same bits), for s->coarse_by_table. */
VM_KERNEL static void coarse_table_fill(ess_sensor *s)
{
    int n = (int)s->coarse_cells;
    double tr = s->coarse_tan_res;
    double *restrict lo = s->coarse_lo_tan, *restrict hi = s->coarse_hi_tan;
    VM_SIMD for (int i = 0; i < (int)vm_pad((size_t)n); i++) {
        ess_lane_edges e = ess_lane_coarse_edges(s, (double)i, tr);
        lo[i] = e.lo;
        hi[i] = e.hi;
    }
}

/* The rows of least and greatest x, and per cell k the x of the row
 * whose Gray bit differs between k and k + 1: Gray(k) ^ Gray(k + 1) is
 * bit t, t the trailing zeros of k + 1, read by row n - 1 - t. */
static void coarse_rows_index(ess_sensor *s)
{
    int n = s->n_coarse;
    s->coarse_row_min = s->coarse_row_max = 0;
    for (int j = 1; j < n; j++) {
        if (s->coarse_x_mm[j] < s->coarse_x_mm[s->coarse_row_min])
            s->coarse_row_min = j;
        if (s->coarse_x_mm[j] > s->coarse_x_mm[s->coarse_row_max])
            s->coarse_row_max = j;
    }
    int cells = (int)s->coarse_cells;
    for (int k = 0; k + 1 < cells; k++)
        s->coarse_step_x_mm[k] = s->coarse_x_mm[n - 1 - __builtin_ctz((unsigned)(k + 1))];
    s->coarse_step_x_mm[cells - 1] = s->coarse_x_mm[0]; /* no cell above: never read */
}

void ess_sensor_init(ess_sensor *s, const ess_design *d, const ess_deviations *dev)
{
    memset(s, 0, sizeof *s);
    s->H_mm = d->H_mm;
    s->Hr_mm = d->H_mm + dev->dH_um * MM_PER_UM;
    s->dd_mm = dev->dd_um * MM_PER_UM;
    s->tan_dphi = tan(dev->dphi_deg * RAD_PER_DEG);
    s->tan_tau = tan(dev->dial_tilt_deg * RAD_PER_DEG);
    s->Hp_mm = s->Hr_mm + d->tilt_pivot_mm * s->tan_tau;
    s->theta0_rad = d->theta0_deg * RAD_PER_DEG;
    s->coarse_res_rad = d->coarse_resolution_deg * RAD_PER_DEG;
    s->n_coarse = d->coarse_rows_x_mm.n;
    s->coarse_cells = (double)(1ULL << s->n_coarse);
    s->coarse_origin_rad = -0.5 * s->coarse_cells * s->coarse_res_rad;
    for (int j = 0; j < s->n_coarse; j++)
        s->coarse_x_mm[j] = d->coarse_rows_x_mm.v[j] - d->tilt_pivot_mm;
    for (int m = 0; m < ESS_FINE_ROWS; m++) {
        s->fine_x_mm[m] = d->fine_rows_x_mm.v[m] - d->tilt_pivot_mm;
        s->gain[m] = 1.0 + dev->gain_pct[m] * FRACTION_PER_PCT;
        s->etch_mm[m] = dev->etch_um[m] * MM_PER_UM;
    }
    s->coarse_by_compare = coarse_spread(s) < 0.5 * s->coarse_res_rad;
    s->fine_by_series = 1;
    s->fine_turn = 2.0 * M_PI / s->theta0_rad;
    for (int m = 0; m < ESS_FINE_ROWS; m++) {
        s->fine_dt[m] = -((s->fine_x_mm[m] - s->fine_x_mm[0]) * s->tan_dphi +
                          (s->etch_mm[m] - s->etch_mm[0])) / s->H_mm;
        s->fine_dt_w[m] = (s->fine_x_mm[m] - s->fine_x_mm[0]) * s->tan_tau / s->H_mm;
        /* |atan(dt / (1 + t0 (t0 + dt)))| <= |dt| / (1 - dt^2 / 4): the
         * factor's margin is within the limits' last digit */
        double a = fabs(s->fine_dt[m]) * (1.0 + 1e-4);
        s->fine_by_series &= a <= ESS_FINE_SERIES_TAN &&
                             2.0 * M_PI / s->theta0_rad * a <= ESS_FINE_SERIES_PHASE;
    }
    s->coarse_tan_res = tan(s->coarse_res_rad);
    s->coarse_by_table = s->n_coarse > 0 && s->coarse_cells <= ESS_COARSE_TABLE_CELLS;
    if (s->coarse_by_table) {
        coarse_table_fill(s);
        coarse_rows_index(s);
    }
    s->harmonics_given = d->harmonics == 1;
    s->given_ratio[0] = 1.0;
    s->given_ratio[1] = d->a3_ratio;
    s->given_ratio[2] = d->a5_ratio;
    s->slit_width_mm = (d->slit_width_um + dev->slit_width_um) * MM_PER_UM;
    if (s->slit_width_mm < 0)
        s->slit_width_mm = 0;
    s->duty = d->dial_duty;
    s->sun_diameter_rad = d->sun_diameter_deg * RAD_PER_DEG;
    s->harmonic_phase_rad = dev->harmonic_phase_deg * RAD_PER_DEG;
    s->harmonic_cos = cos(s->harmonic_phase_rad);
    s->harmonic_sin = sin(s->harmonic_phase_rad);
    ess_finecode_init(s);
    s->inv_H = 1.0 / s->H_mm;
    s->period_per_turn = s->theta0_rad / (2.0 * M_PI);
    s->inv_theta0 = 1.0 / s->theta0_rad;
    s->slit_z_per_cos2 = s->slit_width_mm / s->H_mm / s->theta0_rad;
    for (int n = 0; n < ESS_HARMONICS; n++) {
        s->harm_scale[n] = s->dial_sun[n] / s->norm1;
        s->harm_scale_n[n] = s->harm_scale[n] / (2 * n + 1);
    }
    s->phase0_by_series = 1;
    s->w_safe = w_safe_of(s);
}

/* The Gray-decoding state (parity, cell) of kp lanes after every coarse
 * row, each row's dial angle an arctangent of its tangent. */
VM_KERNEL static void coarse_by_atan(const ess_sensor *s, size_t kp, const double *u,
                                     const double *v, double *parity, double *cell)
{
    for (int j = 0; j < s->n_coarse; j++) {
        double xj = s->coarse_x_mm[j], two_m = ess_lane_row_bit(s, j);
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            double psi = atan(ess_lane_eta(s, xj, u[i], v[i]) / s->H_mm);
            ess_lane_coarse acc = {parity[i], cell[i]};
            acc = ess_lane_coarse_row(s, two_m, psi, acc);
            parity[i] = acc.parity;
            cell[i] = acc.cell;
        }
    }
}

/* The same without an arctangent (s->coarse_by_compare): every row's cell
 * is fine row 0's (dial angle psi0) or a neighbour, told apart by
 * comparing the row's tangent with those of the cell's edges: one
 * tangent a reading (the upper edge's by the addition formula) instead of
 * an arctangent a row.  Only a row within an ulp or so of a cell edge can
 * read the other cell than its arctangent would, and then either cell is
 * within half a fine period of the angle: the output is the same. */
VM_KERNEL static void coarse_by_compare(const ess_sensor *s, size_t kp, const double *u,
                                        const double *v, const double *psi0, double *parity,
                                        double *cell)
{
    _Alignas(VM_ALIGN) double k0[ESS_CHUNK], lo[ESS_CHUNK], hi[ESS_CHUNK];
    double tr = s->coarse_tan_res;
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        double k = ess_lane_coarse_cell(s, psi0[i]);
        ess_lane_edges e = ess_lane_coarse_edges(s, k, tr);
        k0[i] = k;
        lo[i] = e.lo;
        hi[i] = e.hi;
    }
    /* each row's offset from k0 (-1, 0 or 1); while every row of every
     * lane has the same one, the Gray code decodes to k0 + that offset */
    _Alignas(VM_ALIGN) double d[ESS_MAX_COARSE_ROWS][ESS_CHUNK], off[ESS_CHUNK] = {0};
    for (int j = 0; j < s->n_coarse; j++) {
        double xj = s->coarse_x_mm[j];
        double *restrict dj = d[j];
        const double *restrict d0 = d[0];
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            double t = ess_lane_eta(s, xj, u[i], v[i]) / s->H_mm;
            dj[i] = ess_lane_coarse_near(0.0, lo[i], hi[i], t);
        }
        VM_SIMD for (size_t i = 0; i < kp; i++)
            off[i] += fabs(dj[i] - d0[i]);
    }
    int agree = 1;
    for (size_t i = 0; i < kp; i++)
        agree &= off[i] == 0.0;
    if (agree) {
        VM_SIMD for (size_t i = 0; i < kp; i++)
            cell[i] = k0[i] + d[0][i];
        return;
    }
    for (int j = 0; j < s->n_coarse; j++) {
        double two_m = ess_lane_row_bit(s, j);
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            ess_lane_coarse acc = {parity[i], cell[i]};
            acc = ess_lane_coarse_bit(two_m, k0[i] + d[j][i], acc);
            parity[i] = acc.parity;
            cell[i] = acc.cell;
        }
    }
}

/* The same from the tables (s->coarse_by_table), reading two rows a
 * reading.  A row's dial tangent, eta / H with eta = Hr v - dd - (x + Hr
 * u) tan(dphi), is monotonic in its x in every rounding step, and so is
 * the cell it reads (ess_lane_coarse_near): every row reads a cell
 * between those of the rows of least and greatest x.  Where these two
 * agree every row does, and the Gray code decodes to that cell.  Where
 * they differ the rows read two neighbouring cells c and c + 1 (their
 * tangents lie within half a cell of fine row 0's), whose Gray codes
 * differ in one bit: the word the rows read is Gray(c) or Gray(c + 1),
 * as that bit's row reads, and decodes to its cell.  The same cells as
 * coarse_by_compare, bit for bit. */
VM_KERNEL static void coarse_by_table(const ess_sensor *s, size_t kp, const double *u,
                                      const double *v, const double *psi0, double *cell)
{
    _Alignas(VM_ALIGN) double k0[ESS_CHUNK], lo[ESS_CHUNK], hi[ESS_CHUNK];
    _Alignas(VM_ALIGN) double da[ESS_CHUNK], db[ESS_CHUNK], x[ESS_CHUNK];
    double xa = s->coarse_x_mm[s->coarse_row_min], xb = s->coarse_x_mm[s->coarse_row_max];
    VM_SIMD for (size_t i = 0; i < kp; i++)
        k0[i] = ess_lane_coarse_cell(s, psi0[i]);
    /* the tables' entries (GCC's generic tuning makes no vector gathers,
     * and AVX2's are no faster here) */
    for (size_t i = 0; i < kp; i++) {
        int k = (int)k0[i];
        lo[i] = s->coarse_lo_tan[k];
        hi[i] = s->coarse_hi_tan[k];
    }
    double split = 0.0;
    _Pragma("omp simd reduction(+ : split)") for (size_t i = 0; i < kp; i++) {
        double a = ess_lane_coarse_near(0.0, lo[i], hi[i], ess_lane_eta(s, xa, u[i], v[i]) / s->H_mm);
        double b = ess_lane_coarse_near(0.0, lo[i], hi[i], ess_lane_eta(s, xb, u[i], v[i]) / s->H_mm);
        da[i] = a;
        db[i] = b;
        cell[i] = k0[i] + a;
        split += fabs(a - b);
    }
    if (split == 0.0)
        return;
    for (size_t i = 0; i < kp; i++)
        x[i] = s->coarse_step_x_mm[(int)(k0[i] + fmin(da[i], db[i]))];
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        double d = ess_lane_coarse_near(0.0, lo[i], hi[i], ess_lane_eta(s, x[i], u[i], v[i]) / s->H_mm);
        cell[i] = k0[i] + vm_select(da[i] == db[i], da[i], d);
    }
}

/* Fine rows' phases (noisy and noiseless) and row 0's dial angle of kp
 * lanes, each row from its own arctangent, cosine and sine.  The
 * noiseless reading shares everything but the noise's add: its currents
 * are the noisy ones' before it (x + 0 = x). */
VM_KERNEL static void fine_by_atan(const ess_sensor *s, size_t kp, const double *u,
                                   const double *v, const double *z,
                                   const double *const noise[ESS_FINE_ROWS], double *psi0,
                                   double *phase, double *phase0)
{
    const double *n0 = noise[0], *n1 = noise[1], *n2 = noise[2], *n3 = noise[3];
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        double t0 = (ess_lane_eta(s, s->fine_x_mm[0], u[i], v[i]) - s->etch_mm[0]) / s->H_mm;
        double p0 = atan(t0);
        double p1 = atan((ess_lane_eta(s, s->fine_x_mm[1], u[i], v[i]) - s->etch_mm[1]) / s->H_mm);
        double p2 = atan((ess_lane_eta(s, s->fine_x_mm[2], u[i], v[i]) - s->etch_mm[2]) / s->H_mm);
        double p3 = atan((ess_lane_eta(s, s->fine_x_mm[3], u[i], v[i]) - s->etch_mm[3]) / s->H_mm);
        /* the slit's share of the harmonics changes with cos^2(psi): over
         * the few micrometres between rows that is below 1e-9, so one
         * evaluation at the first row serves the four */
        psi0[i] = p0;
        ess_lane_harm h = ess_lane_harmonics_cos2(s, 1.0 / (1.0 + t0 * t0));
        double c0 = ess_lane_current(s, 0, h, p0, z[i], 0.0), c1 = ess_lane_current(s, 1, h, p1, z[i], 0.0);
        double c2 = ess_lane_current(s, 2, h, p2, z[i], 0.0), c3 = ess_lane_current(s, 3, h, p3, z[i], 0.0);
        phase[i] = ess_lane_demodulate(c0 + n0[i], c1 + n1[i], c2 + n2[i], c3 + n3[i]);
        phase0[i] = ess_lane_demodulate(c0, c1, c2, c3);
    }
}

/* The same with rows 1-3 from row 0 (s->fine_by_series): one arctangent,
 * cosine and sine a reading instead of four each, the harmonics with one
 * division (ess_lane_harmonics_q); the noiseless phase only where it is
 * wanted (want0: a constant, so each caller's loop is its own vector
 * loop), from the noisy one by series (s->phase0_by_series), its own
 * atan2 in the lanes beyond the series' range (the bits of a lane depend
 * on its own values only). */
VM_INLINE void fine_by_series_loop(const ess_sensor *s, size_t kp, const double *u,
                                   const double *v, const double *z,
                                   const double *const noise[ESS_FINE_ROWS], double *psi0,
                                   double *phase, double *phase0, int want0)
{
    const double *n0 = noise[0], *n1 = noise[1], *n2 = noise[2], *n3 = noise[3];
    _Alignas(VM_ALIGN) double x0s[ESS_CHUNK], y0s[ESS_CHUNK], far[ESS_CHUNK];
    double nfar = 0.0;
    int by_series = s->phase0_by_series;
    _Pragma("omp simd reduction(+ : nfar)") for (size_t i = 0; i < kp; i++) {
        double t0 = (ess_lane_eta(s, s->fine_x_mm[0], u[i], v[i]) - s->etch_mm[0]) * s->inv_H;
        double p0 = atan(t0), x0 = p0 * s->fine_turn, q = 1.0 / (1.0 + t0 * t0);
        double w = v[i] - u[i] * s->tan_dphi;
        double cx = cos(x0), sx = sin(x0);
        psi0[i] = p0;
        ess_lane_harm h = ess_lane_harmonics_q(s, q);
        double c0 = ess_lane_current_cs(s, 0, h, cx, sx, z[i], 0.0);
        double c1 = ess_lane_current_from0(s, 1, h, t0, q, w, cx, sx, z[i]);
        double c2 = ess_lane_current_from0(s, 2, h, t0, q, w, cx, sx, z[i]);
        double c3 = ess_lane_current_from0(s, 3, h, t0, q, w, cx, sx, z[i]);
        double x = (c2 + n2[i]) - (c0 + n0[i]), y = (c3 + n3[i]) - (c1 + n1[i]);
        double ph = ess_lane_phase_xy(x, y);
        phase[i] = ph;
        if (want0) {
            double xq = c2 - c0, yq = c3 - c1;
            ess_lane_phase p = ess_lane_phase_near(ph, x, y, xq, yq);
            double f = vm_select(by_series, p.far, 1.0);
            x0s[i] = xq;
            y0s[i] = yq;
            far[i] = f;
            phase0[i] = p.ph;
            nfar += f;
        }
    }
    if (want0 && nfar > 0.0)
        VM_SIMD for (size_t i = 0; i < kp; i++)
            phase0[i] = vm_select(far[i] != 0.0, ess_lane_phase_xy(x0s[i], y0s[i]), phase0[i]);
}

VM_KERNEL ESS_CONTRACT static void fine_by_series(const ess_sensor *s, size_t kp, const double *u,
                                     const double *v, const double *z,
                                     const double *const noise[ESS_FINE_ROWS], double *psi0,
                                     double *phase, double *phase0, int want0)
{
    if (want0)
        fine_by_series_loop(s, kp, u, v, z, noise, psi0, phase, phase0, 1);
    else
        fine_by_series_loop(s, kp, u, v, z, noise, psi0, phase, phase0, 0);
}

/* The lanes of a chunk beyond s->w_safe (wide[i] = 1, else 0), read again
 * by the arctangent paths: their fine phases and coarse cells replace the
 * shortcuts' (the bits of a lane depend on its own values only). */
static void wide_by_atan(const ess_sensor *s, size_t kp, const double *u, const double *v,
                         const double *z, const double *const noise[ESS_FINE_ROWS],
                         const double *wide, double *phase, double *phase0, double *cell)
{
    _Alignas(VM_ALIGN) double psi0[ESS_CHUNK], ph[ESS_CHUNK], ph0[ESS_CHUNK];
    _Alignas(VM_ALIGN) double parity[ESS_CHUNK] = {0}, cl[ESS_CHUNK] = {0};
    fine_by_atan(s, kp, u, v, z, noise, psi0, ph, ph0);
    coarse_by_atan(s, kp, u, v, parity, cl);
    for (size_t i = 0; i < kp; i++)
        if (wide[i] != 0.0) {
            phase[i] = ph[i];
            phase0[i] = ph0[i];
            cell[i] = cl[i];
        }
}

/* The readings of lanes [0, k) of a chunk: the fine rows' phases per lane
 * in one vector loop (fine_by_series or fine_by_atan), then the coarse
 * rows one row at a time, then the Gray decoding and combination per
 * lane; lanes beyond s->w_safe (a dial tilt near grazing) again by the
 * arctangent paths (wide_by_atan). */
VM_KERNEL int ess_sensor_output_chunk(const ess_sensor *s, size_t k, const double *sx,
                                      const double *sy, const double *sz,
                                      const double *const noise[ESS_FINE_ROWS], double *out_rad,
                                      double *out0_rad, int *status)
{
    _Alignas(VM_ALIGN) double u[ESS_CHUNK], v[ESS_CHUNK], z[ESS_CHUNK], phase[ESS_CHUNK];
    _Alignas(VM_ALIGN) double psi0[ESS_CHUNK], phase0[ESS_CHUNK];
    if (k > ESS_CHUNK)
        return SUNMC_EINPUT;
    size_t kp = vm_pad(k);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        /* a lane at grazing incidence is computed with s_z = 1 and dropped */
        z[i] = vm_select(sz[i] > ESS_MIN_COS_INCIDENCE, sz[i], 1.0);
        u[i] = sx[i] / z[i];
        v[i] = sy[i] / z[i];
    }
    _Alignas(VM_ALIGN) double wide[ESS_CHUNK];
    double nwide = 0.0;
    if (s->w_safe < HUGE_VAL)
        _Pragma("omp simd reduction(+ : nwide)") for (size_t i = 0; i < kp; i++) {
            double w = v[i] - u[i] * s->tan_dphi;
            wide[i] = vm_select(fabs(w) <= s->w_safe, 0.0, 1.0);
            nwide += wide[i];
        }
    if (s->fine_by_series)
        fine_by_series(s, kp, u, v, z, noise, psi0, phase, phase0, out0_rad != NULL);
    else
        fine_by_atan(s, kp, u, v, z, noise, psi0, phase, phase0);
    /* the table path writes every lane's cell; the others decode from
     * zero (the cell centre needs the cell alone) */
    _Alignas(VM_ALIGN) double parity[ESS_CHUNK], cell[ESS_CHUNK];
    if (s->coarse_by_compare && s->coarse_by_table) {
        coarse_by_table(s, kp, u, v, psi0, cell);
    } else {
        memset(parity, 0, kp * sizeof *parity);
        memset(cell, 0, kp * sizeof *cell);
        if (s->coarse_by_compare)
            coarse_by_compare(s, kp, u, v, psi0, parity, cell);
        else
            coarse_by_atan(s, kp, u, v, parity, cell);
    }
    if (nwide > 0.0)
        wide_by_atan(s, kp, u, v, z, noise, wide, phase, phase0, cell);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        ess_lane_coarse acc = {0.0, cell[i]};
        out_rad[i] = ess_lane_combine_s(s, ess_lane_coarse_angle(s, acc), phase[i]);
    }
    if (out0_rad)
        VM_SIMD for (size_t i = 0; i < kp; i++) {
            ess_lane_coarse acc = {0.0, cell[i]};
            out0_rad[i] =
                ess_lane_combine_s(s, ess_lane_coarse_angle(s, acc), phase0[i]);
        }
    VM_SIMD for (size_t i = 0; i < k; i++)
        status[i] = sz[i] > ESS_MIN_COS_INCIDENCE ? SUNMC_OK : SUNMC_EDOM;
    return SUNMC_OK;
}

int ess_sensor_output(const ess_sensor *s, const double sv[3], const double row_noise[ESS_FINE_ROWS],
                      double *out_rad)
{
    /* one lane of the batch, so a single reading is the same bits */
    _Alignas(VM_ALIGN) double x[VM_PAD] = {0}, y[VM_PAD] = {0}, z[VM_PAD] = {0};
    _Alignas(VM_ALIGN) double nz[ESS_FINE_ROWS][VM_PAD] = {{0}}, out[VM_PAD];
    const double *noise[ESS_FINE_ROWS] = {nz[0], nz[1], nz[2], nz[3]};
    int status[VM_PAD];
    x[0] = sv[0];
    y[0] = sv[1];
    z[0] = sv[2];
    for (int m = 0; m < ESS_FINE_ROWS && row_noise; m++)
        nz[m][0] = row_noise[m];
    ess_sensor_output_chunk(s, 1, x, y, z, noise, out, NULL, status);
    if (status[0] == SUNMC_OK)
        *out_rad = out[0];
    return status[0];
}
