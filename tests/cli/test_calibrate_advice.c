/* test_calibrate_advice.c - calibrate's warnings say what is specific to
 * the data: correlated parameters grouped by their known cause with the
 * campaign's own numbers (each pair with its correlation, once), the
 * ESS installation roll left at its default, a held-out error more than
 * 3 times the in-sample one (both sides of the limit). */
#include "test_util.h"
#include "calreport.h"

static void set_params(calreport *r, int np, const char *const *names)
{
    calreport_init(r, "toy", "toy");
    r->np = np;
    for (int i = 0; i < np; i++) {
        snprintf(r->name[i], sizeof r->name[i], "%s", names[i]);
        r->corr[i][i] = 1;
    }
}

static void set_corr(calreport *r, int i, int j, double v)
{
    r->corr[i][j] = r->corr[j][i] = v;
}

/* Pairs inside a cause's group make one warning naming each pair with its
 * correlation and the cause; a pair outside every group gets the generic
 * one; a pair at the threshold is not flagged. */
static void test_correlations_grouped_by_cause(void **state)
{
    static const char *const names[] = {"p", "q", "r", "s", "t"};
    calreport *r = calloc(1, sizeof *r);
    set_params(r, 5, names);
    set_corr(r, 0, 1, 0.99);
    set_corr(r, 0, 2, -0.985);
    set_corr(r, 1, 2, 0.98); /* at the threshold: not flagged */
    set_corr(r, 3, 4, 0.995);
    const calreport_corr_cause causes[] = {
        {{"p", "q", "r", NULL}, "WHY-PQR", "DO-PQR"},
        {{"s", "x", NULL}, "WHY-S", "DO-S"},
    };
    calreport_check_correlations_explained(r, 0.98, causes, 2);
    assert_int_equal(r->nw, 2);
    assert_non_null(strstr(r->w[0].reason, "p and q +0.9900, p and r -0.9850; why: WHY-PQR"));
    assert_null(strstr(r->w[0].reason, "q and r"));
    assert_string_equal(r->w[0].action, "DO-PQR");
    assert_non_null(strstr(r->w[1].reason, "parameters s and t are nearly unidentifiable: "
                                           "correlation +0.9950"));
    assert_null(strstr(r->w[1].reason, "WHY-S"));
    free(r);
}

static void test_crossval_ratio_limit(void **state)
{
    calreport *r = calloc(1, sizeof *r);
    calreport_init(r, "toy", "toy");
    r->n_folds = 2;
    snprintf(r->fold[0].label, sizeof r->fold[0].label, "A");
    snprintf(r->fold[1].label, sizeof r->fold[1].label, "B");
    r->fold[0].ok = r->fold[1].ok = 1;
    r->fold[0].rms_in_arcsec = 10;
    r->fold[0].rms_out_arcsec = 12;
    r->fold[1].rms_in_arcsec = 9;
    r->fold[1].rms_out_arcsec = 50;
    r->cv_rms_in_arcsec = 10;
    r->cv_rms_out_arcsec = 29.9;
    calreport_check_crossval(r, CALREPORT_CV_RATIO_WARN);
    assert_int_equal(r->nw, 0);
    r->cv_rms_out_arcsec = 30.1;
    calreport_check_crossval(r, CALREPORT_CV_RATIO_WARN);
    assert_int_equal(r->nw, 1);
    assert_non_null(strstr(r->w[0].reason, "the held-out error 30.10 arcsec is 3.0 times the "
                                           "in-sample 10.00"));
    assert_non_null(strstr(r->w[0].reason, "worst: B held out, 50.00 against 9.00"));
    free(r);
}

/* A fold whose refit is worse conditioned than the whole fit by more than
 * CALREPORT_FOLD_COND_WARN is named, with its condition number; just below
 * the factor it is not (both sides of the limit). */
static void test_fold_condition_limit(void **state)
{
    calreport *r = calloc(1, sizeof *r);
    calreport_init(r, "toy", "toy");
    r->n_folds = 3;
    const char *labels[3] = {"A", "B", "C"};
    for (int k = 0; k < 3; k++) {
        snprintf(r->fold[k].label, sizeof r->fold[k].label, "%s", labels[k]);
        r->fold[k].ok = 1;
        r->fold[k].cond = 100;
    }
    r->cond_jacobian = 40;
    r->fold[1].cond = 0.999 * CALREPORT_FOLD_COND_WARN * 40;
    calreport_check_fold_condition(r, CALREPORT_FOLD_COND_WARN);
    assert_int_equal(r->nw, 0);
    r->fold[1].cond = 1.001 * CALREPORT_FOLD_COND_WARN * 40;
    r->fold[2].cond = NAN; /* a model without a Jacobian: never flagged */
    calreport_check_fold_condition(r, CALREPORT_FOLD_COND_WARN);
    assert_int_equal(r->nw, 1);
    assert_non_null(strstr(r->w[0].reason, "refit without B (4e+04) nearly singular"));
    assert_non_null(strstr(r->w[0].reason, "up to 1e+03 times the fit on all the data's (40)"));
    assert_null(strstr(r->w[0].reason, "A ("));
    r->fold[1].ok = 0; /* a failed refit has no condition to speak of */
    r->nw = 0;
    calreport_check_fold_condition(r, CALREPORT_FOLD_COND_WARN);
    assert_int_equal(r->nw, 0);
    free(r);
}

/* `simulate` unit of cfg (with sets) into a private dir named name, then
 * `calibrate` its campaign with the same sets; stdout+stderr in out. */
