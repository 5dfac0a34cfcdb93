/* test_calibrate_files.c - what `sunmc calibrate --out` writes, every column
 * recomputed here from other files: a unit's campaign from `simulate`
 * (campaign.csv), the compensated angles from `sunmc compensate`, the
 * fitted model from params.ini, and the printed report.
 *   residuals.tsv: line numbers and inputs as in the CSV; the ESS residual
 *   (model - output) from params.ini's model, the angle error from
 *   compensate's output against the model's incidence; the DSS compensated
 *   angles from compensate and their errors against the sun in the mount's
 *   frame worked out here (R(b) R(s) e_z, the simulator s as fitted);
 *   bands.tsv: points and residual RMS per band from residuals.tsv (ESS:
 *   bands of |compensated alpha|; DSS: of the field angle of the truth;
 *   lower band edge exclusive except at 0), the ESS calibration sigma's RMS
 *   and max over field.tsv's grid in the band, the predicted RMS from the
 *   residual scaled by sqrt(used / dof) and the calibration sigma;
 *   crossval.tsv: one fold per beta line (ESS) or grid quadrant (DSS) with
 *   its held-out count;
 *   the printed residual standard deviation from the residuals and the
 *   degrees of freedom;
 *   and simulate's truth.csv: the unit's deviations as units.tsv of `run`
 *   has them, the recorded angles and outputs as campaign.csv has them, the
 *   true table angles off the recorded ones by the encoder noise (mean 0,
 *   sigma noise.encoder_arcsec, alpha and beta independent), the DSS truth
 *   by eq. 2-4 of the true table angles, the ESS incidence near alpha;
 *   units.tsv's systematic part (rms_after_sys) from `curve`'s noiseless
 *   errors after calibration of the same unit. */
#include "test_tsv.h"

#include "ess_labfit.h"
#include "rotation.h"
#include "params_io.h"
#include "units.h"

/* ---- a CSV file (comma-separated, '#' comments) with its line numbers ---- */

#define CSV_MAX_ROWS 4096
#define CSV_MAX_COLS 8

typedef struct {
    int nc, nr;
    char names[CSV_MAX_COLS][32];
    double v[CSV_MAX_ROWS][CSV_MAX_COLS];
    int line[CSV_MAX_ROWS];
} csvt;

static csvt *csv_load(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        fail_msg("%s: cannot read", path);
    csvt *t = calloc(1, sizeof *t);
    char buf[4096];
    int ln = 0, header = 1;
    while (fgets(buf, sizeof buf, f)) {
        ln++;
        buf[strcspn(buf, "\r\n")] = '\0';
        if (buf[0] == '#' || buf[0] == '\0')
            continue;
        int n = 0;
        char *save = NULL, raw[4096];
        snprintf(raw, sizeof raw, "%s", buf);
        for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
            assert_true(n < CSV_MAX_COLS);
            if (header)
                snprintf(t->names[n], sizeof t->names[n], "%s", tok);
            else
                t->v[t->nr][n] = strcmp(tok, "-") == 0 ? NAN : strtod(tok, NULL);
            n++;
        }
        if (header) {
            t->nc = n;
            header = 0;
        } else {
            if (n != t->nc)
                fail_msg("%s:%d: %d fields, header %d: %s", path, ln, n, t->nc, raw);
            t->line[t->nr++] = ln;
            assert_true(t->nr < CSV_MAX_ROWS);
        }
    }
    fclose(f);
    return t;
}

static int csv_col(const csvt *t, const char *name)
{
    for (int i = 0; i < t->nc; i++)
        if (strcmp(t->names[i], name) == 0)
            return i;
    fail_msg("no CSV column '%s'", name);
    return -1;
}

/* ---- helpers ---- */

static void run_ok(const char *cmd, char *out, size_t len)
{
    int st = test_run(cmd, out, len);
    if (st != 0)
        fail_msg("%s: exit %d\n%s", cmd, st, out);
}

/* "data: N rows, U used, D degrees of freedom" and the residual standard
 * deviation from calibrate's report. */
static void report_numbers(const char *out, long *used, long *dof, double *sigma_arcsec)
{
    long rows;
    const char *d = strstr(out, "data: ");
    assert_non_null(d);
    assert_int_equal(sscanf(d, "data: %ld rows, %ld used, %ld degrees", &rows, used, dof), 3);
    const char *s = strstr(out, "residual standard deviation: ");
    assert_non_null(s);
    assert_int_equal(sscanf(s, "residual standard deviation: %lf", sigma_arcsec), 1);
}

/* The family's band rule: (lo, hi], or [0, hi] for a band from 0. */
static int in_band(double x, double lo, double hi)
{
    const double eps = 1e-9;
    return (lo == 0 ? x >= 0 : x > lo + eps) && x <= hi + eps;
}

/* Equal to a value written with %.10g / %.12g. */
static void expect_close(double got, double want, double rel, const char *what, int row)
{
    if (!(fabs(got - want) <= rel * fabs(want) + 1e-12))
        fail_msg("%s, row %d: %.12g, expected %.12g", what, row, got, want);
}

