/* test_calibrate_sigma.c - the propagated calibration uncertainty users read
 * (issue 29): field.tsv's sigma at an angle equals sqrt(h^T C h) with C
 * rebuilt from the standard errors and correlations `calibrate` prints and
 * h = d(compensated angle)/d(parameter) taken here by central differences
 * of the compensation of the written params.ini; bands.tsv's cal.sigma (rms,
 * max) and predicted equal their definitions over field.tsv and the
 * residual column. */
#include "test_tsv.h"

#include "ess_labfit.h"
#include "ess_model.h"
#include "params_io.h"
#include "units.h"

#define NP_MAX 18

static char dir[128];
static char out[65536];

static int setup(void **state)
{
    char cmd[2048];
    if (test_private_dir(dir, sizeof dir, "cal_sigma"))
        return -1;
    snprintf(cmd, sizeof cmd,
             "D=%s; %s simulate configs/ess_type_a.ini --unit 3 --seed 1 --quiet --out $D/sim "
             ">/dev/null && %s calibrate --config configs/ess_type_a.ini $D/sim/campaign.csv "
             "--out $D/cal",
             dir, test_sunmc(), test_sunmc());
    return test_run(cmd, out, sizeof out);
}

typedef struct {
    int np;
    char name[NP_MAX][64];
    double se[NP_MAX], r[NP_MAX][NP_MAX];
} printed_cov;

/* The parameter lines and the correlation matrix of calibrate's output. */
static void parse_printed(const char *text, printed_cov *pc)
{
    const char *p = strstr(text, "\nparameters (");
    assert_non_null(p);
    p = strchr(p + 1, '\n') + 1;
    pc->np = 0;
    while (p[0] == ' ' && p[1] == ' ') {
        double v, se;
        char name[64];
        assert_int_equal(sscanf(p, " %63s %lf +- %lf", name, &v, &se), 3);
        snprintf(pc->name[pc->np], sizeof pc->name[0], "%s", name);
        pc->se[pc->np++] = se;
        p = strchr(p, '\n') + 1;
    }
    assert_true(pc->np >= 5);
    p = strstr(p, "correlation matrix:\n");
    assert_non_null(p);
    p = strchr(p, '\n') + 1;
    p = strchr(p, '\n') + 1; /* the column numbers */
    for (int i = 0; i < pc->np; i++) {
        int idx, n;
        char name[64];
        assert_int_equal(sscanf(p, " %d %63s%n", &idx, name, &n), 2);
        assert_int_equal(idx, i + 1);
        assert_string_equal(name, pc->name[i]);
        const char *q = p + n;
        for (int j = 0; j < pc->np; j++) {
            char *e;
            pc->r[i][j] = strtod(q, &e);
            assert_true(e != q);
            q = e;
        }
        p = strchr(p, '\n') + 1;
    }
}

/* Display unit of a parameter name -> internal (rad) scale. */
static double display_scale(const char *name)
{
    size_t n = strlen(name);
    if (n > 4 && strcmp(name + n - 4, "_deg") == 0)
        return DEG_PER_RAD;
    if (n > 7 && strcmp(name + n - 7, "_arcsec") == 0)
        return ARCSEC_PER_RAD;
    return 1.0;
}

static double comp(const ess_model *m, double raw)
{
    double a;
    assert_int_equal(ess_model_compensate(m, raw, &a), 0);
    return a;
}

/* sqrt(h^T C h) (arcsec) at compensated angle alpha (rad). */
static double sigma_at(const ess_model *m0, const printed_cov *pc, double alpha)
{
    double raw = alpha; /* the reading whose compensation is alpha: Newton */
    for (int it = 0; it < 50 && comp(m0, raw) != alpha; it++) {
        double d = 1e-7, slope = (comp(m0, raw + d) - comp(m0, raw - d)) / (2 * d);
        raw += (alpha - comp(m0, raw)) / slope;
    }
    assert_near(comp(m0, raw), alpha, 1e-13);
    double h[NP_MAX];
    for (int j = 0; j < pc->np; j++) {
        double step = 1e-3 * pc->se[j] / display_scale(pc->name[j]);
        ess_model mp = *m0, mm = *m0;
        mp.p[j] += step;
        mm.p[j] -= step;
        ess_model_prepare(&mp);
        ess_model_prepare(&mm);
        h[j] = (comp(&mp, raw) - comp(&mm, raw)) / (2 * step); /* rad per internal unit */
    }
    double v = 0;
    for (int i = 0; i < pc->np; i++)
        for (int j = 0; j < pc->np; j++) {
            double cij = pc->r[i][j] * pc->se[i] * pc->se[j] /
                         (display_scale(pc->name[i]) * display_scale(pc->name[j]));
            v += h[i] * cij * h[j];
        }
    return sqrt(v) * ARCSEC_PER_RAD;
}

