/* test_compensate_accuracy.c - compensate says what the calibration
 * achieved when the rows carry their truth (issue 41): a simulated unit's
 * validation.csv through calibrate and compensate, and the RMS, p99.7 and
 * max per band it reports (stderr, and accuracy.tsv with --out) against
 * the same statistics computed here from the compensated CSV it wrote,
 * with formulas of the test's own (the total angle as the chord's
 * 2 asin(|u - v| / 2), the field angle from the truth's tangents), and
 * the refusals of --out, --config and --set. */
#include "test_util.h"

#include <math.h>

#define MAXROWS 8192
#define P997 0.9973

typedef struct {
    int n;
    double e[3][MAXROWS]; /* alpha, beta, total errors (rms unit) */
    double field[MAXROWS]; /* deg: field angle (two axes) or |truth| */
    int skipped;           /* rows written '-' */
} errors;

/* Column index of name in a CSV header line, -1 when absent. */
static int column(const char *header, const char *name)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s", header);
    buf[strcspn(buf, "\r\n")] = 0;
    int k = 0;
    for (char *s = strtok(buf, ","); s; s = strtok(NULL, ","), k++)
        if (strcmp(s, name) == 0)
            return k;
    return -1;
}

static double field_at(const char *line, int col)
{
    const char *p = line;
    for (int k = 0; k < col; k++)
        p = strchr(p, ',') + 1;
    return strtod(p, NULL);
}

/* The compensated CSV at path into e: two axes (alpha, beta; per_deg
 * rms units per degree) or one (ESS). */
static void read_errors(const char *path, int two, double per_deg, errors *e)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    static char line[8192];
    static char header[8192];
    while (fgets(line, sizeof line, f) && line[0] == '#')
        ;
    snprintf(header, sizeof header, "%s", line);
    int ca = column(header, two ? "compensated_alpha_deg" : "compensated_deg");
    int ta = column(header, two ? "truth_alpha_deg" : "truth_deg");
    int cb = two ? column(header, "compensated_beta_deg") : -1;
    int tb = two ? column(header, "truth_beta_deg") : -1;
    assert_true(ca >= 0 && ta >= 0 && (!two || (cb >= 0 && tb >= 0)));
    e->n = 0;
    e->skipped = 0;
    while (fgets(line, sizeof line, f) && e->n < MAXROWS) {
        double a = field_at(line, ca), a0 = field_at(line, ta);
        const char *p = line;
        for (int k = 0; k < ca; k++)
            p = strchr(p, ',') + 1;
        if (*p == '-' && (p[1] == ',' || p[1] == '\n')) { /* not compensated */
            e->skipped++;
            continue;
        }
        int i = e->n++;
        e->e[0][i] = (a - a0) * per_deg;
        e->field[i] = fabs(a0);
        if (!two)
            continue;
        double b = field_at(line, cb), b0 = field_at(line, tb), r = M_PI / 180;
        double u[3] = {tan(a * r), tan(b * r), 1}, v[3] = {tan(a0 * r), tan(b0 * r), 1};
        double nu = sqrt(u[0] * u[0] + u[1] * u[1] + 1), nv = sqrt(v[0] * v[0] + v[1] * v[1] + 1);
        double d2 = 0;
        for (int k = 0; k < 3; k++)
            d2 += (u[k] / nu - v[k] / nv) * (u[k] / nu - v[k] / nv);
        e->e[1][i] = (b - b0) * per_deg;
        e->e[2][i] = 2 * asin(sqrt(d2) / 2) / r * per_deg;
        e->field[i] = atan(sqrt(v[0] * v[0] + v[1] * v[1])) / r;
    }
    fclose(f);
}

static int cmp(const void *x, const void *y)
{
    double u = *(const double *)x, v = *(const double *)y;
    return (u > v) - (u < v);
}

