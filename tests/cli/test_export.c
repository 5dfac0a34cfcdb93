/* test_export.c - issue 42: `sunmc export` writes a unit's calibration as
 * C99 a flight computer compiles.  Each family's exported code is compiled
 * here with the system's cc (-std=c99 -Wall -Wextra -Werror -pedantic, and
 * -DSUNMC_FLOAT) and run on the unit's validation readings against
 * `sunmc compensate`:
 *   double  within 1e-9 of the unit's after-calibration RMS (params.ini's
 *           crossval_rms_arcsec): the port adds nothing;
 *   float   within FLOAT_ULPS float ulps at 1 rad (the angles are at most
 *           ~1.2 rad; the reading's own rounding to float, half an ulp of
 *           |x| <= 1024 px, moves a DSS angle by 1.2e-7 rad, one ulp), in
 *           deg 16 * 2^-23 * 57.3 = 1.1e-4 deg;
 *   table   the bilinear error of a smooth map, step^2 / 8 times its
 *           curvature: its measured size, and the step^2 law (half the
 *           step, a quarter of the error).
 * And the refusals: exit 2, nothing written. */
#include "test_util.h"

#include <math.h>
#include <unistd.h>

#define FLOAT_ULPS 16.0
#define FLOAT_BOUND_DEG (FLOAT_ULPS * 1.1920928955078125e-07 * 57.29577951308232)
#define DOUBLE_OF_AFTER_RMS 1e-9

static char dir[512];

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    (void)state;
    if (test_private_dir(dir, sizeof dir, "export") != 0)
        return -1;
    static const char *const steps[] = {
        "simulate configs/dss.ini --unit 3 --quiet --out $D/sd",
        "calibrate --config configs/dss.ini $D/sd/campaign.csv --quiet --out $D/cd",
        "compensate $D/cd/params.ini $D/sd/validation.csv > $D/cd.csv 2> $D/cd.err && true",
        "calibrate --config configs/dss.ini --set calibration.model=polynomial "
        "$D/sd/campaign.csv --quiet --out $D/cl",
        "compensate $D/cl/params.ini $D/sd/validation.csv > $D/cl.csv 2> $D/cl.err && true",
        "simulate configs/dss.ini --set campaign.mount=aligned --unit 2 --quiet --out $D/sa",
        "calibrate --config configs/dss.ini --set campaign.mount=aligned $D/sa/campaign.csv "
        "--quiet --out $D/ca",
        "compensate $D/ca/params.ini $D/sa/validation.csv > $D/ca.csv 2> $D/ca.err && true",
        "simulate configs/psd.ini --unit 3 --quiet --out $D/sp",
        "calibrate --config configs/psd.ini $D/sp/campaign.csv --quiet --out $D/cp",
        "compensate $D/cp/params.ini $D/sp/validation.csv > $D/cp.csv 2> $D/cp.err && true",
        "simulate configs/psd_aeroztark.ini --unit 1 --quiet --out $D/sz",
        "calibrate --config configs/psd_aeroztark.ini $D/sz/campaign.csv --quiet --out $D/cz",
        "compensate $D/cz/params.ini $D/sz/validation.csv > $D/cz.csv 2> $D/cz.err && true",
        "simulate configs/psd_14og.ini --unit 2 --quiet --out $D/sq",
        "calibrate --config configs/psd_14og.ini $D/sq/campaign.csv --quiet --out $D/cq",
        "compensate $D/cq/params.ini $D/sq/validation.csv > $D/cq.csv 2> $D/cq.err && true",
        "simulate configs/psd_kenscl.ini --unit 1 --quiet --out $D/sk",
        "calibrate --config configs/psd_kenscl.ini $D/sk/campaign.csv --quiet --out $D/ck",
        "compensate $D/ck/params.ini $D/sk/validation.csv > $D/ck.csv 2> $D/ck.err && true",
        "simulate configs/ess_type_a.ini --unit 3 --quiet --out $D/se",
        "calibrate --config configs/ess_type_a.ini $D/se/campaign.csv --quiet --out $D/ce",
        "compensate $D/ce/params.ini $D/se/validation.csv > $D/ce.csv 2> $D/ce.err && true",
        "calibrate --config configs/ess_type_a.ini --set calibration.model=extended "
        "$D/se/campaign.csv --quiet --out $D/cx",
        "compensate $D/cx/params.ini $D/se/validation.csv > $D/cx.csv 2> $D/cx.err && true"};
    return test_sunmc_steps(dir, steps, (int)(sizeof steps / sizeof *steps));
}

