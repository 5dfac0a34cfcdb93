/* test_lab_drift.c - issue 39 item 3: campaigns in one lab file and how
 * much they differ (lab_drift.h).
 *  - three campaigns of one table line, two alike and one with a zero and
 *    a scale change, on a common model error: the odd one's change is
 *    recovered exactly (the median profile is the alike ones'), its shift
 *    is the closed-form RMS of zero + scale theta, the alike ones' ~0;
 *    drift is reported and the odd campaign named;
 *  - the same campaigns with noise only: between far below within, no
 *    drift; within is the noise's standard deviation;
 *  - campaigns on different table lines are not compared (alone);
 *  - rows of weight 0 or with a NaN error are not counted;
 *  - one campaign, or none named: nothing to compare;
 *  - the "# source:" lines of a CSV give each row its campaign, rows
 *    before the first line a campaign "(head)" of their own;
 *  - campaigns.tsv: a header of unique names and a row per campaign. */
#include "test_util.h"

#include "lab.h"
#include "lab_drift.h"
#include "units.h"

#define NC 3
#define NR 801 /* -40 .. 40 deg by 0.1 */
#define N (NC * NR)

typedef struct {
    double a[N], b[N], ea[N], eb[N], w[N];
    int src[N];
    const char *names[NC];
    lab_drift_input in;
} data;

static double uniform(unsigned long *r)
{
    *r = *r * 6364136223846793005UL + 1442695040888963407UL;
    return (double)(*r >> 11) / 9007199254740992.0 - 0.5;
}

/* Campaign c: alpha swept, beta fixed at fixed[c]; error = a common model
 * error + zero[c] + scale[c] alpha + noise (uniform of sd noise_arcsec). */
static void make(data *t, const double *zero_arcsec, const double *scale_pct,
                 const double *fixed_deg, double noise_arcsec)
{
    static const char *const nm[NC] = {"one", "two", "three"};
    unsigned long r = 99;
    for (int c = 0; c < NC; c++) {
        t->names[c] = nm[c];
        for (int j = 0; j < NR; j++) {
            int i = c * NR + j;
            t->a[i] = -40.0 + 0.1 * j;
            t->b[i] = fixed_deg[c];
            double th = t->a[i] * RAD_PER_DEG;
            double e = 50.0 * sin(3 * th) + zero_arcsec[c] + scale_pct[c] / 100 * th * ARCSEC_PER_RAD +
                       noise_arcsec * sqrt(12.0) * uniform(&r);
            t->ea[i] = e / ARCSEC_PER_RAD;
            t->eb[i] = 7.0 / ARCSEC_PER_RAD;
            t->w[i] = 1.0;
            t->src[i] = c;
        }
    }
    t->in = (lab_drift_input){.n = N, .angle_deg = {t->a, t->b}, .error_rad = {t->ea, t->eb},
                              .error_stride = 1, .weight = t->w, .source = t->src,
                              .n_sources = NC, .source_name = t->names};
}

/* RMS over alpha of zero + scale alpha (arcsec), the grid of make. */
static double line_rms(double zero_arcsec, double scale_pct)
{
    double ss = 0;
    for (int j = 0; j < NR; j++) {
        double e = zero_arcsec + scale_pct / 100 * (-40.0 + 0.1 * j) * RAD_PER_DEG * ARCSEC_PER_RAD;
        ss += e * e;
    }
    return sqrt(ss / NR);
}

static void test_one_changed_campaign(void **state)
{
    static data t;
    static lab_drift d;
    const double z[NC] = {0, 0, 300}, k[NC] = {0, 0, -1.0}, f[NC] = {0, 0, 0};
    make(&t, z, k, f, 0.0);
    assert_int_equal(lab_drift_analyse(&t.in, &d), 3);
    assert_int_equal(d.compared, 3);
    assert_int_equal(d.c[2].group, d.c[0].group);
    assert_int_equal(d.c[2].group_size, 3);
    assert_int_equal(d.c[2].axis, 0);
    assert_true(fabs(d.c[2].dzero_arcsec - 300) < 1.0);
    assert_true(fabs(d.c[2].dscale_pct + 1.0) < 1e-3);
    double want = line_rms(300, -1.0);
    assert_true(fabs(d.c[2].shift_arcsec - want) < 0.01 * want);
    assert_true(d.c[0].shift_arcsec < 1.0 && d.c[1].shift_arcsec < 1.0);
    /* the alike ones' own lines: the common error's line only */
    assert_true(fabs(d.c[0].zero_arcsec - d.c[1].zero_arcsec) < 1e-9);
    assert_true(fabs(d.c[2].scale_pct - d.c[0].scale_pct + 1.0) < 1e-9);
    assert_true(d.drift);
    assert_true(fabs(d.between_arcsec - want / sqrt(3.0)) < 0.02 * want);
    assert_non_null(strstr(d.note, "three: zero +300 arcsec, scale -1.00 %"));
    assert_null(strstr(d.note, "one:"));
}

