/* test_dss_curve.c - `sunmc curve` on the DSS: error maps over the sun
 * angles (alpha, beta) on a small grid, checked against closed forms derived
 * here and the DSS paper's findings (Figs. 2-5), and its input errors. */
#include "test_util.h"

/* 13 x 13 map, -60..60 every 10 deg (holds the centre), noiseless campaign,
 * no S-curve: every number below is a closed form. */
#define SMALL                                                                                     \
    "--set validation.b_step_deg=10 --set validation.b_offset_deg=0 "                             \
    "--set noise.centroid_px=0 --set noise.encoder_arcsec=0 --set noise.s_curve=off "              \
    "--set design.sun_disc_deg=0 --quiet"
#define NO_GLASS "--set design.glass_thickness_mm=0 --set calibration.fit_glass_index=off"
#define GRID_N 13
#define MAX_ROWS (GRID_N * GRID_N)

static const double h_mm = 3.0, pixel_mm = 5.5e-3, t_mm = 0.4, n_glass = 1.52;
static const double arcsec_per_rad = 180.0 * 3600.0 / M_PI, rad_per_deg = M_PI / 180.0;

/* One row of curve.tsv: alpha, beta, then before/after/source of alpha,
 * beta, total. */
typedef struct {
    double a_deg, b_deg;
    double v[9];
} row;
enum { BEF_A = 0, AFT_A, SRC_A, BEF_B, AFT_B, SRC_B, BEF_T, AFT_T, SRC_T };

/* Run curve with args, read its curve.tsv into rows; returns the count. */
static long run_curve(const char *args, row *rows, long max)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd, "%s curve configs/dss.ini %s " SMALL " --out %s", test_sunmc(),
             args, test_tmp("c"));
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("'%s' exited %d: %s", cmd, rc, out);
    FILE *f = fopen(test_tmp("c/curve.tsv"), "r");
    assert_non_null(f);
    char line[2048];
    assert_non_null(fgets(line, sizeof line, f));
    assert_non_null(strstr(line, "alpha_deg\tbeta_deg\terror_before_alpha_arcsec\t"
                                 "error_after_alpha_arcsec\terror_source_alpha_arcsec"));
    long n = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '\n')
            continue;
        assert_true(n < max);
        row *r = &rows[n++];
        /* "-" (a number curve could not form) read as nan */
        char text[4096];
        size_t o = 0;
        for (const char *c = line; *c && o + 4 < sizeof text; c++)
            if (*c == '-' && (c == line || c[-1] == '\t') && (c[1] == '\t' || c[1] == '\n')) {
                memcpy(text + o, "nan", 3);
                o += 3;
            } else
                text[o++] = *c;
        text[o] = '\0';
        int k = sscanf(text, "%lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf", &r->a_deg,
                       &r->b_deg, &r->v[0], &r->v[1], &r->v[2], &r->v[3], &r->v[4], &r->v[5],
                       &r->v[6], &r->v[7], &r->v[8]);
        assert_int_equal(k, 11);
    }
    fclose(f);
    return n;
}

/* Fig. 2, dh alone without glass: the spot is at -(h + dh) tan(alpha), so
 * the on-board alpha is atan((1 + dh/h) tan alpha): the alpha error depends
 * on alpha only (the same for every beta), beta's on beta only; the fit
 * removes it. */
static void dh_closed_form(void **state)
{
    static row r[MAX_ROWS];
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        const double dh_px = 0.2 * sgn;
        char args[256];
        snprintf(args, sizeof args, "--only dh_px=%g " NO_GLASS, dh_px);
        long n = run_curve(args, r, MAX_ROWS);
        assert_int_equal(n, MAX_ROWS);
        const double k = 1.0 + dh_px * pixel_mm / h_mm;
        long seen = 0;
        for (long i = 0; i < n; i++) {
            if (isnan(r[i].v[BEF_A]))
                continue; /* spot off the detector in the corners */
            seen++;
            double a = r[i].a_deg * rad_per_deg, b = r[i].b_deg * rad_per_deg;
            double want_a = (atan(k * tan(a)) - a) * arcsec_per_rad;
            double want_b = (atan(k * tan(b)) - b) * arcsec_per_rad;
            assert_near(r[i].v[SRC_A], want_a, 1e-6);
            assert_near(r[i].v[BEF_A], want_a, 1e-6); /* nominal has no error without glass */
            assert_near(r[i].v[SRC_B], want_b, 1e-6);
            assert_near(r[i].v[AFT_A], 0.0, 1e-3);
            assert_near(r[i].v[AFT_B], 0.0, 1e-3);
        }
        assert_true(seen > MAX_ROWS / 2);
        /* rise then fall: largest near 45 deg (sin(2 alpha) / 2 dh/h), less at 60 */
        double e40 = NAN, e60 = NAN;
        for (long i = 0; i < n; i++)
            if (r[i].b_deg == 0 && r[i].a_deg == 40)
                e40 = fabs(r[i].v[SRC_A]);
            else if (r[i].b_deg == 0 && r[i].a_deg == 60)
                e60 = fabs(r[i].v[SRC_A]);
        assert_true(e40 > e60);
        assert_near(e40, 0.5 * sin(80 * rad_per_deg) * fabs(k - 1) * arcsec_per_rad, 0.1);
    }
}

/* Fig. 3, dx alone (principal point along X) without glass: the spot moves
 * along X only, so beta has no error and alpha's is
 * atan(tan alpha -+ dx/h) - alpha, whatever beta. */
