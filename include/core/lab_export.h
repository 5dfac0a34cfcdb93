/* lab_export.h - `sunmc export` (issue 42): a unit's calibration as C99
 * source a flight computer compiles, the part every family shares.  The
 * family gives its model's arithmetic as C statements (lab_export, a hook
 * of family_lab); core writes around them the header, the reading check,
 * the function, the table form, the test vectors and the test program.
 *
 * The exported function (NAME = the params' model line, e.g. dss_physical):
 *     int sunmc_NAME_cal(const sunmc_real raw[N_RAW], sunmc_real angle_deg[N_ANGLES]);
 * raw in the units of compensate's raw columns, angles in deg as
 * compensate's columns; returns SUNMC_CAL_OK (0) or why the reading has no
 * angle (the codes of enum lab_reading).  sunmc_real is float with
 * -DSUNMC_FLOAT, double with -DSUNMC_DOUBLE, else the --precision chosen.
 * The generated code uses <math.h> and <stdint.h> only, no allocation, no
 * recursion, loops of fixed bounds, no writable static data.
 *
 * The table form (step > 0) tabulates the compensated angles on a grid of
 * the family's reading axes (lab_export.n_axes: 1 linear, 2 bilinear)
 * with the step in the axes' unit; a cell with a node the model cannot
 * invert gives SUNMC_CAL_NO_INVERSE.
 */
#ifndef SUNMC_LAB_EXPORT_H
#define SUNMC_LAB_EXPORT_H

#include "lab.h"
#include "params_io.h"

#include <stdio.h>

#define LAB_EXPORT_MAX_AXES 2
/* Largest table the export writes (nodes per angle). */
#define LAB_EXPORT_MAX_NODES 1000000L
/* Test vectors per axis (a grid reaching LAB_EXPORT_VEC_MARGIN beyond the
 * axes' range on each side, so that refused readings are in it too). */
#define LAB_EXPORT_VEC_2D 41
#define LAB_EXPORT_VEC_1D 801
#define LAB_EXPORT_VEC_MARGIN 0.05

/* A family's model as C code (NULL hooks: that model is not exported). */
typedef struct lab_export {
    int n_axes;                     /* the table's reading axes: 1 or 2 */
    const char *const *axis_names;  /* with their unit ("x_px") */
    /* Can this model be exported?  Non-OK (message) when not. */
    int (*supported)(const void *model, char *err, size_t errlen);
    /* The range of the axes the unit's readings take. */
    void (*axes_range)(const void *model, double *lo, double *hi);
    /* 1 when the axes are the raw reading's first n_axes columns
     * themselves (q[a] = raw[a]): core then gives raw_at, emit_axes and
     * axes_at (lab_export_axes.c), and the family leaves them NULL. */
    int axes_are_raw;
    /* The raw reading (compensate's raw columns) at axes values q. */
    void (*raw_at)(const void *model, const double *q, double *raw);
    /* Static functions the model calls (NULL: none; not in the table form). */
    void (*emit_helpers)(const void *model, FILE *f);
    /* C statements: the axes q[] (sunmc_real) of the reading raw[]; may
     * `return SUNMC_CAL_NO_INVERSE;`. */
    void (*emit_axes)(const void *model, FILE *f);
    /* C statements of the reading check, from raw[]: `return
     * SUNMC_CAL_...;` for a reading the unit cannot produce (the rules of
     * reading_check); falls through otherwise. */
    void (*emit_check)(const void *model, FILE *f);
    /* C statements of the model, from raw[] into ang[] (rad); may `return
     * SUNMC_CAL_NO_INVERSE;`.  Constants as SR(literal), functions as
     * SR_SQRT, SR_ATAN2, SR_ATAN, SR_ASIN, SR_SIN, SR_COS, SR_FABS. */
    void (*emit_model)(const void *model, FILE *f);
    /* The fixed loop counts of the model, for the header comment. */
    const char *iterations;
    /* In process (lab_onboard.h): the axes q of reading raw as emit_axes's
     * statements compute them, in double; non-OK where they give no number. */
    int (*axes_at)(const void *model, const double *raw, double *q);
    /* The exported function built with -DSUNMC_FLOAT, in process: the
     * reading check and the model, each operation in float as the
     * generated code does it, into ang_rad (sunmc_model's angles, rad, one
     * per comp_column); core then makes the function's last step
     * (lab_onboard.c: an angle of 1e29 or more is none, the rest in deg).
     * Returns enum lab_reading; NULL: the family has no float path (the
     * onboard float is refused). */
    int (*eval_float)(const void *model, const float *raw, float *ang_rad);
    /* Has eval_float this (supported) model?  Non-OK (message) when not;
     * NULL: every model the export takes. */
    int (*float_supported)(const void *model, char *err, size_t errlen);
    /* 1 when the family's Monte Carlo validates through lab_onboard
     * (calibration.onboard; its unit model is this model's type). */
    int onboard_mc;
    /* onboard_mc: the nominal model of config c (its table's size is
     * checked with the config, and a thread's table made for it). */
    void (*nominal)(const sunmc_config *c, void *model);
    /* Can the model form (no --form table:STEP) be written?  Non-OK (a
     * message naming the alternative) when not: an empirical model (a
     * spline, a table) is exported as the table form only.  NULL: yes. */
    int (*model_form)(const void *model, char *err, size_t errlen);
} lab_export;