static void test_noise_only_no_drift(void **state)
{
    static data t;
    static lab_drift d;
    const double z[NC] = {0, 0, 0}, k[NC] = {0, 0, 0}, f[NC] = {5, 5, 5};
    make(&t, z, k, f, 100.0);
    lab_drift_analyse(&t.in, &d);
    assert_int_equal(d.compared, 3);
    assert_false(d.drift);
    /* within: the noise less the median profile's share of it */
    assert_true(d.within_arcsec > 60 && d.within_arcsec < 110);
    assert_true(d.between_arcsec < 0.2 * d.within_arcsec);
    assert_null(strstr(d.note, "drifted"));
    assert_true(fabs(d.c[0].fixed_deg - 5) < 1e-12);
}

static void test_other_lines_alone(void **state)
{
    static data t;
    static lab_drift d;
    const double z[NC] = {0, 0, 300}, k[NC] = {0, 0, 1}, f[NC] = {-10, 0, 10};
    make(&t, z, k, f, 0.0);
    lab_drift_analyse(&t.in, &d);
    assert_int_equal(d.compared, 0);
    assert_false(d.drift);
    for (int c = 0; c < NC; c++) {
        assert_true(isnan(d.c[c].shift_arcsec));
        assert_int_equal(d.c[c].group_size, 1);
    }
    assert_non_null(strstr(d.note, "none sweeping the same table line"));
    /* just inside the same line (0.05 deg apart) and just outside */
    const double in[NC] = {0, 0.05, 0.05}, out[NC] = {0, 0.051, 0.051};
    make(&t, z, k, in, 0.0);
    lab_drift_analyse(&t.in, &d);
    assert_int_equal(d.compared, 3);
    make(&t, z, k, out, 0.0);
    lab_drift_analyse(&t.in, &d);
    assert_int_equal(d.c[1].group, d.c[2].group);
    assert_true(d.c[0].group != d.c[1].group);
    assert_int_equal(d.compared, 2);
}

static void test_rows_not_used(void **state)
{
    static data t;
    static lab_drift d;
    const double z[NC] = {0, 0, 0}, k[NC] = {0, 0, 0}, f[NC] = {0, 0, 0};
    make(&t, z, k, f, 0.0);
    t.w[0] = 0.0;
    t.ea[1] = NAN;
    t.eb[NR + 5] = NAN;
    lab_drift_analyse(&t.in, &d);
    assert_int_equal(d.c[0].n, NR - 2);
    assert_int_equal(d.c[1].n, NR - 1);
    assert_int_equal(d.c[2].n, NR);
    assert_true(isfinite(d.between_arcsec));
}

static void test_nothing_to_compare(void **state)
{
    static data t;
    static lab_drift d;
    const double z[NC] = {0}, k[NC] = {0}, f[NC] = {0};
    make(&t, z, k, f, 0.0);
    t.in.source = NULL;
    assert_int_equal(lab_drift_analyse(&t.in, &d), 1);
    assert_non_null(strstr(d.note, "one campaign"));
    t.in.source = t.src;
    t.in.n_sources = 1;
    assert_int_equal(lab_drift_analyse(&t.in, &d), 1);
    t.in.n_sources = 2; /* two named, rows of "three" counted in the last */
    for (int i = 0; i < N; i++)
        t.src[i] = t.src[i] > 1 ? 1 : t.src[i];
    assert_int_equal(lab_drift_analyse(&t.in, &d), 2);
    assert_int_equal(d.c[1].n, 2 * NR);
    assert_string_equal(d.c[1].name, "two");
    /* more campaigns than the report holds: the rest together, and named so */
    for (int i = 0; i < N; i++)
        t.src[i] = i % NR < NR / 2 ? 0 : LAB_DRIFT_MAX_CAMPAIGNS + 5;
    static const char *many[LAB_DRIFT_MAX_CAMPAIGNS + 6];
    for (int j = 0; j < LAB_DRIFT_MAX_CAMPAIGNS + 6; j++)
        many[j] = "x";
    t.in.source_name = many;
    t.in.n_sources = LAB_DRIFT_MAX_CAMPAIGNS + 6;
    assert_int_equal(lab_drift_analyse(&t.in, &d), LAB_DRIFT_MAX_CAMPAIGNS);
    assert_true(d.truncated);
    assert_string_equal(d.c[LAB_DRIFT_MAX_CAMPAIGNS - 1].name, "(campaigns 64 to 70 together)");
    assert_int_equal(d.c[LAB_DRIFT_MAX_CAMPAIGNS - 1].n, N - NC * (NR / 2));
    t.in.n_sources = LAB_DRIFT_MAX_CAMPAIGNS; /* exactly as many: none together */
    for (int i = 0; i < N; i++)
        t.src[i] = t.src[i] ? LAB_DRIFT_MAX_CAMPAIGNS - 1 : 0;
    lab_drift_analyse(&t.in, &d);
    assert_false(d.truncated);
    assert_string_equal(d.c[LAB_DRIFT_MAX_CAMPAIGNS - 1].name, "x");
}

