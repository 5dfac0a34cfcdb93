/* test_compensate_strict.c - issue 36 rule 6: compensate reads params.ini
 * strictly.  Every refusal is of a params.ini a real `calibrate` wrote for
 * a `simulate`d unit, edited here with sed/awk: FILE:LINE, exit 2, nothing
 * written (each used to be read laxly, exit 0):
 *   - a whole number that is not one (an order 2.5 read as 2, 3.0, a
 *     detector side, data_rows, pilot_units);
 *   - a coefficient beyond the order (the PSD's and the DSS's polynomial);
 *   - an unknown key in any section of any family, with a did-you-mean;
 *   - an unknown section;
 *   - a model line naming another model than the file holds, or one the
 *     family does not have;
 *   - the writing version: newer major refused, newer minor or patch read
 *     with a warning, older or equal read, malformed or missing refused.
 * And every params.ini calibrate writes, for every family and model, is
 * read back and compensates its unit's validation readings. */
#include "test_util.h"

static char dir[512];

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

/* Calibrations (directory, sim directory, config and sets). */
static const struct {
    const char *cal, *sim, *args;
} cals[] = {
    {"ce", "se", "--config configs/ess_type_a.ini"},
    {"cx", "se", "--config configs/ess_type_a.ini --set calibration.model=extended"},
    {"cy", "se", "--config configs/ess_type_a.ini --set calibration.sun_y=measured"},
    {"cel", "se", "--config configs/ess_type_a.ini --set calibration.model=spline "
                  "--set calibration.max_residual_ratio=1000"},
    {"ceh", "se", "--config configs/ess_type_a.ini --set calibration.model=hybrid"},
    {"ceb", "se", "--config configs/ess_type_a.ini --set calibration.model=table "
                  "--set calibration.max_residual_ratio=1000"},
    {"cd", "sd", "--config configs/dss.ini"},
    {"cdp", "sd", "--config configs/dss.ini --set calibration.model=polynomial"},
    {"cds", "sd", "--config configs/dss.ini --set calibration.sun=measured"},
    {"cdt", "sd", "--config configs/dss.ini --set calibration.fit_detector_tilt=on"},
    {"cdl", "sd", "--config configs/dss.ini --set calibration.model=spline"},
    {"cdh", "sd", "--config configs/dss.ini --set calibration.model=hybrid"},
    {"cdb", "sd", "--config configs/dss.ini --set calibration.model=table "
                  "--set calibration.max_residual_ratio=1000"},
    {"cp", "sp", "--config configs/psd.ini"},
    {"ct", "sp", "--config configs/psd.ini --set calibration.fit_tilt=on"},
    {"cf", "sp", "--config configs/psd.ini --set calibration.model=polynomial "
                 "--set calibration.poly_form=fss20"},
    {"cq", "sq", "--config configs/psd_14og.ini"},
    {"cs", "sp", "--config configs/psd.ini --set calibration.model=spline"},
    {"ch", "sp", "--config configs/psd.ini --set calibration.model=hybrid"},
    {"cl", "sp", "--config configs/psd.ini --set calibration.model=table"},
};
#define N_CALS (sizeof cals / sizeof cals[0])

static int setup(void **state)
{
    (void)state;
    if (test_private_dir(dir, sizeof dir, "strict") != 0)
        return -1;
    static const char *const sims[] = {
        "simulate configs/ess_type_a.ini --unit 3 --quiet --out $D/se",
        "simulate configs/dss.ini --unit 3 --quiet --out $D/sd",
        "simulate configs/psd.ini --unit 3 --quiet --out $D/sp",
        "simulate configs/psd_14og.ini --unit 2 --quiet --out $D/sq"};
    char out[16384], args[1024];
    for (size_t i = 0; i < sizeof sims / sizeof *sims; i++)
        if (sunmc(sims[i], out, sizeof out) != 0) {
            fprintf(stderr, "%s: %s\n", sims[i], out);
            return -1;
        }
    for (size_t i = 0; i < N_CALS; i++) {
        snprintf(args, sizeof args, "calibrate %s $D/%s/campaign.csv --quiet --out $D/%s",
                 cals[i].args, cals[i].sim, cals[i].cal);
        if (sunmc(args, out, sizeof out) != 0) {
            fprintf(stderr, "%s: %s\n", args, out);
            return -1;
        }
    }
    return 0;
}

