/* test_dss_independent.c - `sunmc calibrate --sensor dss` and `compensate`
 * on campaigns from an independent DSS model, against an independent
 * least-squares fit of the same data.
 *
 * The independent model shares no code with sunmc: a pinhole at (px, py, H)
 * mm over the detector, a flat glass plate of thickness t and index n lying
 * on it, traced with its own Snell's law; the unit mounted on the table top
 * with a rotation Q given as a rotation vector (Rodrigues; sunmc uses zxy
 * angles); the sun simulator's direction in the table's base frame given
 * as a unit vector through its x and y components (sunmc uses two table
 * angles); the table's passive Ry(b2) Rx(b1) written out.  Sun in the
 * sensor frame: Q R(b) v_sun (as mounted) or Q R(b) Q^T e_z (the lab
 * aligns the sun to the detector normal at table zero, DSS paper eq. 6).
 * Truth, as the README documents it: as mounted, the angles
 * (atan(w_x/w_z), atan(w_y/w_z)) of the sun w = R(b) v_sun in the table-top
 * frame; aligned, eq. 3-4 of the table angles.
 *
 * The independent fit: GSL's nonlinear least squares (finite-difference
 * Jacobian, not sunmc's fit engine or its analytic Jacobian) of the
 * independent model's own parameters to the same campaign, then its own
 * inverse (2-D Newton on the spot) for the validation spots.  sunmc must come
 * within 1.25x of its after-calibration RMS; noise-free both reach zero. */
#include "test_util.h"

#include "csv.h"
#include "status.h"
#include "units.h"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>

#define NP 10 /* px, py, H, t, n, rv[3], sun x, sun y */

typedef struct {
    double p[NP];
    double pixel_mm;
    int aligned;
} indep_dss;

enum { PX = 0, PY, PH, PT, PN, RV0, RV1, RV2, SX, SY };

static void rodrigues(const double rv[3], double Q[3][3])
{
    double th = sqrt(rv[0] * rv[0] + rv[1] * rv[1] + rv[2] * rv[2]);
    if (th == 0) {
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                Q[i][j] = i == j;
        return;
    }
    double k[3] = {rv[0] / th, rv[1] / th, rv[2] / th}, c = cos(th), s = sin(th);
    double K[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double kk = 0;
            for (int l = 0; l < 3; l++)
                kk += K[i][l] * K[l][j];
            Q[i][j] = (i == j) + s * K[i][j] + (1 - c) * kk;
        }
}

/* The sun simulator in the table's base frame. */
static void sun_vector(const indep_dss *m, double v[3])
{
    double Q[3][3];
    rodrigues(&m->p[RV0], Q);
    if (m->aligned) {
        for (int i = 0; i < 3; i++)
            v[i] = Q[2][i]; /* Q^T e_z */
        return;
    }
    v[0] = m->p[SX];
    v[1] = m->p[SY];
    v[2] = sqrt(1 - v[0] * v[0] - v[1] * v[1]);
}

/* Passive Rx(b1) then Ry(b2): the table top's view of a base-frame vector. */
static void table(double b1, double b2, const double v[3], double u[3])
{
    double y1 = cos(b1) * v[1] + sin(b1) * v[2], z1 = -sin(b1) * v[1] + cos(b1) * v[2];
    u[0] = cos(b2) * v[0] - sin(b2) * z1;
    u[1] = y1;
    u[2] = sin(b2) * v[0] + cos(b2) * z1;
}

/* Spot (px) of a sun w in the sensor frame. */
static void spot_of(const indep_dss *m, const double w[3], double *x_px, double *y_px)
{
    const double *p = m->p;
    double d[3] = {-w[0], -w[1], -w[2]};
    double air = (p[PH] - p[PT]) / w[2];
    double A[2] = {p[PX] + d[0] * air, p[PY] + d[1] * air};
    double eta = 1 / p[PN], ci = w[2], ct = sqrt(1 - eta * eta * (1 - ci * ci));
    double tr[3] = {eta * d[0], eta * d[1], eta * d[2] + (eta * ci - ct)};
    double g = p[PT] / -tr[2];
    *x_px = (A[0] + tr[0] * g) / m->pixel_mm;
    *y_px = (A[1] + tr[1] * g) / m->pixel_mm;
}

