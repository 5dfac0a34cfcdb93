/* test_dss_paper_rotation.c - design.principal_point = paper_eq6 on a
 * tilted unit (issue 43).  The paper's ray at the table's zero, S_b0 =
 * (dx, dy, -h), is the sun w = (-dx, -dy, h) / |.| in the sensor frame
 * (no glass); the table's rotation turns it with the sun, so the sun the
 * spots see, in the sensor frame, is R u0 with u0 = M v0 the true sun in
 * the sensor frame and R the least rotation taking e_z to w.  R is built
 * here as a matrix, axis n = e_z x w / |.|, angle atan2(|e_z x w|, w_z),
 * R = I + sin(t) K + (1 - cos(t)) K^2 (K the cross-product matrix of n),
 * and the unit's v_sun must satisfy M v_sun = R M v0 for tilts on every
 * axis, both mounts, and offsets of both signs.  The on-board formula
 * measures from (dx, dy). */
#include "test_util.h"

#include "config.h"
#include "dss_config.h"
#include "dss_sensor.h"
#include "rotation.h"
#include "units.h"

#include <math.h>
#include <string.h>

static void least_rotation(const double w[3], mat3 R)
{
    double kx = -w[1], ky = w[0], s = hypot(kx, ky), t = atan2(s, w[2]);
    double n[3] = {kx / s, ky / s, 0};
    mat3 K = {{0, -n[2], n[1]}, {n[2], 0, -n[0]}, {-n[1], n[0], 0}}, K2;
    mat3_mul(K, K, K2);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            R[i][j] = (i == j) + sin(t) * K[i][j] + (1 - cos(t)) * K2[i][j];
}

/* The default DSS design, as the command line builds it. */
static void default_design(dss_design *d)
{
    const char *sets[] = {"sensor.family=dss"};
    config_state st;
    test_build(&st, NULL, sets, 1);
    memcpy(d, &dss_cfg(&st.cfg)->design, sizeof *d);
    config_state_free(&st);
}

static void check_unit(const dss_design *d, const dss_deviations *dev)
{
    dss_sensor s;
    dss_sensor_init(&s, d, dev, 0);
    double pix = d->pixel_um * MM_PER_UM, H = d->h_mm + dev->dh_px * pix;
    double w[3] = {-dev->dx_px * pix, -dev->dy_px * pix, H}, nw = sqrt(w[0] * w[0] + w[1] * w[1] + H * H);
    for (int i = 0; i < 3; i++)
        w[i] /= nw;
    mat3 R;
    least_rotation(w, R);
    /* R takes e_z to w */
    assert_near(R[0][2], w[0], 1e-15);
    assert_near(R[1][2], w[1], 1e-15);
    assert_near(R[2][2], w[2], 1e-15);
    double u0[3], want[3], got[3];
    mat3_vec(s.M, s.v0, u0);
    mat3_vec(R, u0, want);
    mat3_vec(s.M, s.v_sun, got);
    for (int i = 0; i < 3; i++)
        assert_near(got[i], want[i], 1e-13);
    assert_near(s.onboard.x0_px, dev->dx_px, 0);
    assert_near(s.onboard.y0_px, dev->dy_px, 0);
    assert_near(s.pinhole_mm[0], 0, 0);
    assert_near(s.pinhole_mm[1], 0, 0);
}

static void tilted_units_both_mounts(void **state)
{
    dss_design d;
    default_design(&d);
    d.principal_point = DSS_PP_PAPER_EQ6;
    d.glass_thickness_mm = 0;
    const double off[][2] = {{40, -25}, {-30, 55}, {0, 35}, {60, 0}};
    const double tilt[][3] = {{3000, -2000, 5000}, {-4000, 2500, -1500}, {0, 0, 7000}};
    for (int mount = 0; mount < 2; mount++)
        for (size_t i = 0; i < sizeof off / sizeof off[0]; i++)
            for (size_t j = 0; j < sizeof tilt / sizeof tilt[0]; j++) {
                dss_deviations dev;
                memset(&dev, 0, sizeof dev);
                dev.dx_px = off[i][0];
                dev.dy_px = off[i][1];
                dev.dh_px = 7;
                dev.c1_arcsec = tilt[j][0];
                dev.c2_arcsec = tilt[j][1];
                dev.c3_arcsec = tilt[j][2];
                dev.sun_b1_arcsec = 900;
                dev.sun_b2_arcsec = -600;
                d.mount = mount ? DSS_MOUNT_AS_MOUNTED : DSS_MOUNT_ALIGNED;
                check_unit(&d, &dev);
            }
}

/* The physical default leaves the sun alone: v_sun = v0. */
static void physical_leaves_the_sun(void **state)
{
    dss_design d;
    default_design(&d);
    d.principal_point = DSS_PP_PHYSICAL;
    dss_deviations dev;
    memset(&dev, 0, sizeof dev);
    dev.dx_px = 40;
    dev.c1_arcsec = 3000;
    dss_sensor s;
    dss_sensor_init(&s, &d, &dev, 0);
    for (int i = 0; i < 3; i++)
        assert_near(s.v_sun[i], s.v0[i], 0);
    assert_near(s.onboard.x0_px, 0, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(tilted_units_both_mounts),
        cmocka_unit_test(physical_leaves_the_sun),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