/* The sim directory whose validation.csv calibration cal compensates. */
static const char *sim_of(const char *cal)
{
    for (size_t i = 0; i < N_CALS; i++)
        if (strcmp(cals[i].cal, cal) == 0)
            return cals[i].sim;
    return "sp";
}

/* params.ini of cal edited by the shell command edit (reading $IN,
 * writing $OUT): compensate's exit status, its stdout+stderr in out
 * (stdout to `to`, when not NULL). */
static int edited(const char *cal, const char *edit, const char *to, char *out, size_t len)
{
    char args[2048];
    snprintf(args, sizeof args, "true; IN=$D/%s/params.ini; OUT=$D/edited.ini; %s && { %s "
             "compensate $OUT $D/%s/validation.csv%s%s; }",
             cal, edit, test_sunmc(), sim_of(cal), to ? " > " : "", to ? to : "");
    return sunmc(args, out, len);
}

/* ... refused with `says`, nothing written. */
static void refused(const char *cal, const char *edit, const char *says)
{
    char out[8192];
    int rc = edited(cal, edit, NULL, out, sizeof out);
    if (rc != 2 || !strstr(out, says) || strstr(out, "compensated_"))
        fail_msg("%s: %s: exit %d, want 2 and '%s': %s", cal, edit, rc, says, out);
}

/* ... read (exit 0), with `warns` on stderr (NULL: no message at all). */
static void read_ok(const char *cal, const char *edit, const char *warns)
{
    char out[8192];
    int rc = edited(cal, edit, "$D/read.csv", out, sizeof out);
    int said = 0; /* a message other than the accuracy against the truth columns */
    for (const char *m = strstr(out, "sunmc compensate:"); m; m = strstr(m + 1, "sunmc compensate:"))
        said |= strncmp(m, "sunmc compensate: accuracy against", 34) != 0;
    if (rc != 0 || (warns ? !strstr(out, warns) : said))
        fail_msg("%s: %s: exit %d, want 0 and %s%s: %s", cal, edit, rc,
                 warns ? "warning " : "no message", warns ? warns : "", out);
}

static void order_must_be_whole(void **state)
{
    (void)state;
    refused("cq", "sed 's/^order = 3/order = 2.5/' $IN > $OUT",
            "edited.ini:31: key polynomial.order: '2.5' is not a whole number");
    /* whole numbers are written as digits: 3.0 and 3e0 are not */
    refused("cq", "sed 's/^order = 3/order = 3.0/' $IN > $OUT",
            "edited.ini:31: key polynomial.order: '3.0' is not a whole number");
    refused("cdp", "sed 's/^order  *= 3 /order = 3e0 /' $IN > $OUT",
            "key design.order: '3e0' is not a whole number");
    refused("cdp", "sed 's/^order  *= 3 /order = 2.5 /' $IN > $OUT",
            "key design.order: '2.5' is not a whole number");
    refused("cd", "sed 's/^detector_px  *= 2048/detector_px = 2048.5/' $IN > $OUT",
            "key design.detector_px: '2048.5' is not a whole number");
    refused("ce", "sed 's/^data_rows = 534/data_rows = 534.5/' $IN > $OUT",
            "key calibration.data_rows: '534.5' is not a whole number");
    refused("cd", "sed 's/^pilot_units  *= 48/pilot_units = 48.5/' $IN > $OUT",
            "key prior.pilot_units: '48.5' is not a whole number");
    /* the edges, as calibrate writes them, are read */
    read_ok("cq", "cp $IN $OUT", NULL);
    read_ok("cdp", "cp $IN $OUT", NULL);
}