/* Column k of a CSV line (0-based) into buf. */
static void field(const char *line, int k, char *buf, size_t len)
{
    const char *p = line;
    for (int i = 0; i < k && p; i++) {
        p = strchr(p, ',');
        if (p)
            p++;
    }
    size_t n = 0;
    while (p && p[n] && p[n] != ',' && p[n] != '\n' && n + 1 < len) {
        buf[n] = p[n];
        n++;
    }
    buf[n] = '\0';
}

static int column(const char *header, const char *name)
{
    char buf[128];
    for (int k = 0; k < 32; k++) {
        field(header, k, buf, sizeof buf);
        if (strcmp(buf, name) == 0)
            return k;
    }
    fail_msg("no column %s in %s", name, header);
    return -1;
}

/* compensate's output comp (its raw and compensated columns) as test vectors
 * in the export's format, the raw values rounded to float when to_float;
 * rows compensate wrote '-' are left out.  Returns the rows written. */
static int vectors_of(const char *comp, const char *vec, const char *const *raw, int n_raw,
                      const char *const *ang, int n_ang, int to_float)
{
    FILE *in = fopen(comp, "r"), *out = fopen(vec, "w");
    assert_non_null(in);
    assert_non_null(out);
    char line[4096], header[4096] = "", buf[128];
    int col[8] = {0}, rows = 0;
    while (fgets(line, sizeof line, in)) {
        if (line[0] == '#')
            continue;
        if (!header[0]) {
            snprintf(header, sizeof header, "%s", line);
            for (int k = 0; k < n_raw; k++)
                col[k] = column(header, raw[k]);
            for (int k = 0; k < n_ang; k++)
                col[n_raw + k] = column(header, ang[k]);
            fputs("header\n", out);
            continue;
        }
        field(line, col[n_raw], buf, sizeof buf);
        if (strcmp(buf, "-") == 0)
            continue;
        for (int k = 0; k < n_raw; k++) {
            field(line, col[k], buf, sizeof buf);
            if (to_float)
                fprintf(out, "%.9g,", (double)(float)strtod(buf, NULL));
            else
                fprintf(out, "%s,", buf);
        }
        fputs("0", out);
        for (int k = 0; k < n_ang; k++) {
            field(line, col[n_raw + k], buf, sizeof buf);
            fprintf(out, ",%s", buf);
        }
        fputc('\n', out);
        rows++;
    }
    fclose(in);
    assert_int_equal(fclose(out), 0);
    return rows;
}

typedef struct {
    long ok, mismatch;
    double err_deg[2];
    double ns;
} run_result;

/* Compile the export in $D/x (flags), run it on vec; its printout parsed. */
static run_result compile_run(const char *x, const char *name, const char *flags, const char *vec)
{
    char args[2800], out[16384];
    snprintf(args, sizeof args,
             "%s/%s/test_main.c %s/%s/sunmc_%s_cal.c -o %s/%s/t -lm 2>&1 && %s/%s/t %s", dir, x,
             dir, x, name, dir, x, dir, x, vec);
    char cmd[4000];
    snprintf(cmd, sizeof cmd, "cc -std=c99 -Wall -Wextra -Werror -pedantic -O1 %s %s", flags,
             args);
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s: exit %d: %s", cmd, rc, out);
    run_result r = {0, 0, {0, 0}, 0};
    const char *p = strstr(out, " ok ");
    assert_non_null(p);
    assert_int_equal(sscanf(p, " ok %ld status_mismatch %ld", &r.ok, &r.mismatch), 2);
    p = strstr(out, "max_abs_error_deg[0] ");
    assert_non_null(p);
    assert_int_equal(sscanf(p, "max_abs_error_deg[0] %lf", &r.err_deg[0]), 1);
    p = strstr(out, "max_abs_error_deg[1] ");
    if (p)
        assert_int_equal(sscanf(p, "max_abs_error_deg[1] %lf", &r.err_deg[1]), 1);
    p = strstr(out, "ns_per_reading ");
    assert_non_null(p);
    assert_int_equal(sscanf(p, "ns_per_reading %lf", &r.ns), 1);
    return r;
}

