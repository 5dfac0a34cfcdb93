/* h5out.c - a run's TSV tables and config as one HDF5 file (h5out.h). */
#include "h5out.h"
#include "status.h"

#include <hdf5.h>

#include <dlfcn.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The HDF5 library is loaded when a run asks for results.h5 (dlopen), not
 * linked: linked, it and its thirty-odd dependencies (curl, TLS, Kerberos,
 * ...) cost every sunmc process about 12 ms of CPU at start-up, a test
 * suite's worth of seconds.  The functions and global type ids h5out uses
 * come from the library through the table h5; the macros below send the
 * code's (and hdf5.h's) names there, so the code reads as plain HDF5. */
#ifndef SUNMC_HDF5_LIB
#define SUNMC_HDF5_LIB "libhdf5_serial.so"
#endif
/* Overrides the library's name (a path, or a name the loader searches). */
#define H5OUT_LIB_ENV "SUNMC_HDF5_LIB"

#define H5OUT_FUNCS(X)                                                                            \
    X(H5open) X(H5Fcreate) X(H5Fclose) X(H5Gcreate2) X(H5Gclose) X(H5Dcreate2) X(H5Dwrite)        \
    X(H5Dclose) X(H5Acreate2) X(H5Awrite) X(H5Aclose) X(H5Screate) X(H5Screate_simple)           \
    X(H5Sclose) X(H5Tcopy) X(H5Tset_size) X(H5Tset_strpad) X(H5Tset_cset) X(H5Tclose)            \
    X(H5Pcreate) X(H5Pclose) X(H5Pset_obj_track_times) X(H5Lexists) X(H5Eset_auto2)        \
    X(H5check_version)
#define H5OUT_IDS(X)                                                                              \
    X(H5T_NATIVE_DOUBLE_g) X(H5T_NATIVE_INT64_g) X(H5T_STD_I64LE_g) X(H5T_IEEE_F64LE_g)         \
    X(H5T_C_S1_g) X(H5P_CLS_DATASET_CREATE_ID_g) X(H5P_CLS_FILE_CREATE_ID_g)                    \
    X(H5P_CLS_GROUP_CREATE_ID_g)

static struct {
    void *lib;
#define H5OUT_FUNC_PTR(f) __typeof__(f) *f;
#define H5OUT_ID_PTR(g) hid_t *g;
    H5OUT_FUNCS(H5OUT_FUNC_PTR)
    H5OUT_IDS(H5OUT_ID_PTR)
} h5;

int h5out_load(char *err, size_t errlen)
{
    if (h5.lib)
        return SUNMC_OK;
    const char *name = getenv(H5OUT_LIB_ENV);
    if (!name || !*name)
        name = SUNMC_HDF5_LIB;
    void *lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
    if (!lib)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--format hdf5 needs the HDF5 library (%s): %s; install libhdf5 "
                          "(scripts/install-deps.sh) or set " H5OUT_LIB_ENV " to its path",
                          name, dlerror());
    const char *missing = NULL;