static void coefficients_beyond_order(void **state)
{
    (void)state;
    refused("cq", "sed 's/^order = 3/order = 2/' $IN > $OUT",
            "unknown key polynomial.tana_x3y0: not a term of order 2 (full): a coefficient "
            "beyond the order");
    refused("cq", "(cat $IN; echo 'tana_x4y0 = 1') > $OUT",
            "unknown key polynomial.tana_x4y0: not a term of order 3");
    refused("cdp", "sed 's/^order  *= 3 /order = 2 /' $IN > $OUT",
            "unknown key parameters.ca_6: not a term of order 2 (ca_0, cb_0 .. ca_5, cb_5): a "
            "coefficient beyond the order");
    refused("cdp", "(cat $IN; echo 'cb_10 = 1') > $OUT",
            "unknown key parameters.cb_10: not a term of order 3 (ca_0, cb_0 .. ca_9, cb_9)");
}

static void unknown_parameter_key(void **state)
{
    (void)state;
    refused("cp", "awk '{ print } /^dark4_raw/ { print \"foo_um = 1\" }' $IN > $OUT",
            "edited.ini:45: unknown key parameters.foo_um");
    refused("ce", "sed 's/^ks_deg /ks_dg /' $IN > $OUT",
            "unknown key parameters.ks_dg (did you mean ks_deg?)");
    refused("cd", "sed 's/^fit_dy_px /fit_dy_pix /' $IN > $OUT",
            "unknown key parameters.fit_dy_pix (did you mean fit_dy_px?)");
    /* the key that tells the model apart: the model line is then doubted */
    refused("cd", "sed 's/^fit_dx_px /fit_dx_pix /' $IN > $OUT",
            "model = dss_physical, but the file has no parameters.fit_dx_px");
    refused("cdp", "sed 's/^ca_3 /ca_x /' $IN > $OUT", "unknown key parameters.ca_x");
}

/* One unknown key in each section calibrate writes, family by family. */
static void unknown_key_every_section(void **state)
{
    (void)state;
    static const struct {
        const char *cal, *after, *key, *says;
    } k[] = {
        {"ce", "^\\[calibration\\]", "sensr = ess", "unknown key calibration.sensr (did you mean sensor?)"},
        {"ce", "^\\[design\\]", "theta0_dg = 2", "unknown key design.theta0_dg (did you mean theta0_deg?)"},
        {"ce", "^\\[fixed\\]", "roll_measured_arcsecs = 0", "unknown key fixed.roll_measured_arcsecs (did you mean roll_measured_arcsec?)"},
        {"ce", "^\\[derived\\]", "t_rd = 0", "unknown key derived.t_rd (did you mean t_rad?)"},
        {"ce", "^\\[prior\\]", "a_men = 1", "unknown key prior.a_men (did you mean a_mean?)"},
        {"cx", "^\\[parameters\\]", "k1s_dg = 0", "unknown key parameters.k1s_dg (did you mean k1s_deg?)"},
        {"cy", "^\\[fixed\\]", "fit_sun_y_arcsec = 0", "unknown key fixed.fit_sun_y_arcsec"},
        {"cd", "^\\[design\\]", "pixel_mm = 0.0055", "unknown key design.pixel_mm"},
        {"cd", "^\\[prior\\]", "fit_dz_px_mean = 0", "unknown key prior.fit_dz_px_mean (did you mean fit_dx_px_mean?)"},
        {"cdp", "^\\[design\\]", "h_nom_mm = 3", "unknown key design.h_nom_mm"},
        {"cdp", "^\\[design\\]", "mount = aligned", "unknown key design.mount"},
        {"cp", "^\\[design\\]", "gap_mm = 0.04", "unknown key design.gap_mm (did you mean gap_um?)"},
        {"cp", "^\\[campaign\\]", "table_beta_sgn = plus", "unknown key campaign.table_beta_sgn (did you mean table_beta_sign?)"},
        {"cq", "^\\[polynomial\\]", "scales = 1", "unknown key polynomial.scales (did you mean scale?)"},
    };
    char edit[512];
    for (size_t i = 0; i < sizeof k / sizeof *k; i++) {
        snprintf(edit, sizeof edit, "awk '{ print } /%s/ { print \"%s\" }' $IN > $OUT",
                 k[i].after, k[i].key);
        refused(k[i].cal, edit, k[i].says);
    }
}