/* Fold k's line of the printed cross-validation ("held out LABEL  N
 * points: in-sample X  held-out Y", two decimals) against crossval.tsv. */
static void expect_fold_printed(const char *out, int k, long n, double in, double held)
{
    const char *p = strstr(out, "cross-validation");
    assert_non_null(p);
    for (int i = 0; i <= k; i++) {
        p = strstr(p + 1, "held out ");
        assert_non_null(p);
    }
    const char *q = strstr(p, " points: in-sample ");
    assert_non_null(q);
    long pn;
    double pi, po;
    const char *num = q;
    while (num > p && num[-1] != ' ')
        num--;
    assert_int_equal(sscanf(num, "%ld points: in-sample %lf held-out %lf", &pn, &pi, &po), 3);
    assert_int_equal(pn, n);
    assert_near(pi, in, 0.005 + 1e-5 * in);
    assert_near(po, held, 0.005 + 1e-5 * held);
}

/* A unit simulated, calibrated and compensated: `simulate` unit U of cfg,
 * `calibrate` its campaign (both with the --set options) and `compensate` it; the
 * files read back and the report's numbers (its text in out). */
typedef struct {
    char sim[512], cal[512];
    csvt *camp, *comp;     /* campaign.csv, compensate's output */
    tsv *res, *bands, *cv; /* residuals.tsv, bands.tsv, crossval.tsv */
    long used, dof;
    double sigma;
} calrun;

static tsv *tsv_in(const char *dir, const char *name)
{
    char path[600];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return tsv_load(path);
}

static void calrun_load(calrun *r, const char *cfg, int unit, const char *cal_sets,
                        const char *tag, char *out, size_t len)
{
    char cmd[4096], name[64], comp[512], cout[4096];
    snprintf(name, sizeof name, "%s_sim", tag);
    snprintf(r->sim, sizeof r->sim, "%s", test_tmp(name));
    snprintf(name, sizeof name, "%s_cal", tag);
    snprintf(r->cal, sizeof r->cal, "%s", test_tmp(name));
    snprintf(name, sizeof name, "%s_comp.csv", tag);
    snprintf(comp, sizeof comp, "%s", test_tmp(name));
    snprintf(cmd, sizeof cmd, "%s simulate %s --unit %d %s --out %s", test_sunmc(), cfg, unit,
             cal_sets, r->sim);
    run_ok(cmd, out, len);
    snprintf(cmd, sizeof cmd, "%s calibrate --config %s --set calibration.priors=off %s %s/campaign.csv "
             "--out %s", test_sunmc(), cfg, cal_sets, r->sim, r->cal);
    run_ok(cmd, out, len);
    report_numbers(out, &r->used, &r->dof, &r->sigma);
    /* stderr apart: it counts the rows not compensated (a DSS campaign's
     * no-spot rows) */
    snprintf(cmd, sizeof cmd, "(%s compensate %s/params.ini %s/campaign.csv 2> %s.err > %s)",
             test_sunmc(), r->cal, r->sim, comp, comp);
    run_ok(cmd, cout, sizeof cout);
    snprintf(cmd, sizeof cmd, "%s/campaign.csv", r->sim);
    r->camp = csv_load(cmd);
    r->comp = csv_load(comp);
    r->res = tsv_in(r->cal, "residuals.tsv");
    r->bands = tsv_in(r->cal, "bands.tsv");
    r->cv = tsv_in(r->cal, "crossval.tsv");
}

static void calrun_free(calrun *r)
{
    free(r->camp);
    free(r->comp);
    tsv_free(r->res);
    tsv_free(r->bands);
    tsv_free(r->cv);
}

/* ---- ESS ---- */