/* RMS, p99.7 (nearest rank) and max of |e[k]| over lo < field <= hi (lo 0: from 0). */
static long band_stats(const errors *e, int k, double lo, double hi, double *rms, double *p, double *mx)
{
    static double a[MAXROWS];
    long n = 0;
    double s2 = 0;
    for (int i = 0; i < e->n; i++)
        if (e->field[i] <= hi + 1e-9 && (lo == 0 || e->field[i] > lo + 1e-9)) {
            a[n++] = fabs(e->e[k][i]);
            s2 += e->e[k][i] * e->e[k][i];
        }
    qsort(a, (size_t)n, sizeof *a, cmp);
    *rms = sqrt(s2 / (double)n);
    *p = a[(long)ceil(P997 * (double)n) - 1];
    *mx = a[n - 1];
    return n;
}

static void near(double got, double want)
{
    if (!(fabs(got - want) <= 2e-5 * fabs(want) + 1e-12))
        fail_msg("accuracy %.9g, computed here %.9g", got, want);
}

/* Every row of accuracy.tsv against the test's own statistics. */
static int check_tsv(const char *tsv, const errors *e, const char *const *angles, const char *spec,
                     double spec_value)
{
    FILE *f = fopen(tsv, "r");
    assert_non_null(f);
    char line[1024];
    assert_non_null(fgets(line, sizeof line, f));
    assert_string_equal(line, "angle\tband\tband_lo_deg\tband_hi_deg\tpoints\tunit\trms\tp99_7\tmax\t"
                              "spec_statistic\tspec\tmeets_spec\n");
    int rows = 0;
    while (fgets(line, sizeof line, f)) {
        char angle[16], band[32], unit[16], stat[16], specs[32], meets[8];
        double lo, hi, rms, p, mx, r0, p0, m0;
        long n;
        assert_int_equal(sscanf(line, "%15s %31s %lf %lf %ld %15s %lf %lf %lf %15s %31s %7s", angle,
                                band, &lo, &hi, &n, unit, &rms, &p, &mx, stat, specs, meets), 12);
        int k = 0;
        while (strcmp(angles[k], angle) != 0)
            k++;
        assert_int_equal(n, band_stats(e, k, lo, hi, &r0, &p0, &m0));
        near(rms, r0);
        near(p, p0);
        near(mx, m0);
        assert_string_equal(stat, spec);
        if (spec_value > 0) {
            near(strtod(specs, NULL), spec_value);
            assert_string_equal(meets, rms <= spec_value ? "yes" : "no");
        } else {
            assert_string_equal(specs, "-");
            assert_string_equal(meets, "-");
        }
        rows++;
    }
    fclose(f);
    return rows;
}

static const char *const two_axes[] = {"alpha", "beta", "total"};

/* DSS unit 3: calibrate, compensate with the config's bands and spec; every
 * band's RMS, p99.7 and max equal the test's; the stderr summary says it. */
