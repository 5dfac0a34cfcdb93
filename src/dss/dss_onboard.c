/* dss_onboard.c - the on-board formula (see dss_onboard.h). */
#include "dss_onboard.h"
#include "dss_optics.h"
#include "status.h"
#include "units.h"

#include <math.h>

void dss_onboard_init(dss_onboard *o, const dss_design *d)
{
    o->h_mm = d->h_mm;
    o->pixel_mm = d->pixel_um * MM_PER_UM;
    o->glass_t_mm = d->onboard_refraction == DSS_ONBOARD_CORRECTED ? d->glass_thickness_mm : 0.0;
    o->glass_n = d->glass_index;
}

int dss_onboard_angles(const dss_onboard *o, double x_px, double y_px, double *alpha,
                       double *beta)
{
    double x = x_px * o->pixel_mm, y = y_px * o->pixel_mm, r = hypot(x, y), theta;
    /* k = tan(theta) / r: 1 / h without glass (eq. 9-10). */
    double k = 1.0 / o->h_mm;
    if (o->glass_t_mm > 0.0 && r > 0.0) {
        if (dss_optics_field_angle(r, o->h_mm, o->glass_t_mm, o->glass_n, &theta) != SUNMC_OK) {
            *alpha = *beta = NAN;
            return SUNMC_EDOM;
        }
        k = tan(theta) / r;
    }
    *alpha = atan(-x * k);
    *beta = atan(-y * k);
    return SUNMC_OK;
}