/* Sun in the sensor frame for a sun w_top in the table-top frame. */
static void to_sensor(const indep_dss *m, const double w_top[3], double w[3])
{
    double Q[3][3];
    rodrigues(&m->p[RV0], Q);
    for (int i = 0; i < 3; i++)
        w[i] = Q[i][0] * w_top[0] + Q[i][1] * w_top[1] + Q[i][2] * w_top[2];
}

static void indep_spot(const indep_dss *m, double b1, double b2, double *x_px, double *y_px)
{
    double v[3], top[3], w[3];
    sun_vector(m, v);
    table(b1, b2, v, top);
    to_sensor(m, top, w);
    spot_of(m, w, x_px, y_px);
}

/* The truth of the table at (b1, b2) (see the top of the file). */
static void indep_truth(const indep_dss *m, double b1, double b2, double *a, double *b)
{
    if (m->aligned) {
        *a = -b2;
        *b = atan(tan(b1) / cos(b2));
        return;
    }
    double v[3], top[3];
    sun_vector(m, v);
    table(b1, b2, v, top);
    *a = atan(top[0] / top[2]);
    *b = atan(top[1] / top[2]);
}

/* Angles in the truth's frame (as mounted: the table top's sun; aligned:
 * the table angles) -> spot.  Aligned: the table angles (b1, b2) that give
 * truth (a, b) are b2 = -a, b1 = atan(tan b cos b2). */
static void spot_at_truth(const indep_dss *m, double a, double b, double *x, double *y)
{
    if (m->aligned) {
        double b2 = -a, b1 = atan(tan(b) * cos(b2));
        indep_spot(m, b1, b2, x, y);
        return;
    }
    double n = sqrt(1 + tan(a) * tan(a) + tan(b) * tan(b));
    double top[3] = {tan(a) / n, tan(b) / n, 1 / n}, w[3];
    to_sensor(m, top, w);
    spot_of(m, w, x, y);
}

/* The independent inverse: 2-D Newton on spot_at_truth, finite-difference
 * derivatives, from the pinhole formula's angles. */
static int indep_compensate(const indep_dss *m, double x, double y, double *a, double *b)
{
    double ga = atan(-x * m->pixel_mm / m->p[PH]), gb = atan(-y * m->pixel_mm / m->p[PH]);
    const double h = 1e-7;
    for (int it = 0; it < 50; it++) {
        double fx, fy, xa, ya, xb, yb;
        spot_at_truth(m, ga, gb, &fx, &fy);
        spot_at_truth(m, ga + h, gb, &xa, &ya);
        spot_at_truth(m, ga, gb + h, &xb, &yb);
        double J[2][2] = {{(xa - fx) / h, (xb - fx) / h}, {(ya - fy) / h, (yb - fy) / h}};
        double det = J[0][0] * J[1][1] - J[0][1] * J[1][0], rx = x - fx, ry = y - fy;
        double da = (J[1][1] * rx - J[0][1] * ry) / det, db = (-J[1][0] * rx + J[0][0] * ry) / det;
        ga += da;
        gb += db;
        if (fabs(da) + fabs(db) < 1e-14)
            break;
    }
    *a = ga;
    *b = gb;
    return 0;
}

/* ---- a campaign ---- */

#define NB 25 /* -60 .. 60 deg step 5, both axes */
#define NV 24 /* validation: -55.3 + 4.7 k */

typedef struct {
    int n;
    double b1[NB * NB], b2[NB * NB], x[NB * NB], y[NB * NB];
} campaign;

