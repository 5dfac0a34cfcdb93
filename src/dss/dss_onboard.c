/* dss_onboard.c - the on-board formula (see dss_onboard.h), many spots at a
 * time (vectorised: the field angle by Newton on arrays); one spot is a
 * chunk of one, so it gives the same bits however it is asked for. */
#include "dss_onboard.h"
#include "dss_lane.h"
#include "optics.h"
#include "status.h"
#include "units.h"
#include "vmath.h"

#include <math.h>

void dss_onboard_init(dss_onboard *o, const dss_design *d)
{
    o->h_mm = d->h_mm;
    o->pixel_um = d->pixel_um;
    o->pixel_mm = d->pixel_um * MM_PER_UM;
    o->glass_t_mm = d->onboard_refraction == DSS_ONBOARD_CORRECTED ? d->glass_thickness_mm : 0.0;
    o->glass_n = d->glass_index;
    o->x0_px = o->y0_px = 0.0;
}

VM_KERNEL void dss_onboard_chunk(const dss_onboard *o, size_t k, const double *x_px,
                                 const double *y_px, double *alpha, double *beta, int *status)
{
    _Alignas(VM_ALIGN) double x[DSS_CHUNK], y[DSS_CHUNK], r[DSS_CHUNK], T[DSS_CHUNK];
    long failed[DSS_CHUNK] = {0};
    size_t kp = vm_pad(k);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        x[i] = (x_px[i] - o->x0_px) * o->pixel_mm;
        y[i] = (y_px[i] - o->y0_px) * o->pixel_mm;
        r[i] = hypot(x[i], y[i]);
        T[i] = 0.0;
    }
    int glass = o->glass_t_mm > 0.0;
    if (glass)
        dss_field_tan_chunk(k, r, o->h_mm, o->glass_t_mm, o->glass_n, 0.0, NULL, T, NULL,
                            failed);
    VM_SIMD for (size_t i = 0; i < kp; i++) {
        /* k = tan(theta) / r: 1 / h without glass (eq. 9-10) and at r = 0 */
        double rr = vm_select(r[i] > 0.0, r[i], 1.0);
        double kr = vm_select(glass & (r[i] > 0.0), T[i] / rr, 1.0 / o->h_mm);
        alpha[i] = atan(-x[i] * kr);
        beta[i] = atan(-y[i] * kr);
    }
    for (size_t i = 0; i < k; i++) {
        status[i] = failed[i] ? SUNMC_EDOM : SUNMC_OK;
        if (failed[i])
            alpha[i] = beta[i] = NAN;
    }
}

int dss_onboard_angles(const dss_onboard *o, double x_px, double y_px, double *alpha,
                       double *beta)
{
    _Alignas(VM_ALIGN) double x[VM_PAD], y[VM_PAD], a[VM_PAD], b[VM_PAD];
    int status[VM_PAD];
    for (size_t i = 0; i < VM_PAD; i++) {
        x[i] = x_px;
        y[i] = y_px;
    }
    dss_onboard_chunk(o, 1, x, y, a, b, status);
    *alpha = a[0];
    *beta = b[0];
    return status[0];
}
