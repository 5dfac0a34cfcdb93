/* lab_onboard.h - the on-board arithmetic of `sunmc export` in process
 * (issue 42 item 2): a unit's calibration evaluated as the exported C
 * evaluates it, so that `compensate --onboard` and the Monte Carlo key
 * calibration.onboard count what the flight software's form costs.
 *
 *   double       the family's compensate itself (the exported model in
 *                double: the same arithmetic to the last bits)
 *   float        the exported model with -DSUNMC_FLOAT: the family's
 *                float path (lab_export.eval_float), the reading rounded
 *                to float on the way in, the angles float on the way out
 *   table:STEP   the exported table form (double): the nodes by the
 *                double compensate, STEP in the reading axes' unit
 *                shortened to whole cells of the range, the lookup and
 *                its (bi)linear interpolation in the exported code's
 *                order of operations (tests/cli/test_onboard.c compares
 *                both with the compiled export)
 *
 * A unit's table is built into the evaluator's own buffer, grown to the
 * largest table asked for and then reused: a thread's evaluator allocates
 * once for every unit it runs.
 */
#ifndef SUNMC_LAB_ONBOARD_H
#define SUNMC_LAB_ONBOARD_H

#include "lab.h"
#include "lab_export.h"

#include <stddef.h>

enum lab_onboard_form { LAB_ONBOARD_DOUBLE = 0, LAB_ONBOARD_FLOAT, LAB_ONBOARD_TABLE };

typedef struct {
    int form;     /* enum lab_onboard_form */
    double step;  /* table:STEP's step (the reading axes' unit); 0 otherwise */
} lab_onboard_spec;

/* "double", "float" or "table:STEP" (STEP a finite number > 0) into *s;
 * non-OK with a message naming what was wrong otherwise (what: the key or
 * option for the message, e.g. "calibration.onboard"). */
int lab_onboard_parse(const char *text, const char *what, lab_onboard_spec *s, char *err,
                      size_t errlen);

/* calibration.onboard of c into *s, checked: its form, and a family whose
 * Monte Carlo and export take it (a family's unit pipeline validates
 * through lab_onboard when c asks for it: ESS, DSS, PSD).  Messages name the
 * key. */
int lab_onboard_config(const sunmc_config *c, lab_onboard_spec *s, char *err, size_t errlen);

/* The source's name in budget's tables: "ONBOARD_FLOAT", "ONBOARD_TABLE". */
const char *lab_onboard_source_name(const lab_onboard_spec *s);

typedef struct lab_onboard {
    lab_onboard_spec spec;
    const family_lab *lab;
    const void *model;           /* the prepared unit's model (lab.h's model) */
    int n_axes, n_raw, n_comp;
    long n[LAB_EXPORT_MAX_AXES]; /* the table's nodes per axis */
    double lo[LAB_EXPORT_MAX_AXES], h[LAB_EXPORT_MAX_AXES]; /* first node, step */
    double *table;               /* nodes x n_comp, deg; LAB_ONBOARD_NO_NODE: no angle */
    long cap;                    /* doubles table holds */
} lab_onboard;

/* The exported table's mark of a node without an angle. */
#define LAB_ONBOARD_NO_NODE 1e30

/* o for family lab and form s (nothing allocated yet). */
void lab_onboard_init(lab_onboard *o, const family_lab *lab, const lab_onboard_spec *s);
void lab_onboard_free(lab_onboard *o);

/* A Monte Carlo thread's evaluator for config c (a family's workspace):
 * calibration.onboard checked (lab_onboard_config) and, for a table, the
 * table of c's nominal unit built, so that the memory the units' tables
 * take is had now.  Non-OK with a message. */
int lab_onboard_mc_init(lab_onboard *o, const sunmc_config *c, char *err, size_t errlen);

/* The on-board form to validate a unit's fitted model through: NULL for
 * double (the family's own compensation), else o prepared with model; a
 * model the export cannot take sets *fit_ok = 0 (the unit has no on-board
 * calibration: counted as a failed fit). */
const lab_onboard *lab_onboard_mc_unit(lab_onboard *o, const void *model, int *fit_ok);

/* Take model (lab_params_load's, or a Monte Carlo unit's fitted model of
 * the same type) for the evaluations that follow: the table form builds
 * its table.  Non-OK with a message: the family has no export or no
 * float path, the export (or its float path) does not take this model, a
 * table beyond
 * LAB_EXPORT_MAX_NODES, no memory. */
int lab_onboard_prepare(lab_onboard *o, const void *model, char *err, size_t errlen);

/* The prepared model's reading raw through the on-board form:
 * LAB_READING_OK and the angles in deg[n_comp], or why not (enum
 * lab_reading; deg NaN).  raw as family_lab.compensate gets it: the raw
 * columns, then every optional column (NaN when absent): the family's
 * hooks read them. */
int lab_onboard_eval(const lab_onboard *o, const double *raw, double *deg);
/* The same for the raw columns alone (the Monte Carlo's readings), the
 * optional ones NaN. */
int lab_onboard_eval_raw(const lab_onboard *o, const double *raw, double *deg);

/* compensate through o: a copy of o's family_lab whose reading_check and
 * compensate are o's (the model they get is the wrap itself; the optional
 * columns, e.g. the truth of the table angles, still from the family's
 * compensate). */
typedef struct {
    family_lab lab;
    lab_onboard *ob;
} lab_onboard_wrap;

void lab_onboard_wrap_init(lab_onboard_wrap *w, lab_onboard *ob);

#endif