static void dss_validation_scored(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd,
             "S=%s; D=%s; $S simulate configs/dss.ini --unit 3 --out $D/sim >/dev/null && "
             "$S calibrate --config configs/dss.ini $D/sim/campaign.csv --out $D/cal >/dev/null && "
             "$S compensate $D/cal/params.ini $D/sim/validation.csv --config configs/dss.ini "
             "--out $D/acc 2>$D/err >$D/comp.csv; echo rc=$?; cat $D/err",
             test_sunmc(), test_tmp("dss"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    if (!strstr(out, "rc=0"))
        fail_msg("%s", out);
    assert_non_null(strstr(out, "accuracy against truth_alpha_deg, truth_beta_deg: 808 rows, 0 "
                                "without a compensated angle; arcsec, bands of field angle; spec "
                                "rms <= 10 arcsec (configs/dss.ini)"));
    char row[64];
    snprintf(row, sizeof row, "  %-6s %-12s %8ld ", "total", "0:60", 710L);
    assert_non_null(strstr(out, row));
    errors *e = malloc(sizeof *e);
    read_errors(test_tmp("dss/comp.csv"), 1, 3600, e);
    assert_int_equal(e->n, 808);
    assert_int_equal(check_tsv(test_tmp("dss/acc/accuracy.tsv"), e, two_axes, "rms", 10), 9);
    free(e);
}

/* ESS unit 3 (one axis, deg, bands of |alpha|) without a config: one band
 * from 0 to the largest |truth|, no spec. */
static void ess_validation_one_band(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd,
             "S=%s; D=%s; R=$($S simulate configs/ess_type_a.ini --unit 3 --out $D/sim | grep -o "
             "'calibration.roll_measured_arcsec=[^ ]*') && "
             "$S calibrate --config configs/ess_type_a.ini --set $R $D/sim/campaign.csv --out "
             "$D/cal >/dev/null && $S compensate $D/cal/params.ini $D/sim/validation.csv --out "
             "$D/acc 2>$D/err >$D/comp.csv; echo rc=$?; cat $D/err",
             test_sunmc(), test_tmp("ess"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    if (!strstr(out, "rc=0"))
        fail_msg("%s", out);
    assert_non_null(strstr(out, "accuracy against truth_deg: 3816 rows"));
    assert_non_null(strstr(out, "(one band over the data: --config CONFIG gives its bands and spec)"));
    errors *e = malloc(sizeof *e);
    read_errors(test_tmp("ess/comp.csv"), 0, 1, e);
    static const char *const one[] = {"alpha"};
    assert_int_equal(check_tsv(test_tmp("ess/acc/accuracy.tsv"), e, one, "-", 0), 1);
    /* with the config: its bands of |alpha| and its 54" spec in deg */
    snprintf(cmd, sizeof cmd, "D=%s; { %s compensate $D/cal/params.ini $D/sim/validation.csv "
             "--config configs/ess_type_a.ini --out $D/acc2 >/dev/null; }", test_tmp("ess"),
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "deg, bands of |alpha|; spec rms <= 0.015 deg (configs/ess_type_a.ini)"));
    assert_int_equal(check_tsv(test_tmp("ess/acc2/accuracy.tsv"), e, one, "rms", 0.015), 3);
    free(e);
}

/* Without truth columns: no summary, exit 0; with --out, refused (exit 2,
 * FILE:LINE, nothing written, nothing on stdout). */
static void no_truth_columns(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd,
             "S=%s; D=%s; $S simulate configs/dss.ini --unit 3 --out $D/sim >/dev/null && "
             "$S calibrate --config configs/dss.ini $D/sim/campaign.csv --out $D/cal >/dev/null && "
             "{ $S compensate $D/cal/params.ini $D/sim/campaign.csv 2>&1 >/dev/null; }",
             test_sunmc(), test_tmp("nt"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_null(strstr(out, "accuracy"));
    snprintf(cmd, sizeof cmd, "D=%s; { %s compensate $D/cal/params.ini $D/sim/campaign.csv --out $D/acc "
             ">$D/stdout; }", test_tmp("nt"), test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "campaign.csv:15: no truth columns (truth_alpha_deg, truth_beta_deg) to score"));
    snprintf(cmd, sizeof cmd, "D=%s; test -e $D/acc || test -s $D/stdout", test_tmp("nt"));
    assert_int_not_equal(system(cmd), 0);
}

/* --config of another family, --set without --config, a truth value that
 * is no number: exit 2, each said. */
static void refusals(void **state)
{
    char out[16384], cmd[4096];
    const char *d = test_tmp("rf");
    snprintf(cmd, sizeof cmd,
             "S=%s; D=%s; $S simulate configs/dss.ini --unit 3 --out $D/sim >/dev/null && "
             "$S calibrate --config configs/dss.ini $D/sim/campaign.csv --out $D/cal >/dev/null",
             test_sunmc(), d);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "D=%s; { %s compensate $D/cal/params.ini $D/sim/validation.csv --config "
             "configs/psd.ini >/dev/null; }", d, test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "configs/psd.ini is a psd config, but"));
    snprintf(cmd, sizeof cmd, "D=%s; { %s compensate $D/cal/params.ini $D/sim/validation.csv --set "
             "report.spec_arcsec=5 >/dev/null; }", d, test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "--set needs --config CONFIG"));
    snprintf(cmd, sizeof cmd, "D=%s; awk -F, 'BEGIN{OFS=\",\"} NR==17{$6=\"x\"} {print}' "
             "$D/sim/validation.csv > $D/bad.csv; { %s compensate $D/cal/params.ini $D/bad.csv "
             ">/dev/null; }", d, test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 2);
    assert_non_null(strstr(out, "bad.csv:17:"));
}

