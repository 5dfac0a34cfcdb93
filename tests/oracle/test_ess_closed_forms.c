/* test_ess_closed_forms.c - the ESS physics against values this file works
 * out on its own: the fine-code harmonic transfer (by numerical quadrature
 * of the dial, slit and sun profiles, not the closed forms the code uses),
 * the DC level, the row currents, the four-quadrant demodulation, etching,
 * gain and tilt errors, the cos(incidence) illumination, eq. 7 with a phase
 * and with the fifth harmonic, the Gray coarse code at its cell edges, the
 * coarse/fine combination, and the compensation model (eq. 12-14) and its
 * inverse.
 *
 * Conventions (from ess_sensor.h, derived again here):
 *  - row m (0..3) reads psi_m = atan((eta(x_m) - etch_m) / H) with
 *    eta = Hr v - dd - (x_m + Hr u) tan(dphi), u = s_x/s_z, v = s_y/s_z;
 *  - its current is I_m = illum g_m [DC - sum_n c_n cos(n (x_m - m pi/2) + phi_n)]
 *    + noise_m, x_m = 2 pi psi_m / theta0, illum = s_z;
 *  - with no harmonics the demodulated phase is therefore
 *        atan2(I3 - I1, I2 - I0) = atan2(sin x1 + sin x3, cos x0 + cos x2)
 *    (DC cancels), which every closed form below starts from. */
#include "test_util.h"

#include "config.h"
#include "ess_config.h"
#include "ess_model.h"
#include "ess_sensor.h"
#include "status.h"
#include "units.h"

#define TWO_PI (2.0 * M_PI)

static sunmc_config default_ess(void) { return test_family_config("ess"); }

/* Harmonics given as 1, a3, a5 (a3 = a5 = 0: a pure fundamental). */
static sunmc_config given(double a3, double a5)
{
    sunmc_config c = default_ess();
    ess_cfg(&c)->design.harmonics = 1;
    ess_cfg(&c)->design.a3_ratio = a3;
    ess_cfg(&c)->design.a5_ratio = a5;
    return c;
}

static void sun_vector(double alpha_deg, double beta_deg, double sv[3])
{
    double a = alpha_deg * RAD_PER_DEG, b = beta_deg * RAD_PER_DEG;
    sv[0] = sin(b);
    sv[1] = cos(b) * sin(a);
    sv[2] = cos(b) * cos(a);
}

static double output_deg(const ess_sensor *s, double alpha_deg, double beta_deg,
                         const double noise[ESS_FINE_ROWS])
{
    double sv[3], out;
    sun_vector(alpha_deg, beta_deg, sv);
    assert_int_equal(ess_sensor_output(s, sv, noise, &out), SUNMC_OK);
    return out * DEG_PER_RAD;
}

/* The fine phase (rad) put into the period nearest alpha (deg): what the
 * coarse code does away from its cell edges. */
static double in_period_deg(double phase_rad, double theta0_deg, double alpha_deg)
{
    double fine = phase_rad / TWO_PI * theta0_deg;
    return fine + theta0_deg * round((alpha_deg - fine) / theta0_deg);
}

/* ---- harmonic transfer by quadrature ---- */

/* Simpson's rule of f over [a, b] with n (even) intervals. */
static double simpson(double (*f)(double, const double *), const double *par, double a, double b,
                      int n)
{
    double h = (b - a) / n, s = f(a, par) + f(b, par);
    for (int i = 1; i < n; i++)
        s += (i % 2 ? 4.0 : 2.0) * f(a + i * h, par);
    return s * h / 3.0;
}

/* par[0] = harmonic n; y in periods. */
static double cos_n(double y, const double *par) { return cos(TWO_PI * par[0] * y); }

/* Disc, y = (d/2) sin t: profile sqrt(R^2 - y^2) dy = R^2 cos^2 t dt.
 * par[0] = n, par[1] = d (diameter in periods). */
static double disc_integrand(double t, const double *par)
{
    return cos(t) * cos(t) * cos(TWO_PI * par[0] * 0.5 * par[1] * sin(t));
}

/* Fourier cosine coefficient of a 0/1 dial of duty D (window centred). */
static double dial_coef(int n, double D)
{
    double par[1] = {n};
    return 2.0 * simpson(cos_n, par, -D / 2, D / 2, 2000);
}

/* Transfer of a box of width w periods (the slit). */
static double box_transfer(int n, double w)
{
    if (w == 0)
        return 1.0;
    double par[1] = {n};
    return simpson(cos_n, par, -w / 2, w / 2, 2000) / w;
}

