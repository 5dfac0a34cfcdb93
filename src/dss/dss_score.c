/* dss_score.c - scoring DSS readings in vectorised chunks (see dss_score.h;
 * the formulas are dss_lane.h's). */
#include "dss_score.h"
#include "dss_lane.h"
#include "units.h"
#include "vmath.h"

#include <math.h>

VM_KERNEL void dss_table_truth_batch(size_t k, const double *b1, const double *b2, double *alpha,
                                     double *beta)
{
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        alpha[i] = -b2[i];
        beta[i] = dss_lane_truth_beta(b1[i], b2[i]);
    }
}

VM_KERNEL void dss_truth_batch(int mount, const double v_sun[3], size_t k, const double *b1,
                               const double *b2, double *alpha, double *beta)
{
    geo_v3 v = geo_v3_of(v_sun);
    if (mount == DSS_MOUNT_ALIGNED) {
        VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
            dss_lane_ab t = dss_lane_truth_aligned(b1[i], b2[i]);
            alpha[i] = t.alpha;
            beta[i] = t.beta;
        }
        return;
    }
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        dss_lane_ab t = dss_lane_truth_mounted(geo_table_of(b1[i], b2[i]), v);
        alpha[i] = t.alpha;
        beta[i] = t.beta;
    }
}

VM_KERNEL void dss_truth_batch_trig(int mount, const double v_sun[3], size_t k, const double *b1,
                                    const double *b2, const double *c1, const double *s1,
                                    const double *c2, const double *s2, double *alpha,
                                    double *beta)
{
    geo_v3 v = geo_v3_of(v_sun);
    if (mount == DSS_MOUNT_ALIGNED) {
        /* dss_lane_truth_beta with cos b2 given */
        VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
            alpha[i] = -b2[i];
            beta[i] = atan(tan(b1[i]) / c2[i]);
        }
        return;
    }
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        dss_lane_ab t = dss_lane_truth_mounted(geo_table_trig(c1[i], s1[i], c2[i], s2[i]), v);
        alpha[i] = t.alpha;
        beta[i] = t.beta;
    }
}

VM_KERNEL void dss_field_chunk(size_t k, const double *alpha0, const double *beta0,
                               double *field_deg)
{
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++)
        field_deg[i] = atan(hypot(tan(alpha0[i]), tan(beta0[i]))) * DEG_PER_RAD;
}

VM_KERNEL void dss_total_error_chunk(size_t k, const double *alpha, const double *beta,
                                     const double *alpha0, const double *beta0, double *total)
{
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        geo_v3 u = dss_lane_vector_of(tan(alpha[i]), tan(beta[i]));
        geo_v3 v = dss_lane_vector_of(tan(alpha0[i]), tan(beta0[i]));
        total[i] = dss_lane_angle_between(u, v);
    }
}

VM_KERNEL void dss_truth_vector_chunk(size_t k, const double *alpha0, const double *beta0,
                                      double *vx, double *vy, double *vz, double *field_deg)
{
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        double ta = tan(alpha0[i]), tb = tan(beta0[i]);
        geo_v3 v = dss_lane_vector_of(ta, tb);
        vx[i] = v.x;
        vy[i] = v.y;
        vz[i] = v.z;
        field_deg[i] = atan(hypot(ta, tb)) * DEG_PER_RAD;
    }
}

VM_KERNEL void dss_total_error_vec_chunk(size_t k, const double *alpha, const double *beta,
                                         const double *vx, const double *vy, const double *vz,
                                         double *total)
{
    VM_SIMD for (size_t i = 0; i < vm_pad(k); i++) {
        geo_v3 u = dss_lane_vector_of(tan(alpha[i]), tan(beta[i]));
        geo_v3 v = {vx[i], vy[i], vz[i]};
        total[i] = dss_lane_angle_between(u, v);
    }
}