static void ess_files(void **state)
{
    (void)state;
    char out[1 << 16];
    calrun run;
    calrun_load(&run, "configs/ess_type_a.ini", 3, "--set calibration.roll_measured_arcsec=-7",
                "ess", out, sizeof out);
    csvt *camp = run.camp, *comp = run.comp;
    tsv *res = run.res, *bands = run.bands, *cv = run.cv;
    long used = run.used, dof = run.dof;
    double sigma = run.sigma;
    char path[600], err[SUNMC_ERRLEN];
    snprintf(path, sizeof path, "%s/field.tsv", run.cal);
    tsv *field = tsv_load(path);
    params_file pf;
    snprintf(path, sizeof path, "%s/params.ini", run.cal);
    assert_int_equal(params_read(path, &pf, err, sizeof err), SUNMC_OK);
    ess_model m;
    assert_int_equal(ess_params_load(&pf, &m, err, sizeof err), SUNMC_OK);
    assert_near(m.roll_rad * ARCSEC_PER_RAD, -7.0, 1e-9);

    /* residuals.tsv row by row */
    assert_int_equal(res->nr, camp->nr);
    assert_int_equal(comp->nr, camp->nr);
    int ca = csv_col(camp, "alpha_deg"), cb = csv_col(camp, "beta_deg");
    int co = csv_col(camp, "output_deg"), cw = csv_col(camp, "weight");
    int cc = csv_col(comp, "compensated_deg");
    double chi2 = 0;
    long n_used = 0;
    double *err_as = calloc((size_t)res->nr, sizeof *err_as);
    for (int i = 0; i < res->nr; i++) {
        double a = camp->v[i][ca], b = camp->v[i][cb], o = camp->v[i][co], w = camp->v[i][cw];
        assert_int_equal(atoi(tsv_str(res, i, "line")), camp->line[i]);
        expect_close(tsv_num(res, i, "alpha_deg"), a, 1e-9, "alpha_deg", i);
        expect_close(tsv_num(res, i, "beta_deg"), b, 1e-9, "beta_deg", i);
        expect_close(tsv_num(res, i, "output_deg"), o, 1e-11, "output_deg", i);
        assert_near(tsv_num(res, i, "weight"), w, 0);
        double r = (ess_model_predict(&m, a * RAD_PER_DEG, b * RAD_PER_DEG, NULL) -
                    o * RAD_PER_DEG) * ARCSEC_PER_RAD;
        expect_g6(tsv_num(res, i, "residual_arcsec"), r, "residual_arcsec");
        /* the model's incidence at the table angles, from its installation */
        mat3 M;
        double wv[3], s[3];
        ess_turntable_matrix(a * RAD_PER_DEG, b * RAD_PER_DEG, M);
        mat3_vec(M, m.v, wv);
        mat3_vec(m.R, wv, s);
        double e = (comp->v[i][cc] * RAD_PER_DEG - atan2(s[1], s[2])) * ARCSEC_PER_RAD;
        expect_g6(tsv_num(res, i, "angle_error_arcsec"), e, "angle_error_arcsec");
        err_as[i] = e;
        if (w > 0) {
            chi2 += w * r * r;
            n_used++;
        }
    }
    assert_int_equal(n_used, used);
    assert_int_equal(dof, used - ESS_NP); /* no aliased direction at a 0.2 deg step */
    assert_near(sigma, sqrt(chi2 / (double)dof), 5.0001e-4); /* printed with 3 decimals */

    /* bands.tsv: one row per band of alpha */
    const double lo[3] = {0, 30, 0}, hi[3] = {30, 60, 62};
    assert_int_equal(bands->nr, 3);
    for (int bnd = 0; bnd < 3; bnd++) {
        assert_string_equal(tsv_str(bands, bnd, "angle"), "alpha");
        assert_near(tsv_num(bands, bnd, "band_lo_deg"), lo[bnd], 0);
        assert_near(tsv_num(bands, bnd, "band_hi_deg"), hi[bnd], 0);
        long pts = 0;
        double s2 = 0;
        for (int i = 0; i < res->nr; i++)
            if (camp->v[i][cw] > 0 && in_band(fabs(comp->v[i][cc]), lo[bnd], hi[bnd])) {
                pts++;
                s2 += err_as[i] * err_as[i];
            }
        assert_true(pts > 100);
        assert_int_equal(atol(tsv_str(bands, bnd, "points")), pts);
        double rr = sqrt(s2 / (double)pts);
        expect_g6(tsv_num(bands, bnd, "residual_rms_arcsec"), rr, "residual_rms_arcsec");
        /* the calibration's sigma over field.tsv's grid in the band */
        long nf = 0;
        double f2 = 0, fmax_ = 0;
        for (int j = 0; j < field->nr; j++) {
            double aj = tsv_num(field, j, "alpha_deg"), sj = tsv_num(field, j, "sigma_arcsec");
            if (in_band(fabs(aj), lo[bnd], hi[bnd])) {
                nf++;
                f2 += sj * sj;
                fmax_ = fmax(fmax_, sj);
            }
        }
        assert_true(nf > 100);
        double crms = sqrt(f2 / (double)nf);
        expect_g6(tsv_num(bands, bnd, "cal_sigma_rms_arcsec"), crms, "cal_sigma_rms_arcsec");
        /* field.tsv holds %.6g roundings of the values the max is taken of */
        assert_near(tsv_num(bands, bnd, "cal_sigma_max_arcsec"), fmax_, 2e-5 * fmax_);
        double noise = rr * sqrt((double)used / (double)dof);
        expect_g6(tsv_num(bands, bnd, "predicted_rms_arcsec"), sqrt(noise * noise + crms * crms),
                  "predicted_rms_arcsec");
    }
    /* field.tsv: the campaign's alpha range, -61.95..61.95, in 0.1 deg
     * steps: 123.9 / 0.1 + 1 = 1240 */
    assert_near(tsv_num(field, 0, "alpha_deg"), -61.95, 1e-9);
    assert_near(tsv_num(field, field->nr - 1, "alpha_deg"), 61.95, 1e-6);
    assert_int_equal(field->nr, 1240);

    /* crossval.tsv: one fold per beta line, its points held out */
    double betas[16];
    long count[16] = {0};
    int nb = 0;
    for (int i = 0; i < camp->nr; i++) {
        int k = 0;
        while (k < nb && betas[k] != camp->v[i][cb])
            k++;
        if (k == nb) {
            assert_true(nb < 16);
            betas[nb++] = camp->v[i][cb];
        }
        count[k] += camp->v[i][cw] > 0;
    }
    assert_true(nb >= 2);
    assert_int_equal(cv->nr, nb);
    for (int k = 0; k < nb; k++) {
        assert_int_equal(atoi(tsv_str(cv, k, "fold")), k + 1);
        assert_int_equal(atol(tsv_str(cv, k, "points")), count[k]);
        assert_int_equal(atoi(tsv_str(cv, k, "ok")), 1);
        /* held out, a line is predicted about as well as the others */
        double in = tsv_num(cv, k, "rms_in_arcsec"), outr = tsv_num(cv, k, "rms_out_arcsec");
        expect_fold_printed(out, k, count[k], in, outr);
        assert_true(in > 0.5 * sigma && in < 2 * sigma);
        assert_true(outr > 0.5 * sigma && outr < 4 * sigma);
    }
    /* refit_condition: without the beta = 0 line the two symmetric lines
     * at +-30 deg see b, c and the simulator's tilt alike (1 - cos beta is
     * the same on both), so that refit is near-singular; with it held in,
     * each outer fold's refit is as well posed as the whole fit */
    double cond0 = NAN, cond_other = 0;
    for (int k = 0; k < nb; k++) {
        double q = tsv_num(cv, k, "refit_condition");
        assert_true(q >= 1);
        if (betas[k] == 0)
            cond0 = q;
        else
            cond_other = fmax(cond_other, q);
    }
    assert_true(cond0 > CALREPORT_FOLD_COND_WARN * cond_other);
    free(err_as);
    tsv_free(field);
    calrun_free(&run);
}