static double max2(const double *e)
{
    return e[0] > e[1] ? e[0] : e[1];
}

/* The value of key in cal's params.ini. */
static double param_of(const char *cal, const char *key)
{
    char path[700], line[512], fmt[128];
    snprintf(path, sizeof path, "%s/%s/params.ini", dir, cal);
    snprintf(fmt, sizeof fmt, "%s = %%lf", key);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    double v = NAN;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, fmt, &v) == 1)
            break;
    fclose(f);
    if (!isfinite(v))
        fail_msg("%s: no %s", path, key);
    return v;
}

/* params.ini's residual_sigma_arcsec (the after-calibration RMS of its
 * data), in deg. */
static double after_rms_deg(const char *cal)
{
    double v = param_of(cal, "residual_sigma_arcsec");
    assert_true(v > 0);
    return v / 3600.0;
}

static const char *const dss_raw[] = {"x_px", "y_px"};
static const char *const psd_raw[] = {"i1", "i2", "i3", "i4"};
static const char *const two_ang[] = {"compensated_alpha_deg", "compensated_beta_deg"};

/* Export calibration cal (params.ini in $D/cal, compensate's output of its
 * unit's validation readings in $D/cal.csv) into $D/x, compile it in double
 * and float, and run it on those readings against compensate:
 *   double: within DOUBLE_OF_AFTER_RMS of the after RMS;
 *   float:  within 4 e_in + FLOAT_BOUND_DEG, e_in the error the readings'
 *           own rounding to float makes through the double build (the
 *           input's half ulp propagated; 4: the arithmetic's roundings of
 *           the same size), FLOAT_BOUND_DEG the angle's own ulps.
 * And the export's own test vectors, statuses included. */
static void model_form(const char *cal, const char *x, const char *name, const char *const *raw,
                       int n_raw, const char *const *ang, int n_ang, int min_rows)
{
    char args[1024], out[8192], comp[700], vec[700], vecf[700];
    snprintf(args, sizeof args, "export $D/%s/params.ini --out $D/%s", cal, x);
    if (sunmc(args, out, sizeof out) != 0)
        fail_msg("%s: %s", args, out);
    snprintf(comp, sizeof comp, "%s/%s.csv", dir, cal);
    snprintf(vec, sizeof vec, "%s/%s.vec", dir, cal);
    snprintf(vecf, sizeof vecf, "%s/%s.vecf", dir, cal);
    int n = vectors_of(comp, vec, raw, n_raw, ang, n_ang, 0);
    assert_int_equal(vectors_of(comp, vecf, raw, n_raw, ang, n_ang, 1), n);
    if (n < min_rows)
        fail_msg("%s: %d validation readings compensated, expected %d", cal, n, min_rows);
    run_result d = compile_run(x, name, "", vec);
    assert_int_equal(d.ok, n);
    assert_int_equal(d.mismatch, 0);
    double rms = after_rms_deg(cal);
    if (!(max2(d.err_deg) <= DOUBLE_OF_AFTER_RMS * rms))
        fail_msg("double: %g deg against compensate, above 1e-9 of the after RMS %g deg",
                 max2(d.err_deg), rms);
    double e_in = max2(compile_run(x, name, "", vecf).err_deg);
    run_result f = compile_run(x, name, "-DSUNMC_FLOAT", vec);
    assert_int_equal(f.ok, n);
    double bound = 4 * e_in + FLOAT_BOUND_DEG;
    if (!(max2(f.err_deg) <= bound))
        fail_msg("float: %g deg, above the bound %g (e_in %g)", max2(f.err_deg), bound, e_in);
    /* and it is float arithmetic: an error no double computation makes */
    assert_true(max2(f.err_deg) > 1e3 * max2(d.err_deg));
    print_message("%s: %d readings, double %.2e deg, float %.2e deg (bound %.2e), "
                  "%.0f ns/reading\n", cal, n, max2(d.err_deg), max2(f.err_deg), bound, d.ns);
    /* the export's own vectors agree too, statuses included */
    snprintf(vec, sizeof vec, "%s/%s/test_vectors.csv", dir, x);
    d = compile_run(x, name, "", vec);
    assert_int_equal(d.mismatch, 0);
    assert_true(d.ok > 700);
    assert_true(max2(d.err_deg) <= 1e-12);
}