/* Transfer of a uniform disc of diameter d periods, seen edge-on (the sun). */
static double disc_transfer_q(int n, double d)
{
    double par[2] = {n, d};
    return simpson(disc_integrand, par, -M_PI / 2, M_PI / 2, 2000) / (M_PI / 2);
}

typedef struct {
    double H_mm, slit_mm, duty, sun_deg, theta0_deg;
} fine_design;

/* Amplitude of harmonic n at dial angle psi, unnormalised: the slit's
 * angular width is w cos^2(psi) / H (d eta / d psi = H / cos^2 psi). */
static double amp(const fine_design *f, int n, double psi)
{
    double th0 = f->theta0_deg * RAD_PER_DEG;
    double slit_periods = f->slit_mm * cos(psi) * cos(psi) / f->H_mm / th0;
    return dial_coef(n, f->duty) * disc_transfer_q(n, f->sun_deg / f->theta0_deg) *
           box_transfer(n, slit_periods);
}

/* c_n = a_n(psi) / a_1(0), and DC / a_1(0) (the dial's mean is its duty). */
static void ref_harmonics(const fine_design *f, double psi, double c[3], double *dc)
{
    double a1 = amp(f, 1, 0.0);
    const int order[3] = {1, 3, 5};
    for (int i = 0; i < 3; i++)
        c[i] = amp(f, order[i], psi) / a1;
    *dc = f->duty / a1;
}

static fine_design design_of(const sunmc_config *c)
{
    fine_design f = {ess_cfg(c)->design.H_mm, ess_cfg(c)->design.slit_width_um * MM_PER_UM, ess_cfg(c)->design.dial_duty,
                     ess_cfg(c)->design.sun_diameter_deg, ess_cfg(c)->design.theta0_deg};
    return f;
}

static void check_harmonics(sunmc_config c, double psi)
{
    ess_deviations dev = {0};
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    fine_design f = design_of(&c);
    double want[3], dc, got[3];
    ref_harmonics(&f, psi, want, &dc);
    ess_finecode_harmonics(&s, psi, got);
    for (int i = 0; i < 3; i++)
        assert_near(got[i], want[i], 1e-9 * fmax(1.0, fabs(want[i])));
}

/* c3/c1 and c5/c1 (with their signs) for several slits, duties, suns and
 * dial angles; the slit's share shrinks as cos^2(psi). */
static void test_harmonic_transfer(void **state)
{
    const double slits_um[] = {0, 20, 150, 400};
    const double duties[] = {0.5, 0.3, 0.62};
    const double suns[] = {0, 0.53, 1.4};
    const double psis_deg[] = {0, 35, 61};
    for (size_t i = 0; i < 4; i++)
        for (size_t j = 0; j < 3; j++)
            for (size_t k = 0; k < 3; k++)
                for (size_t p = 0; p < 3; p++) {
                    sunmc_config c = default_ess();
                    ess_cfg(&c)->design.slit_width_um = slits_um[i];
                    ess_cfg(&c)->design.dial_duty = duties[j];
                    ess_cfg(&c)->design.sun_diameter_deg = suns[k];
                    check_harmonics(c, psis_deg[p] * RAD_PER_DEG);
                }
    /* The order matters: a duty-0.3 dial has c3 > 0, unlike the square wave. */
    sunmc_config c = default_ess();
    ess_cfg(&c)->design.dial_duty = 0.3;
    ess_cfg(&c)->design.sun_diameter_deg = 0;
    ess_cfg(&c)->design.slit_width_um = 0;
    ess_deviations dev = {0};
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    double h[3];
    ess_finecode_harmonics(&s, 0.0, h);
    assert_near(h[1], sin(0.9 * M_PI) / 3 / sin(0.3 * M_PI), 1e-12);
    assert_near(h[2], sin(1.5 * M_PI) / 5 / sin(0.3 * M_PI), 1e-12);
    /* A slit width deviation is part of the slit. */
    c = default_ess();
    dev.slit_width_um = 30;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    ess_cfg(&c)->design.slit_width_um += 30;
    fine_design f = design_of(&c);
    double want[3], dc;
    ref_harmonics(&f, 0.4, want, &dc);
    ess_finecode_harmonics(&s, 0.4, h);
    assert_near(h[1], want[1], 1e-9);
    assert_near(h[2], want[2], 1e-9);
}

/* The four row currents: quarter-period shifts, gains, illumination, the
 * harmonics' own shifts (n (x - m pi/2)), the phase on the third harmonic
 * only, additive noise (harmonics given, so each row may read its own psi);
 * then the DC level of derived harmonics. */