/* ---- DSS ---- */

/* The sun simulator on the table's axis (no tilt tolerances): the sun in
 * the mount's frame is then the table's truth of eq. 2-4. */
#define DSS_SUN_ON_AXIS "--set tolerance.sun_b1_arcsec=0 --set tolerance.sun_b2_arcsec=0"

static void dss_files(void **state)
{
    (void)state;
    char out[1 << 16];
    calrun run;
    calrun_load(&run, "configs/dss.ini", 2, DSS_SUN_ON_AXIS, "dss", out, sizeof out);
    csvt *camp = run.camp, *comp = run.comp;
    tsv *res = run.res, *bands = run.bands, *cv = run.cv;
    long used = run.used, dof = run.dof;
    double sigma = run.sigma;

    assert_int_equal(res->nr, camp->nr);
    assert_int_equal(comp->nr, camp->nr);
    /* the fitted sun simulator direction R(s) e_z from params.ini */
    params_file pf;
    char ppath[600], err[SUNMC_ERRLEN];
    double sb1, sb2, v_sun[3];
    mat3 Rs;
    snprintf(ppath, sizeof ppath, "%s/params.ini", run.cal);
    assert_int_equal(params_read(ppath, &pf, err, sizeof err), SUNMC_OK);
    assert_int_equal(params_get_double(&pf, "parameters", "fit_sun_b1_arcsec", &sb1, err, sizeof err),
                     SUNMC_OK);
    assert_int_equal(params_get_double(&pf, "parameters", "fit_sun_b2_arcsec", &sb2, err, sizeof err),
                     SUNMC_OK);
    table_rotation(sb1 * RAD_PER_ARCSEC, sb2 * RAD_PER_ARCSEC, Rs);
    for (int i = 0; i < 3; i++)
        v_sun[i] = Rs[i][2];
    int c1 = csv_col(camp, "b1_deg"), c2 = csv_col(camp, "b2_deg"), cx = csv_col(camp, "x_px");
    int cy = csv_col(camp, "y_px");
    int kw = -1;
    for (int j = 0; j < camp->nc; j++)
        if (strcmp(camp->names[j], "weight") == 0)
            kw = j;
    int ka = csv_col(comp, "compensated_alpha_deg"), kb = csv_col(comp, "compensated_beta_deg");
    double *ea = calloc((size_t)res->nr, sizeof *ea), *eb = calloc((size_t)res->nr, sizeof *eb);
    double *fd = calloc((size_t)res->nr, sizeof *fd);
    long n_used = 0;
    long quadrant[4] = {0};
    double sum2 = 0;
    for (int i = 0; i < res->nr; i++) {
        double b1 = camp->v[i][c1], b2 = camp->v[i][c2], w = kw >= 0 ? camp->v[i][kw] : 1.0;
        assert_int_equal(atoi(tsv_str(res, i, "line")), camp->line[i]);
        expect_close(tsv_num(res, i, "b1_deg"), b1, 1e-9, "b1_deg", i);
        expect_close(tsv_num(res, i, "b2_deg"), b2, 1e-9, "b2_deg", i);
        expect_close(tsv_num(res, i, "x_px"), camp->v[i][cx], 1e-9, "x_px", i);
        expect_close(tsv_num(res, i, "y_px"), camp->v[i][cy], 1e-9, "y_px", i);
        assert_near(tsv_num(res, i, "weight"), w, 0);
        double a = comp->v[i][ka], b = comp->v[i][kb];
        if (w == 0) { /* a "no spot" row: no angle (compensate's '-') */
            assert_true(isnan(a) && isnan(b));
            continue;
        }
        expect_close(tsv_num(res, i, "alpha_deg"), a, 1e-9, "alpha_deg", i);
        expect_close(tsv_num(res, i, "beta_deg"), b, 1e-9, "beta_deg", i);
        /* the sun in the mount's frame, the simulator as fitted:
         * w = R(b) R(s) e_z, alpha = atan2(w_x, w_z), beta = atan2(w_y, w_z) */
        mat3 Rb;
        double sv[3];
        table_rotation(b1 * RAD_PER_DEG, b2 * RAD_PER_DEG, Rb);
        mat3_vec(Rb, v_sun, sv);
        double a0 = atan2(sv[0], sv[2]), b0 = atan2(sv[1], sv[2]);
        ea[i] = (a * RAD_PER_DEG - a0) * ARCSEC_PER_RAD;
        eb[i] = (b * RAD_PER_DEG - b0) * ARCSEC_PER_RAD;
        fd[i] = atan(hypot(tan(a0), tan(b0))) * DEG_PER_RAD;
        expect_g6(tsv_num(res, i, "alpha_error_arcsec"), ea[i], "alpha_error_arcsec");
        expect_g6(tsv_num(res, i, "beta_error_arcsec"), eb[i], "beta_error_arcsec");
        if (w > 0) {
            n_used++;
            sum2 += ea[i] * ea[i] + eb[i] * eb[i];
            quadrant[2 * (b1 >= 0) + (b2 >= 0)]++;
        }
    }
    assert_int_equal(n_used, used);
    /* physical model (dss.ini fits the glass index and the sun simulator as mounted): two
     * residuals per reading, 10 parameters */
    long n_res = 2 * used;
    assert_int_equal(dof, n_res - 10);
    /* the printed sigma: the angle-domain RMS scaled to the degrees of freedom */
    assert_near(sigma, sqrt(sum2 / (double)n_res * (double)n_res / (double)dof), 5.0001e-4);

    const double lo[3] = {0, 20, 0}, hi[3] = {20, 40, 60};
    const char *angle[2] = {"alpha", "beta"};
    assert_int_equal(bands->nr, 6);
    for (int an = 0; an < 2; an++)
        for (int bnd = 0; bnd < 3; bnd++) {
            int r = an * 3 + bnd;
            assert_string_equal(tsv_str(bands, r, "angle"), angle[an]);
            assert_near(tsv_num(bands, r, "band_lo_deg"), lo[bnd], 0);
            assert_near(tsv_num(bands, r, "band_hi_deg"), hi[bnd], 0);
            long pts = 0;
            double s2 = 0;
            for (int i = 0; i < res->nr; i++)
                if ((kw < 0 || camp->v[i][kw] > 0) && in_band(fd[i], lo[bnd], hi[bnd])) {
                    double e = an == 0 ? ea[i] : eb[i];
                    pts++;
                    s2 += e * e;
                }
            assert_true(pts > 20);
            assert_int_equal(atol(tsv_str(bands, r, "points")), pts);
            double rr = sqrt(s2 / (double)pts);
            expect_g6(tsv_num(bands, r, "residual_rms_arcsec"), rr, "residual_rms_arcsec");
            double crms = tsv_num(bands, r, "cal_sigma_rms_arcsec");
            double cmax = tsv_num(bands, r, "cal_sigma_max_arcsec");
            assert_true(crms > 0 && cmax >= crms * (1 - 1e-5));
            double noise = rr * sqrt((double)n_res / (double)dof);
            expect_g6(tsv_num(bands, r, "predicted_rms_arcsec"),
                      sqrt(noise * noise + crms * crms), "predicted_rms_arcsec");
        }
    /* crossval.tsv: the four quadrants of the grid, by the signs of b1, b2 */
    static const char *const qname[4] = {"b1<0,b2<0", "b1<0,b2>=0", "b1>=0,b2<0",
                                         "b1>=0,b2>=0"};
    assert_int_equal(cv->nr, 4);
    for (int k = 0; k < 4; k++) {
        assert_string_equal(tsv_str(cv, k, "held_out"), qname[k]);
        assert_int_equal(atol(tsv_str(cv, k, "points")), quadrant[k]);
    }
    free(ea);
    free(eb);
    free(fd);
    calrun_free(&run);
}

