/* test_calibrate_drift.c - issue 39 item 3: `calibrate` finds the
 * campaigns of a lab file (its "# source:" blocks) and the drift between
 * them.  A simulated PSD unit read three times on two beta lines, each
 * repeat of each line a campaign:
 *  - as read: the campaigns printed and in campaigns.tsv, no drift;
 *  - one campaign's table angles 2 % too large (a table that lost its
 *    scale): drift warned, that campaign named with a scale change near
 *    -2 % (the fit, which sees it too, takes a little of it);
 *  - a file without "# source:" lines: no campaigns.tsv;
 *  - an ESS campaign three times over, the third's beta = 0 line with
 *    its table scale 0.2 % off: that pass named (every family's drift is
 *    core's, through family_lab.cal_row_error). */
#include "test_util.h"
#include "test_tsv.h"

#include <math.h>
#include <unistd.h>

static char dir[512];

#define P "configs/psd.ini"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    if (test_private_dir(dir, sizeof dir, "caldrift") != 0)
        return -1;
    const char *steps[] = {
        "simulate " P " --unit 3 --quiet --set campaign.repeats=3 --set campaign.beta_deg=-10,10 "
        "--set campaign.alpha_step_deg=1 --out $D/s",
        "true; awk -F, 'BEGIN{OFS=\",\"} /^#/{next} /^alpha/{print; next} "
        "{k=(n++)%3; r[$2\",\"k]=r[$2\",\"k] $0 \"\\n\"} END{for (b=-10;b<=10;b+=20) "
        "for (k=0;k<3;k++) {print \"# source: beta \" b \" repeat \" k; printf \"%s\", "
        "r[b\",\"k]}}' $D/s/campaign.csv > $D/ok.csv",
        "true; awk -F, 'BEGIN{OFS=\",\"} /^# source: beta 10 repeat 2/{d=1} /^#/{print; next} "
        "/^alpha/{print; next} {if (d) $1=$1*1.02; print}' $D/ok.csv > $D/drift.csv",
        /* an ESS unit's campaign three times over: the second with a little
         * output noise, the third with its beta = 0 line's table 0.2 % off */
        "simulate configs/ess_type_a.ini --unit 3 --out $D/es > $D/es.txt",
        "true; awk -F, 'BEGIN{OFS=\",\"} /^#/{next} /^alpha/{h=$0; next} {r[n++]=$0} "
        "END{print h; for (k=0;k<3;k++) {print \"# source: pass \" k; for (i=0;i<n;i++) "
        "{split(r[i],f,\",\"); if (k>0) f[3]=f[3]+0.0004*sin(i*12.9898+k*78.233); "
        "if (k==2 && f[2]==0) f[1]=f[1]*1.002; print f[1],f[2],f[3],f[4]}}}' "
        "$D/es/campaign.csv > $D/ess3.csv"};
    return test_sunmc_steps(dir, steps, 5);
}

static void test_campaigns_no_drift(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " $D/ok.csv --out $D/c1", out, sizeof out), 0);
    assert_non_null(strstr(out, "campaigns (the file's \"# source:\" blocks"));
    assert_non_null(strstr(out, "6 of 6 campaigns repeat another's table line"));
    assert_null(strstr(out, "drift between campaigns"));
    char p[700];
    snprintf(p, sizeof p, "%s/c1/campaigns.tsv", dir);
    tsv *t = tsv_load(p);
    assert_non_null(t);
    assert_int_equal(t->nr, 6);
    for (int r = 0; r < 6; r++) {
        assert_int_equal((int)tsv_num(t, r, "rows"), 41);
        assert_int_equal((int)tsv_num(t, r, "group_campaigns"), 3);
        assert_true(fabs(tsv_num(t, r, "scale_change_pct")) < 0.3);
    }
    tsv_free(t);
}

static void test_drifted_campaign_named(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " $D/drift.csv --out $D/c2", out, sizeof out),
                     0);
    const char *w = strstr(out, "drift between campaigns");
    assert_non_null(w);
    assert_non_null(strstr(w, "beta 10 repeat 2: zero"));
    assert_null(strstr(w, "beta -10 repeat"));
    char p[700];
    snprintf(p, sizeof p, "%s/c2/campaigns.tsv", dir);
    tsv *t = tsv_load(p);
    assert_non_null(t);
    double k = tsv_num(t, 5, "scale_change_pct");
    assert_true(k < -1.4 && k > -2.2);
    assert_string_equal(tsv_str(t, 5, "name"), "beta 10 repeat 2");
    tsv_free(t);
}

static void test_no_sources_no_file(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config " P " $D/s/campaign.csv --out $D/c3", out,
                           sizeof out), 0);
    assert_null(strstr(out, "campaigns (the file's"));
    char p[700];
    snprintf(p, sizeof p, "%s/c3/campaigns.tsv", dir);
    assert_int_not_equal(access(p, F_OK), 0);
}

/* The ESS (core's drift report through its cal_row_error): the pass
 * whose beta = 0 line lost 0.2 % of its table scale is named. */
static void test_ess_pass_named(void **state)
{
    static char out[65536];
    assert_int_equal(sunmc("calibrate --config configs/ess_type_a.ini --set "
                           "$(grep -o 'calibration.roll_measured_arcsec=[^ ]*' $D/es.txt) "
                           "$D/ess3.csv --out $D/ce",
                           out, sizeof out),
                     0);
    const char *w = strstr(out, "drift between campaigns");
    assert_non_null(w);
    assert_non_null(strstr(w, "pass 2: zero"));
    assert_null(strstr(w, "pass 0: zero"));
    char p[700];
    snprintf(p, sizeof p, "%s/ce/campaigns.tsv", dir);
    tsv *t = tsv_load(p);
    assert_non_null(t);
    assert_int_equal(t->nr, 3);
    assert_true(tsv_num(t, 2, "scale_change_pct") < -0.03);
    assert_true(fabs(tsv_num(t, 0, "scale_change_pct")) < 0.01);
    tsv_free(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_campaigns_no_drift),
        cmocka_unit_test(test_drifted_campaign_named),
        cmocka_unit_test(test_no_sources_no_file),
        cmocka_unit_test(test_ess_pass_named),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