static void dx_moves_alpha_only(void **state)
{
    static row r[MAX_ROWS];
    const double dx_px = 0.1;
    long n = run_curve("--only dx_px=0.1 " NO_GLASS, r, MAX_ROWS);
    const double e = dx_px * pixel_mm / h_mm;
    for (long i = 0; i < n; i++) {
        if (isnan(r[i].v[BEF_A]))
            continue;
        double a = r[i].a_deg * rad_per_deg;
        double want = (atan(tan(a) - e) - a) * arcsec_per_rad;
        /* the pinhole's shift moves the spot by +dx: alpha_m = atan(-(dx - h tan a)/h) */
        assert_near(r[i].v[SRC_A], want, 1e-6);
        assert_near(r[i].v[SRC_B], 0.0, 1e-9);
    }
}

/* Fig. 4, c1..c3 = 10 arcsec alone: nothing at the centre of the field,
 * growing toward its edge. */
static void installation_vanishes_at_centre(void **state)
{
    static row r[MAX_ROWS];
    const char *keys[] = {"c1_arcsec", "c2_arcsec", "c3_arcsec"};
    for (int k = 0; k < 3; k++) {
        char args[256];
        snprintf(args, sizeof args, "--only %s=10 --set campaign.mount=aligned " NO_GLASS,
                 keys[k]);
        long n = run_curve(args, r, MAX_ROWS);
        double centre = NAN, edge = 0;
        for (long i = 0; i < n; i++) {
            if (isnan(r[i].v[SRC_T]))
                continue;
            if (r[i].a_deg == 0 && r[i].b_deg == 0)
                centre = r[i].v[SRC_T];
            edge = fmax(edge, r[i].v[SRC_T]);
        }
        assert_near(centre, 0.0, 1e-6);
        assert_true(edge > 1.0);  /* a 10" rotation: arcseconds at the edge */
        assert_true(edge < 30.0); /* and of its own order */
    }
}

/* Fig. 5, the nominal design's refraction read by the paper's eq. 9-10
 * (design.onboard_refraction = ignored): at beta = 0 the spot is at (h - t) tan alpha + t tan theta_g with
 * sin theta_g = sin alpha / n, so the error is
 * atan(that / h) - alpha: negative for alpha > 0, growing with |alpha|. */
static void refraction_closed_form(void **state)
{
    static row r[MAX_ROWS];
    long n = run_curve("--only glass_index=0 --set design.onboard_refraction=ignored", r,
                       MAX_ROWS);
    double prev = 0;
    long checked = 0;
    for (long i = 0; i < n; i++) {
        if (r[i].b_deg != 0 || r[i].a_deg < 0)
            continue;
        double a = r[i].a_deg * rad_per_deg;
        double tg = tan(asin(sin(a) / n_glass));
        double want = (atan(((h_mm - t_mm) * tan(a) + t_mm * tg) / h_mm) - a) * arcsec_per_rad;
        assert_near(r[i].v[BEF_A], want, 1e-7 * fabs(want) + 1e-6); /* curve.tsv's 8 digits */
        assert_near(r[i].v[SRC_A], 0.0, 1e-9); /* the nominal unit itself */
        assert_true(fabs(r[i].v[BEF_A]) >= prev);
        prev = fabs(r[i].v[BEF_A]);
        checked++;
    }
    assert_int_equal(checked, 7);
    assert_true(prev > 3600); /* degrees at 60 deg: the fit must model it */
}

/* A Monte Carlo unit's map is reproducible, and its calibration removes
 * nearly all of its error (the refraction is modelled). */
static void unit_map_reproducible(void **state)
{
    static row r1[MAX_ROWS], r2[MAX_ROWS];
    long n1 = run_curve("--unit 3", r1, MAX_ROWS);
    long n2 = run_curve("--unit 3", r2, MAX_ROWS);
    assert_int_equal(n1, n2);
    assert_memory_equal(r1, r2, (size_t)n1 * sizeof *r1);
    long after_small = 0, seen = 0;
    for (long i = 0; i < n1; i++)
        if (!isnan(r1[i].v[AFT_T])) {
            seen++;
            after_small += fabs(r1[i].v[AFT_T]) < 0.01 * fabs(r1[i].v[BEF_T]);
        }
    assert_true(seen > MAX_ROWS / 2);
    assert_true(after_small > seen / 2); /* refraction is fitted: after << before */
}

static void dss_curve_errors(void **state)
{
    char out[8192], cmd[4096];
    const char *bad[] = {"configs/dss.ini --only dH_um=2",
                         "configs/dss.ini --only dh_px",
                         "configs/dss.ini --only dh_px=abc",
                         "configs/dss.ini --unit 1 --set validation.b_step_deg=-1"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(cmd, sizeof cmd, "%s curve %s --out %s --quiet", test_sunmc(), bad[i],
                 test_tmp("bad"));
        int rc = test_run(cmd, out, sizeof out);
        if (rc != 2)
            fail_msg("'%s' exited %d: %s", bad[i], rc, out);
    }
    snprintf(cmd, sizeof cmd, "test -e %s", test_tmp("bad"));
    assert_int_not_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dh_closed_form),
        cmocka_unit_test(dx_moves_alpha_only),
        cmocka_unit_test(installation_vanishes_at_centre),
        cmocka_unit_test(refraction_closed_form),
        cmocka_unit_test(unit_map_reproducible),
        cmocka_unit_test(dss_curve_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