static double normal(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    double u1 = ((*s >> 11) + 0.5) / 9007199254740992.0;
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    double u2 = ((*s >> 11) + 0.5) / 9007199254740992.0;
    return sqrt(-2 * log(u1)) * cos(2 * M_PI * u2);
}

/* The campaign on the table grid with centroid noise sigma_px; spots off a
 * 2048 px detector of 5.5 um pixels (with the spot's 60 um disc) are not
 * seen, as sunmc documents. */
static void make_campaign(const indep_dss *m, double sigma_px, uint64_t seed, campaign *c)
{
    const double lim = 1024 - 0.5 * 60 / 5.5;
    c->n = 0;
    for (int i = 0; i < NB; i++)
        for (int j = 0; j < NB; j++) {
            double b1 = (-60 + 5.0 * i) * RAD_PER_DEG, b2 = (-60 + 5.0 * j) * RAD_PER_DEG, x, y;
            indep_spot(m, b1, b2, &x, &y);
            double nx = sigma_px * normal(&seed), ny = sigma_px * normal(&seed);
            if (fabs(x) > lim || fabs(y) > lim)
                continue;
            c->b1[c->n] = b1;
            c->b2[c->n] = b2;
            c->x[c->n] = x + nx;
            c->y[c->n] = y + ny;
            c->n++;
        }
}

/* ---- the independent least-squares fit ---- */

typedef struct {
    const campaign *c;
    indep_dss base;
    int np; /* 8 when aligned (no sun parameters) */
} fit_ctx;

static int resid(const gsl_vector *x, void *params, gsl_vector *f)
{
    fit_ctx *fc = params;
    indep_dss m = fc->base;
    for (int k = 0; k < fc->np; k++)
        m.p[k] = gsl_vector_get(x, (size_t)k);
    for (int i = 0; i < fc->c->n; i++) {
        double sx, sy;
        indep_spot(&m, fc->c->b1[i], fc->c->b2[i], &sx, &sy);
        gsl_vector_set(f, 2 * (size_t)i, sx - fc->c->x[i]);
        gsl_vector_set(f, 2 * (size_t)i + 1, sy - fc->c->y[i]);
    }
    return GSL_SUCCESS;
}

/* Fit the parameters of start (its design values) to c. */
static indep_dss independent_fit(const indep_dss *start, const campaign *c)
{
    fit_ctx fc = {.c = c, .base = *start, .np = start->aligned ? 8 : NP};
    gsl_multifit_nlinear_fdf fdf = {.f = resid, .df = NULL, .fvv = NULL,
                                    .n = 2 * (size_t)c->n, .p = (size_t)fc.np, .params = &fc};
    gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
    par.scale = gsl_multifit_nlinear_scale_more;
    gsl_multifit_nlinear_workspace *w =
        gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, fdf.n, fdf.p);
    gsl_vector *x0 = gsl_vector_alloc(fdf.p);
    for (int k = 0; k < fc.np; k++)
        gsl_vector_set(x0, (size_t)k, start->p[k]);
    int info;
    gsl_multifit_nlinear_init(x0, &fdf, w);
    int st = gsl_multifit_nlinear_driver(200, 1e-14, 1e-14, 1e-14, NULL, NULL, &info, w);
    assert_int_equal(st, GSL_SUCCESS);
    indep_dss out = *start;
    for (int k = 0; k < fc.np; k++)
        out.p[k] = gsl_vector_get(w->x, (size_t)k);
    gsl_vector_free(x0);
    gsl_multifit_nlinear_free(w);
    return out;
}

/* ---- sunmc on the same data ---- */

/* Write the campaign and the noise-free validation spots of the true unit
 * m, calibrate and compensate with the CLI (extra: --set options), and
 * return the RMS (rad, alpha and beta) of sunmc's compensated angles and
 * of the independent fit's against the truth. */