static void test_row_currents(void **state)
{
    sunmc_config c = given(-0.07, 0.03);
    ess_cfg(&c)->design.slit_width_um = 60;
    ess_cfg(&c)->design.dial_duty = 0.45;
    ess_deviations dev = {0};
    dev.harmonic_phase_deg = 40;
    const double gain_pct[4] = {0.7, -1.1, 0.3, 2.0};
    for (int m = 0; m < 4; m++)
        dev.gain_pct[m] = gain_pct[m];
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    fine_design f = design_of(&c);
    const double psi_deg[4] = {17.3, 17.5, 17.9, 18.6};
    const double noise[4] = {0.01, -0.02, 0.003, 0.0};
    const double illum = 0.62;
    double psi[4], cur[4];
    for (int m = 0; m < 4; m++)
        psi[m] = psi_deg[m] * RAD_PER_DEG;
    ess_finecode_currents(&s, psi, illum, noise, cur);
    double ch[3] = {1, -0.07, 0.03}, unused[3], dc;
    ref_harmonics(&f, 0.0, unused, &dc); /* the DC is derived even when the harmonics are given */
    const int order[3] = {1, 3, 5};
    const double th0 = ess_cfg(&c)->design.theta0_deg * RAD_PER_DEG, phi3 = 40 * RAD_PER_DEG;
    for (int m = 0; m < 4; m++) {
        double x = TWO_PI * psi[m] / th0, sum = 0;
        for (int i = 0; i < 3; i++)
            sum += ch[i] * cos(order[i] * (x - m * M_PI / 2) + (order[i] == 3 ? phi3 : 0));
        double want = illum * (1 + gain_pct[m] / 100) * (dc - sum) + noise[m];
        assert_near(cur[m], want, 1e-9);
    }
    /* Derived harmonics, equal gains, no noise, one psi: the currents are
     * illum (DC - sum c_n cos(n (x - m pi/2))) and average to illum x DC
     * (every odd harmonic sums to zero over four quarter shifts). */
    ess_cfg(&c)->design.harmonics = 0;
    memset(&dev, 0, sizeof dev);
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    for (int m = 0; m < 4; m++)
        psi[m] = psi_deg[0] * RAD_PER_DEG;
    ess_finecode_currents(&s, psi, illum, NULL, cur);
    ref_harmonics(&f, psi[0], ch, &dc);
    double x = TWO_PI * psi[0] / th0;
    for (int m = 0; m < 4; m++) {
        double sum = 0;
        for (int i = 0; i < 3; i++)
            sum += ch[i] * cos(order[i] * (x - m * M_PI / 2));
        assert_near(cur[m], illum * (dc - sum), 1e-9);
    }
    assert_near((cur[0] + cur[1] + cur[2] + cur[3]) / 4, illum * dc, 1e-9);
    /* The DC of a bare square wave: D / ((2/pi) sin(pi D)) = pi/4. */
    c = default_ess();
    ess_cfg(&c)->design.slit_width_um = 0;
    ess_cfg(&c)->design.sun_diameter_deg = 0;
    ess_cfg(&c)->design.dial_duty = 0.5;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    ess_finecode_currents(&s, psi, 1.0, NULL, cur);
    assert_near((cur[0] + cur[1] + cur[2] + cur[3]) / 4, M_PI / 4, 1e-9);
}

/* Demodulation of hand-made currents: the phase of the fundamental, in
 * [0, 2 pi), whatever the DC. */
static void test_demodulation(void **state)
{
    for (double x = -7.0; x < 7.0; x += 0.37) {
        double dc = 1.3 + 0.1 * x;
        double I[4] = {dc - cos(x), dc - sin(x), dc + cos(x), dc + sin(x)};
        double ph = ess_finecode_demodulate(I);
        double want = fmod(x, TWO_PI);
        if (want < 0)
            want += TWO_PI;
        assert_true(ph >= 0 && ph < TWO_PI);
        assert_near(ph, want, 1e-12);
    }
    /* An amplitude and quadrature imbalance: atan2(I3 - I1, I2 - I0). */
    double I[4] = {0.2, 1.7, 0.9, 0.4};
    assert_near(ess_finecode_demodulate(I), atan2(0.4 - 1.7, 0.9 - 0.2) + TWO_PI, 1e-15);
}

