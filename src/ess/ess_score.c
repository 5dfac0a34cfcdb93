/* ess_score.c - a calibrated ESS unit's validation scores: its readings
 * compensated a chunk at a time and their errors summed per report band
 * (RMS before and after calibration, and the systematic part), in vector
 * loops (a kernel file: the Makefile's KERNEL_SRC). */
#include "ess_score.h"
#include "bands.h"
#include "lab_onboard.h"
#include "verdict.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

#include <math.h>

/* What the fitted model makes of a chunk's readings: the noisy ones and,
 * with the systematic pass, the same without the noise. */
typedef struct {
    double comp[ESS_CHUNK], comp0[ESS_CHUNK];
    int st_comp[ESS_CHUNK], st_comp0[ESS_CHUNK];
} ess_val_chunk;

/* What each band sum takes of a chunk's readings: mask (0: no band) and
 * squared error (rad^2), before and after calibration and the systematic
 * part. */
typedef struct {
    _Alignas(VM_ALIGN) unsigned mb[ESS_CHUNK];
    _Alignas(VM_ALIGN) unsigned ma[ESS_CHUNK];
    _Alignas(VM_ALIGN) unsigned ms[ESS_CHUNK];
    _Alignas(VM_ALIGN) double eb[ESS_CHUNK];
    _Alignas(VM_ALIGN) double ea[ESS_CHUNK];
    _Alignas(VM_ALIGN) double es[ESS_CHUNK];
} ess_score_chunk;

/* The readings raw_rad[0..k) through the on-board form: its angle (rad)
 * or status SUNMC_EDOM (comp 0) for a reading it gives none. */
static void onboard_chunk(const lab_onboard *ob, size_t k, const double *raw_rad, double *comp,
                          int *st)
{
    for (size_t q = 0; q < k; q++) {
        double raw_deg = raw_rad[q] * DEG_PER_RAD, deg;
        int ok = lab_onboard_eval_raw(ob, &raw_deg, &deg) == LAB_READING_OK;
        st[q] = ok ? SUNMC_OK : SUNMC_EDOM;
        comp[q] = ok ? deg * RAD_PER_DEG : 0.0;
    }
}

static void compensate_chunk(const ess_model *m, const lab_onboard *ob, const ess_val_readings *v,
                             size_t i0, size_t k, int sys, ess_val_chunk *w)
{
    if (ob) {
        onboard_chunk(ob, k, v->raw_rad + i0, w->comp, w->st_comp);
        if (sys)
            onboard_chunk(ob, k, v->raw0_rad + i0, w->comp0, w->st_comp0);
        return;
    }
    if (sys)
        ess_model_compensate_pair_batch(m, k, v->raw_rad + i0, v->raw0_rad + i0, w->comp,
                                        w->comp0, w->st_comp, w->st_comp0);
    else
        ess_model_compensate_batch(m, k, v->raw_rad + i0, w->comp, w->st_comp);
}

/* The report bands holding each true angle truth[q], q < k, as bits
 * (band_mask), and the squared errors of the raw readings raw[q]. */
VM_KERNEL static void chunk_bands(const band_list *bands, size_t k, const double *truth,
                                  const double *raw, unsigned *m, double *e2)
{
    VM_SIMD for (size_t q = 0; q < k; q++) {
        m[q] = 0u;
        e2[q] = (raw[q] - truth[q]) * (raw[q] - truth[q]);
    }
    for (int i = 0; i < bands->n; i++)
        VM_SIMD for (size_t q = 0; q < k; q++)
            m[q] |= (unsigned)band_holds(bands, i, fabs(truth[q]) * DEG_PER_RAD) << i;
}

/* The squared errors of compensated angles comp[q] against truth[q]. */
VM_KERNEL static void chunk_errors(size_t k, const double *comp, const double *truth, double *e2)
{
    VM_SIMD for (size_t q = 0; q < k; q++)
        e2[q] = (comp[q] - truth[q]) * (comp[q] - truth[q]);
}

