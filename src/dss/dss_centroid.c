/* dss_centroid.c - S-curve centroid bias of a disc spot (see dss_centroid.h). */
#include "dss_centroid.h"
#include "dss_lane.h"
#include "units.h"

#include <gsl/gsl_sf_bessel.h>
#include <math.h>

void dss_scurve_amplitudes(double spot_px, double amp_px[DSS_SCURVE_HARMONICS])
{
    for (int k = 1; k <= DSS_SCURVE_HARMONICS; k++) {
        double z = M_PI * spot_px * k;
        gsl_sf_result j1;
        /* J1 of a finite argument cannot fail; 0 if GSL reports otherwise. */
        double F = gsl_sf_bessel_J1_e(z, &j1) == 0 ? 2.0 * j1.val / z : 0.0;
        double sign = (k % 2) ? -1.0 : 1.0;
        amp_px[k - 1] = sign * F / (M_PI * k);
    }
}

VM_NOSAN double dss_scurve_bias(const double amp_px[DSS_SCURVE_HARMONICS], double x_px)
{
    return dss_lane_scurve(amp_px, x_px, 0.0).x;
}