/* No harmonics: phase from the four rows' own phases x_m (see the top). */
static double phase_of_rows(const double x[4])
{
    double ph = atan2(sin(x[1]) + sin(x[3]), cos(x[0]) + cos(x[2]));
    return ph < 0 ? ph + TWO_PI : ph;
}

/* Etching: a common etch e on the four fine rows is an offset,
 * atan(tan alpha - e/H), exactly; an etch on row m alone shifts that row's
 * phase only, with the row-specific closed form. */
static void test_etch_offsets(void **state)
{
    sunmc_config c = given(0, 0);
    const double H = ess_cfg(&c)->design.H_mm, th0 = ess_cfg(&c)->design.theta0_deg;
    ess_deviations dev = {0};
    for (int m = 0; m < 4; m++)
        dev.etch_um[m] = 0.4;
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    for (double a = -60; a <= 60; a += 1.37) {
        double want = atan(tan(a * RAD_PER_DEG) - 0.4e-3 / H) * DEG_PER_RAD;
        assert_near(output_deg(&s, a, 9, NULL), want, 1e-10);
    }
    for (int row = 0; row < 4; row++) {
        memset(&dev, 0, sizeof dev);
        dev.etch_um[row] = 0.3;
        ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
        for (double a = -58.9; a <= 60; a += 2.11) {
            double ar = a * RAD_PER_DEG, x[4];
            for (int m = 0; m < 4; m++) {
                double e = m == row ? 0.3e-3 : 0.0;
                x[m] = TWO_PI * atan(tan(ar) - e / H) / (th0 * RAD_PER_DEG);
            }
            double want = in_period_deg(phase_of_rows(x), th0, a);
            assert_near(output_deg(&s, a, 0, NULL), want, 1e-10);
        }
    }
}

/* Every geometric deviation at once: height, offset, tilt and per-row
 * etching, each row reading atan((Hr v - dd - (x_m + Hr u) tan dphi - e_m) / H)
 * against the rule etched for the nominal H. */
static void test_geometry_closed_form(void **state)
{
    sunmc_config c = given(0, 0);
    const double H = ess_cfg(&c)->design.H_mm, th0 = ess_cfg(&c)->design.theta0_deg;
    ess_deviations dev = {0};
    dev.dH_um = -1.7;
    dev.dd_um = 0.8;
    dev.dphi_deg = -0.02;
    const double etch_um[4] = {0.1, -0.15, 0.05, 0.2};
    for (int m = 0; m < 4; m++)
        dev.etch_um[m] = etch_um[m];
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    const double Hr = H - 1.7e-3, dd = 0.8e-3, tp = tan(-0.02 * RAD_PER_DEG);
    for (double b = -25; b <= 25; b += 25)
        for (double a = -60.2; a <= 60; a += 1.19) {
            double ar = a * RAD_PER_DEG, br = b * RAD_PER_DEG, x[4];
            double u = tan(br) / cos(ar), v = tan(ar);
            for (int m = 0; m < 4; m++) {
                double eta = Hr * v - dd - (ess_cfg(&c)->design.fine_rows_x_mm.v[m] + Hr * u) * tp -
                             etch_um[m] * 1e-3;
                x[m] = TWO_PI * atan(eta / H) / (th0 * RAD_PER_DEG);
            }
            assert_near(output_deg(&s, a, b, NULL), in_period_deg(phase_of_rows(x), th0, a), 1e-10);
        }
}

/* Row gains: equal gains change nothing; gain g on one row gives, e.g. for
 * row 0, atan2(2 sin x, DC (1 - g) + (1 + g) cos x). */
static void test_gain_closed_form(void **state)
{
    sunmc_config c = given(0, 0);
    const double th0 = ess_cfg(&c)->design.theta0_deg;
    fine_design f = design_of(&c);
    double ch[3], dc;
    ref_harmonics(&f, 0.0, ch, &dc); /* the DC is derived even when the harmonics are given */
    for (int row = 0; row < 4; row++) {
        ess_deviations dev = {0};
        dev.gain_pct[row] = -1.0;
        ess_sensor s;
        ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
        double g = 0.99;
        for (double a = -60; a <= 60; a += 0.77) {
            double x = TWO_PI * a / th0;
            double I[4];
            for (int m = 0; m < 4; m++)
                I[m] = (m == row ? g : 1.0) * (dc - cos(x - m * M_PI / 2));
            double ph = atan2(I[3] - I[1], I[2] - I[0]);
            double want = in_period_deg(ph < 0 ? ph + TWO_PI : ph, th0, a);
            assert_near(output_deg(&s, a, 0, NULL), want, 1e-10);
        }
    }
}