static void dss_physical_as_mounted(void **state)
{
    (void)state;
    model_form("cd", "xd", "dss_physical", dss_raw, 2, two_ang, 2, 700);
}

static void dss_physical_aligned(void **state)
{
    (void)state;
    model_form("ca", "xa", "dss_physical", dss_raw, 2, two_ang, 2, 700);
}

/* The DSS polynomial: the on-board formula (its glass's Newton) and the
 * correction's monomials. */
static void dss_polynomial(void **state)
{
    (void)state;
    model_form("cl", "xl", "dss_polynomial", dss_raw, 2, two_ang, 2, 700);
}

/* The PSD: its physical model (tetra-lateral; the inverting aeroztark unit)
 * and its polynomial (tetra and duo-lateral). */
static void psd_physical(void **state)
{
    (void)state;
    model_form("cp", "xp", "psd_physical", psd_raw, 4, two_ang, 2, 50);
    model_form("cz", "xz", "psd_physical", psd_raw, 4, two_ang, 2, 50);
}

static void psd_polynomial(void **state)
{
    (void)state;
    model_form("cq", "xq", "psd_polynomial", psd_raw, 4, two_ang, 2, 50);
    model_form("ck", "xk", "psd_polynomial", psd_raw, 4, two_ang, 2, 50);
}

static const char *const ess_raw[] = {"output_deg"};
static const char *const ess_ang[] = {"compensated_deg"};

static void ess_paper_model(void **state)
{
    (void)state;
    model_form("ce", "xe", "ess_eq12_finecode", ess_raw, 1, ess_ang, 1, 3000);
}

/* The extended model: its fine-code terms by Newton (a fixed 12 steps). */
static void ess_extended_model(void **state)
{
    (void)state;
    model_form("cx", "xx", "ess_extended", ess_raw, 1, ess_ang, 1, 3000);
}

/* The ESS table, linear in output_deg: its error is step^2 / 8 times the
 * curvature of the fine code's inverse, x = r + k sin(w x + t): |x''| =
 * k w^2 |sin| / g'^3 with g' in [1 - w k, 1 + w k] (w = 2 pi / (theta0 / 4),
 * 720 / rad for theta0 = 2 deg; k = params' k_deg), so between k w^2 /
 * (1 + w k)^3 and k w^2 / (1 - w k)^3 times step^2 / 8 -- the unit's w k
 * is 0.5, a wide bracket; and a quarter at half the step. */