typedef struct {
    const family_lab *lab;
    const void *model;          /* lab_params_load's */
    const params_file *pf;
    const char *params_path;
    unsigned long long params_fnv1a64; /* of the params file's bytes */
    int use_float;              /* the default sunmc_real */
    double step;                /* table step in the axes' unit; 0: the model form */
} lab_export_job;

/* The model_form refusal of a model exported as its table form only
 * (lab_export_form.c): names the model (family_model, as params.ini's
 * model line) and the axes' unit of STEP. */
int lab_export_table_only(const char *family, const char *model, const char *axes, char *err,
                          size_t errlen);

/* The reading axes of x whichever gives them (lab_export_axes.c): the
 * family's hooks, or with x->axes_are_raw the identity on the first
 * x->n_axes raw columns (the units of compensate's raw columns, e.g. deg,
 * px).  raw_at: raw[0 .. n_axes-1] at axes q[0 .. n_axes-1] (no other
 * column written); axes_at: q from raw, non-OK where the family gives no
 * number; emit_axes: the C statements "q[a] = raw[a];"; has_axes: 1 when
 * axes_at is there (lab_onboard's table path), 0 when not. */
void lab_export_raw_at(const lab_export *x, const void *model, const double *q, double *raw);
int lab_export_axes_at(const lab_export *x, const void *model, const double *raw, double *q);
void lab_export_emit_axes(const lab_export *x, const void *model, FILE *f);
int lab_export_has_axes(const lab_export *x);

/* File names of the export (header, source, vectors, test program). */
#define LAB_EXPORT_FILES 4
#define LAB_EXPORT_NAME_MAX 48

/* The model's name as the files and function take it ("dss_physical"),
 * checked: letters, digits and '_'. */
int lab_export_name(const lab_export_job *j, char *name, size_t len, char *err, size_t errlen);

/* Nodes per axis of j's table and their total (*nodes); non-OK for a table
 * beyond LAB_EXPORT_MAX_NODES or a step that is not positive. */
int lab_export_table_size(const lab_export_job *j, long n[LAB_EXPORT_MAX_AXES], long *nodes,
                          char *err, size_t errlen);

/* The reading's status and angles (deg) by sunmc's double compensate:
 * reading_check, then compensate (comp_one of lab.c). */
int lab_export_reference(const family_lab *lab, const void *model, const double *raw,
                         double *deg);

/* Write the four files (f[0] header, f[1] source, f[2] test_vectors.csv,
 * f[3] test_main.c). */
int lab_export_write(const lab_export_job *j, FILE *const f[LAB_EXPORT_FILES], char *err,
                     size_t errlen);

#endif
