/* lab_table.h - the family-neutral look-up table calibration model
 * (calibration.model = table, issue 39): each output of a calibration
 * tabulated on a regular grid of the family's natural reading and read
 * back by linear (dims 1) or bilinear (dims 2) interpolation between the
 * nodes, the field's "look-up table" a flight computer holds.
 *
 *   dims 1: output j is tabulated over input j alone, `nodes` values from
 *           lo[j] to hi[j] (single-axis sweeps);
 *   dims 2: every output is tabulated on the nodes x nodes grid of
 *           inputs 0 and 1.
 *
 * How a node gets its value: it is the penalised B-spline of the same rows
 * (lab_spline.h, its smoothing chosen by the folds) sampled at the node,
 * and rounded to a 32-bit float, the table's stored form: the table is the
 * smoothed calibration points, not a raw average of the points that fell
 * near it, so an empty bin between points still has a value the curvature
 * penalty carried across it.
 *
 * The grid step: nodes = 2^k + 1 (each step halves the one before, so
 * every coarser table's nodes are a subset of the finest one's).  For each
 * of the caller's cross-validation folds the spline is refitted without
 * the fold (at the full fit's smoothing) and sampled; the held-out rows are
 * scored through each table; the coarsest table whose pooled held-out RMS
 * lies within LAB_TABLE_STEP_TOL of the best wins: a finer one would cost
 * memory for an error the folds cannot see.
 *
 * The tabulated field is the spline's calibrated field (each input within
 * the range of the used rows; dims 2: a cell of the spline's knot grid that
 * held a row).  lab_table_eval refuses a reading outside it (SUNMC_EDOM). */
#ifndef SUNMC_LAB_TABLE_H
#define SUNMC_LAB_TABLE_H

#include "lab_spline.h"
#include "params_io.h"

#include <stddef.h>

#define LAB_TABLE_MAX_OUT LAB_SPLINE_MAX_OUT
#define LAB_TABLE_MIN_LOG 1                      /* 3 nodes per input */
#define LAB_TABLE_MAX_LOG1 8                     /* 257 nodes, dims 1 */
#define LAB_TABLE_MAX_LOG2 4                     /* 17 x 17 nodes, dims 2 */
#define LAB_TABLE_MAX_NODES1 ((1 << LAB_TABLE_MAX_LOG1) + 1)
#define LAB_TABLE_MAX_NODES2 ((1 << LAB_TABLE_MAX_LOG2) + 1)
#define LAB_TABLE_MAX_VALUES                                                        \
    (LAB_TABLE_MAX_NODES1 > LAB_TABLE_MAX_NODES2 * LAB_TABLE_MAX_NODES2             \
         ? LAB_TABLE_MAX_NODES1 : LAB_TABLE_MAX_NODES2 * LAB_TABLE_MAX_NODES2)
/* The coarsest table within this fraction of the best held-out RMS wins. */
#define LAB_TABLE_STEP_TOL 0.02
/* Node values per params.ini value (v<output>_<block> = "v v v ..."). */
#define LAB_TABLE_VALUES_PER_KEY 24

typedef struct {
    int dims, n_out;
    int nodes;                          /* per input: 2^k + 1 */
    double lo[2], hi[2];                /* the tabulated field per input */
    int field_cells;                    /* dims 2: cells per input of the field's grid */
    unsigned char cell[LAB_SPLINE_MAX_CELLS]; /* dims 2: cells the data visited */
    float v[LAB_TABLE_MAX_OUT][LAB_TABLE_MAX_VALUES]; /* dims 2: v[j][a * nodes + b] */
} lab_table;

/* s's values at nodes = 2^log_nodes + 1 per input, its field: t.
 * SUNMC_EINPUT when log_nodes is out of range for s's dims. */
int lab_table_sample(lab_table *t, const lab_spline *s, int log_nodes, char *err, size_t errlen);

/* Outputs y[j] at reading x[k] by (bi)linear interpolation: SUNMC_OK, or
 * SUNMC_EDOM outside the tabulated field (y left NaN). */
int lab_table_eval(const lab_table *t, const double *x, double *y);

/* The grid step by cross-validation (the header's rule) for the rows d
 * whose spline s was fitted (by lab_spline_fit or lab_spline_choose):
 * fold[i] < n_folds as lab_spline_choose's (n_folds < 2: the finest
 * table).  *cv_rms: the chosen table's pooled held-out RMS (NaN when no
 * fold could be scored), *n_outside: held-out rows outside their refit's
 * field. */
int lab_table_choose(lab_table *t, const lab_spline *s, const lab_spline_data *d,
                     const int *fold, int n_folds, double *cv_rms, long *n_outside, char *err,
                     size_t errlen);

/* The same on a thread's workspace (lab_spline.h): nothing allocated. */
int lab_table_choose_ws(lab_table *t, const lab_spline *s, const lab_spline_data *d,
                        const int *fold, int n_folds, lab_spline_ws *w, double *cv_rms,
                        long *n_outside, char *err, size_t errlen);

/* Grid step of input k (same unit as the input). */
double lab_table_step(const lab_table *t, int k);
/* The table's size as stored: its node values, 4 bytes each. */
size_t lab_table_bytes(const lab_table *t);

/* params.ini: t into section (keys dims, outputs, nodes, lo_<k>, hi_<k>,
 * field_cells and field_<row> (dims 2), v<j>_<block>), and back strictly:
 * every key known, every count in range, every value a finite number
 * ("FILE:LINE: ..."). */
int lab_table_params_fill(const lab_table *t, params_file *p, const char *section);
int lab_table_params_load(const params_file *p, const char *section, lab_table *t, char *err,
                          size_t errlen);

#endif