static void compare(const indep_dss *m, const indep_dss *design, double sigma_px,
                    const char *extra, const char *tag, double *rms_sunmc, double *rms_indep)
{
    static char text[1 << 17];
    static campaign c;
    char path[600], vpath[600], cmd[4096], out[1 << 15], err[SUNMC_ERRLEN];
    make_campaign(m, sigma_px, 12345, &c);
    size_t len = (size_t)snprintf(text, sizeof text, "# independent model\nb1_deg,b2_deg,x_px,y_px\n");
    for (int i = 0; i < c.n; i++)
        len += (size_t)snprintf(text + len, sizeof text - len, "%.17g,%.17g,%.17g,%.17g\n",
                                c.b1[i] * DEG_PER_RAD, c.b2[i] * DEG_PER_RAD, c.x[i], c.y[i]);
    snprintf(path, sizeof path, "%s.csv", test_tmp(tag));
    assert_int_equal(test_write_file(path, text), 0);

    indep_dss fit = independent_fit(design, &c);
    len = (size_t)snprintf(text, sizeof text, "x_px,y_px,truth_alpha_deg,truth_beta_deg\n");
    double sum_i = 0;
    int nv = 0;
    for (int i = 0; i < NV; i++)
        for (int j = 0; j < NV; j++) {
            double b1 = (-55.3 + 4.7 * i) * RAD_PER_DEG, b2 = (-55.3 + 4.7 * j) * RAD_PER_DEG;
            double x, y, a0, be0, a, b;
            indep_spot(m, b1, b2, &x, &y);
            if (fabs(x) > 1018 || fabs(y) > 1018)
                continue;
            indep_truth(m, b1, b2, &a0, &be0);
            indep_compensate(&fit, x, y, &a, &b);
            sum_i += (a - a0) * (a - a0) + (b - be0) * (b - be0);
            nv++;
            len += (size_t)snprintf(text + len, sizeof text - len, "%.17g,%.17g,%.17g,%.17g\n", x,
                                    y, a0 * DEG_PER_RAD, be0 * DEG_PER_RAD);
        }
    *rms_indep = sqrt(sum_i / (2.0 * nv));
    snprintf(vpath, sizeof vpath, "%s_val.csv", test_tmp(tag));
    assert_int_equal(test_write_file(vpath, text), 0);

    /* The unit is outside configs/dss.ini's tolerances (dh 2.2 px against
     * 0.2, tilts of 60-90" against 10"): the lab check would refuse its data
     * as another sensor's.  Tolerances that hold it (priors off, they change
     * nothing else). */
    snprintf(cmd, sizeof cmd, "%s calibrate --sensor dss --config configs/dss.ini --set calibration.priors=off "
             "--set tolerance.dh_px=2.5 --set tolerance.dx_px=1 --set tolerance.dy_px=1.2 "
             "--set tolerance.c1_arcsec=100 --set tolerance.c2_arcsec=100 "
             "--set tolerance.c3_arcsec=100 --set tolerance.sun_b1_arcsec=50 "
             "--set tolerance.sun_b2_arcsec=50 --set design.sun_disc_deg=0 %s %s --out %s_cal",
             test_sunmc(), extra, path, test_tmp(tag));
    if (test_run(cmd, out, sizeof out) != 0)
        fail_msg("%s: %s", cmd, out);
    snprintf(cmd, sizeof cmd, "{ %s compensate %s_cal/params.ini %s > %s_comp.csv; }", test_sunmc(),
             test_tmp(tag), vpath, test_tmp(tag));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(path, sizeof path, "%s_comp.csv", test_tmp(tag));
    csv_table *t;
    assert_int_equal(csv_read(path, &t, err, sizeof err), SUNMC_OK);
    const char *names[4] = {"truth_alpha_deg", "truth_beta_deg", "compensated_alpha_deg",
                            "compensated_beta_deg"};
    double *col[4];
    for (int k = 0; k < 4; k++) {
        int ci;
        col[k] = malloc(t->n_rows * sizeof(double));
        assert_int_equal(csv_column(t, names[k], 1, &ci, err, sizeof err), SUNMC_OK);
        assert_int_equal(csv_doubles(t, ci, col[k], err, sizeof err), SUNMC_OK);
    }
    assert_int_equal((int)t->n_rows, nv);
    double sum = 0;
    for (size_t i = 0; i < t->n_rows; i++)
        for (int a = 0; a < 2; a++) {
            double e = (col[2 + a][i] - col[a][i]) * RAD_PER_DEG;
            sum += e * e;
        }
    *rms_sunmc = sqrt(sum / (2.0 * (double)t->n_rows));
    for (int k = 0; k < 4; k++)
        free(col[k]);
    csv_free(t);
}

