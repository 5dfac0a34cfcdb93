/* cmd_export.c - `sunmc export` (issue 42): a unit's params.ini as C99
 * source for the flight software (lab_export.h). */
#include "cli.h"
#include "lab.h"
#include "lab_export.h"
#include "lab_params.h"
#include "output.h"
#include "registry.h"
#include "status.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char export_help[] =
    "usage: sunmc export PARAMS.ini --out DIR [--precision float|double] [--form model|table:STEP]\n"
    "                    [--quiet]\n"
    "Writes the calibration of PARAMS.ini (from `sunmc calibrate --out`) as C99 source a flight\n"
    "computer compiles: one function from the family's raw reading (compensate's raw columns)\n"
    "to the compensated angles in deg, returning 0 or why the unit cannot produce the reading\n"
    "(compensate's rules: enum sunmc_cal_status).  Only <math.h> and <stdint.h>, no allocation,\n"
    "no recursion, loops of fixed bounds (stated in the header), no writable static data;\n"
    "clean with cc -std=c99 -Wall -Wextra -Werror -pedantic, with or without -DSUNMC_FLOAT.\n"
    "  DIR/sunmc_MODEL_cal.h, .c  the function sunmc_MODEL_cal (MODEL: params' calibration.model,\n"
    "                      e.g. dss_physical); the params' checksum, data file and config in\n"
    "                      their head comment\n"
    "  DIR/test_vectors.csv raw readings over the unit's range (and beyond), with the status\n"
    "                      and angles of sunmc's double compensate\n"
    "  DIR/test_main.c     cc -std=c99 test_main.c sunmc_MODEL_cal.c -lm && ./a.out: statuses\n"
    "                      that differ, largest |error| per angle (deg), time per reading\n"
    "--precision float|double  the sunmc_real it compiles to without -DSUNMC_FLOAT or\n"
    "                      -DSUNMC_DOUBLE (default double)\n"
    "--form model          the calibrated model itself (default)\n"
    "--form table:STEP     the compensated angles on a grid of the reading with STEP in its\n"
    "                      unit (DSS: x_px, y_px in px; PSD: the channels' ratios; ESS:\n"
    "                      output_deg, +-89), bilinear (ESS: linear); its size in bytes in\n"
    "                      the header; near the model's edge it refuses a reading in a cell\n"
    "                      with a node without an angle\n"
    "Exported: dss_physical, dss_polynomial, psd_physical, psd_polynomial, ess_eq12_finecode,\n"
    "ess_extended; the spline, table and hybrid models (dss_, ess_, psd_spline, psd_table)\n"
    "as --form table:STEP only, over their calibrated field (psd_hybrid: not exported).\n"
    "DIR must not exist (export never overwrites).  --quiet: no 'wrote' line.\n";

typedef struct {
    const char *params, *out;
    int use_float, quiet;
    double step;
} export_args;

static int bad(const char *msg, const char *arg)
{
    fprintf(stderr, "sunmc export: %s%s%s (see sunmc export --help)\n", msg, arg ? ": " : "",
            arg ? arg : "");
    return EXIT_BAD_INPUT;
}

static int parse_form(const char *v, double *step)
{
    if (strcmp(v, "model") == 0) {
        *step = 0;
        return 0;
    }
    if (strncmp(v, "table:", 6) != 0)
        return bad("--form takes model or table:STEP", v);
    char *end;
    double s = strtod(v + 6, &end);
    if (end == v + 6 || *end || !(s > 0) || !(s < 1e300))
        return bad("--form table:STEP: STEP must be a number > 0", v);
    *step = s;
    return 0;
}

static int parse(int argc, char **argv, export_args *a)
{
    memset(a, 0, sizeof *a);
    for (int i = 2; i < argc; i++) {
        const char *o = argv[i];
        int has = i + 1 < argc;
        if (strcmp(o, "--out") == 0 || strcmp(o, "--precision") == 0 ||
            strcmp(o, "--form") == 0) {
            if (!has)
                return bad("option needs a value", o);
            const char *v = argv[++i];
            if (strcmp(o, "--out") == 0)
                a->out = v;
            else if (strcmp(o, "--form") == 0) {
                if (parse_form(v, &a->step))
                    return EXIT_BAD_INPUT;
            } else if (strcmp(v, "float") == 0 || strcmp(v, "double") == 0)
                a->use_float = v[0] == 'f';
            else
                return bad("--precision takes float or double", v);
        } else if (strcmp(o, "--quiet") == 0) {
            a->quiet = 1;
        } else if (o[0] == '-' && o[1]) {
            return bad("unknown option", o);
        } else if (a->params) {
            return bad("one PARAMS.ini only", o);
        } else {
            a->params = o;
        }
    }
    if (!a->params || !a->out)
        return bad("needs PARAMS.ini and --out DIR", NULL);
    struct stat sb;
    if (stat(a->out, &sb) == 0) {
        fprintf(stderr, "sunmc export: --out %s exists: export never overwrites; give a new "
                        "directory\n", a->out);
        return EXIT_BAD_INPUT;
    }
    char err[SUNMC_ERRLEN];
    if (out_check(a->out, err, sizeof err) != SUNMC_OK) {
        fprintf(stderr, "sunmc export: %s\n", err);
        return EXIT_BAD_INPUT;
    }
    return 0;
}