static void test_sources_of_a_csv(void **state)
{
    char dir[512], path[700];
    assert_int_equal(test_private_dir(dir, sizeof dir, "labdrift"), 0);
    snprintf(path, sizeof path, "%s/lab.csv", dir);
    assert_int_equal(test_write_file(path, "# made by hand\n"
                                           "x,y\n"
                                           "1,0\n"
                                           "# source: first file.txt  \n"
                                           "2,0\n"
                                           "3,0\n"
                                           "  # source:second\n"
                                           "# a comment\n"
                                           "4,0\n"),
                     0);
    static const char *const names[] = {"x", "y", "weight", NULL};
    lab_columns d;
    char err[256];
    if (lab_columns_read(path, names, 1, "test", &d, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(d.n, 4);
    assert_int_equal(d.n_sources, 3);
    assert_string_equal(d.source_name[0], "(head)");
    assert_string_equal(d.source_name[1], "first file.txt");
    assert_string_equal(d.source_name[2], "second");
    const int want[4] = {0, 1, 1, 2};
    for (int i = 0; i < 4; i++)
        assert_int_equal(d.source[i], want[i]);
    lab_columns_free(&d);
    assert_int_equal(test_write_file(path, "x,y\n1,0\n2,0\n"), 0);
    assert_int_equal(lab_columns_read(path, names, 1, "test", &d, err, sizeof err), 0);
    assert_int_equal(d.n_sources, 0);
    assert_null(d.source);
    lab_columns_free(&d);
}

/* 1 when the first line's tab-separated names are all different. */
static int header_unique(const char *buf)
{
    char names[32][64];
    int n = 0;
    const char *p = buf;
    while (*p && *p != '\n' && n < 32) {
        size_t k = strcspn(p, "\t\n");
        snprintf(names[n], sizeof names[n], "%.*s", (int)k, p);
        for (int j = 0; j < n; j++)
            if (strcmp(names[j], names[n]) == 0)
                return 0;
        n++;
        p += k + (p[k] == '\t');
    }
    return n > 1;
}

static void test_campaigns_tsv(void **state)
{
    static data t;
    static lab_drift d;
    const double z[NC] = {0, 0, 300}, k[NC] = {0, 0, -1.0}, f[NC] = {0, 0, 0};
    make(&t, z, k, f, 0.0);
    lab_drift_analyse(&t.in, &d);
    char *buf = NULL;
    size_t len = 0;
    FILE *f2 = open_memstream(&buf, &len);
    assert_int_equal(lab_drift_write(f2, &d), 0);
    fclose(f2);
    assert_true(header_unique(buf));
    int lines = 0;
    for (char *p = buf; *p; p++)
        lines += *p == '\n';
    assert_int_equal(lines, 1 + NC);
    assert_non_null(strstr(buf, "\n3\tthree\t801\talpha\t0\t-40\t40\t1\t3\t"));
    free(buf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_one_changed_campaign), cmocka_unit_test(test_noise_only_no_drift),
        cmocka_unit_test(test_other_lines_alone),    cmocka_unit_test(test_rows_not_used),
        cmocka_unit_test(test_nothing_to_compare),   cmocka_unit_test(test_sources_of_a_csv),
        cmocka_unit_test(test_campaigns_tsv),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