/* ---- simulate's truth.csv ---- */

/* "# name = value" comment lines of a file, looked up by name. */
static double comment_value(const char *path, const char *name)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[512], key[256];
    double v;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "# %255s = %lf", key, &v) == 2 && strcmp(key, name) == 0) {
            fclose(f);
            return v;
        }
    fclose(f);
    fail_msg("%s: no comment '# %s = '", path, name);
    return NAN;
}

/* Mean, standard deviation and correlation of two samples of n. */
static void moments2(const double *x, const double *y, long n, double *sx, double *sy,
                     double *mx, double *my, double *r)
{
    double ax = 0, ay = 0, xx = 0, yy = 0, xy = 0;
    for (long i = 0; i < n; i++) {
        ax += x[i];
        ay += y[i];
    }
    ax /= (double)n;
    ay /= (double)n;
    for (long i = 0; i < n; i++) {
        xx += (x[i] - ax) * (x[i] - ax);
        yy += (y[i] - ay) * (y[i] - ay);
        xy += (x[i] - ax) * (y[i] - ay);
    }
    *mx = ax;
    *my = ay;
    *sx = sqrt(xx / (double)(n - 1));
    *sy = sqrt(yy / (double)(n - 1));
    *r = xy / sqrt(xx * yy);
}

/* The encoder errors (arcsec) of a campaign: sigma `enc`, mean 0, alpha
 * and beta independent. */