static void unknown_section(void **state)
{
    (void)state;
    refused("cp", "sed 's/^\\[campaign\\]/[campain]/' $IN > $OUT",
            "unknown section [campain] (key table_order): a psd_physical params.ini has the "
            "sections calibration design campaign parameters prior (did you mean campaign?)");
    refused("ce", "(cat $IN; printf '[fitted]\\nk = 1\\n') > $OUT", "unknown section [fitted]");
    /* another model's section: the PSD's physical file with a polynomial */
    refused("cp", "(cat $IN; printf '[polynomial]\\nform = full\\n') > $OUT",
            "unknown section [polynomial] (key form): a psd_physical params.ini has");
    refused("cd", "(cat $IN; printf '[fixed]\\nd = 1\\n') > $OUT",
            "unknown section [fixed] (key d): a dss_physical params.ini has");
}

static void model_line_names_another_model(void **state)
{
    (void)state;
    refused("ce", "sed 's/^model = ess_eq12_finecode/model = ess_extended/' $IN > $OUT",
            "edited.ini:7: model = ess_extended, but the file has no parameters.ks_cos4_deg, "
            "which every ess_extended params.ini has");
    refused("cx", "sed 's/^model = ess_extended/model = ess_eq12_finecode/' $IN > $OUT",
            "edited.ini:7: model = ess_eq12_finecode, but the file holds the ess_extended model "
            "(parameters.ks_cos4_deg at line");
    refused("cd", "sed 's/^model = dss_physical/model = dss_polynomial/' $IN > $OUT",
            "edited.ini:7: model = dss_polynomial, but the file holds the dss_physical model "
            "(parameters.fit_dx_px at line");
    refused("cdp", "sed 's/^model = dss_polynomial/model = dss_physical/' $IN > $OUT",
            "edited.ini:7: model = dss_physical, but the file holds the dss_polynomial model "
            "(design.order at line");
    refused("cp", "sed 's/^model = psd_physical/model = psd_polynomial/' $IN > $OUT",
            "edited.ini:6: model = psd_polynomial, but the file holds the psd_physical model "
            "(parameters.dx_um at line");
    refused("cq", "sed 's/^model = psd_polynomial/model = psd_physical/' $IN > $OUT",
            "edited.ini:6: model = psd_physical, but the file holds the psd_polynomial model "
            "(polynomial.order at line");
    /* issue 39: the hybrid holds the physical model's parameters and its
     * correction; either model line on the other's file is caught */
    refused("ch", "sed 's/^model = psd_hybrid/model = psd_physical/' $IN > $OUT",
            "edited.ini:6: model = psd_physical, but the file holds the psd_hybrid model "
            "(correction.breakpoints at line");
    refused("cp", "sed 's/^model = psd_physical/model = psd_hybrid/' $IN > $OUT",
            "edited.ini:6: model = psd_hybrid, but the file has no correction.breakpoints");
    refused("cs", "sed 's/^model = psd_spline/model = psd_polynomial/' $IN > $OUT",
            "edited.ini:6: model = psd_polynomial, but the file holds the psd_spline model "
            "(spline.breakpoints at line");
    refused("cs", "sed 's/^c1_0 *= [^ ]* /c1_0 = /' $IN > $OUT",
            "key spline.c1_0");
    refused("ceh", "sed 's/^model = ess_hybrid/model = ess_eq12_finecode/' $IN > $OUT",
            "model = ess_eq12_finecode, but the file holds the ess_hybrid model "
            "(correction.breakpoints at line");
    refused("ceb", "sed 's/^nodes .*/nodes = 300/' $IN > $OUT", "table.nodes");
    refused("cel", "sed 's/^breakpoints .*/breakpoints = 1/' $IN > $OUT", "spline.breakpoints");
    refused("cdh", "sed 's/^model = dss_hybrid/model = dss_physical/' $IN > $OUT",
            "model = dss_physical, but the file holds the dss_hybrid model "
            "(correction.breakpoints at line");
    refused("cdl", "sed 's/^model = dss_spline/model = dss_table/' $IN > $OUT",
            "model = dss_table, but the file holds the dss_spline model (spline.breakpoints at "
            "line");
    refused("cdb", "sed 's/^dims .*/dims = 0/' $IN > $OUT", "table.dims");
    refused("cdl", "sed 's/^smoothing .*/smoothing = -1/' $IN > $OUT", "spline.smoothing");
    refused("cl", "sed 's/^model = psd_table/model = psd_spline/' $IN > $OUT",
            "edited.ini:6: model = psd_spline, but the file holds the psd_table model "
            "(table.nodes at line");
    refused("cl", "sed 's/^nodes *= .*/nodes = 6/' $IN > $OUT", "table.nodes");
    refused("cl", "sed 's/^v1_0 *= [^ ]* /v1_0 = /' $IN > $OUT", "key table.v1_0");
    refused("cl", "sed 's/^field_cells *=.*/field_cells = 0/' $IN > $OUT", "table.field_cells");
    refused("cl", "sed 's/^hi_1 *=.*/hi_1 = -1/' $IN > $OUT", "table.hi_1");
    refused("cl", "sed 's/^lo_0 .*/&\\nstep_0 = 1/' $IN > $OUT", "table.step_0");
    refused("cp", "sed 's/^polarity .*/polarity = inverse/' $IN > $OUT",
            "design.polarity");
}