static void ess_table_form(void **state)
{
    (void)state;
    char out[8192], vec[700], comp[700], args[1024];
    snprintf(comp, sizeof comp, "%s/ce.csv", dir);
    snprintf(vec, sizeof vec, "%s/ce.tvec", dir);
    assert_true(vectors_of(comp, vec, ess_raw, 1, ess_ang, 1, 0) > 3000);
    double k = param_of("ce", "k_deg"), w = 2 * M_PI / (param_of("ce", "theta0_deg") / 4);
    double err[2], step[2] = {0.02, 0.01};
    const char *xs[2] = {"te2", "te1"};
    for (int i = 0; i < 2; i++) {
        snprintf(args, sizeof args, "export $D/ce/params.ini --out $D/%s --form table:%g",
                 xs[i], step[i]);
        assert_int_equal(sunmc(args, out, sizeof out), 0);
        run_result r = compile_run(xs[i], "ess_eq12_finecode", "", vec);
        assert_int_equal(r.mismatch, 0);
        err[i] = r.err_deg[0];
        double c = step[i] * step[i] / 8 * k * w * w;
        double lo = c / pow(1 + w * k, 3), hi = c / pow(1 - w * k, 3);
        if (!(err[i] > lo && err[i] < hi))
            fail_msg("table:%g: error %g deg outside %g .. %g", step[i], err[i], lo, hi);
        print_message("ess table:%g: %.2e deg (%.2e .. %.2e), %.0f ns/reading\n", step[i],
                      err[i], lo, hi, r.ns);
    }
    double ratio = err[0] / err[1];
    if (!(ratio > 3.0 && ratio < 5.0))
        fail_msg("half the step: error ratio %g, not ~4", ratio);
    /* its size: 2 * 89 / 0.01 + 1 nodes of 4 bytes in float */
    snprintf(args, sizeof args, "%s/te1/sunmc_ess_eq12_finecode_cal.h", dir);
    assert_true(test_file_has(args, "17801 nodes x 1 angles, 71204 bytes as float"));
}

/* The PSD table, bilinear in the dark-corrected ratios: its error on the
 * unit's validation readings quarters at half the step (a smooth map),
 * and at 0.01 it is below a twentieth of the unit's after RMS (152"). */
static void psd_table_form(void **state)
{
    (void)state;
    char out[8192], vec[700], comp[700], args[1024];
    snprintf(comp, sizeof comp, "%s/cp.csv", dir);
    snprintf(vec, sizeof vec, "%s/cp.tvec", dir);
    assert_true(vectors_of(comp, vec, psd_raw, 4, two_ang, 2, 0) > 50);
    double err[2], step[2] = {0.02, 0.01};
    const char *xs[2] = {"tp2", "tp1"};
    for (int i = 0; i < 2; i++) {
        snprintf(args, sizeof args, "export $D/cp/params.ini --out $D/%s --form table:%g",
                 xs[i], step[i]);
        assert_int_equal(sunmc(args, out, sizeof out), 0);
        run_result r = compile_run(xs[i], "psd_physical", "", vec);
        assert_int_equal(r.mismatch, 0);
        err[i] = max2(r.err_deg);
        print_message("psd table:%g: %.2e deg, %.0f ns/reading\n", step[i], err[i], r.ns);
        /* the export's own vectors: the table refuses near the model's
         * edge, never gives an angle compensate would not (test_main's exit) */
        snprintf(args, sizeof args, "%s/%s/test_vectors.csv", dir, xs[i]);
        compile_run(xs[i], "psd_physical", "", args);
    }
    double ratio = err[0] / err[1];
    if (!(ratio > 3.0 && ratio < 5.0))
        fail_msg("half the step: error ratio %g, not ~4", ratio);
    assert_true(err[1] < 0.05 * after_rms_deg("cp"));
    /* the polynomial's table ends just inside its reading check: no edge
     * node refused by its ratios' rounding, no reading of its range refused */
    assert_int_equal(sunmc("export $D/cq/params.ini --out $D/tq --form table:0.1", out,
                           sizeof out), 0);
    snprintf(args, sizeof args, "%s/tq/test_vectors.csv", dir);
    run_result r = compile_run("tq", "psd_polynomial", "", args);
    assert_int_equal(r.mismatch, 0);
    assert_int_equal(r.ok, 41 * 41);
}

/* The table form: bilinear on x_px, y_px.  Its error is the curvature of
 * the spot-to-angle map times step^2 / 8: alpha ~ atan(k x), k = pitch /
 * height (5.5 um / 2.87 mm = 1.92e-3 rad/px), |d2 alpha / dx2| <= 0.65 k^2;
 * the glass bends wide rays more, so the measured error may reach twice
 * the pinhole's estimate. */
