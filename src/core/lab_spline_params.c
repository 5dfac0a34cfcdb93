/* lab_spline_params.c - a spline calibration in params.ini and back,
 * strictly (lab_spline.h). */
#include "lab_spline.h"
#include "status.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KEY_LEN 32
/* The most keys a spline section has: the fixed ones, the field rows and
 * the coefficient blocks. */
#define MAX_KEYS (16 + LAB_SPLINE_MAX_BREAK2 + \
                  LAB_SPLINE_MAX_OUT * (LAB_SPLINE_MAX_COEF / LAB_SPLINE_COEF_PER_KEY + 1))

static int blocks_of(int n_coef)
{
    return (n_coef + LAB_SPLINE_COEF_PER_KEY - 1) / LAB_SPLINE_COEF_PER_KEY;
}

static int n_inputs(const lab_spline *s) { return s->dims == 2 ? 2 : s->n_out; }

int lab_spline_params_fill(const lab_spline *s, params_file *p, const char *section)
{
    char key[KEY_LEN], val[PARAMS_VALUE_MAX];
    int st = params_set_double(p, section, "dims", s->dims,
                               "1: output j of input j; 2: tensor product of both inputs");
    st |= params_set_double(p, section, "outputs", s->n_out, NULL);
    if (s->cross)
        st |= params_set_double(p, section, "cross", 1,
                                "plus a spline of the other input (an additive model)");
    st |= params_set_double(p, section, "breakpoints", s->nbreak, "uniform, per input");
    st |= params_set_double(p, section, "smoothing", s->smooth,
                            "chosen by the held-out error of calibrate's folds");
    for (int j = 0; j < s->n_out; j++) {
        snprintf(key, sizeof key, "edf_%d", j);
        st |= params_set_double(p, section, key, s->edf[j], "effective degrees of freedom");
    }
    for (int k = 0; k < n_inputs(s); k++) {
        snprintf(key, sizeof key, "lo_%d", k);
        st |= params_set_double(p, section, key, s->lo[k], "the calibrated field");
        snprintf(key, sizeof key, "hi_%d", k);
        st |= params_set_double(p, section, key, s->hi[k], NULL);
    }
    int nc = s->nbreak - 1;
    for (int r = 0; s->dims == 2 && r < nc; r++) {
        for (int c = 0; c < nc; c++)
            val[c] = s->cell[r * nc + c] ? '1' : '0';
        val[nc] = '\0';
        snprintf(key, sizeof key, "field_%d", r);
        st |= params_set_text(p, section, key, val, r ? NULL : "cells the data visited");
    }
    for (int j = 0; j < s->n_out; j++)
        for (int b = 0; b < blocks_of(s->n_coef); b++) {
            size_t at = 0;
            for (int q = b * LAB_SPLINE_COEF_PER_KEY;
                 q < s->n_coef && q < (b + 1) * LAB_SPLINE_COEF_PER_KEY; q++)
                at += (size_t)snprintf(val + at, sizeof val - at, "%s%.17g", at ? " " : "",
                                       s->coef[j][q]);
            snprintf(key, sizeof key, "c%d_%d", j, b);
            st |= params_set_text(p, section, key, val, NULL);
        }
    return st ? SUNMC_EINPUT : SUNMC_OK;
}

/* Every key of section is one of s's (its counts known). */
static int keys_known(const params_file *p, const char *section, const lab_spline *s,
                      char *err, size_t errlen)
{
    char buf[MAX_KEYS][KEY_LEN];
    const char *names[MAX_KEYS];
    int n = 0;
    static const char *const fixed[] = {"dims", "outputs", "breakpoints", "smoothing", "cross"};
    for (; n < 4 + (s->cross ? 1 : 0); n++)
        names[n] = fixed[n];
    for (int j = 0; j < s->n_out; j++)
        snprintf(buf[n], KEY_LEN, "edf_%d", j), names[n] = buf[n], n++;
    for (int k = 0; k < n_inputs(s); k++) {
        snprintf(buf[n], KEY_LEN, "lo_%d", k), names[n] = buf[n], n++;
        snprintf(buf[n], KEY_LEN, "hi_%d", k), names[n] = buf[n], n++;
    }
    for (int r = 0; s->dims == 2 && r < s->nbreak - 1; r++)
        snprintf(buf[n], KEY_LEN, "field_%d", r), names[n] = buf[n], n++;
    for (int j = 0; j < s->n_out; j++)
        for (int b = 0; b < blocks_of(s->n_coef); b++)
            snprintf(buf[n], KEY_LEN, "c%d_%d", j, b), names[n] = buf[n], n++;
    return params_check_keys(p, section, names, n, err, errlen);
}