static void model_line_not_of_the_family(void **state)
{
    (void)state;
    refused("ce", "sed 's/^model = .*/model = dss_physical/' $IN > $OUT",
            "edited.ini:7: model 'dss_physical' is not one this sensor's params.ini can hold "
            "(ess_eq12_finecode, ess_extended, ess_spline, ess_hybrid, ess_table)");
    refused("cd", "sed 's/^model = .*/model = psd_polynomial/' $IN > $OUT",
            "model 'psd_polynomial' is not one this sensor's params.ini can hold "
            "(dss_physical, dss_polynomial, dss_spline, dss_hybrid, dss_table)");
    refused("cp", "sed 's/^model = .*/model = psd_physcal/' $IN > $OUT",
            "edited.ini:6: model 'psd_physcal' is not one this sensor's params.ini can hold "
            "(psd_physical, psd_polynomial, psd_spline, psd_hybrid, psd_table) (did you mean "
            "psd_physical?)");
    refused("cp", "sed '/^model = /d' $IN > $OUT", "missing key calibration.model");
}

/* This build's version with part k (0 major, 1 minor, 2 patch) moved by
 * by (other parts: the lower ones 0 when raising). */
static void version_moved(int k, int by, char *buf, size_t len)
{
    long v[3] = {0, 0, 0};
    sscanf(SUNMC_VERSION, "%ld.%ld.%ld", &v[0], &v[1], &v[2]);
    v[k] += by;
    for (int j = k + 1; j < 3 && by > 0; j++)
        v[j] = 0;
    snprintf(buf, len, "%ld.%ld.%ld", v[0], v[1], v[2]);
}