#define H5OUT_FUNC_LOAD(f)                                                                        \
    if (!missing && !(*(void **)&h5.f = dlsym(lib, #f)))                                          \
        missing = #f;
#define H5OUT_ID_LOAD(g)                                                                          \
    if (!missing && !(h5.g = (hid_t *)dlsym(lib, #g)))                                            \
        missing = #g;
    H5OUT_FUNCS(H5OUT_FUNC_LOAD)
    H5OUT_IDS(H5OUT_ID_LOAD)
    if (missing) {
        dlclose(lib);
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--format hdf5: %s is not an HDF5 library sunmc can use (no %s)", name,
                          missing);
    }
    h5.lib = lib;
    return SUNMC_OK;
}

/* From here on, HDF5's names are the loaded library's. */
#define H5OUT_FUNC_NAME(f) (*h5.f)
#define H5open H5OUT_FUNC_NAME(H5open)
#define H5check_version H5OUT_FUNC_NAME(H5check_version)
#define H5Fcreate H5OUT_FUNC_NAME(H5Fcreate)
#define H5Fclose H5OUT_FUNC_NAME(H5Fclose)
#define H5Gcreate2 H5OUT_FUNC_NAME(H5Gcreate2)
#define H5Gclose H5OUT_FUNC_NAME(H5Gclose)
#define H5Dcreate2 H5OUT_FUNC_NAME(H5Dcreate2)
#define H5Dwrite H5OUT_FUNC_NAME(H5Dwrite)
#define H5Dclose H5OUT_FUNC_NAME(H5Dclose)
#define H5Acreate2 H5OUT_FUNC_NAME(H5Acreate2)
#define H5Awrite H5OUT_FUNC_NAME(H5Awrite)
#define H5Aclose H5OUT_FUNC_NAME(H5Aclose)
#define H5Screate H5OUT_FUNC_NAME(H5Screate)
#define H5Screate_simple H5OUT_FUNC_NAME(H5Screate_simple)
#define H5Sclose H5OUT_FUNC_NAME(H5Sclose)
#define H5Tcopy H5OUT_FUNC_NAME(H5Tcopy)
#define H5Tset_size H5OUT_FUNC_NAME(H5Tset_size)
#define H5Tset_strpad H5OUT_FUNC_NAME(H5Tset_strpad)
#define H5Tset_cset H5OUT_FUNC_NAME(H5Tset_cset)
#define H5Tclose H5OUT_FUNC_NAME(H5Tclose)
#define H5Pcreate H5OUT_FUNC_NAME(H5Pcreate)
#define H5Pclose H5OUT_FUNC_NAME(H5Pclose)
#define H5Pset_obj_track_times H5OUT_FUNC_NAME(H5Pset_obj_track_times)
#define H5Lexists H5OUT_FUNC_NAME(H5Lexists)
#define H5Eset_auto2 H5OUT_FUNC_NAME(H5Eset_auto2)
#define H5T_NATIVE_DOUBLE_g (*h5.H5T_NATIVE_DOUBLE_g)
#define H5T_NATIVE_INT64_g (*h5.H5T_NATIVE_INT64_g)
#define H5T_STD_I64LE_g (*h5.H5T_STD_I64LE_g)
#define H5T_IEEE_F64LE_g (*h5.H5T_IEEE_F64LE_g)
#define H5T_C_S1_g (*h5.H5T_C_S1_g)
#define H5P_CLS_DATASET_CREATE_ID_g (*h5.H5P_CLS_DATASET_CREATE_ID_g)
#define H5P_CLS_FILE_CREATE_ID_g (*h5.H5P_CLS_FILE_CREATE_ID_g)
#define H5P_CLS_GROUP_CREATE_ID_g (*h5.H5P_CLS_GROUP_CREATE_ID_g)

/* A TSV table read whole: cell (r, c) is cell[r * ncol + c], r = 0 the header. */
typedef struct {
    char *text;
    char **cell;
    size_t nrow, ncol; /* nrow counts the data rows, not the header */
} h5_table;

static int slurp(const char *path, char **text, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot read (%s)", path, strerror(errno));
    size_t cap = 1 << 16, n = 0;
    char *b = malloc(cap);
    for (size_t got = 1; b && got > 0;) {
        if (n + 1 >= cap) {
            char *nb = realloc(b, cap *= 2);
            if (!nb) {
                free(b);
                b = NULL;
                break;
            }
            b = nb;
        }
        got = fread(b + n, 1, cap - n - 1, f);
        n += got;
    }
    int bad = ferror(f);
    fclose(f);
    if (!b)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory reading it", path);
    if (bad) {
        free(b);
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: read error", path);
    }
    b[n] = '\0';
    *text = b;
    return SUNMC_OK;
}

/* Split t->text in place into lines and tab-separated cells. */
static int table_split(h5_table *t, const char *path, char *err, size_t errlen)
{
    size_t lines = 0, tabs = 0;
    for (const char *p = t->text; *p; p++)
        lines += *p == '\n', tabs += *p == '\t';
    if (lines == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: no header line", path);
    t->cell = malloc((lines + tabs + 1) * sizeof *t->cell);
    if (!t->cell)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", path);
    size_t n = 0, row = 0, in_row = 0;
    char *p = t->text;
    while (*p) {
        t->cell[n++] = p;
        in_row++;
        p += strcspn(p, "\t\n");
        int eol = *p == '\n';
        if (*p)
            *p++ = '\0';
        if (eol || !*p) {
            if (row == 0)
                t->ncol = in_row;
            else if (in_row != t->ncol)
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "%s:%zu: %zu cells, the header has %zu", path, row + 1, in_row,
                                  t->ncol);
            row++;
            in_row = 0;
        }
    }
    t->nrow = row - 1;
    return SUNMC_OK;
}

static int table_read(h5_table *t, const char *path, char *err, size_t errlen)
{
    memset(t, 0, sizeof *t);
    int st = slurp(path, &t->text, err, errlen);
    return st == SUNMC_OK ? table_split(t, path, err, errlen) : st;
}

static void table_free(h5_table *t)
{
    free(t->text);
    free(t->cell);
}

enum { COL_INT, COL_FLOAT, COL_TEXT };

/* The type of column c: int64, float64 or text (see h5out.h). */
static int column_kind(const h5_table *t, size_t c, size_t *maxlen)
{
    int kind = COL_INT, missing = 0;
    *maxlen = 1;
    for (size_t r = 1; r <= t->nrow; r++) {
        const char *s = t->cell[r * t->ncol + c];
        size_t len = strlen(s);
        *maxlen = len > *maxlen ? len : *maxlen;
        char *end;
        if (strcmp(s, H5OUT_MISSING) == 0) {
            missing = 1;
            continue;
        }
        if (kind == COL_INT) {
            errno = 0;
            (void)strtoll(s, &end, 10);
            if (len == 0 || *end || errno)
                kind = COL_FLOAT;
        }
        if (kind == COL_FLOAT) {
            (void)strtod(s, &end);
            if (len == 0 || *end)
                kind = COL_TEXT;
        }
    }
    return kind == COL_INT && missing ? COL_FLOAT : kind;
}

/* Dataset NAME of group g holding column c. */
static int write_column(hid_t g, hid_t dcpl, const h5_table *t, size_t c, char *err,
                        size_t errlen)
{
    size_t maxlen, n = t->nrow;
    int kind = column_kind(t, c, &maxlen);
    size_t elem = kind == COL_TEXT ? maxlen : 8;
    char *buf = calloc(n ? n : 1, elem);
    if (!buf)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    for (size_t r = 0; r < n; r++) {
        const char *s = t->cell[(r + 1) * t->ncol + c];
        if (kind == COL_INT)
            ((int64_t *)buf)[r] = strtoll(s, NULL, 10);
        else if (kind == COL_FLOAT)
            ((double *)buf)[r] = strcmp(s, H5OUT_MISSING) == 0 ? NAN : strtod(s, NULL);
        else
            memcpy(buf + r * elem, s, strlen(s));
    }
    hid_t type = kind == COL_INT ? H5Tcopy(H5T_STD_I64LE)
                 : kind == COL_FLOAT ? H5Tcopy(H5T_IEEE_F64LE) : H5Tcopy(H5T_C_S1);
    hsize_t dim = n;
    hid_t space = H5Screate_simple(1, &dim, NULL), d = -1;
    herr_t h = type < 0 || space < 0 ? -1 : 0;
    if (h >= 0 && kind == COL_TEXT)
        h = H5Tset_size(type, elem) < 0 || H5Tset_strpad(type, H5T_STR_NULLPAD) < 0 ? -1 : 0;
    hid_t mem = kind == COL_INT ? H5T_NATIVE_INT64 : kind == COL_FLOAT ? H5T_NATIVE_DOUBLE : type;
    const char *name = t->cell[c];
    if (h >= 0 && (d = H5Dcreate2(g, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT)) < 0)
        h = -1;
    if (h >= 0 && n > 0)
        h = H5Dwrite(d, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
    if (d >= 0)
        H5Dclose(d);
    if (space >= 0)
        H5Sclose(space);
    if (type >= 0)
        H5Tclose(type);
    free(buf);
    if (h < 0)
        return sunmc_fail(err, errlen, SUNMC_EIO, "cannot write dataset %s", name);
    return SUNMC_OK;
}

static int attr_columns(hid_t g, const h5_table *t);
static int attr_str(hid_t f, const char *name, const char *value);

/* Group gname of f with one dataset per column of the table at path. */
static int write_table(hid_t f, hid_t gcpl, hid_t dcpl, const char *gname, const char *path,
                       char *err, size_t errlen)
{
    h5_table t;
    int st = table_read(&t, path, err, errlen);
    hid_t g = st == SUNMC_OK ? H5Gcreate2(f, gname, H5P_DEFAULT, gcpl, H5P_DEFAULT) : -1;
    if (st == SUNMC_OK && g < 0)
        st = sunmc_fail(err, errlen, SUNMC_EIO, "cannot create group /%s", gname);
    for (size_t c = 0; st == SUNMC_OK && c < t.ncol; c++)
        if (H5Lexists(g, t.cell[c], H5P_DEFAULT) != 0)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: column %s twice or unnamed", path,
                            t.cell[c]);
        else
            st = write_column(g, dcpl, &t, c, err, errlen);
    if (st == SUNMC_OK && attr_columns(g, &t) != 0)
        st = sunmc_fail(err, errlen, SUNMC_EIO, "cannot write /%s's columns attribute", gname);
    if (g >= 0)
        H5Gclose(g);
    table_free(&t);
    return st;
}

/* Attribute "columns" of g: the header, tab-separated (HDF5 lists a group's
 * datasets by name, not in the table's order). */
static int attr_columns(hid_t g, const h5_table *t)
{
    size_t len = 1;
    for (size_t c = 0; c < t->ncol; c++)
        len += strlen(t->cell[c]) + 1;
    char *h = malloc(len);
    if (!h)
        return -1;
    h[0] = '\0';
    for (size_t c = 0; c < t->ncol; c++) {
        if (c)
            strcat(h, "\t");
        strcat(h, t->cell[c]);
    }
    int bad = attr_str(g, "columns", h);
    free(h);
    return bad;
}

static int attr_str(hid_t f, const char *name, const char *value)
{
    hid_t type = H5Tcopy(H5T_C_S1), space = H5Screate(H5S_SCALAR), a = -1;
    /* Variable-length UTF-8: h5py reads it as str, not bytes. */
    herr_t h = type < 0 || space < 0 ? -1 : H5Tset_size(type, H5T_VARIABLE);
    if (h >= 0)
        h = H5Tset_cset(type, H5T_CSET_UTF8);
    if (h >= 0 && (a = H5Acreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT)) < 0)
        h = -1;
    if (h >= 0)
        h = H5Awrite(a, type, &value);
    if (a >= 0)
        H5Aclose(a);
    if (space >= 0)
        H5Sclose(space);
    if (type >= 0)
        H5Tclose(type);
    return h < 0 ? -1 : 0;
}

static int attr_long(hid_t f, const char *name, long value)
{
    int64_t v = value;
    hid_t space = H5Screate(H5S_SCALAR), a = -1;
    herr_t h = space < 0 ? -1 : 0;
    if (h >= 0 && (a = H5Acreate2(f, name, H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT)) < 0)
        h = -1;
    if (h >= 0)
        h = H5Awrite(a, H5T_NATIVE_INT64, &v);
    if (a >= 0)
        H5Aclose(a);
    if (space >= 0)
        H5Sclose(space);
    return h < 0 ? -1 : 0;
}

static int write_attrs(hid_t f, const char *config_ini, const h5out_meta *m, char *err,
                       size_t errlen)
{
    char *cfg;
    int st = slurp(config_ini, &cfg, err, errlen);
    if (st != SUNMC_OK)
        return st;
    int bad = attr_str(f, "config", cfg) | attr_str(f, "family", m->family) |
              attr_str(f, "product", m->product) | attr_long(f, "seed", m->seed) |
              attr_long(f, "units", m->units) | attr_long(f, "first", m->first) |
              attr_long(f, "end", m->end);
    free(cfg);
    return bad ? sunmc_fail(err, errlen, SUNMC_EIO, "cannot write the attributes") : SUNMC_OK;
}

int h5out_write(const char *path, const char *units_tsv, const char *summary_tsv,
                const char *config_ini, const h5out_meta *meta, char *err, size_t errlen)
{
    int ld = h5out_load(err, errlen);
    if (ld != SUNMC_OK)
        return ld;
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* modules never print */
    hid_t fcpl = H5Pcreate(H5P_FILE_CREATE), gcpl = H5Pcreate(H5P_GROUP_CREATE),
          dcpl = H5Pcreate(H5P_DATASET_CREATE), f = -1;
    int st = SUNMC_OK;
    /* No modification times anywhere: the same tables give the same bytes. */
    if (fcpl < 0 || gcpl < 0 || dcpl < 0 || H5Pset_obj_track_times(gcpl, 0) < 0 ||
        H5Pset_obj_track_times(dcpl, 0) < 0 || H5Pset_obj_track_times(fcpl, 0) < 0)
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: HDF5 property lists failed", path);
    if (st == SUNMC_OK && (f = H5Fcreate(path, H5F_ACC_TRUNC, fcpl, H5P_DEFAULT)) < 0)
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot create", path);
    if (st == SUNMC_OK)
        st = write_attrs(f, config_ini, meta, err, errlen);
    if (st == SUNMC_OK)
        st = write_table(f, gcpl, dcpl, "units", units_tsv, err, errlen);
    if (st == SUNMC_OK)
        st = write_table(f, gcpl, dcpl, "summary", summary_tsv, err, errlen);
    if (f >= 0 && H5Fclose(f) < 0 && st == SUNMC_OK)
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot close (disk full?)", path);
    H5Pclose(fcpl);
    H5Pclose(gcpl);
    H5Pclose(dcpl);
    if (st != SUNMC_OK && f >= 0)
        remove(path);
    return st;
}