/* The family's model of pf, checked exportable, into *model (malloc'd). */
static int load(const export_args *a, const params_file *pf, const family_lab **lab,
                void **model, char *err, size_t errlen)
{
    const char *sensor = NULL;
    int st = params_get_text(pf, "calibration", "sensor", &sensor, err, errlen);
    if (st != SUNMC_OK)
        return st;
    const sensor_family *fam = sensor_family_find(sensor);
    const params_entry *e = params_find(pf, "calibration", "sensor");
    if (!fam || !fam->lab || !fam->lab->export)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: sensor '%s' %s", a->params, e->line,
                          sensor, fam && fam->lab ? "has no export yet"
                                                  : "is not available");
    *lab = fam->lab;
    char warn[SUNMC_ERRLEN] = "";
    *model = malloc(fam->lab->model_size);
    st = *model ? lab_params_load(fam->lab, pf, *model, warn, sizeof warn, err, errlen)
                : sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    if (warn[0])
        fprintf(stderr, "sunmc export: WARNING: %s\n", warn);
    if (st == SUNMC_OK) {
        char why[SUNMC_ERRLEN];
        const params_entry *m = params_find(pf, "calibration", "model");
        if (fam->lab->export->supported(*model, why, sizeof why) != SUNMC_OK)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: %s", a->params,
                            m ? m->line : 0, why);
        else if (!(a->step > 0) && fam->lab->export->model_form &&
                 fam->lab->export->model_form(*model, why, sizeof why) != SUNMC_OK)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: %s", a->params,
                            m ? m->line : 0, why);
    }
    return st;
}

static int write_all(const export_args *a, const lab_export_job *j, char *err, size_t errlen)
{
    char name[LAB_EXPORT_NAME_MAX], files[LAB_EXPORT_FILES][OUT_NAME_MAX];
    int st = lab_export_name(j, name, sizeof name, err, errlen);
    long n[LAB_EXPORT_MAX_AXES], nodes;
    if (st == SUNMC_OK && j->step > 0)
        st = lab_export_table_size(j, n, &nodes, err, errlen);
    if (st != SUNMC_OK)
        return st;
    snprintf(files[0], OUT_NAME_MAX, "sunmc_%s_cal.h", name);
    snprintf(files[1], OUT_NAME_MAX, "sunmc_%s_cal.c", name);
    snprintf(files[2], OUT_NAME_MAX, "test_vectors.csv");
    snprintf(files[3], OUT_NAME_MAX, "test_main.c");
    const char *names[LAB_EXPORT_FILES] = {files[0], files[1], files[2], files[3]};
    FILE *f[LAB_EXPORT_FILES] = {NULL};
    out_set os;
    st = out_begin(&os, a->out, err, errlen);
    if (st != SUNMC_OK)
        return st;
    st = out_open_all(&os, names, f, LAB_EXPORT_FILES, err, errlen);
    if (st == SUNMC_OK)
        st = lab_export_write(j, f, err, errlen);
    if (st == SUNMC_OK)
        st = out_commit(&os, err, errlen);
    else
        out_abort(&os);
    if (st == SUNMC_OK && !a->quiet)
        printf("wrote %s/%s, %s, %s, %s\n", a->out, names[0], names[1], names[2], names[3]);
    return st;
}

int cmd_export(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, export_help))
        return 0;
    export_args a;
    int rc = parse(argc, argv, &a);
    if (rc)
        return rc;
    params_file *pf = malloc(sizeof *pf);
    char err[SUNMC_ERRLEN];
    int st = pf ? params_read(a.params, pf, err, sizeof err)
                : sunmc_fail(err, sizeof err, SUNMC_ENOMEM, "out of memory");
    if (st != SUNMC_OK && st != SUNMC_ENOMEM) /* a params file not read: a bad input */
        st = SUNMC_EINPUT;
    const family_lab *lab = NULL;
    void *model = NULL;
    if (st == SUNMC_OK)
        st = load(&a, pf, &lab, &model, err, sizeof err);
    lab_export_job j = {lab, model, pf, a.params, 0, a.use_float, a.step};
    if (st == SUNMC_OK)
        st = params_file_fnv1a64(a.params, &j.params_fnv1a64, err, sizeof err);
    if (st == SUNMC_OK)
        st = write_all(&a, &j, err, sizeof err);
    if (st != SUNMC_OK)
        fprintf(stderr, "sunmc export: %s\n", err);
    free(model);
    free(pf);
    return cli_exit_code(st);
}