static void expect_encoder(const double *da, const double *db, long n, double enc)
{
    double sa, sb, ma, mb, r;
    moments2(da, db, n, &sa, &sb, &ma, &mb, &r);
    double se = enc / sqrt((double)n);
    if (!(fabs(sa / enc - 1) < 0.12 && fabs(sb / enc - 1) < 0.12 && fabs(ma) < 5 * se &&
          fabs(mb) < 5 * se && fabs(r) < 5 / sqrt((double)n)))
        fail_msg("encoder errors: sigma %g, %g (want %g), mean %g, %g, correlation %g", sa, sb,
                 enc, ma, mb, r);
}

/* The deviation columns of units.tsv (unit U alone) against truth.csv's
 * comments. */
static void expect_deviations(const char *units_path, const char *truth_path)
{
    tsv *u = tsv_load(units_path);
    assert_int_equal(u->nr, 1);
    int first = tsv_col(u, "gross_val") + 1, last = -1;
    for (int j = first; j < u->nc; j++)
        if (strncmp(u->names[j], "fit_", 4) == 0) {
            last = j;
            break;
        }
    assert_true(last > first + 3);
    for (int j = first; j < last; j++)
        expect_close(comment_value(truth_path, u->names[j]), strtod(u->cell[0][j], NULL), 1e-9,
                     u->names[j], 0);
    tsv_free(u);
}

/* Unit U of cfg simulated and run alone (same --set options): truth.csv's
 * deviations checked against units.tsv; truth.csv and campaign.csv read. */
static void truth_and_campaign(const char *cfg, int unit, const char *sets, const char *tag,
                               csvt **truth, csvt **camp)
{
    char cmd[4096], out[1 << 16], path[600], upath[600], name[64];
    snprintf(name, sizeof name, "%s_truth_sim", tag);
    const char *sim = test_tmp(name);
    snprintf(cmd, sizeof cmd, "%s simulate %s --unit %d %s --out %s", test_sunmc(), cfg, unit,
             sets, sim);
    run_ok(cmd, out, sizeof out);
    snprintf(path, sizeof path, "%s/truth.csv", sim);
    snprintf(name, sizeof name, "%s_truth_run", tag);
    const char *run = test_tmp(name);
    snprintf(cmd, sizeof cmd, "%s run %s --units %d:%d %s --quiet --out %s", test_sunmc(), cfg,
             unit, unit + 1, sets, run);
    run_ok(cmd, out, sizeof out);
    snprintf(upath, sizeof upath, "%s/units.tsv", run);
    expect_deviations(upath, path);
    *truth = csv_load(path);
    snprintf(path, sizeof path, "%s/campaign.csv", sim);
    *camp = csv_load(path);
    assert_int_equal((*truth)->nr, (*camp)->nr);
}

static void ess_truth(void **state)
{
    (void)state;
    csvt *t, *camp;
    truth_and_campaign("configs/ess_type_a.ini", 5, "", "ess", &t, &camp);
    int ta = csv_col(t, "alpha_deg"), tb = csv_col(t, "beta_deg");
    int tat = csv_col(t, "alpha_true_deg"), tbt = csv_col(t, "beta_true_deg");
    int ti = csv_col(t, "incidence_deg"), to = csv_col(t, "output_deg"), ts = csv_col(t, "seen");
    double *da = calloc((size_t)t->nr, sizeof *da), *db = calloc((size_t)t->nr, sizeof *db);
    for (int i = 0; i < t->nr; i++) {
        assert_near(t->v[i][ta], camp->v[i][csv_col(camp, "alpha_deg")], 0);
        assert_near(t->v[i][tb], camp->v[i][csv_col(camp, "beta_deg")], 0);
        assert_near(t->v[i][to], camp->v[i][csv_col(camp, "output_deg")], 0);
        assert_near(t->v[i][ts], 1, 0);
        da[i] = (t->v[i][tat] - t->v[i][ta]) * ARCSEC_PER_DEG;
        db[i] = (t->v[i][tbt] - t->v[i][tb]) * ARCSEC_PER_DEG;
        /* the incidence is the true alpha seen through the installation
         * (arcminutes at most) and the output reads it to a few 0.01 deg */
        assert_true(fabs(t->v[i][ti] - t->v[i][tat]) < 0.2);
        assert_true(fabs(t->v[i][to] - t->v[i][ti]) < 0.1);
    }
    expect_encoder(da, db, t->nr, 1.0); /* noise.encoder_arcsec's default */
    free(da);
    free(db);
    free(t);
    free(camp);
}