static void dss_table_form(void **state)
{
    (void)state;
    char out[8192], vec[700];
    char comp[700];
    snprintf(comp, sizeof comp, "%s/cd.csv", dir);
    snprintf(vec, sizeof vec, "%s/cd.tvec", dir);
    assert_true(vectors_of(comp, vec, dss_raw, 2, two_ang, 2, 0) > 700);
    double err[2], step[2] = {16, 8};
    const char *xs[2] = {"t16", "t8"};
    for (int i = 0; i < 2; i++) {
        char args[1024];
        snprintf(args, sizeof args, "export $D/cd/params.ini --out $D/%s --form table:%g "
                 "--precision float", xs[i], step[i]);
        assert_int_equal(sunmc(args, out, sizeof out), 0);
        run_result r = compile_run(xs[i], "dss_physical", "-DSUNMC_DOUBLE", vec);
        assert_int_equal(r.mismatch, 0);
        err[i] = max2(r.err_deg);
        double k = 5.5e-3 / 2.87, est = step[i] * step[i] / 8 * 0.65 * k * k * 57.29578;
        if (!(err[i] > 0.25 * est && err[i] < 2.0 * est))
            fail_msg("table:%g: error %g deg against the estimate %g", step[i], err[i], est);
        /* the float build of the table (its values in float) adds little */
        r = compile_run(xs[i], "dss_physical", "", vec);
        assert_true(max2(r.err_deg) < err[i] + FLOAT_BOUND_DEG);
    }
    double ratio = err[0] / err[1];
    if (!(ratio > 3.0 && ratio < 5.0))
        fail_msg("half the step: error ratio %g, not ~4", ratio);
    /* its size is stated: (2048 / 8 + 1)^2 nodes, 2 angles, 4 bytes */
    char path[700];
    snprintf(path, sizeof path, "%s/t8/sunmc_dss_physical_cal.h", dir);
    assert_true(test_file_has(path, "66049 nodes x 2 angles, 528392 bytes as float"));
}

/* What the files say: the params' checksum and the unit's data file. */
static void dss_provenance(void **state)
{
    (void)state;
    char path[700], out[4096];
    snprintf(path, sizeof path, "%s/xd/sunmc_dss_physical_cal.c", dir);
    assert_true(test_file_has(path, "data_fnv1a64 = "));
    assert_true(test_file_has(path, "sd/campaign.csv"));
    assert_true(test_file_has(path, "its bytes' FNV-1a 64: "));
    assert_true(test_file_has(path, "10 steps"));
    /* no header beyond the two the issue allows */
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "grep -h '#include <' %s/xd/sunmc_dss_physical_cal.[ch] | sort -u",
             dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_string_equal(out, "#include <math.h>\n#include <stdint.h>\n");
    snprintf(cmd, sizeof cmd, "grep -cE 'malloc|static [a-z_]+ [a-z_]+ *=|while' "
             "%s/xd/sunmc_dss_physical_cal.c", dir);
    test_run(cmd, out, sizeof out);
    assert_string_equal(out, "0\n");
}