static void version_rule(void **state)
{
    (void)state;
    char edit[512], says[1024], v[64];
    /* equal: read, no message */
    read_ok("cp", "cp $IN $OUT", NULL);
    /* older (0.0.0 is older than any other version): read, no message */
    read_ok("cp", "sed 's/^sunmc_version = .*/sunmc_version = 0.0.0/' $IN > $OUT", NULL);
    /* newer patch and newer minor of this major: read with a warning */
    for (int k = 1; k <= 2; k++) {
        version_moved(k, 1, v, sizeof v);
        snprintf(edit, sizeof edit, "sed 's/^sunmc_version = .*/sunmc_version = %s/' $IN > $OUT",
                 v);
        for (int f = 0; f < 2; f++) { /* the version's line: after the title's lines */
            snprintf(says, sizeof says,
                     "sunmc compensate: WARNING: %s/edited.ini:%d: written by sunmc %s, newer "
                     "than this %s: read as this version reads it",
                     dir, f ? 5 : 4, v, SUNMC_VERSION);
            read_ok(f ? "cd" : "cp", edit, says);
        }
    }
    /* newer major: refused, for the brief's 9.9.9 and the next major */
    refused("cp", "sed 's/^sunmc_version = .*/sunmc_version = 9.9.9/' $IN > $OUT",
            "edited.ini:4: written by sunmc 9.9.9, newer than this " SUNMC_VERSION ": ");
    version_moved(0, 1, v, sizeof v);
    snprintf(edit, sizeof edit, "sed 's/^sunmc_version = .*/sunmc_version = %s/' $IN > $OUT", v);
    snprintf(says, sizeof says, "written by sunmc %s, newer than this %s", v, SUNMC_VERSION);
    refused("ce", edit, says);
    refused("cdp", edit, says);
    refused("cq", edit, says);
    /* malformed, and missing */
    static const char *const bad[] = {"0.1", "0.1.0.0", "v0.1.0", "0.1.0-rc1", "0..1",
                                      "1234567890.0.0", "0.1.x"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        snprintf(edit, sizeof edit, "sed 's/^sunmc_version = .*/sunmc_version = %s/' $IN > $OUT",
                 bad[i]);
        snprintf(says, sizeof says,
                 "edited.ini:4: calibration.sunmc_version '%s' is not a version "
                 "MAJOR.MINOR.PATCH",
                 bad[i]);
        refused("cp", edit, says);
    }
    refused("cd", "sed '/^sunmc_version/d' $IN > $OUT",
            "edited.ini: missing key calibration.sunmc_version");
}

static void fixed_scale_and_hash(void **state)
{
    (void)state;
    refused("ce", "sed 's/^d  *= 1 /d = 2 /' $IN > $OUT",
            "key fixed.d must be 1 (eq. 12's common scale");
    refused("cd", "sed 's/^data_fnv1a64  *= [0-9a-f]*/data_fnv1a64 = 0123456789abcdeg/' $IN > $OUT",
            "key calibration.data_fnv1a64 must be 16 hex digits");
    refused("cq", "sed 's/^data_rows = .*/data_rows = -1/' $IN > $OUT",
            "key calibration.data_rows must be >= 0");
    refused("ce", "sed 's/^pilot_units  *= 48/pilot_units = 0/' $IN > $OUT",
            "key prior.pilot_units must be >= 1");
    refused("ce", "sed 's/^a_mean = .*/a_mean = x/' $IN > $OUT",
            "key prior.a_mean: 'x' is not a number");
}

/* The detector tilt's two parameters (calibration.fit_detector_tilt = on):
 * both or neither, each within its tolerance's range; neither (and no
 * prior for them) is the paper's model, read silently; a prior for a tilt
 * the file does not carry is refused as any unknown prior key. */
