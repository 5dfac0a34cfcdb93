/* test_calibrate_csv_limits.c - the limits of the lab's data files on both sides of
 * each boundary: CSV field counts per row, data rows against the model's
 * parameters (n <= p refused, n = p + 1 accepted) as read and as usable
 * (weight > 0), the weight's sign, and the ranges `compensate` checks in
 * params.ini.  Refused means exit status 2 with "FILE:LINE: message" naming
 * what is wrong; accepted means the same command gets past the check. */
#include "test_util.h"

#include "csv.h"
#include "status.h"
#include "units.h"


static void path_of(const char *name, char *out, size_t len)
{
    snprintf(out, len, "%s", test_tmp(name));
}

/* ---- csv.h directly ---- */

/* A row with one field fewer or one more than the header is refused at its
 * line; the header's count is accepted. */
static void test_field_counts(void **state)
{
    char p[128], err[SUNMC_ERRLEN];
    csv_table *t;
    path_of("fields.csv", p, sizeof p);
    const char *rows[] = {"1,2", "1,2,3", "1,2,3,4", "1,2,", ",,"};
    const int ok[] = {0, 1, 0, 1, 1};
    const int nf[] = {2, 3, 4, 3, 3};
    for (int i = 0; i < 5; i++) {
        char text[256];
        snprintf(text, sizeof text, "# lab\na,b,c\n\n7,8,9\n%s\n", rows[i]);
        assert_int_equal(test_write_file(p, text), 0);
        int st = csv_read(p, &t, err, sizeof err);
        if (ok[i]) {
            assert_int_equal(st, SUNMC_OK);
            assert_int_equal(t->n_rows, 2);
            assert_int_equal(t->line[1], 5);
            csv_free(t);
        } else {
            assert_int_equal(st, SUNMC_EINPUT);
            char want[256];
            snprintf(want, sizeof want, "%s:5: %d fields, but the header (line 2) has 3 columns",
                     p, nf[i]);
            assert_string_equal(err, want);
        }
    }
    /* an empty header name, and no header at all */
    assert_int_equal(test_write_file(p, "a,,c\n1,2,3\n"), 0);
    assert_int_equal(csv_read(p, &t, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, ":1: header column 2 has no name"));
    assert_int_equal(test_write_file(p, "# only a comment\n\n"), 0);
    assert_int_equal(csv_read(p, &t, err, sizeof err), SUNMC_EINPUT);
    assert_non_null(strstr(err, "no header line"));
}

/* csv_require_rows: n rows meet a minimum of n, not n + 1 (named at the
 * file's last line). */