static void field_sigma_is_hT_C_h(void **state)
{
    printed_cov pc;
    parse_printed(out, &pc);
    char path[512], err[256];
    snprintf(path, sizeof path, "%s/cal/params.ini", dir);
    params_file *pf = calloc(1, sizeof *pf);
    assert_int_equal(params_read(path, pf, err, sizeof err), 0);
    ess_model m;
    if (ess_params_load(pf, &m, err, sizeof err) != 0)
        fail_msg("%s", err);
    free(pf);
    assert_true(m.np >= pc.np);
    assert_string_equal(pc.name[0], "a");
    assert_string_equal(pc.name[4], "kc_deg");
    snprintf(path, sizeof path, "%s/cal/field.tsv", dir);
    tsv *f = tsv_load(path);
    assert_true(f->nr > 1000);
    int checked = 0;
    for (int r = 0; r < f->nr; r += 37) {
        double a_deg = tsv_num(f, r, "alpha_deg"), s = tsv_num(f, r, "sigma_arcsec");
        double want = sigma_at(&m, &pc, a_deg * RAD_PER_DEG);
        /* C rebuilt from 4-digit standard errors and 3-decimal correlations:
         * agreement seen 8e-5, allowed 0.2 % */
        if (!(fabs(s - want) <= 2e-3 * want))
            fail_msg("alpha %g deg: field.tsv sigma %.6g arcsec, h^T C h gives %.6g", a_deg, s,
                     want);
        checked++;
    }
    assert_true(checked > 30);
    tsv_free(f);
}

static void bands_from_field(void **state)
{
    char path[512];
    snprintf(path, sizeof path, "%s/cal/field.tsv", dir);
    tsv *f = tsv_load(path);
    snprintf(path, sizeof path, "%s/cal/bands.tsv", dir);
    tsv *b = tsv_load(path);
    /* the campaign's alpha range (rows with weight > 0) bounds the field */
    char cmd[1024], range[128];
    snprintf(cmd, sizeof cmd,
             "awk -F, '/^#/ {next} !h {h=1; next} $NF > 0 {if (n++ == 0 || $1 < lo) lo = $1; "
             "if (n == 1 || $1 > hi) hi = $1} END {print lo, hi}' %s/sim/campaign.csv",
             dir);
    assert_int_equal(test_run(cmd, range, sizeof range), 0);
    double lo_deg, hi_deg;
    assert_int_equal(sscanf(range, "%lf %lf", &lo_deg, &hi_deg), 2);
    long used, dof;
    const char *d = strstr(out, "data: ");
    assert_non_null(d);
    assert_int_equal(sscanf(d, "data: %*d rows, %ld used, %ld degrees of freedom", &used, &dof),
                     2);
    for (int r = 0; r < b->nr; r++) {
        double blo = tsv_num(b, r, "band_lo_deg"), bhi = tsv_num(b, r, "band_hi_deg");
        double s2 = 0, smax = 0;
        long n = 0;
        for (int i = 0; i < f->nr; i++) {
            double a = tsv_num(f, i, "alpha_deg"), s = tsv_num(f, i, "sigma_arcsec");
            if (a < lo_deg - 1e-9 || a > hi_deg + 1e-9 || fabs(a) < blo || fabs(a) > bhi)
                continue;
            s2 += s * s;
            smax = fmax(smax, s);
            n++;
        }
        assert_true(n > 10);
        double rms = sqrt(s2 / (double)n);
        expect_g6(tsv_num(b, r, "cal_sigma_rms_arcsec"), rms, "cal_sigma_rms_arcsec");
        expect_g6(tsv_num(b, r, "cal_sigma_max_arcsec"), smax, "cal_sigma_max_arcsec");
        double noise = tsv_num(b, r, "residual_rms_arcsec") * sqrt((double)used / (double)dof);
        expect_g6(tsv_num(b, r, "predicted_rms_arcsec"), sqrt(noise * noise + rms * rms),
                  "predicted_rms_arcsec");
    }
    tsv_free(b);
    tsv_free(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(field_sigma_is_hT_C_h),
        cmocka_unit_test(bands_from_field),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