static void detector_tilt_keys(void **state)
{
    (void)state;
    refused("cdt", "grep -v '^fit_detector_tilt_y_arcsec' $IN > $OUT",
            "missing key parameters.fit_detector_tilt_y_arcsec");
    refused("cdt", "grep -v '^fit_detector_tilt_x_arcsec ' $IN > $OUT",
            "missing key parameters.fit_detector_tilt_x_arcsec");
    refused("cdt",
            "sed 's/^fit_detector_tilt_x_arcsec  *= [^ ]*/fit_detector_tilt_x_arcsec = 36001/' "
            "$IN > $OUT",
            "fit_detector_tilt_x_arcsec = 36001 is out of range: allowed -36000 to 36000 arcsec");
    refused("cdt",
            "sed 's/^fit_detector_tilt_y_arcsec  *= [^ ]*/fit_detector_tilt_y_arcsec = x/' "
            "$IN > $OUT",
            "fit_detector_tilt_y_arcsec: 'x' is not a number");
    read_ok("cdt", "grep -v '^fit_detector_tilt_' $IN > $OUT", NULL);
    refused("cdt", "grep -v '^fit_detector_tilt_[xy]_arcsec ' $IN > $OUT",
            "unknown key prior.fit_detector_tilt_x_arcsec_mean");
    /* the tilt read is the tilt used: without it the angles move */
    char cmp[2048];
    snprintf(cmp, sizeof cmp,
             "true; grep -v '^fit_detector_tilt_' $D/cdt/params.ini > $D/flat.ini && "
             "%s compensate $D/cdt/params.ini $D/sd/validation.csv > $D/tilt.csv && "
             "%s compensate $D/flat.ini $D/sd/validation.csv > $D/flat.csv && "
             "! cmp -s $D/tilt.csv $D/flat.csv",
             test_sunmc(), test_sunmc());
    static char res[65536];
    assert_int_equal(sunmc(cmp, res, sizeof res), 0);
    /* calibrate names the tilt's correlation with the mount and says why
     * (a tilt tolerance the priors do not pin to 0: dss.ini's is 0) */
    assert_int_equal(sunmc("calibrate --config configs/dss.ini --set "
                           "calibration.fit_detector_tilt=on --set tolerance.detector_tilt_x_arcsec=360 "
                           "--set tolerance.detector_tilt_y_arcsec=360 $D/sd/campaign.csv --quiet "
                           "--out $D/cdt2",
                           res, sizeof res),
                     0);
    assert_non_null(strstr(res, "fit_c1_arcsec and fit_detector_tilt_x_arcsec"));
    assert_non_null(strstr(res, "fit_dx_px and fit_detector_tilt_y_arcsec"));
    assert_non_null(strstr(res, "why: a detector tilt about X (Y) moves a spot"));
    /* each of the two pairs under that cause, not the generic warning */
    assert_null(strstr(res, "fit_detector_tilt_x_arcsec are nearly unidentifiable"));
    assert_null(strstr(res, "fit_detector_tilt_y_arcsec are nearly unidentifiable"));
    /* the paper's model's params.ini has no tilt keys; the extension's has both */
    char out[4096];
    assert_int_equal(sunmc("true; grep -c '^fit_detector_tilt_' $D/cd/params.ini; true", out,
                           sizeof out),
                     0);
    assert_int_equal(atoi(out), 0);
    assert_int_equal(sunmc("true; grep -c '^fit_detector_tilt_[xy]_arcsec ' $D/cdt/params.ini",
                           out, sizeof out),
                     0);
    assert_int_equal(atoi(out), 2);
}

/* Every params.ini calibrate writes is read and compensates every row of
 * its unit's validation readings, saying nothing but its accuracy against
 * the truth columns (and, for a spline or table, the count of readings
 * outside its calibrated field: the DSS's validation reaches spots
 * beyond the campaign's); the ESS's and the DSS's
 * default models' angles are checked to the last bit by tests/golden. */
static void every_model_round_trips(void **state)
{
    (void)state;
    char args[2048], out[8192];
    for (size_t i = 0; i < N_CALS; i++) {
        snprintf(args, sizeof args,
                 "true; V=$D/%s/validation.csv; %s compensate $D/%s/params.ini $V > $D/rt.csv "
                 "2> $D/rt.err && grep -q '^sunmc compensate: accuracy against truth_' $D/rt.err && "
                 "! grep -v -e '^sunmc compensate: accuracy against' -e '^  ' "
                 "-e 'outside the calibrated field (the model would extrapolate)' $D/rt.err && "
                 "test $(grep -vc '^#' $V) -eq $(grep -vc '^#' $D/rt.csv) && "
                 "test $(grep -v '^#' $D/rt.csv | grep -c ',-') -lt $(grep -vc '^#' $V)",
                 cals[i].sim, test_sunmc(), cals[i].cal);
        if (sunmc(args, out, sizeof out) != 0)
            fail_msg("%s (%s): not read back: %s", cals[i].cal, cals[i].args, out);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(order_must_be_whole),
        cmocka_unit_test(coefficients_beyond_order),
        cmocka_unit_test(unknown_parameter_key),
        cmocka_unit_test(unknown_key_every_section),
        cmocka_unit_test(unknown_section),
        cmocka_unit_test(model_line_names_another_model),
        cmocka_unit_test(model_line_not_of_the_family),
        cmocka_unit_test(version_rule),
        cmocka_unit_test(fixed_scale_and_hash),
        cmocka_unit_test(detector_tilt_keys),
        cmocka_unit_test(every_model_round_trips),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