static void test_require_rows(void **state)
{
    char p[128], err[SUNMC_ERRLEN];
    csv_table *t;
    path_of("rows.csv", p, sizeof p);
    assert_int_equal(test_write_file(p, "x\n1\n2\n3\n# end\n"), 0);
    assert_int_equal(csv_read(p, &t, err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_require_rows(t, 3, "why", err, sizeof err), SUNMC_OK);
    assert_int_equal(csv_require_rows(t, 4, "the model needs 4", err, sizeof err), SUNMC_EINPUT);
    char want[256];
    snprintf(want, sizeof want, "%s:5: only 3 data rows; the model needs 4", p);
    assert_string_equal(err, want);
    csv_free(t);
}

/* ---- calibrate: rows against parameters ---- */

static int calibrate(const char *sensor, const char *config, const char *sets, const char *text,
                     char *out, size_t outlen)
{
    char p[128], cmd[1024];
    path_of("data.csv", p, sizeof p);
    assert_int_equal(test_write_file(p, text), 0);
    snprintf(cmd, sizeof cmd, "%s calibrate --sensor %s --config %s %s %s", test_sunmc(), sensor,
             config, sets, p);
    return test_run(cmd, out, outlen);
}

static void expect_refused(int rc, const char *out, const char *needle)
{
    if (rc != 2 || !strstr(out, needle))
        fail_msg("expected exit 2 and '%s', got %d:\n%s", needle, rc, out);
}

static void expect_accepted(int rc, const char *out)
{
    if (rc != 0)
        fail_msg("expected exit 0, got %d:\n%s", rc, out);
}

/* ESS rows of a sensor with a height error (output atan(1.0005 tan alpha),
 * at beta = 0 and 10) plus a little deterministic noise, n of them, with
 * weights w[i] (NULL: no weight column).  (Data the identity model fits
 * exactly would start the fit at its solution, where GSL's driver reports
 * no progress.) */
/* End row i: its weight w[i] when there is a weight column, a newline. */
static size_t end_row(char *text, size_t len, size_t used, const double *w, int i)
{
    if (w)
        used += (size_t)snprintf(text + used, len - used, ",%g", w[i]);
    return used + (size_t)snprintf(text + used, len - used, "\n");
}

static void ess_rows(int n, const double *w, char *text, size_t len)
{
    size_t used = (size_t)snprintf(text, len, "alpha_deg,beta_deg,output_deg%s\n", w ? ",weight" : "");
    for (int i = 0; i < n; i++) {
        double a = -48 + 12.3 * i, b = i % 2 ? 10 : 0;
        double out = atan(1.0005 * tan(a * RAD_PER_DEG)) * DEG_PER_RAD + 1e-4 * ((i * 7) % 5 - 2);
        used += (size_t)snprintf(text + used, len - used, "%.6f,%g,%.8f", a, b, out);
        used = end_row(text, len, used, w, i);
    }
}

/* The ESS model has 8 parameters: 8 rows refused, 9 accepted; 8 usable of
 * 10 refused, 9 usable accepted; weight 0 allowed, negative refused. */
static void test_ess_rows_vs_parameters(void **state)
{
    char text[4096], out[1 << 14];
    const char *cfg = "configs/ess_type_a.ini";
    ess_rows(8, NULL, text, sizeof text);
    expect_refused(calibrate("ess", cfg, "", text, out, sizeof out), out,
                   "data.csv:9: only 8 data rows; the ess model has 8 parameters: need at least 9");
    ess_rows(9, NULL, text, sizeof text);
    expect_accepted(calibrate("ess", cfg, "", text, out, sizeof out), out);
    const double w9[10] = {1, 1, 0, 1, 1, 1, 1, 1, 1, 1};
    ess_rows(10, w9, text, sizeof text);
    expect_accepted(calibrate("ess", cfg, "", text, out, sizeof out), out);
    const double w8[10] = {1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    ess_rows(10, w8, text, sizeof text);
    expect_refused(calibrate("ess", cfg, "", text, out, sizeof out), out,
                   "only 8 usable data rows");
    const double wneg[10] = {1, 1, 1, 1, -1e-9, 1, 1, 1, 1, 1};
    ess_rows(10, wneg, text, sizeof text);
    expect_refused(calibrate("ess", cfg, "", text, out, sizeof out), out,
                   "data.csv:6: column 'weight': -1e-09 is negative");
}

/* DSS rows of the nominal design (pinhole at 3 mm, 5.5 um pixels, 0.4 mm
 * of glass of index 1.52, the plate displacement t (tan th - tan thg)) on a
 * b1 x b2 grid of 5 x 5 (the first n of them), weights w (NULL: none). */
static void dss_rows(int n, const double *w, char *text, size_t len)
{
    const double h = 3.0, pix = 5.5e-3, t = 0.4, gn = 1.52;
    size_t used = (size_t)snprintf(text, len, "b1_deg,b2_deg,x_px,y_px%s\n", w ? ",weight" : "");
    for (int i = 0; i < n; i++) {
        double b1 = -30 + 15 * (i / 5), b2 = -30 + 15 * (i % 5);
        double r1 = b1 * RAD_PER_DEG, r2 = b2 * RAD_PER_DEG;
        double u[3] = {-sin(r2) * cos(r1), sin(r1), cos(r1) * cos(r2)};
        double th = acos(u[2]), ph = atan2(u[1], u[0]), thg = asin(sin(th) / gn);
        double r = h * tan(th) - t * (tan(th) - tan(thg));
        used += (size_t)snprintf(text + used, len - used, "%g,%g,%.12f,%.12f", b1, b2,
                                 -r * cos(ph) / pix, -r * sin(ph) / pix);
        used = end_row(text, len, used, w, i);
    }
}

/* The physical model: the file needs 11 rows (10 parameters at most); the
 * fit needs 2 n > free parameters: as mounted 10 with the glass index
 * fitted; aligned (no sun-simulator angles) 8, or 7 with the index held. */
static void test_dss_physical_rows(void **state)
{
    char text[8192], out[1 << 14];
    const char *cfg = "configs/dss.ini";
    dss_rows(10, NULL, text, sizeof text);
    expect_refused(calibrate("dss", cfg, "", text, out, sizeof out), out,
                   "data.csv:11: only 10 data rows; the dss model has up to 10 parameters: need "
                   "at least 11 rows");
    dss_rows(11, NULL, text, sizeof text);
    expect_accepted(calibrate("dss", cfg, "", text, out, sizeof out), out);
    double w[11] = {1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1}; /* 6 usable: 12 residuals > 10 */
    dss_rows(11, w, text, sizeof text);
    expect_accepted(calibrate("dss", cfg, "", text, out, sizeof out), out);
    w[10] = 0; /* 5 usable: 10 residuals */
    dss_rows(11, w, text, sizeof text);
    expect_refused(calibrate("dss", cfg, "", text, out, sizeof out), out,
                   "only 5 usable readings (weight > 0); the dss_physical model has 10 parameters");
    const char *al = "--set campaign.mount=aligned";
    expect_accepted(calibrate("dss", cfg, al, text, out, sizeof out), out); /* 10 > 8 */
    w[8] = 0; /* 4 usable: 8 residuals */
    dss_rows(11, w, text, sizeof text);
    expect_refused(calibrate("dss", cfg, al, text, out, sizeof out), out,
                   "only 4 usable readings (weight > 0); the dss_physical model has 8 parameters");
    const char *off = "--set campaign.mount=aligned --set calibration.fit_glass_index=off";
    expect_accepted(calibrate("dss", cfg, off, text, out, sizeof out), out); /* 8 > 7 */
    w[6] = 0; /* 3 usable: 6 residuals <= 7 */
    dss_rows(11, w, text, sizeof text);
    expect_refused(calibrate("dss", cfg, off, text, out, sizeof out), out,
                   "only 3 usable readings (weight > 0); the dss_physical model has 7 parameters");
}

/* The polynomial of order k has (k + 1)(k + 2)/2 terms per axis: order 3
 * needs 11 rows, order 1 needs 4; and as many usable ones. */
static void test_dss_polynomial_rows(void **state)
{
    char text[8192], out[1 << 14];
    const char *cfg = "configs/dss.ini";
    const char *o3 = "--set calibration.model=polynomial --set calibration.poly_order=3";
    const char *o1 = "--set calibration.model=polynomial --set calibration.poly_order=1";
    dss_rows(10, NULL, text, sizeof text);
    expect_refused(calibrate("dss", cfg, o3, text, out, sizeof out), out,
                   "only 10 data rows; the dss model has up to 10 parameters: need at least 11");
    dss_rows(11, NULL, text, sizeof text);
    expect_accepted(calibrate("dss", cfg, o3, text, out, sizeof out), out);
    double w[12] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0};
    dss_rows(12, w, text, sizeof text);
    expect_accepted(calibrate("dss", cfg, o3, text, out, sizeof out), out);
    w[0] = 0;
    dss_rows(12, w, text, sizeof text);
    expect_refused(calibrate("dss", cfg, o3, text, out, sizeof out), out,
                   "only 10 usable readings (weight > 0); the dss_polynomial model has 10 "
                   "parameters");
    dss_rows(3, NULL, text, sizeof text);
    expect_refused(calibrate("dss", cfg, o1, text, out, sizeof out), out,
                   "only 3 data rows; the dss model has up to 3 parameters: need at least 4");
    dss_rows(4, NULL, text, sizeof text);
    expect_accepted(calibrate("dss", cfg, o1, text, out, sizeof out), out);
}

/* ---- compensate: params.ini ranges ---- */

static int compensate(const char *params, const char *raw, char *out, size_t outlen)
{
    char pp[128], rp[128], cmd[1024];
    path_of("p.ini", pp, sizeof pp);
    path_of("raw.csv", rp, sizeof rp);
    assert_int_equal(test_write_file(pp, params), 0);
    assert_int_equal(test_write_file(rp, raw), 0);
    snprintf(cmd, sizeof cmd, "%s compensate %s %s", test_sunmc(), pp, rp);
    return test_run(cmd, out, outlen);
}

/* The writing version compensate requires, last (the other keys keep
 * their lines). */
#define PARAMS_VERSION "[calibration]\nsunmc_version = " SUNMC_VERSION "\n"

static const char ess_params_fmt[] =
    "[calibration]\nsensor = ess\nmodel = ess_eq12_finecode\n[design]\ntheta0_deg = %s\n"
    "[fixed]\nroll_measured_arcsec = 0\n[parameters]\na = 1\nb = 0\nc = 0\nks_deg = 0\n"
    "kc_deg = 0\nfit_install_y_arcsec = 0\nfit_install_z_arcsec = 0\nfit_sun_y_arcsec = 0\n"
    PARAMS_VERSION;

/* theta0_deg within design.theta0_deg's range 0.1..10 deg: 0, -2 and a
 * hair outside refused at its line, both ends accepted. */
static void test_ess_params_theta0(void **state)
{
    char params[2048], out[4096], want[160];
    const char *bad[] = {"0", "-2", "0.0999", "10.001"};
    for (int i = 0; i < 4; i++) {
        snprintf(params, sizeof params, ess_params_fmt, bad[i]);
        snprintf(want, sizeof want, "p.ini:5: design.theta0_deg = %s is out of range: allowed "
                 "0.1 to 10 deg", bad[i]);
        expect_refused(compensate(params, "output_deg\n10\n", out, sizeof out), out, want);
    }
    const char *good[] = {"0.1", "10"};
    for (int i = 0; i < 2; i++) {
        snprintf(params, sizeof params, ess_params_fmt, good[i]);
        int rc = compensate(params, "output_deg\n10\n", out, sizeof out);
        expect_accepted(rc, out);
        assert_non_null(strstr(out, "output_deg,compensated_deg\n10,10\n"));
    }
}

/* A polynomial params.ini of order k with all its terms 0. */
static void poly_params(const char *order, int terms, const char *pixel, char *text, size_t len)
{
    size_t used = (size_t)snprintf(text, len,
                                   "[calibration]\nsensor = dss\nmodel = dss_polynomial\n"
                                   "[design]\norder = %s\nscale_rad = 1\nh_mm = 3\n"
                                   "pixel_um = %s\nglass_thickness_mm = 0\nglass_index = 1.52\n"
                                   "[parameters]\n",
                                   order, pixel);
    for (int k = 0; k < terms; k++)
        used += (size_t)snprintf(text + used, len - used, "ca_%d = 0\ncb_%d = 0\n", k, k);
    snprintf(text + used, len - used, "%s", PARAMS_VERSION);
}

/* order must be a whole number 1..7: 0, 8 and 2.5 refused at its line; 1
 * and 7 accepted (and with zero terms the on-board formula comes back). */
static void test_dss_params_order(void **state)
{
    char params[8192], out[4096];
    const struct {
        const char *order;
        int terms, ok;
    } cases[] = {{"0", 1, 0}, {"1", 3, 1}, {"7", 36, 1}, {"8", 45, 0}, {"2.5", 10, 0}};
    for (int i = 0; i < 5; i++) {
        poly_params(cases[i].order, cases[i].terms, "5.5", params, sizeof params);
        int rc = compensate(params, "x_px,y_px\n100,-50\n", out, sizeof out);
        if (cases[i].ok) {
            expect_accepted(rc, out);
            double a = strtod(strstr(out, "100,-50,") + 8, NULL);
            assert_near(a, atan(-100 * 0.0055 / 3) * DEG_PER_RAD, 1e-12);
        } else {
            expect_refused(rc, out, strchr(cases[i].order, '.')
                                        ? "p.ini:5: key design.order: '2.5' is not a whole number"
                                        : "p.ini:5: key design.order must be 1..7");
        }
    }
}

/* pixel_um, h_mm, glass_thickness_mm, mount, fit_dh_px,
 * fit_glass_thickness_um */
static const char dss_phys_fmt[] =
    "[calibration]\nsensor = dss\nmodel = dss_physical\n[design]\npixel_um = %s\n"
    "h_mm = %s\nglass_thickness_mm = %s\nglass_index = 1.52\nmount = %s\n"
    "[parameters]\nfit_dx_px = 0\nfit_dy_px = 0\nfit_dh_px = %s\nfit_glass_thickness_um = %s\n"
    "fit_c1_arcsec = 0\nfit_c2_arcsec = 0\nfit_c3_arcsec = 0\nfit_glass_index = 0\n"
    "fit_sun_b1_arcsec = 0\nfit_sun_b2_arcsec = 0\n" PARAMS_VERSION;

/* The physical model needs a pitch and a height, and the glass under the
 * pinhole: pixel_um and h_mm > 0, the fitted height above the detector,
 * the fitted thickness below the fitted height (a negative one, the fit's
 * extrapolation for a sensor without glass, is its business), a known
 * mount. */
static void test_dss_params_physical(void **state)
{
    char params[2048], out[4096];
    const struct {
        const char *pixel, *h, *t, *mount, *dh, *dt, *needle;
    } cases[] = {
        {"5.5", "3", "0.4", "as_mounted", "0", "0", NULL},
        {"5.5", "3", "0.4", "aligned", "0", "0", NULL},
        {"5.5", "3", "0.4", "tilted", "0", "0",
         "p.ini:9: key design.mount must be aligned or as_mounted"},
        {"0", "3", "0.4", "as_mounted", "0", "0",
         "p.ini:5: design.pixel_um = 0 is out of range: allowed 0.5 to 100 um"},
        {"0.5", "3", "0.4", "as_mounted", "0", "0", NULL},
        {"0.499", "3", "0.4", "as_mounted", "0", "0", "design.pixel_um = 0.499 is out of range"},
        {"100", "3", "0.4", "as_mounted", "0", "0", NULL},
        {"100.001", "3", "0.4", "as_mounted", "0", "0", "design.pixel_um = 100.001 is out of range"},
        {"-5.5", "3", "0.4", "as_mounted", "0", "0", "design.pixel_um = -5.5 is out of range"},
        {"5.5", "0", "0", "as_mounted", "0", "0", "p.ini:6: design.h_mm = 0 is out of range"},
        {"5.5", "50.001", "0", "as_mounted", "0", "0", "design.h_mm = 50.001 is out of range"},
        {"5.5", "3", "0.4", "as_mounted", "1000.5", "0",
         "p.ini:13: parameters.fit_dh_px = 1000.5 is out of range: allowed -1000 to 1000 px"},
        {"5.5", "3", "0", "as_mounted", "-545.45454545", "0", NULL}, /* h + dh = 2.5e-9 mm */
        {"5.5", "3", "0", "as_mounted", "-545.4545454546", "0",
         "p.ini:13: key parameters.fit_dh_px must be > -design.h_mm / design.pixel_um"},
        {"5.5", "3", "2.9", "as_mounted", "0", "100.001",
         "p.ini:14: key parameters.fit_glass_thickness_um must be such that the glass lies "
         "under the pinhole"},
        {"5.5", "3", "2.9", "as_mounted", "0", "99.999", NULL},
        {"5.5", "3", "0.4", "as_mounted", "0", "1000.001",
         "parameters.fit_glass_thickness_um = 1000.001 is out of range"},
        {"5.5", "3", "0.4", "as_mounted", "0", "-400.001", NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(params, sizeof params, dss_phys_fmt, cases[i].pixel, cases[i].h, cases[i].t,
                 cases[i].mount, cases[i].dh, cases[i].dt);
        int rc = compensate(params, "x_px,y_px\n10,-5\n", out, sizeof out);
        if (cases[i].needle)
            expect_refused(rc, out, cases[i].needle);
        else
            expect_accepted(rc, out);
    }
    /* the nominal design through its own glass: the spot of a sun at
     * (alpha, beta) = (20, 0) deg compensates back to it */
    snprintf(params, sizeof params, dss_phys_fmt, "5.5", "3", "0.4", "as_mounted", "0", "0");
    double th = 20 * RAD_PER_DEG, thg = asin(sin(th) / 1.52);
    double x = -(3 * tan(th) - 0.4 * (tan(th) - tan(thg))) / 0.0055;
    char raw[128];
    snprintf(raw, sizeof raw, "x_px,y_px\n%.12f,0\n", x);
    expect_accepted(compensate(params, raw, out, sizeof out), out);
    const char *comma = strstr(out, ",0,"); /* the row: x, y = 0, alpha, beta */
    assert_non_null(comma);
    assert_near(strtod(comma + 3, NULL), 20.0, 1e-9);
}

/* The polynomial's normalisation: scale_rad, h_mm, pixel_um within
 * their ranges (0 is outside each). */
static void test_dss_params_polynomial_design(void **state)
{
    char params[8192], out[4096];
    const char *keys[] = {"scale_rad = 1", "h_mm = 3", "pixel_um = 5.5"};
    const char *zero[] = {"scale_rad = 0", "h_mm = 0", "pixel_um = 0"};
    const char *names[] = {"design.scale_rad", "design.h_mm", "design.pixel_um"};
    for (int i = 0; i < 3; i++) {
        poly_params("1", 3, "5.5", params, sizeof params);
        char *at = strstr(params, keys[i]);
        assert_non_null(at);
        memcpy(at, zero[i], strlen(zero[i]));
        memmove(at + strlen(zero[i]), at + strlen(keys[i]), strlen(at + strlen(keys[i])) + 1);
        char want[128];
        snprintf(want, sizeof want, "%s = 0 is out of range", names[i]);
        expect_refused(compensate(params, "x_px,y_px\n1,1\n", out, sizeof out), out, want);
    }
}

/* The on-board formula's glass: 0 <= glass_thickness_mm < h_mm (0
 * ignores it), glass_index >= 1; each limit refused just outside, accepted on it. */
static void test_dss_params_polynomial_glass(void **state)
{
    char params[8192], out[4096];
    const struct {
        const char *from, *to;
        int ok;
    } cases[] = {
        {"glass_thickness_mm = 0\n", "glass_thickness_mm = -1e-9\n", 0},
        {"glass_thickness_mm = 0\n", "glass_thickness_mm = 2.999999\n", 1},
        {"glass_thickness_mm = 0\n", "glass_thickness_mm = 3\n", 0},
        {"glass_index = 1.52\n", "glass_index = 0.999999\n", 0},
        {"glass_index = 1.52\n", "glass_index = 1\n", 1},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        poly_params("1", 3, "5.5", params, sizeof params);
        char *at = strstr(params, cases[i].from);
        assert_non_null(at);
        size_t lf = strlen(cases[i].from), lt = strlen(cases[i].to);
        memmove(at + lt, at + lf, strlen(at + lf) + 1);
        memcpy(at, cases[i].to, lt);
        int rc = compensate(params, "x_px,y_px\n1,1\n", out, sizeof out);
        if (cases[i].ok)
            expect_accepted(rc, out);
        else
            expect_refused(rc, out, strncmp(cases[i].to, "glass_index", 11) == 0
                                        ? "design.glass_index"
                                        : "design.glass_thickness_mm");
    }
}

/* Files written before params.ini's keys took their config keys' names
 * (h_nom_mm, pixel_mm in mm, glass_t_mm, glass_n) compensate as the same
 * file with the names of today, both models, to the digit. */
static void test_dss_params_earlier_names(void **state)
{
    char now[8192], before[8192], out_now[4096], out_before[4096];
    poly_params("2", 6, "5.5", now, sizeof now);
    snprintf(before, sizeof before, "%s", now);
    const char *const pairs[][2] = {{"h_mm = 3", "h_nom_mm = 3"},
                                    {"pixel_um = 5.5", "pixel_mm = 0.0055"},
                                    {"glass_thickness_mm = 0", "glass_t_mm = 0"},
                                    {"glass_index = 1.52", "glass_n = 1.52"}};
    for (int k = 0; k < 4; k++) {
        char *at = strstr(before, pairs[k][0]);
        assert_non_null(at);
        size_t lf = strlen(pairs[k][0]), lt = strlen(pairs[k][1]);
        memmove(at + lt, at + lf, strlen(at + lf) + 1);
        memcpy(at, pairs[k][1], lt);
    }
    char *ca = strstr(now, "ca_1 = 0"), *cb = strstr(before, "ca_1 = 0");
    memcpy(ca, "ca_1 = 1", 8); /* a term that moves the answer */
    memcpy(cb, "ca_1 = 1", 8);
    expect_accepted(compensate(now, "x_px,y_px\n100,-50\n", out_now, sizeof out_now), out_now);
    expect_accepted(compensate(before, "x_px,y_px\n100,-50\n", out_before, sizeof out_before),
                    out_before);
    assert_string_equal(out_now, out_before);
    snprintf(now, sizeof now, dss_phys_fmt, "5.5", "3", "0.4", "as_mounted", "2", "1");
    snprintf(before, sizeof before, dss_phys_fmt, "0.0055", "3", "0.4", "as_mounted", "2", "1");
    char *px = strstr(before, "pixel_um");
    memcpy(px, "pixel_mm", 8);
    expect_accepted(compensate(now, "x_px,y_px\n300,-50\n", out_now, sizeof out_now), out_now);
    expect_accepted(compensate(before, "x_px,y_px\n300,-50\n", out_before, sizeof out_before),
                    out_before);
    assert_string_equal(out_now, out_before);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_field_counts),
        cmocka_unit_test(test_require_rows),
        cmocka_unit_test(test_ess_rows_vs_parameters),
        cmocka_unit_test(test_dss_physical_rows),
        cmocka_unit_test(test_dss_polynomial_rows),
        cmocka_unit_test(test_ess_params_theta0),
        cmocka_unit_test(test_dss_params_order),
        cmocka_unit_test(test_dss_params_physical),
        cmocka_unit_test(test_dss_params_polynomial_design),
        cmocka_unit_test(test_dss_params_polynomial_glass),
        cmocka_unit_test(test_dss_params_earlier_names),
    };
    return cmocka_run_group_tests_name("limits_csv", tests, NULL, NULL);
}