/* The spec from --config and --set: a spec below the bands' RMS says "no". */
static void spec_not_met(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd,
             "S=%s; D=%s; $S simulate configs/dss.ini --unit 3 --out $D/sim >/dev/null && "
             "$S calibrate --config configs/dss.ini $D/sim/campaign.csv --out $D/cal >/dev/null && "
             "$S compensate $D/cal/params.ini $D/sim/validation.csv --config configs/dss.ini --set "
             "report.spec_arcsec=4 --set report.spec_statistic=max --out $D/acc >/dev/null 2>&1; "
             "cut -f1,2,9,10,11,12 $D/acc/accuracy.tsv",
             test_sunmc(), test_tmp("sp"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    /* every band's max is above 4 arcsec */
    assert_non_null(strstr(out, "total\t0:60\t10.32"));
    assert_non_null(strstr(out, "\tmax\t4\tno\n"));
    assert_null(strstr(out, "\tyes\n"));
}

/* The PSD's truth comes from its table angles (validation.csv has no truth
 * columns): scored the same way. */
static void psd_truth_from_table_angles(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd,
             "S=%s; D=%s; $S simulate configs/psd.ini --unit 3 --out $D/sim >/dev/null && "
             "$S calibrate --config configs/psd.ini $D/sim/campaign.csv --out $D/cal >/dev/null && "
             "$S compensate $D/cal/params.ini $D/sim/validation.csv --config configs/psd.ini "
             "--out $D/acc 2>$D/err >$D/comp.csv; echo rc=$?; cat $D/err",
             test_sunmc(), test_tmp("psd"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    if (!strstr(out, "rc=0"))
        fail_msg("%s", out);
    assert_non_null(strstr(out, "accuracy against truth_alpha_deg, truth_beta_deg: 72 rows"));
    errors *e = malloc(sizeof *e);
    read_errors(test_tmp("psd/comp.csv"), 1, 3600, e);
    assert_int_equal(e->n, 72);
    assert_int_equal(check_tsv(test_tmp("psd/acc/accuracy.tsv"), e, two_axes, "rms", 360), 9);
    free(e);
}

/* A row the calibrated sensor cannot read (its spot moved off the
 * detector) is counted without a compensated angle and left out. */
static void uncompensated_row_is_counted(void **state)
{
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd,
             "S=%s; D=%s; $S simulate configs/dss.ini --unit 3 --out $D/sim >/dev/null && "
             "$S calibrate --config configs/dss.ini $D/sim/campaign.csv --out $D/cal >/dev/null && "
             "awk -F, 'BEGIN{OFS=\",\"} NR==17{$3=\"99999\"} {print}' $D/sim/validation.csv > $D/v.csv"
             " && $S compensate $D/cal/params.ini $D/v.csv --config configs/dss.ini --out $D/acc "
             "2>$D/err >$D/comp.csv; echo rc=$?; cat $D/err",
             test_sunmc(), test_tmp("miss"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    if (!strstr(out, "rc=0"))
        fail_msg("%s", out);
    assert_non_null(strstr(out, "808 rows, 1 without a compensated angle"));
    errors *e = malloc(sizeof *e);
    read_errors(test_tmp("miss/comp.csv"), 1, 3600, e);
    assert_int_equal(e->skipped, 1);
    assert_int_equal(e->n, 807);
    assert_int_equal(check_tsv(test_tmp("miss/acc/accuracy.tsv"), e, two_axes, "rms", 10), 9);
    free(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dss_validation_scored), cmocka_unit_test(ess_validation_one_band),
        cmocka_unit_test(no_truth_columns),      cmocka_unit_test(refusals),
        cmocka_unit_test(spec_not_met),          cmocka_unit_test(psd_truth_from_table_angles),
        cmocka_unit_test(uncompensated_row_is_counted),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