/* Slit tilt at the sensor's output: each row at its own x reads
 * atan(tan a - (x_m + H u) tan(dphi) / H), u = tan b / cos a. */
static void test_tilt_closed_form(void **state)
{
    sunmc_config c = given(0, 0);
    const double H = ess_cfg(&c)->design.H_mm, th0 = ess_cfg(&c)->design.theta0_deg, tp = tan(0.01 * RAD_PER_DEG);
    ess_deviations dev = {0};
    dev.dphi_deg = 0.01;
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    for (double b = -20; b <= 20; b += 20)
        for (double a = -60.3; a <= 60; a += 0.91) {
            double ar = a * RAD_PER_DEG, br = b * RAD_PER_DEG, x[4];
            double u = tan(br) / cos(ar);
            for (int m = 0; m < 4; m++) {
                double xm = ess_cfg(&c)->design.fine_rows_x_mm.v[m];
                x[m] = TWO_PI * atan(tan(ar) - (xm + H * u) * tp / H) / (th0 * RAD_PER_DEG);
            }
            assert_near(output_deg(&s, a, b, NULL), in_period_deg(phase_of_rows(x), th0, a), 1e-10);
        }
}

/* Row noise enters against illumination cos(incidence) = s_z (not cos alpha):
 * I_m = s_z (DC - cos(x - m pi/2)) + n_m. */
static void test_illumination_scaling(void **state)
{
    sunmc_config c = given(0, 0);
    const double th0 = ess_cfg(&c)->design.theta0_deg;
    ess_deviations dev = {0};
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    const double n[4] = {0.02, -0.01, 0.015, 0.03};
    for (double b = -30; b <= 30; b += 15)
        for (double a = -60; a <= 60; a += 4.9) {
            double sv[3];
            sun_vector(a, b, sv);
            double x = TWO_PI * a / th0, sz = sv[2];
            double ph = atan2(2 * sz * sin(x) + n[3] - n[1], 2 * sz * cos(x) + n[2] - n[0]);
            double want = in_period_deg(ph < 0 ? ph + TWO_PI : ph, th0, a);
            assert_near(output_deg(&s, a, b, n), want, 1e-10);
        }
}

/* Eq. 7 generalised: harmonics 3 (phase phi) and 5 give the fundamental's
 * bin Z = e^{ix} (1 + r3 e^{-i(4x + phi)} + r5 e^{i 4x}): the error is the
 * argument of the bracket.  Third alone with phi = 0 is eq. 7 with eq. 8's
 * minus sign; the fifth harmonic has the opposite sign. */
static double harmonic_error_deg(double r3, double r5, double phi, double x, double th0_deg)
{
    double re = 1 + r3 * cos(4 * x + phi) + r5 * cos(4 * x);
    double im = -r3 * sin(4 * x + phi) + r5 * sin(4 * x);
    return atan2(im, re) * th0_deg / TWO_PI;
}

static void test_harmonics_error_closed_form(void **state)
{
    const double cases[][3] = {{-0.12, 0, 0}, {-0.12, 0, 40}, {0.08, 0, -110},
                               {0, 0.06, 0},  {0, -0.09, 0},  {-0.1, 0.04, 75}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        sunmc_config c = given(cases[k][0], cases[k][1]);
        ess_deviations dev = {0};
        dev.harmonic_phase_deg = cases[k][2];
        ess_sensor s;
        ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
        const double th0 = ess_cfg(&c)->design.theta0_deg;
        for (double a = -61; a <= 61; a += 0.0917) {
            double x = TWO_PI * a / th0;
            double e = harmonic_error_deg(cases[k][0], cases[k][1], cases[k][2] * RAD_PER_DEG, x,
                                          th0);
            assert_near(output_deg(&s, a, 0, NULL) - a, e, 1e-10);
        }
    }
}

/* Derived harmonics at the output: c3, c5 at the incidence's own psi (the
 * slit's share changes with cos^2 psi), computed by quadrature. */
static void test_derived_harmonics_output(void **state)
{
    sunmc_config c = default_ess();
    ess_cfg(&c)->design.slit_width_um = 120;
    ess_cfg(&c)->design.dial_duty = 0.4;
    fine_design f = design_of(&c);
    ess_deviations dev = {0};
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    const double th0 = ess_cfg(&c)->design.theta0_deg;
    for (double a = -60.1; a <= 61; a += 1.03) {
        double ch[3], dc;
        ref_harmonics(&f, a * RAD_PER_DEG, ch, &dc);
        double x = TWO_PI * a / th0;
        double e = harmonic_error_deg(ch[1] / ch[0], ch[2] / ch[0], 0, x, th0);
        assert_near(output_deg(&s, a, 0, NULL) - a, e, 1e-9);
    }
}