static void dss_truth(void **state)
{
    (void)state;
    csvt *t, *camp;
    truth_and_campaign("configs/dss.ini", 4, "--set noise.encoder_arcsec=20 " DSS_SUN_ON_AXIS,
                       "dss", &t, &camp);
    int t1 = csv_col(t, "b1_deg"), t2 = csv_col(t, "b2_deg");
    int tal = csv_col(t, "truth_alpha_deg"), tbe = csv_col(t, "truth_beta_deg");
    int ts = csv_col(t, "seen"), cw = csv_col(camp, "weight");
    double *da = calloc((size_t)t->nr, sizeof *da), *db = calloc((size_t)t->nr, sizeof *db);
    long n = 0;
    for (int i = 0; i < t->nr; i++) {
        double b1 = t->v[i][t1], b2 = t->v[i][t2];
        assert_near(b1, camp->v[i][csv_col(camp, "b1_deg")], 0);
        assert_near(b2, camp->v[i][csv_col(camp, "b2_deg")], 0);
        assert_near(t->v[i][ts], camp->v[i][cw], 0);
        /* alpha = -b2 and beta = atan(tan b1 / cos b2) of the true table
         * angles: b2 and b1 recovered from them are off the recorded ones
         * by the encoder errors */
        double b2t = -t->v[i][tal] * RAD_PER_DEG;
        double b1t = atan(tan(t->v[i][tbe] * RAD_PER_DEG) * cos(b2t));
        da[n] = (b2t * DEG_PER_RAD - b2) * ARCSEC_PER_DEG;
        db[n] = (b1t * DEG_PER_RAD - b1) * ARCSEC_PER_DEG;
        n++;
    }
    expect_encoder(da, db, n, 20.0);
    free(da);
    free(db);
    free(t);
    free(camp);
}

/* A unit whose slit tilt makes the coarse rows misread near cell edges:
 * campaign.csv weighs 0 exactly the readings off the table alpha by half
 * a fine period (1 deg) or more, as many as simulate reports and run's
 * units.tsv counts (gross_cal); calibrate uses the others. */
static void ess_gross_rows(void **state)
{
    (void)state;
    char cmd[4096], out[1 << 16], path[600];
    const char *sim = test_tmp("ess_gross_sim"), *run = test_tmp("ess_gross_run");
    /* a 0.2 x (-15, 0, 15) campaign: from beta +-20 on, the 1 deg tilt (100
     * times the config's tolerance) moves more than 10 % of the rows beyond
     * what the config's tolerances allow (lab_predict.c), which calibrate's
     * lab check refuses before any fit */
    const char *sets = "--set tolerance.dphi_deg=1 --set tolerance.dphi_deg_dist=fixed "
                       "--set campaign.alpha_step_deg=0.2 --set campaign.beta_deg=-15,0,15";
    snprintf(cmd, sizeof cmd, "%s simulate configs/ess_type_a.ini --unit 3 %s --out %s",
             test_sunmc(), sets, sim);
    run_ok(cmd, out, sizeof out);
    long n_pts, n_gross;
    const char *p = strstr(out, "): ");
    assert_non_null(p);
    assert_int_equal(sscanf(p, "): %ld campaign points (%ld dropped", &n_pts, &n_gross), 2);
    assert_true(n_gross > 10);
    snprintf(path, sizeof path, "%s/campaign.csv", sim);
    csvt *camp = csv_load(path);
    assert_int_equal(camp->nr, n_pts);
    int ca = csv_col(camp, "alpha_deg"), co = csv_col(camp, "output_deg");
    int cw = csv_col(camp, "weight");
    long zero = 0;
    for (int i = 0; i < camp->nr; i++) {
        int off = !(fabs(camp->v[i][co] - camp->v[i][ca]) < 1.0);
        if (camp->v[i][cw] != (off ? 0.0 : 1.0))
            fail_msg("line %d: output %g at alpha %g has weight %g", camp->line[i],
                     camp->v[i][co], camp->v[i][ca], camp->v[i][cw]);
        zero += off;
    }
    assert_int_equal(zero, n_gross);
    snprintf(cmd, sizeof cmd, "%s run configs/ess_type_a.ini --units 3:4 %s --quiet --out %s",
             test_sunmc(), sets, run);
    run_ok(cmd, out, sizeof out);
    snprintf(path, sizeof path, "%s/units.tsv", run);
    tsv *u = tsv_load(path);
    assert_int_equal(atol(tsv_str(u, 0, "gross_cal")), n_gross);
    tsv_free(u);
    /* the unit's 1 deg tilt is 100 times the config's tolerance: its fit
     * leaves 150", 12 times the config's noise, which calibrate refuses at
     * the default ratio of 10 */
    snprintf(cmd, sizeof cmd,
             "%s calibrate --sensor ess --config configs/ess_type_a.ini %s/campaign.csv "
             "--set calibration.max_residual_ratio=20",
             test_sunmc(), sim);
    run_ok(cmd, out, sizeof out);
    long used, dof;
    double sigma;
    report_numbers(out, &used, &dof, &sigma);
    assert_int_equal(used, n_pts - n_gross);
    free(camp);
}

