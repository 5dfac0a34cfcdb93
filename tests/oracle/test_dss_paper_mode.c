/* test_dss_paper_mode.c - design.principal_point = paper_eq6: the DSS
 * paper's eq. 5-6 taken literally (S_b0 = (dx, dy, -h) rotated with the
 * table, then eq. 9-10), checked against a closed form written here, and
 * the paper's Fig. 3 text: dx errs in both alpha and beta, none at the
 * centre; dy errs in beta only. */
#include "test_util.h"

#define SMALL                                                                                     \
    "--set validation.b_step_deg=10 --set validation.b_offset_deg=0 "                             \
    "--set noise.centroid_px=0 --set noise.encoder_arcsec=0 --set noise.s_curve=off "             \
    "--set design.glass_thickness_mm=0 --set calibration.fit_glass_index=off "                    \
    "--set campaign.mount=aligned --set design.sun_disc_deg=0 --quiet "
#define PAPER "--set design.principal_point=paper_eq6 "
#define MAX_ROWS 169

static const double h_mm = 3.0, pixel_mm = 5.5e-3;
static const double arcsec_per_rad = 180.0 * 3600.0 / M_PI, rad_per_deg = M_PI / 180.0;

typedef struct {
    double a_deg, b_deg, bef_a, bef_b;
} row;

static long run_curve(const char *args, row *rows, long max)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd, "%s curve configs/dss.ini %s " SMALL " --out %s", test_sunmc(),
             args, test_tmp("pp"));
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("'%s' exited %d: %s", cmd, rc, out);
    FILE *f = fopen(test_tmp("pp/curve.tsv"), "r");
    assert_non_null(f);
    char line[2048];
    assert_non_null(fgets(line, sizeof line, f));
    long n = 0;
    double v[9];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '\n')
            continue;
        assert_true(n < max);
        row *r = &rows[n++];
        int k = sscanf(line, "%lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf", &r->a_deg, &r->b_deg,
                       &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6], &v[7], &v[8]);
        assert_int_equal(k, 11);
        r->bef_a = v[0];
        r->bef_b = v[3];
    }
    fclose(f);
    return n;
}

/* The paper's eqs. written out: the table turns about X by b1, then about Y
 * by b2 (eq. 3-4: alpha = -b2, beta = atan(tan b1 / cos b2)); the ray at
 * the table's zero is S_b0 = (dx, dy, -h), so the sun is s0 = (-dx, -dy, h)
 * / |.|; s = Ry(b2) Rx(b1) s0; the spot x_t = -h s_x / s_z; eq. 9:
 * alpha_m = atan(-(x_t - dx) / h).  Errors in arcsec. */
static void paper_closed_form(double a_deg, double b_deg, double dx_mm, double dy_mm,
                              double *ea, double *eb)
{
    double a = a_deg * rad_per_deg, b = b_deg * rad_per_deg;
    double b2 = -a, b1 = atan(tan(b) * cos(b2));
    double n = sqrt(dx_mm * dx_mm + dy_mm * dy_mm + h_mm * h_mm);
    double s0[3] = {-dx_mm / n, -dy_mm / n, h_mm / n};
    /* Rx(b1): y' = c y + s z, z' = -s y + c z */
    double c1 = cos(b1), s1 = sin(b1), c2 = cos(b2), s2 = sin(b2);
    double r[3] = {s0[0], c1 * s0[1] + s1 * s0[2], -s1 * s0[1] + c1 * s0[2]};
    /* Ry(b2): x' = c x - s z, z' = s x + c z */
    double s[3] = {c2 * r[0] - s2 * r[2], r[1], s2 * r[0] + c2 * r[2]};
    double xt = -h_mm * s[0] / s[2], yt = -h_mm * s[1] / s[2];
    *ea = (atan(-(xt - dx_mm) / h_mm) - a) * arcsec_per_rad;
    *eb = (atan(-(yt - dy_mm) / h_mm) - b) * arcsec_per_rad;
}

static void check(const char *only, double dx_px, double dy_px, row *at5050)
{
    static row r[MAX_ROWS];
    long n = run_curve(only, r, MAX_ROWS), seen = 0;
    assert_int_equal(n, MAX_ROWS);
    for (long i = 0; i < n; i++) {
        if (isnan(r[i].bef_a))
            continue;
        seen++;
        double ea, eb;
        paper_closed_form(r[i].a_deg, r[i].b_deg, dx_px * pixel_mm, dy_px * pixel_mm, &ea, &eb);
        assert_near(r[i].bef_a, ea, 1e-5);
        assert_near(r[i].bef_b, eb, 1e-5);
        if (r[i].a_deg == 0 && r[i].b_deg == 0) {
            assert_near(r[i].bef_a, 0.0, 1e-9);
            assert_near(r[i].bef_b, 0.0, 1e-9);
        }
        if (r[i].a_deg == 50 && r[i].b_deg == 50)
            *at5050 = r[i];
    }
    assert_true(seen > 100);
}

/* dx = 0.1 px: both alpha and beta err at (50, 50), about 32 and 29 arcsec
 * (the closed form: 32.0, 27.95), none at the centre. */
static void dx_errs_both_not_centre(void **state)
{
    row c = {0};
    check("--only dx_px=0.1 " PAPER, 0.1, 0.0, &c);
    assert_true(c.a_deg == 50 && c.b_deg == 50);
    assert_true(fabs(c.bef_a) > 25.0 && fabs(c.bef_a) < 40.0);
    assert_true(fabs(c.bef_b) > 20.0 && fabs(c.bef_b) < 35.0);
}

/* dy = 0.1 px: beta only; alpha's error is nil everywhere. */
static void dy_errs_beta_only(void **state)
{
    static row r[MAX_ROWS];
    row c = {0};
    check("--only dy_px=0.1 " PAPER, 0.0, 0.1, &c);
    assert_true(fabs(c.bef_b) > 15.0);
    long n = run_curve("--only dy_px=0.1 " PAPER, r, MAX_ROWS);
    for (long i = 0; i < n; i++)
        if (!isnan(r[i].bef_a))
            assert_near(r[i].bef_a, 0.0, 1e-6);
}

/* The physical default differs: dx alone errs most at the centre. */
static void physical_default_differs(void **state)
{
    static row r[MAX_ROWS];
    long n = run_curve("--only dx_px=0.1", r, MAX_ROWS), seen = 0;
    for (long i = 0; i < n; i++)
        if (r[i].a_deg == 0 && r[i].b_deg == 0) {
            /* the pinhole displaced: atan(dx / h) at the centre, 37.8 arcsec */
            assert_near(fabs(r[i].bef_a), atan(0.1 * pixel_mm / h_mm) * arcsec_per_rad, 1e-3);
            seen++;
        }
    assert_int_equal(seen, 1);
}

static void bad_value_refused(void **state)
{
    char out[8192], cmd[4096];
    snprintf(cmd, sizeof cmd, "%s curve configs/dss.ini --only dx_px=0.1 "
             "--set design.principal_point=paper --quiet --out %s",
             test_sunmc(), test_tmp("bad"));
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    snprintf(cmd, sizeof cmd, "test -e %s", test_tmp("bad"));
    assert_int_not_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dx_errs_both_not_centre),
        cmocka_unit_test(dy_errs_beta_only),
        cmocka_unit_test(physical_default_differs),
        cmocka_unit_test(bad_value_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