/* configs/dss.ini's design, as the independent model's start. */
static indep_dss design_of(int aligned)
{
    indep_dss d = {.p = {0, 0, 3.0, 0.4, 1.52, 0, 0, 0, 0, 0}, .pixel_mm = 5.5e-3,
                   .aligned = aligned};
    return d;
}

/* A unit with a tilted mount (about 1.5' about each axis) and, as mounted,
 * a sun simulator 40" and 25" off the table's zero axis. */
static indep_dss unit_of(int aligned)
{
    indep_dss m = design_of(aligned);
    const double p[NP] = {0.004, -0.006, 3.0 + 0.012, 0.4 - 0.01, 1.52 + 0.004,
                          90 * RAD_PER_ARCSEC, -75 * RAD_PER_ARCSEC, 60 * RAD_PER_ARCSEC,
                          40 * RAD_PER_ARCSEC, -25 * RAD_PER_ARCSEC};
    memcpy(m.p, p, sizeof p);
    return m;
}

static void as_mounted_noise_free(void **state)
{
    indep_dss m = unit_of(0), d = design_of(0);
    double rs, ri;
    compare(&m, &d, 0.0, "", "clean", &rs, &ri);
    assert_true(ri < 0.01 * RAD_PER_ARCSEC); /* the independent fit is exact */
    assert_true(rs < 0.01 * RAD_PER_ARCSEC);
}

/* With 0.02 px of centroid noise sunmc's after-RMS is within 1.25x of the
 * independent fit's, and the noise did reach the fit. */
static void expect_as_good(int aligned, const char *extra, const char *tag)
{
    indep_dss m = unit_of(aligned), d = design_of(aligned);
    double rs, ri;
    compare(&m, &d, 0.02, extra, tag, &rs, &ri);
    assert_true(ri > 0.01 * RAD_PER_ARCSEC);
    if (!(rs < 1.25 * ri))
        fail_msg("sunmc %.3f\" against the independent fit's %.3f\"", rs * ARCSEC_PER_RAD,
                 ri * ARCSEC_PER_RAD);
}

/* The finding: as mounted (it was 5-7x when sunmc could only model
 * the aligned lab). */
static void as_mounted_noisy(void **state) { expect_as_good(0, "", "noisy"); }

/* The aligned lab (the DSS paper's eq. 6) with campaign.mount = aligned. */
static void aligned_noisy(void **state)
{
    expect_as_good(1, "--set campaign.mount=aligned", "aligned");
}

/* An as-mounted campaign calibrated with the aligned model is worse by a
 * wide margin: the mount option matters. */
static void wrong_mount_is_worse(void **state)
{
    indep_dss m = unit_of(0), d = design_of(0);
    double rs, ri;
    /* the wrong model leaves a residual far above the noise, which
     * calibrate refuses by default: allowed here to measure how much worse */
    compare(&m, &d, 0.02,
            "--set campaign.mount=aligned --set calibration.max_residual_ratio=1000000", "wrong",
            &rs, &ri);
    assert_true(rs > 3 * ri);
}

int main(void)
{
    gsl_set_error_handler_off();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(as_mounted_noise_free),
        cmocka_unit_test(as_mounted_noisy),
        cmocka_unit_test(aligned_noisy),
        cmocka_unit_test(wrong_mount_is_worse),
    };
    return cmocka_run_group_tests_name("dss_independent", tests, NULL, NULL);
}