/* Refused, exit 2, nothing written. */
static void refusals(void **state)
{
    (void)state;
    char out[8192], args[2200];
    static const char *const bad[] = {
        "export $D/nothing.ini --out $D/r1",
        "export $D/cd/params.ini --out $D/r1 --precision half",
        "export $D/cd/params.ini --out $D/r1 --form table:0",
        "export $D/cd/params.ini --out $D/r1 --form table:-4",
        "export $D/cd/params.ini --out $D/r1 --form table:x",
        "export $D/cd/params.ini --out $D/r1 --form tableau",
        "export $D/cd/params.ini --out $D/r1 --form table:0.001",
        "export $D/cd/params.ini --out $D/r1 --colour",
        "export $D/cd/params.ini $D/cd/params.ini --out $D/r1",
        "export $D/cd/params.ini",
        "export $D/cd/params.ini --out $D/r1 --form",
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        int rc = sunmc(bad[i], out, sizeof out);
        if (rc != 2)
            fail_msg("%s: exit %d: %s", bad[i], rc, out);
    }
    snprintf(args, sizeof args, "%s/r1", dir);
    assert_int_not_equal(access(args, F_OK), 0);
    /* the table's limit, both sides: 1e6 nodes; 2048 px / 2.0501 -> 999 cells a side,
     * (999 + 1)^2 = 1e6 nodes exactly; 2.05 -> 1000 cells, 1001^2 nodes */
    assert_int_equal(sunmc("export $D/cd/params.ini --out $D/r2 --form table:2.05", out,
                           sizeof out), 2);
    assert_non_null(strstr(out, "nodes or more"));
    assert_int_equal(sunmc("export $D/cd/params.ini --out $D/r2 --form table:2.0501 "
                           "--precision float", out, sizeof out), 0);
    snprintf(args, sizeof args, "%s/r2/sunmc_dss_physical_cal.h", dir);
    assert_true(test_file_has(args, "1000000 nodes x 2 angles"));
    snprintf(args, sizeof args, "rm -r %s/r2", dir);
    assert_int_equal(system(args), 0);
    /* a sensor no family has, at its line */
    snprintf(args, sizeof args, "sed 's/^sensor = dss/sensor = xyz/' %s/cd/params.ini > "
             "%s/bad.ini", dir, dir);
    assert_int_equal(test_run(args, out, sizeof out), 0);
    assert_int_equal(sunmc("export $D/bad.ini --out $D/r3", out, sizeof out), 2);
    assert_non_null(strstr(out, "bad.ini:6: sensor 'xyz' is not available"));
    /* a model line no C name can take, at its line */
    snprintf(args, sizeof args, "sed 's/^model = dss_physical/model = dss-physical/' "
             "%s/cd/params.ini > %s/bad2.ini", dir, dir);
    assert_int_equal(test_run(args, out, sizeof out), 0);
    assert_int_equal(sunmc("export $D/bad2.ini --out $D/r3", out, sizeof out), 2);
    assert_non_null(strstr(out, "bad2.ini:"));
    /* a params path that would end the head comment ("*" then "/") */
    snprintf(args, sizeof args, "mkdir -p '%s/a*' && cp %s/cd/params.ini '%s/a*/p.ini'", dir,
             dir, dir);
    assert_int_equal(test_run(args, out, sizeof out), 0);
    assert_int_equal(sunmc("export \"$D/a*/p.ini\" --out $D/xc --quiet", out, sizeof out), 0);
    snprintf(args, sizeof args, "cd %s/xc && cc -std=c99 -Wall -Wextra -Werror -pedantic -c "
             "sunmc_dss_physical_cal.c -o /dev/null", dir);
    if (test_run(args, out, sizeof out) != 0)
        fail_msg("%s: %s", args, out);
    /* --quiet: nothing printed */
    assert_int_equal(sunmc("export $D/cd/params.ini --out $D/q --quiet", out, sizeof out), 0);
    assert_string_equal(out, "");
    /* an existing directory, even empty, is never written */
    assert_int_equal(sunmc("export $D/cd/params.ini --out $D/xd", out, sizeof out), 2);
    assert_non_null(strstr(out, "never overwrites"));
    snprintf(args, sizeof args, "%s/empty", dir);
    assert_int_equal(mkdir(args, 0700), 0);
    assert_int_equal(sunmc("export $D/cd/params.ini --out $D/empty", out, sizeof out), 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dss_physical_as_mounted),
        cmocka_unit_test(dss_physical_aligned),
        cmocka_unit_test(dss_polynomial),
        cmocka_unit_test(psd_physical),
        cmocka_unit_test(psd_polynomial),
        cmocka_unit_test(ess_paper_model),
        cmocka_unit_test(ess_extended_model),
        cmocka_unit_test(ess_table_form),
        cmocka_unit_test(psd_table_form),
        cmocka_unit_test(dss_table_form),
        cmocka_unit_test(dss_provenance),
        cmocka_unit_test(refusals),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
