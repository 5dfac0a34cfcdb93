/* lab_table_params.c - a look-up table calibration in params.ini and back,
 * strictly (lab_table.h).  Node values are floats, written with 9
 * significant digits: they read back bit for bit. */
#include "lab_table.h"
#include "status.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KEY_LEN 32
#define MAX_KEYS (16 + LAB_SPLINE_MAX_BREAK2 + \
                  LAB_TABLE_MAX_OUT * (LAB_TABLE_MAX_VALUES / LAB_TABLE_VALUES_PER_KEY + 1))

static int n_values(const lab_table *t) { return t->dims == 2 ? t->nodes * t->nodes : t->nodes; }
static int blocks_of(const lab_table *t)
{
    return (n_values(t) + LAB_TABLE_VALUES_PER_KEY - 1) / LAB_TABLE_VALUES_PER_KEY;
}
static int n_inputs(const lab_table *t) { return t->dims == 2 ? 2 : t->n_out; }

int lab_table_params_fill(const lab_table *t, params_file *p, const char *section)
{
    char key[KEY_LEN], val[PARAMS_VALUE_MAX];
    int st = params_set_double(p, section, "dims", t->dims,
                               "1: output j over input j; 2: a grid of both inputs");
    st |= params_set_double(p, section, "outputs", t->n_out, NULL);
    st |= params_set_double(p, section, "nodes", t->nodes,
                            "per input, uniform; the step chosen by calibrate's folds");
    for (int k = 0; k < n_inputs(t); k++) {
        snprintf(key, sizeof key, "lo_%d", k);
        st |= params_set_double(p, section, key, t->lo[k], "the tabulated field");
        snprintf(key, sizeof key, "hi_%d", k);
        st |= params_set_double(p, section, key, t->hi[k], NULL);
    }
    if (t->dims == 2)
        st |= params_set_double(p, section, "field_cells", t->field_cells, "per input");
    int nc = t->field_cells;
    for (int r = 0; t->dims == 2 && r < nc; r++) {
        for (int c = 0; c < nc; c++)
            val[c] = t->cell[r * nc + c] ? '1' : '0';
        val[nc] = '\0';
        snprintf(key, sizeof key, "field_%d", r);
        st |= params_set_text(p, section, key, val, r ? NULL : "cells the data visited");
    }
    for (int j = 0; j < t->n_out; j++)
        for (int b = 0; b < blocks_of(t); b++) {
            size_t at = 0;
            for (int q = b * LAB_TABLE_VALUES_PER_KEY;
                 q < n_values(t) && q < (b + 1) * LAB_TABLE_VALUES_PER_KEY; q++)
                at += (size_t)snprintf(val + at, sizeof val - at, "%s%.9g", at ? " " : "",
                                       (double)t->v[j][q]);
            snprintf(key, sizeof key, "v%d_%d", j, b);
            st |= params_set_text(p, section, key, val, b ? NULL : "node values, row by row");
        }
    return st ? SUNMC_EINPUT : SUNMC_OK;
}

static int keys_known(const params_file *p, const char *section, const lab_table *t, char *err,
                      size_t errlen)
{
    char buf[MAX_KEYS][KEY_LEN];
    const char *names[MAX_KEYS];
    int n = 0;
    static const char *const fixed[] = {"dims", "outputs", "nodes", "field_cells"};
    for (; n < (t->dims == 2 ? 4 : 3); n++)
        names[n] = fixed[n];
    for (int k = 0; k < n_inputs(t); k++) {
        snprintf(buf[n], KEY_LEN, "lo_%d", k), names[n] = buf[n], n++;
        snprintf(buf[n], KEY_LEN, "hi_%d", k), names[n] = buf[n], n++;
    }
    for (int r = 0; t->dims == 2 && r < t->field_cells; r++)
        snprintf(buf[n], KEY_LEN, "field_%d", r), names[n] = buf[n], n++;
    for (int j = 0; j < t->n_out; j++)
        for (int b = 0; b < blocks_of(t); b++)
            snprintf(buf[n], KEY_LEN, "v%d_%d", j, b), names[n] = buf[n], n++;
    return params_check_keys(p, section, names, n, err, errlen);
}