static void sim_calibrate(const char *name, const char *cfg, int unit, const char *sets,
                          char *out, size_t len)
{
    char args[2048];
    const char *d = test_tmp(name);
    snprintf(args, sizeof args,
             "simulate %s --unit %d %s --out $D --quiet > /dev/null && %s calibrate --config %s "
             "--set calibration.priors=off %s $D/campaign.csv",
             cfg, unit, sets, test_sunmc(), cfg, sets);
    assert_int_equal(test_sunmc_in(d, args, out, len), 0);
}

/* The shipped ESS campaign (beta -30, 0, 30): one warning for b, c and the
 * simulator's tilt, with 1 - cos 30 deg; the roll left at its default is
 * warned about, and not once it is given (even as 0). */
static void test_ess_default_campaign_advice(void **state)
{
    static char out[65536];
    char args[2048];
    sim_calibrate("ess_sim", "configs/ess_type_a.ini", 1, "", out, sizeof out);
    assert_non_null(strstr(out, "b and fit_sun_y_arcsec -0.99"));
    assert_non_null(strstr(out, "c and fit_sun_y_arcsec +0.98"));
    assert_non_null(strstr(out, "1 - cos(beta) = 0.13 at this campaign's widest |beta| = 30 deg"));
    assert_null(strstr(out, "widen the campaign (a wider angle range"));
    /* without the beta = 0 line, the +-30 lines alone cannot tell b, c
     * and the simulator's tilt apart (symmetric lines: 1 - cos is the
     * same on both), so that fold's refit is named, and only that one */
    assert_non_null(strstr(out, "refit without beta = 0 deg ("));
    assert_null(strstr(out, "refit without beta = -30"));
    assert_non_null(strstr(out, "calibration.roll_measured_arcsec is left at its default (0 "
                                "arcsec)"));
    snprintf(args, sizeof args,
             "calibrate --config configs/ess_type_a.ini --set calibration.roll_measured_arcsec=0 "
             "$D/campaign.csv");
    assert_int_equal(test_sunmc_in(test_tmp("ess_sim"), args, out, sizeof out), 0);
    assert_null(strstr(out, "roll_measured_arcsec is left"));
}

/* A campaign of alpha >= 0 only: holding a beta line out multiplies the
 * error (4.2 times with the noise drawn before issue 27's stream change,
 * 9.6 with today's), and the report says so.  At 0.8 deg over 0..62 (the shipped 0.7
 * deg over 0..61.95 gives 3.1 times, too close to the 3x threshold for a
 * test of the warning). */
static void test_ess_half_campaign_crossval_flagged(void **state)
{
    static char out[65536];
    sim_calibrate("ess_half", "configs/ess_type_a.ini", 3,
                  "--set campaign.alpha_min_deg=0 --set campaign.alpha_max_deg=62 "
                  "--set campaign.alpha_step_deg=0.8 --set tolerance.dial_tilt_deg=0",
                  out, sizeof out);
    assert_non_null(strstr(out, "the held-out error 235.62 arcsec is 9.6 times the in-sample "
                                "24.64 (above 3x)"));
    /* the report to a file: its warnings on stderr too */
    assert_int_equal(test_sunmc_in(test_tmp("ess_half"),
                                   "calibrate --config configs/ess_type_a.ini --set "
                                   "calibration.priors=off --set "
                                   "campaign.alpha_min_deg=0 $D/campaign.csv > $D/report.txt "
                                   "2> $D/err.txt; cat $D/err.txt",
                                   out, sizeof out),
                     0);
    assert_non_null(strstr(out, "sunmc calibrate: WARNING: the held-out error 235.62 arcsec"));
}

/* The DSS's default campaign: height, glass thickness and index, once,
 * with the campaign's corner field angle. */
static void test_dss_default_campaign_advice(void **state)
{
    static char out[65536];
    sim_calibrate("dss_sim", "configs/dss.ini", 1, "", out, sizeof out);
    assert_non_null(strstr(out, "fit_dh_px and fit_glass_thickness_um +0.98"));
    assert_non_null(strstr(out, "fit_dh_px and fit_glass_index +0.99"));
    assert_non_null(strstr(out, "this campaign reaches 68 deg of field angle at its corners"));
    assert_null(strstr(out, "widen the campaign (a wider angle range"));
    assert_null(strstr(out, "refit without")); /* every quadrant's refit is determined */
}

/* One DSS reading far beyond the detector, at a tiny weight: the fit
 * stands, the reading cannot be compensated, and the report counts it
 * (it was left out of the band statistics without a word). */
static void test_dss_uncompensated_counted(void **state)
{
    static char out[65536];
    char args[2048];
    const char *d = test_tmp("dss_far");
    snprintf(args, sizeof args,
             "simulate configs/dss.ini --unit 1 --out $D --quiet > /dev/null && "
             "awk -F, 'BEGIN{OFS=\",\"} /^#/||/^b1/{print;next} $5>0 && !k {$3=1e7; $4=1e7; "
             "$5=1e-12; k=1} {print}' $D/campaign.csv > $D/far.csv && "
             "%s calibrate --config configs/dss.ini $D/far.csv",
             test_sunmc());
    assert_int_equal(test_sunmc_in(d, args, out, sizeof out), 0);
    assert_non_null(strstr(out, "1 readings could not be compensated with the fitted model"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_correlations_grouped_by_cause),
        cmocka_unit_test(test_crossval_ratio_limit),
        cmocka_unit_test(test_fold_condition_limit),
        cmocka_unit_test(test_ess_default_campaign_advice),
        cmocka_unit_test(test_ess_half_campaign_crossval_flagged),
        cmocka_unit_test(test_dss_default_campaign_advice),
        cmocka_unit_test(test_dss_uncompensated_counted),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