/* Which of readings i0 .. i0 + k - 1 of v each sum takes, as one reading
 * at a time would: unseen ones none, gross ones counted (res->gross_val)
 * and left out; before = the rest; after = those while the fit is good
 * (fit_ok: w holds their compensations) and compensates them (the first
 * it cannot fails the unit's fit and ends the after sums; a spline
 * model's reading outside its calibrated field, field = 1, is a counted
 * gross error instead: the model refuses to extrapolate); the
 * systematic part (sys) = after's whose noise-free reading is not gross
 * and compensates. */
static void chunk_uses(const sunmc_config *c, const ess_val_readings *v, size_t i0, size_t k,
                       int fit_ok, int sys, int field, const ess_val_chunk *w,
                       unit_result *res, ess_score_chunk *o)
{
    double half_period = ess_half_period_rad(c);
    for (size_t q = 0; q < k; q++) {
        int st = v->status[i0 + q];
        res->gross_val += st == ESS_READING_GROSS;
        o->ma[q] = o->ms[q] = 0u;
        if (st != ESS_READING_OK) {
            o->mb[q] = 0u;
            continue;
        }
        if (!fit_ok || res->fit_status != UNIT_FIT_OK)
            continue;
        if (w->st_comp[q] != SUNMC_OK || (field && sys && w->st_comp0[q] != SUNMC_OK)) {
            if (field)
                res->gross_val++;
            else
                res->fit_status = UNIT_FIT_FAILED;
            continue;
        }
        o->ma[q] = o->mb[q];
        if (sys && !ess_is_gross(v->raw0_rad[i0 + q], v->truth_rad[i0 + q], half_period) &&
            w->st_comp0[q] == SUNMC_OK)
            o->ms[q] = o->mb[q];
    }
}

void ess_score_validation(const sunmc_config *c, const ess_model *m, const lab_onboard *ob,
                          const ess_val_readings *v, unit_result *res)
{
    band_acc before, after, after_sys;
    band_acc_reset(&before);
    band_acc_reset(&after);
    band_acc_reset(&after_sys);
    band_tail tail; /* the spec's order statistic (verdict.h) */
    band_tail_reset(&tail, verdict_tail_keep(c));
    long points[CONFIG_BANDS_MAX] = {0};
    int nb = c->bands_deg.n, sys = !c->no_systematic;
    ess_val_chunk w;
    ess_score_chunk o;
    band_acc *const acc[3] = {&before, &after, &after_sys};
    const unsigned *const m3[3] = {o.mb, o.ma, o.ms};
    const double *const e3[3] = {o.eb, o.ea, o.es};
    for (size_t i0 = 0; i0 < v->n; i0 += ESS_CHUNK) {
        size_t k = v->n - i0 < ESS_CHUNK ? v->n - i0 : ESS_CHUNK;
        int fit_ok = res->fit_status == UNIT_FIT_OK;
        if (fit_ok)
            compensate_chunk(m, ob, v, i0, k, sys, &w);
        chunk_bands(&c->bands_deg, k, v->truth_rad + i0, v->raw_rad + i0, o.mb, o.eb);
        band_count_chunk(points, nb, k, o.mb);
        chunk_uses(c, v, i0, k, fit_ok, sys, ESS_MODEL_HAS_SPLINE(m->kind), &w, res, &o);
        if (!fit_ok) {
            band_acc_add_chunk(&before, nb, k, o.mb, o.eb);
            continue;
        }
        chunk_errors(k, w.comp, v->truth_rad + i0, o.ea);
        if (sys)
            chunk_errors(k, w.comp0, v->truth_rad + i0, o.es);
        band_acc_add_chunks(2 + sys, acc, nb, k, m3, e3);
        band_tail_add_chunk(&tail, nb, k, o.ma, o.ea);
    }
    unit_result_set_rms(res, 0, &before, &after, &c->bands_deg, DEG_PER_RAD);
    unit_result_set_stat(res, c, 0, &after, &tail, points, DEG_PER_RAD);
    unit_result_set_sys(res, 0, sys ? &after_sys : NULL, &c->bands_deg, DEG_PER_RAD);
}