/* ---- coarse code ---- */

static unsigned long gray(unsigned long k) { return k ^ (k >> 1); }

/* Gray rows: row j (0 = most significant) carries bit n-1-j of gray(cell).
 * Every cell's centre decodes to itself; at the edge between cells k and
 * k+1 only the one row whose bit differs decides, and its side gives k or
 * k+1 whatever the others read; beyond the ends the reading is clamped. */
static void test_coarse_cell_edges(void **state)
{
    sunmc_config c = given(0, 0);
    ess_deviations dev = {0};
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    const int n = s.n_coarse;
    const long ncell = 1L << n;
    const double res = ess_cfg(&c)->design.coarse_resolution_deg, origin = -(double)(ncell / 2) * res;
    double psi[ESS_MAX_COARSE_ROWS];
    for (long k = 0; k < ncell; k++) {
        for (int j = 0; j < n; j++)
            psi[j] = (origin + (k + 0.5) * res) * RAD_PER_DEG;
        assert_near(ess_coarse_read(&s, psi) * DEG_PER_RAD, origin + (k + 0.5) * res, 1e-9);
    }
    const double eps = 1e-7;
    for (long k = 0; k + 1 < ncell; k++) {
        double edge = origin + (k + 1) * res;
        unsigned long diff = gray((unsigned long)k) ^ gray((unsigned long)k + 1);
        int bit = 0;
        while (!(diff >> bit & 1))
            bit++;
        int decider = n - 1 - bit;
        for (int pattern = 0; pattern < 4; pattern++) {
            /* The decider on one side; every other row on the side the
             * pattern says (all below, all above, alternating). */
            int dec_above = pattern & 1;
            for (int j = 0; j < n; j++) {
                int above = j == decider ? dec_above : (pattern & 2 ? j % 2 : !dec_above);
                psi[j] = (edge + (above ? eps : -eps)) * RAD_PER_DEG;
            }
            double want = origin + (k + dec_above + 0.5) * res;
            assert_near(ess_coarse_read(&s, psi) * DEG_PER_RAD, want, 1e-9);
        }
    }
    /* just inside and just outside each end of the code, and far beyond */
    const double top = origin + ncell * res;
    const double ends[][2] = {{top - eps, ncell - 0.5}, {top + eps, ncell - 0.5},
                              {top + 0.5 * res, ncell - 0.5}, {80, ncell - 0.5},
                              {origin + eps, 0.5}, {origin - eps, 0.5},
                              {origin - 0.5 * res, 0.5}, {-80, 0.5}};
    for (size_t e = 0; e < sizeof ends / sizeof ends[0]; e++) {
        for (int j = 0; j < n; j++)
            psi[j] = ends[e][0] * RAD_PER_DEG;
        assert_near(ess_coarse_read(&s, psi) * DEG_PER_RAD, origin + ends[e][1] * res, 1e-9);
    }
}

/* The combination picks the fine period nearest the coarse estimate: a
 * coarse error just under half a period is harmless, just over it is a
 * whole period off (a gross error). */
static void test_combine_both_sides(void **state)
{
    const double th0 = 2 * RAD_PER_DEG, half = th0 / 2, eps = 1e-9;
    for (double a = -60; a <= 60; a += 0.731) {
        double ar = a * RAD_PER_DEG;
        double ph = fmod(ar / th0, 1.0) * TWO_PI;
        if (ph < 0)
            ph += TWO_PI;
        assert_near(ess_combine(ar + half - eps, ph, th0), ar, 1e-12);
        assert_near(ess_combine(ar - half + eps, ph, th0), ar, 1e-12);
        assert_near(ess_combine(ar + half + eps, ph, th0), ar + th0, 1e-12);
        assert_near(ess_combine(ar - half - eps, ph, th0), ar - th0, 1e-12);
    }
}

/* The whole sensor around a coarse edge with a tilted slit: the coarse rows
 * disagree there, yet the output stays the fine reading (no gross error). */