/* rms_after_sys of units.tsv is the RMS of the noiseless error after
 * calibration that `curve` writes for the same unit, per band of |alpha|
 * (no installation or sun tilt, so the true incidence is the table alpha). */
static void ess_sys_from_curve(void **state)
{
    (void)state;
    char cmd[4096], out[1 << 16], path[600];
    const char *run = test_tmp("ess_sys_run"), *cur = test_tmp("ess_sys_curve");
    const char *sets = "--set tolerance.install_x_arcsec=0 --set tolerance.install_y_arcsec=0 "
                       "--set tolerance.install_z_arcsec=0 --set tolerance.sun_x_arcsec=0 "
                       "--set tolerance.sun_y_arcsec=0";
    snprintf(cmd, sizeof cmd, "%s run configs/ess_type_a.ini --units 6:7 %s --quiet --out %s",
             test_sunmc(), sets, run);
    run_ok(cmd, out, sizeof out);
    snprintf(cmd, sizeof cmd, "%s curve configs/ess_type_a.ini --unit 6 %s --out %s",
             test_sunmc(), sets, cur);
    run_ok(cmd, out, sizeof out);
    snprintf(path, sizeof path, "%s/units.tsv", run);
    tsv *u = tsv_load(path);
    snprintf(path, sizeof path, "%s/curve.tsv", cur);
    tsv *cv = tsv_load(path);
    const double lo[3] = {0, 30, 0}, hi[3] = {30, 60, 62};
    for (int b = 0; b < 3; b++) {
        double s2 = 0;
        long n = 0;
        for (int i = 0; i < cv->nr; i++) {
            double e = tsv_num(cv, i, "error_after_alpha_deg");
            if (in_band(fabs(tsv_num(cv, i, "alpha_deg")), lo[b], hi[b]) && !isnan(e)) {
                s2 += e * e;
                n++;
            }
        }
        assert_true(n > 500);
        char name[64];
        snprintf(name, sizeof name, "rms_after_sys_alpha_%g_%g_deg", lo[b], hi[b]);
        double sys = tsv_num(u, 0, name);
        expect_g6(sys, sqrt(s2 / (double)n), name);
        /* the reading noise adds to it */
        snprintf(name, sizeof name, "rms_after_alpha_%g_%g_deg", lo[b], hi[b]);
        assert_true(tsv_num(u, 0, name) > sys);
    }
    tsv_free(u);
    tsv_free(cv);
}

/* units.tsv's alias_weak: the fine-code term sin/cos(omega alpha), omega =
 * 2 pi / (theta0 / 4) = 2 pi / 0.5 deg, sampled at a 1 deg step is
 * constant (both directions unresolved), at 0.25 deg takes two opposite
 * phases (sin = 0: one direction), at 0.2 deg many (none); the summary
 * counts the units with any. */
static void ess_alias_counts(void **state)
{
    (void)state;
    const double step[3] = {1, 0.25, 0.2};
    const int weak[3] = {2, 1, 0};
    for (int k = 0; k < 3; k++) {
        char cmd[4096], out[1 << 16], path[600];
        const char *run = test_tmp("ess_alias_run");
        snprintf(cmd, sizeof cmd,
                 "rm -rf %s && %s run configs/ess_type_a.ini --units 0:3 "
                 "--set campaign.alpha_step_deg=%g --set validation.alpha_step_deg=1.3 --quiet "
                 "--out %s",
                 run, test_sunmc(), step[k], run);
        run_ok(cmd, out, sizeof out);
        snprintf(path, sizeof path, "%s/units.tsv", run);
        tsv *u = tsv_load(path);
        assert_int_equal(u->nr, 3);
        for (int i = 0; i < 3; i++)
            assert_int_equal(atoi(tsv_str(u, i, "alias_weak")), weak[k]);
        tsv_free(u);
        snprintf(path, sizeof path, "%s/summary.tsv", run);
        tsv *s = tsv_load(path);
        assert_int_equal(atoi(tsv_str(s, 0, "alias_units")), weak[k] ? 3 : 0);
        tsv_free(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ess_files),
        cmocka_unit_test(dss_files),
        cmocka_unit_test(ess_truth),
        cmocka_unit_test(dss_truth),
        cmocka_unit_test(ess_gross_rows),
        cmocka_unit_test(ess_sys_from_curve),
        cmocka_unit_test(ess_alias_counts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