/* The cells of field_<r>: nbreak - 1 characters, each 0 or 1. */
static int load_field(const params_file *p, const char *section, lab_spline *s, char *err,
                      size_t errlen)
{
    int nc = s->nbreak - 1, st = SUNMC_OK;
    for (int r = 0; r < nc && st == SUNMC_OK; r++) {
        char key[KEY_LEN];
        const char *t;
        snprintf(key, sizeof key, "field_%d", r);
        st = params_get_text(p, section, key, &t, err, errlen);
        int ok = st == SUNMC_OK && (int)strlen(t) == nc;
        for (int c = 0; ok && c < nc; c++) {
            ok = t[c] == '0' || t[c] == '1';
            s->cell[r * nc + c] = t[c] == '1';
        }
        if (st == SUNMC_OK && !ok)
            st = params_require(p, section, key, 0, "one 0 or 1 per cell (breakpoints - 1)",
                                err, errlen);
    }
    return st;
}

/* c<j>_<b>: the block's coefficients, whitespace-separated numbers. */
static int load_coef(const params_file *p, const char *section, lab_spline *s, int j, int b,
                     char *err, size_t errlen)
{
    char key[KEY_LEN];
    const char *t;
    snprintf(key, sizeof key, "c%d_%d", j, b);
    int st = params_get_text(p, section, key, &t, err, errlen);
    int q = b * LAB_SPLINE_COEF_PER_KEY;
    int end = q + LAB_SPLINE_COEF_PER_KEY < s->n_coef ? q + LAB_SPLINE_COEF_PER_KEY : s->n_coef;
    while (st == SUNMC_OK && q < end) {
        char *e;
        double v = strtod(t, &e);
        if (e == t || !isfinite(v))
            break;
        s->coef[j][q++] = v;
        t = e;
    }
    while (st == SUNMC_OK && (*t == ' ' || *t == '\t'))
        t++;
    if (st == SUNMC_OK && (q != end || *t != '\0'))
        st = params_require(p, section, key, 0, "the block's coefficients, finite numbers",
                            err, errlen);
    return st;
}

/* cross: absent (off, as before the key existed) or 1, for dims 1 with
 * two outputs only. */
static int load_cross(const params_file *p, const char *section, lab_spline *s, char *err,
                      size_t errlen)
{
    if (!params_find(p, section, "cross"))
        return SUNMC_OK;
    const params_range r[] = {{section, "cross", 1, 1, "", NULL}};
    int st = params_check_ranges(p, r, 1, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_int(p, section, "cross", &s->cross, err, errlen);
    if (st == SUNMC_OK)
        st = params_require(p, section, "cross", s->dims == 1 && s->n_out == 2,
                            "only with dims = 1 and outputs = 2", err, errlen);
    return st;
}

int lab_spline_params_load(const params_file *p, const char *section, lab_spline *s, char *err,
                           size_t errlen)
{
    memset(s, 0, sizeof *s);
    const params_range r[] = {
        {section, "dims", 1, 2, "", NULL},
        {section, "outputs", 1, LAB_SPLINE_MAX_OUT, "", NULL},
        {section, "breakpoints", LAB_SPLINE_MIN_BREAK, LAB_SPLINE_MAX_BREAK1, "", NULL},
        {section, "smoothing", 0, 1e300, "", NULL}};
    int st = params_check_ranges(p, r, 4, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_int(p, section, "dims", &s->dims, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_int(p, section, "outputs", &s->n_out, err, errlen);
    if (st == SUNMC_OK)
        st = params_get_int(p, section, "breakpoints", &s->nbreak, err, errlen);
    if (st == SUNMC_OK && s->dims == 2 && s->nbreak > LAB_SPLINE_MAX_BREAK2)
        st = params_require(p, section, "breakpoints", 0, "at most 11 for dims = 2", err,
                            errlen);
    if (st == SUNMC_OK)
        st = params_get_double(p, section, "smoothing", &s->smooth, err, errlen);
    if (st == SUNMC_OK)
        st = load_cross(p, section, s, err, errlen);
    if (st != SUNMC_OK)
        return st;
    int p1 = s->nbreak + LAB_SPLINE_ORDER - 2;
    s->n_coef = s->dims == 2 ? p1 * p1 : p1 + (s->cross ? LAB_SPLINE_CROSS_COEF : 0);
    st = keys_known(p, section, s, err, errlen);
    char key[KEY_LEN];
    for (int j = 0; j < s->n_out && st == SUNMC_OK; j++) {
        snprintf(key, sizeof key, "edf_%d", j);
        st = params_get_double(p, section, key, &s->edf[j], err, errlen);
    }
    for (int k = 0; k < n_inputs(s) && st == SUNMC_OK; k++) {
        snprintf(key, sizeof key, "lo_%d", k);
        st = params_get_double(p, section, key, &s->lo[k], err, errlen);
        snprintf(key, sizeof key, "hi_%d", k);
        if (st == SUNMC_OK)
            st = params_get_double(p, section, key, &s->hi[k], err, errlen);
        if (st == SUNMC_OK)
            st = params_require(p, section, key, s->hi[k] > s->lo[k], "above lo", err, errlen);
    }
    if (st == SUNMC_OK && s->dims == 2)
        st = load_field(p, section, s, err, errlen);
    for (int j = 0; j < s->n_out && st == SUNMC_OK; j++)
        for (int b = 0; b < blocks_of(s->n_coef) && st == SUNMC_OK; b++)
            st = load_coef(p, section, s, j, b, err, errlen);
    return st;
}