static void test_output_across_coarse_edges(void **state)
{
    sunmc_config c = given(0, 0);
    const double H = ess_cfg(&c)->design.H_mm, th0 = ess_cfg(&c)->design.theta0_deg;
    ess_deviations dev = {0};
    dev.dphi_deg = 0.05;
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    const double tp = tan(0.05 * RAD_PER_DEG);
    for (int edge = -60; edge <= 60; edge += 7)
        for (double d = -0.02; d <= 0.02; d += 0.004) {
            double a = edge + d, ar = a * RAD_PER_DEG, x[4];
            for (int m = 0; m < 4; m++)
                x[m] = TWO_PI * atan(tan(ar) - ess_cfg(&c)->design.fine_rows_x_mm.v[m] * tp / H) /
                       (th0 * RAD_PER_DEG);
            assert_near(output_deg(&s, a, 0, NULL), in_period_deg(phase_of_rows(x), th0, a),
                        1e-10);
        }
}

/* The sun is seen while cos(incidence) = s_z > 0.0175 (89 deg): just
 * inside, a reading; just outside, SUNMC_EDOM. */
static void test_grazing_limit(void **state)
{
    sunmc_config c = given(0, 0);
    ess_deviations dev = {0};
    ess_sensor s;
    ess_sensor_init(&s, &ess_cfg(&c)->design, &dev);
    const double lim = 0.0175;
    for (int side = 0; side < 2; side++) {
        double sz = side ? lim * (1 - 1e-9) : lim * (1 + 1e-9);
        double sy = sz * tan(30 * RAD_PER_DEG), sx = sqrt(1 - sz * sz - sy * sy);
        double sv[3] = {sx, sy, sz}, out;
        assert_int_equal(ess_sensor_output(&s, sv, NULL, &out), side ? SUNMC_EDOM : SUNMC_OK);
        if (!side)
            assert_near(out, atan2(sy, sz), 1e-9);
    }
}

/* ---- the compensation model (eq. 12-14) ---- */

/* Passive rotations of rotation.h, written out. */
static void rx(double a, const double v[3], double o[3])
{
    double t[3] = {v[0], cos(a) * v[1] + sin(a) * v[2], -sin(a) * v[1] + cos(a) * v[2]};
    memcpy(o, t, sizeof t);
}
static void ry(double a, const double v[3], double o[3])
{
    double t[3] = {cos(a) * v[0] + sin(a) * v[2], v[1], -sin(a) * v[0] + cos(a) * v[2]};
    memcpy(o, t, sizeof t);
}
static void rz(double a, const double v[3], double o[3])
{
    double t[3] = {cos(a) * v[0] + sin(a) * v[1], -sin(a) * v[0] + cos(a) * v[1], v[2]};
    memcpy(o, t, sizeof t);
}

typedef struct {
    double a, b, c, ks, kc, iy, iz, sy, roll, sx, omega;
} ref_model;

/* raw = alpha_d - ks sin(w alpha_d) - kc cos(w alpha_d), alpha_d from eq. 12 */
static double ref_structural(const ref_model *r, double T)
{
    double ad = atan2(r->a * T + r->b, r->c * T + 1.0);
    return ad - r->ks * sin(r->omega * ad) - r->kc * cos(r->omega * ad);
}

/* s = rot_x(roll) rot_y(-iy) rot_z(iz) rot_x(alpha) rot_y(-beta) rot_y(-sx) rot_x(sy) e_z
 * (rotation.h's passive rot_y; these angles turn the sensor, the active way) */
static double ref_predict(const ref_model *r, double alpha, double beta)
{
    double v[3] = {0, 0, 1};
    rx(r->sy, v, v);
    ry(r->sx, v, v);
    ry(beta, v, v);
    rx(alpha, v, v);
    rz(r->iz, v, v);
    ry(r->iy, v, v);
    rx(r->roll, v, v);
    return ref_structural(r, v[1] / v[2]);
}

static void to_model(const ref_model *r, ess_model *m)
{
    ess_model_init(m, 2 * RAD_PER_DEG, r->roll);
    m->p[ESS_P_A] = r->a;
    m->p[ESS_P_B] = r->b;
    m->p[ESS_P_C] = r->c;
    m->p[ESS_P_KS] = r->ks;
    m->p[ESS_P_KC] = r->kc;
    m->p[ESS_P_INST_Y] = r->iy;
    m->p[ESS_P_INST_Z] = r->iz;
    m->p[ESS_P_SUN_Y] = r->sy;
    m->sun_x_rad = r->sx;
    ess_model_prepare(m);
}

static const ref_model models[] = {
    {1.0004, -2.4e-4, 3e-5, 1.1e-4, -0.6e-4, 2e-3, -4e-4, 3e-4, 2e-4, 0, 0},
    {0.9991, 3.1e-4, -7e-5, -2e-4, 1.3e-4, -1.5e-3, 5e-4, -2e-4, -3e-4, 0, 0},
    {1.02, 0.01, 0.004, 0.0, 0.0, 0.03, 0.02, 0.01, 0.015, 0, 0},
};