static int load_field(const params_file *p, const char *section, lab_table *t, char *err,
                      size_t errlen)
{
    int nc = t->field_cells, st = SUNMC_OK;
    for (int r = 0; r < nc && st == SUNMC_OK; r++) {
        char key[KEY_LEN];
        const char *s;
        snprintf(key, sizeof key, "field_%d", r);
        st = params_get_text(p, section, key, &s, err, errlen);
        int ok = st == SUNMC_OK && (int)strlen(s) == nc;
        for (int c = 0; ok && c < nc; c++) {
            ok = s[c] == '0' || s[c] == '1';
            t->cell[r * nc + c] = s[c] == '1';
        }
        if (st == SUNMC_OK && !ok)
            st = params_require(p, section, key, 0, "one 0 or 1 per cell (field_cells of them)",
                                err, errlen);
    }
    return st;
}

static int load_values(const params_file *p, const char *section, lab_table *t, int j, int b,
                       char *err, size_t errlen)
{
    char key[KEY_LEN];
    const char *s;
    snprintf(key, sizeof key, "v%d_%d", j, b);
    int st = params_get_text(p, section, key, &s, err, errlen);
    int q = b * LAB_TABLE_VALUES_PER_KEY;
    int end = q + LAB_TABLE_VALUES_PER_KEY < n_values(t) ? q + LAB_TABLE_VALUES_PER_KEY
                                                          : n_values(t);
    while (st == SUNMC_OK && q < end) {
        char *e;
        double v = strtod(s, &e);
        if (e == s || !isfinite(v) || !isfinite((float)v))
            break;
        t->v[j][q++] = (float)v;
        s = e;
    }
    while (st == SUNMC_OK && (*s == ' ' || *s == '\t'))
        s++;
    if (st == SUNMC_OK && (q != end || *s != '\0'))
        st = params_require(p, section, key, 0, "the block's node values, finite numbers", err,
                            errlen);
    return st;
}

/* nodes: 2^k + 1 within the dims' range. */
static int nodes_ok(const lab_table *t)
{
    int top = t->dims == 2 ? LAB_TABLE_MAX_LOG2 : LAB_TABLE_MAX_LOG1;
    for (int lg = LAB_TABLE_MIN_LOG; lg <= top; lg++)
        if (t->nodes == (1 << lg) + 1)
            return 1;
    return 0;
}

static int load_counts(const params_file *p, const char *section, lab_table *t, char *err,
                       size_t errlen)
{
    const params_range r[] = {{section, "dims", 1, 2, "", NULL},
                              {section, "outputs", 1, LAB_TABLE_MAX_OUT, "", NULL},
                              {section, "nodes", 3, LAB_TABLE_MAX_NODES1, "", NULL}};
    int st = params_check_ranges(p, r, 3, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_int(p, section, "dims", &t->dims, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_int(p, section, "outputs", &t->n_out, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_int(p, section, "nodes", &t->nodes, err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, section, "nodes", nodes_ok(t),
                            t->dims == 2 ? "2^k + 1, 3 to 17 for dims = 2"
                                         : "2^k + 1, 3 to 257", err, errlen);
    if (st == SUNMC_OK && t->dims == 2) {
        const params_range f = {section, "field_cells", 1, LAB_SPLINE_MAX_BREAK2 - 1, "", NULL};
        st = params_check_ranges(p, &f, 1, err, errlen);
        if (st == SUNMC_OK)
            st = params_get_int(p, section, "field_cells", &t->field_cells, err, errlen);
    }
    return st;
}

int lab_table_params_load(const params_file *p, const char *section, lab_table *t, char *err,
                          size_t errlen)
{
    memset(t, 0, sizeof *t);
    int st = load_counts(p, section, t, err, errlen);
    if (st == SUNMC_OK)
        st = keys_known(p, section, t, err, errlen);
    char key[KEY_LEN];
    for (int k = 0; k < n_inputs(t) && st == SUNMC_OK; k++) {
        snprintf(key, sizeof key, "lo_%d", k);
        st = params_get_double(p, section, key, &t->lo[k], err, errlen);
        snprintf(key, sizeof key, "hi_%d", k);
        if (st == SUNMC_OK)
            st = params_get_double(p, section, key, &t->hi[k], err, errlen);
        if (st == SUNMC_OK)
            st = params_require(p, section, key, t->hi[k] > t->lo[k], "above lo", err, errlen);
    }
    if (st == SUNMC_OK && t->dims == 2)
        st = load_field(p, section, t, err, errlen);
    for (int j = 0; j < t->n_out && st == SUNMC_OK; j++)
        for (int b = 0; b < blocks_of(t) && st == SUNMC_OK; b++)
            st = load_values(p, section, t, j, b, err, errlen);
    return st;
}