/* The model's prediction against the chain written out here (installation
 * order, sun direction, eq. 12 with d = 1, the fine-code term of period
 * theta0/4). */
static void test_model_prediction(void **state)
{
    for (size_t k = 0; k < sizeof models / sizeof models[0]; k++) {
        ref_model r = models[k];
        r.omega = TWO_PI / (2 * RAD_PER_DEG / 4);
        ess_model m;
        to_model(&r, &m);
        assert_near(m.omega, r.omega, 1e-9);
        for (double a = -60; a <= 60; a += 3.3)
            for (double b = -25; b <= 25; b += 12.5) {
                double ar = a * RAD_PER_DEG, br = b * RAD_PER_DEG;
                assert_near(ess_model_predict(&m, ar, br, NULL), ref_predict(&r, ar, br), 1e-13);
            }
        /* the same with sun_x (fixed, not fitted) */
        r.sx = 4e-4;
        to_model(&r, &m);
        assert_near(ess_model_predict(&m, 0.3, 0.2, NULL), ref_predict(&r, 0.3, 0.2), 1e-13);
    }
}

/* Compensation inverts the model exactly: raw from the forward chain
 * written here, back to tan(alpha) = T; k and t as the paper writes them. */
static void test_compensation_exact(void **state)
{
    for (size_t k = 0; k < sizeof models / sizeof models[0]; k++) {
        ref_model r = models[k];
        r.omega = TWO_PI / (2 * RAD_PER_DEG / 4);
        ess_model m;
        to_model(&r, &m);
        for (double a = -62; a <= 62; a += 0.173) {
            double ar = a * RAD_PER_DEG, got;
            double raw = ref_structural(&r, tan(ar));
            assert_near(ess_model_structural(&m, tan(ar)), raw, 1e-14);
            assert_int_equal(ess_model_compensate(&m, raw, &got), SUNMC_OK);
            assert_near(got, ar, 1e-12);
        }
        double kk, t;
        ess_model_kt(&m, &kk, &t);
        assert_near(kk, hypot(r.ks, r.kc), 1e-18);
        assert_near(t, atan2(r.kc, r.ks), 1e-12);
    }
}

/* The fine-code term can be inverted while omega k < 1: just below the limit
 * it still is, just past it compensation refuses. */
static void test_compensation_limit(void **state)
{
    ess_model m;
    ess_model_init(&m, 2 * RAD_PER_DEG, 0);
    double k = 1.0 / m.omega, got;
    m.p[ESS_P_KS] = k * (1 - 1e-3) * 0.6;
    m.p[ESS_P_KC] = k * (1 - 1e-3) * 0.8;
    ess_model_prepare(&m);
    assert_int_equal(ess_model_compensate(&m, 0.3, &got), SUNMC_OK);
    double ad = got; /* a = 1, b = c = 0: alpha_d = alpha */
    assert_near(ad - m.p[ESS_P_KS] * sin(m.omega * ad) - m.p[ESS_P_KC] * cos(m.omega * ad), 0.3,
                1e-12);
    m.p[ESS_P_KS] = k * 0.6;
    m.p[ESS_P_KC] = k * 0.8 * (1 + 1e-12);
    ess_model_prepare(&m);
    assert_int_equal(ess_model_compensate(&m, 0.3, &got), SUNMC_EDOM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_harmonic_transfer),
        cmocka_unit_test(test_row_currents),
        cmocka_unit_test(test_demodulation),
        cmocka_unit_test(test_etch_offsets),
        cmocka_unit_test(test_geometry_closed_form),
        cmocka_unit_test(test_gain_closed_form),
        cmocka_unit_test(test_tilt_closed_form),
        cmocka_unit_test(test_illumination_scaling),
        cmocka_unit_test(test_harmonics_error_closed_form),
        cmocka_unit_test(test_derived_harmonics_output),
        cmocka_unit_test(test_coarse_cell_edges),
        cmocka_unit_test(test_combine_both_sides),
        cmocka_unit_test(test_output_across_coarse_edges),
        cmocka_unit_test(test_grazing_limit),
        cmocka_unit_test(test_model_prediction),
        cmocka_unit_test(test_compensation_exact),
        cmocka_unit_test(test_compensation_limit),
    };
    return cmocka_run_group_tests_name("ess_closed_forms", tests, NULL, NULL);
}
