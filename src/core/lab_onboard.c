/* lab_onboard.c - the exported arithmetic in process (see lab_onboard.h). */
#include "lab_onboard.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int count(const char *const *names)
{
    int n = 0;
    while (names && names[n])
        n++;
    return n;
}

int lab_onboard_parse(const char *text, const char *what, lab_onboard_spec *s, char *err,
                      size_t errlen)
{
    static const char table[] = "table:";
    s->form = LAB_ONBOARD_DOUBLE;
    s->step = 0;
    if (strcmp(text, "double") == 0)
        return SUNMC_OK;
    if (strcmp(text, "float") == 0) {
        s->form = LAB_ONBOARD_FLOAT;
        return SUNMC_OK;
    }
    if (strncmp(text, table, sizeof table - 1) != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: '%s' is not double, float or table:STEP", what, text);
    const char *v = text + sizeof table - 1;
    char *end;
    errno = 0;
    double step = strtod(v, &end);
    if (end == v || *end != '\0' || errno == ERANGE || !isfinite(step) || !(step > 0))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: table:%s: STEP must be a number > 0 (the table's step in the "
                          "reading axes' unit)",
                          what, v);
    s->form = LAB_ONBOARD_TABLE;
    s->step = step;
    return SUNMC_OK;
}

int lab_onboard_config(const sunmc_config *c, lab_onboard_spec *s, char *err, size_t errlen)
{
    static const char key[] = "calibration.onboard";
    int st = lab_onboard_parse(c->onboard[0] ? c->onboard : "double", key, s, err, errlen);
    if (st != SUNMC_OK || s->form == LAB_ONBOARD_DOUBLE)
        return st;
    const family_lab *lab = c->family ? c->family->lab : NULL;
    const lab_export *x = lab ? lab->export : NULL;
    if (!x || !x->onboard_mc)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s = %s: the %s family's Monte Carlo validates through its model "
                          "in double only",
                          key, c->onboard, c->family ? c->family->name : "?");
    if (s->form == LAB_ONBOARD_FLOAT && !x->eval_float)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s = float: the %s family's export has no float path in sunmc (use "
                          "double or table:STEP)",
                          key, c->family->name);
    if (!x->nominal)
        return SUNMC_OK;
    /* the config's nominal unit: does the export take its model, and its
     * table's size */
    void *m = calloc(1, lab->model_size);
    if (!m)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    x->nominal(c, m);
    char why[SUNMC_ERRLEN];
    st = x->supported ? x->supported(m, why, sizeof why) : SUNMC_OK;
    /* an empirical model (a spline or table fitted per unit) has no field
     * before its fit, nor a float path: validated in double only */
    if (st == SUNMC_OK && x->model_form && x->model_form(m, why, sizeof why) != SUNMC_OK) {
        free(m);
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s = %s: calibration.model is an empirical model, fitted per unit: "
                          "the Monte Carlo validates it in double only (a unit's calibration "
                          "exports as `sunmc export --form table:STEP`, and `compensate "
                          "--onboard table:STEP` measures that table)",
                          key, c->onboard);
    }
    if (st == SUNMC_OK && s->form == LAB_ONBOARD_FLOAT && x->float_supported)
        st = x->float_supported(m, why, sizeof why);
    lab_export_job j = {.lab = lab, .model = m, .step = s->step};
    long n[LAB_EXPORT_MAX_AXES], nodes;
    if (st == SUNMC_OK && s->form == LAB_ONBOARD_TABLE)
        st = lab_export_table_size(&j, n, &nodes, why, sizeof why);
    free(m);
    return st == SUNMC_OK ? st : sunmc_fail(err, errlen, st, "%s = %s: %s", key, c->onboard, why);
}

int lab_onboard_mc_init(lab_onboard *o, const sunmc_config *c, char *err, size_t errlen)
{
    lab_onboard_spec spec = {LAB_ONBOARD_DOUBLE, 0};
    int st = lab_onboard_config(c, &spec, err, errlen);
    memset(o, 0, sizeof *o);
    o->spec = spec;
    if (st != SUNMC_OK || spec.form == LAB_ONBOARD_DOUBLE)
        return st; /* (a form other than double: the family has an export) */
    lab_onboard_init(o, c->family->lab, &spec);
    void *m = calloc(1, o->lab->model_size);
    if (!m)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    o->lab->export->nominal(c, m);
    st = lab_onboard_prepare(o, m, err, errlen);
    free(m);
    o->model = NULL;
    return st;
}

const lab_onboard *lab_onboard_mc_unit(lab_onboard *o, const void *model, int *fit_ok)
{
    char err[SUNMC_ERRLEN];
    if (o->spec.form == LAB_ONBOARD_DOUBLE)
        return NULL;
    if (*fit_ok && lab_onboard_prepare(o, model, err, sizeof err) != SUNMC_OK)
        *fit_ok = 0;
    return o;
}

const char *lab_onboard_source_name(const lab_onboard_spec *s)
{
    return s->form == LAB_ONBOARD_FLOAT   ? "ONBOARD_FLOAT"
           : s->form == LAB_ONBOARD_TABLE ? "ONBOARD_TABLE"
                                          : "ONBOARD_DOUBLE";
}

void lab_onboard_init(lab_onboard *o, const family_lab *lab, const lab_onboard_spec *s)
{
    memset(o, 0, sizeof *o);
    o->spec = *s;
    o->lab = lab;
    o->n_raw = count(lab->raw_columns);
    o->n_comp = count(lab->comp_columns);
    o->n_axes = lab->export ? lab->export->n_axes : 0;
}

void lab_onboard_free(lab_onboard *o)
{
    free(o->table);
    o->table = NULL;
    o->cap = 0;
}

/* The table's nodes: write_table's grid (lab_export.c), the double
 * compensate at each. */
static int build_table(lab_onboard *o, char *err, size_t errlen)
{
    const lab_export *x = o->lab->export;
    lab_export_job j = {.lab = o->lab, .model = o->model, .step = o->spec.step};
    long nodes = 0;
    int st = lab_export_table_size(&j, o->n, &nodes, err, errlen);
    if (st != SUNMC_OK)
        return st;
    long need = nodes * o->n_comp;
    if (need > o->cap) {
        double *t = realloc(o->table, (size_t)need * sizeof *t);
        if (!t)
            return sunmc_fail(err, errlen, SUNMC_ENOMEM,
                              "out of memory for the on-board table (%ld nodes)", nodes);
        o->table = t;
        o->cap = need;
    }
    double hi[LAB_EXPORT_MAX_AXES];
    x->axes_range(o->model, o->lo, hi);
    for (int a = 0; a < LAB_EXPORT_MAX_AXES; a++)
        o->h[a] = a < x->n_axes ? (hi[a] - o->lo[a]) / (double)(o->n[a] - 1) : 1.0;
    double raw[LAB_MAX_COLUMNS], deg[LAB_MAX_COLUMNS];
    double *t = o->table;
    for (long i1 = 0; i1 < o->n[1]; i1++)
        for (long i0 = 0; i0 < o->n[0]; i0++, t += o->n_comp) {
            double q[LAB_EXPORT_MAX_AXES] = {o->lo[0] + (double)i0 * o->h[0],
                                             o->lo[1] + (double)i1 * o->h[1]};
            if (i0 == o->n[0] - 1)
                q[0] = hi[0];
            if (i1 == o->n[1] - 1 && x->n_axes == 2)
                q[1] = hi[1];
            lab_export_raw_at(x, o->model, q, raw);
            int ok = lab_export_reference(o->lab, o->model, raw, deg) == LAB_READING_OK;
            for (int k = 0; k < o->n_comp; k++)
                t[k] = ok ? deg[k] : LAB_ONBOARD_NO_NODE;
        }
    return SUNMC_OK;
}

int lab_onboard_prepare(lab_onboard *o, const void *model, char *err, size_t errlen)
{
    const lab_export *x = o->lab->export;
    o->model = model;
    if (o->spec.form == LAB_ONBOARD_DOUBLE)
        return SUNMC_OK;
    if (!x)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "this family has no export: no on-board form");
    int st = x->supported ? x->supported(model, err, errlen) : SUNMC_OK;
    if (st != SUNMC_OK)
        return st;
    if (o->spec.form == LAB_ONBOARD_FLOAT) {
        if (!x->eval_float)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "this family's export has no float path in sunmc: onboard float "
                              "is not available");
        st = x->float_supported ? x->float_supported(model, err, errlen) : SUNMC_OK;
        if (st == SUNMC_OK && x->model_form && x->model_form(model, err, errlen) != SUNMC_OK)
            st = SUNMC_EINPUT; /* an empirical model: its table form only */
        return st;
    }
    if (!lab_export_has_axes(x))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "this family's export has no table path in sunmc: onboard table is "
                          "not available");
    return build_table(o, err, errlen);
}

/* The exported lookup (write_lookup of lab_export.c), in double: the cell
 * of the axes q, then linear in each axis, in the generated code's order. */
static int table_lookup(const lab_onboard *o, const double *q, double *deg)
{
    long i[2] = {0, 0};
    double u[2] = {0, 0};
    for (int a = 0; a < o->n_axes; a++) {
        double s = (q[a] - o->lo[a]) / o->h[a];
        if (!(s >= 0.0 && s <= (double)(o->n[a] - 1)))
            return LAB_OUTSIDE_RANGE;
        i[a] = (long)floor(s);
        if (i[a] > o->n[a] - 2)
            i[a] = o->n[a] - 2;
        u[a] = s - (double)i[a];
    }
    int nc = o->n_comp;
    for (int k = 0; k < nc; k++) {
        if (o->n_axes == 2) {
            long n0 = o->n[0];
            const double *c00 = o->table + (i[1] * n0 + i[0]) * nc;
            const double *c10 = o->table + (i[1] * n0 + i[0] + 1) * nc;
            const double *c01 = o->table + ((i[1] + 1) * n0 + i[0]) * nc;
            const double *c11 = o->table + ((i[1] + 1) * n0 + i[0] + 1) * nc;
            if (c00[k] >= LAB_ONBOARD_NO_NODE || c10[k] >= LAB_ONBOARD_NO_NODE ||
                c01[k] >= LAB_ONBOARD_NO_NODE || c11[k] >= LAB_ONBOARD_NO_NODE)
                return LAB_NO_INVERSE;
            deg[k] = (1.0 - u[1]) * ((1.0 - u[0]) * c00[k] + u[0] * c10[k]) +
                     u[1] * ((1.0 - u[0]) * c01[k] + u[0] * c11[k]);
        } else {
            const double *c0 = o->table + i[0] * nc, *c1 = o->table + (i[0] + 1) * nc;
            if (c0[k] >= LAB_ONBOARD_NO_NODE || c1[k] >= LAB_ONBOARD_NO_NODE)
                return LAB_NO_INVERSE;
            deg[k] = (1.0 - u[0]) * c0[k] + u[0] * c1[k];
        }
    }
    return LAB_READING_OK;
}

/* The exported function's last check: an angle beyond 1e29 is none. */
#define LAB_ONBOARD_NO_ANGLE 1e29

static int eval_table(const lab_onboard *o, const double *raw, double *deg)
{
    const family_lab *lab = o->lab;
    int why = lab->reading_check ? lab->reading_check(o->model, raw) : LAB_READING_OK;
    if (why < LAB_READING_OK || why >= LAB_N_READING)
        why = LAB_NO_INVERSE;
    if (why != LAB_READING_OK)
        return why;
    double q[LAB_EXPORT_MAX_AXES];
    if (lab_export_axes_at(lab->export, o->model, raw, q) != SUNMC_OK)
        return LAB_NO_INVERSE;
    return table_lookup(o, q, deg);
}

/* The float path: the family's check and model (lab_export.eval_float),
 * then the exported function's last step as write_function emits it
 * (lab_export.c), in float: an angle at or beyond LAB_ONBOARD_NO_ANGLE
 * is none, the others turned into deg. */
static int eval_float(const lab_onboard *o, const double *raw, double *deg)
{
    float in[LAB_MAX_COLUMNS], ang[LAB_MAX_COLUMNS];
    for (int k = 0; k < o->n_raw; k++)
        in[k] = (float)raw[k];
    int why = o->lab->export->eval_float(o->model, in, ang);
    for (int k = 0; why == LAB_READING_OK && k < o->n_comp; k++)
        if (!(fabsf(ang[k]) < (float)LAB_ONBOARD_NO_ANGLE))
            why = LAB_NO_INVERSE;
    for (int k = 0; why == LAB_READING_OK && k < o->n_comp; k++)
        deg[k] = (double)(ang[k] * (float)DEG_PER_RAD);
    return why;
}

int lab_onboard_eval(const lab_onboard *o, const double *raw, double *deg)
{
    int why = o->spec.form == LAB_ONBOARD_TABLE   ? eval_table(o, raw, deg)
              : o->spec.form == LAB_ONBOARD_FLOAT ? eval_float(o, raw, deg)
                                                  : lab_export_reference(o->lab, o->model,
                                                                         raw, deg);
    for (int k = 0; why == LAB_READING_OK && k < o->n_comp; k++)
        if (!(fabs(deg[k]) < LAB_ONBOARD_NO_ANGLE))
            why = LAB_NO_INVERSE;
    if (why < LAB_READING_OK || why >= LAB_N_READING)
        why = LAB_NO_INVERSE;
    for (int k = 0; why != LAB_READING_OK && k < o->n_comp; k++)
        deg[k] = NAN;
    return why;
}

int lab_onboard_eval_raw(const lab_onboard *o, const double *raw, double *deg)
{
    /* the family's hooks read its optional columns after the raw ones
     * (family_lab.opt_columns): absent here, NaN */
    double full[LAB_MAX_COLUMNS];
    for (int k = 0; k < LAB_MAX_COLUMNS; k++)
        full[k] = k < o->n_raw ? raw[k] : NAN;
    return lab_onboard_eval(o, full, deg);
}

/* ---- compensate through the on-board form ---- */

static int wrap_check(const void *model, const double *raw)
{
    const lab_onboard_wrap *w = model;
    double deg[LAB_MAX_COLUMNS];
    return lab_onboard_eval(w->ob, raw, deg);
}

static int wrap_compensate(const void *model, const double *raw, double *comp_rad)
{
    const lab_onboard_wrap *w = model;
    const lab_onboard *o = w->ob;
    double deg[LAB_MAX_COLUMNS];
    if (o->lab->opt_comp_columns) /* the optional columns: the family's */
        (void)o->lab->compensate(o->model, raw, comp_rad);
    int why = lab_onboard_eval(o, raw, deg);
    for (int k = 0; k < o->n_comp; k++)
        comp_rad[k] = why == LAB_READING_OK ? deg[k] * RAD_PER_DEG : NAN;
    return why == LAB_READING_OK ? SUNMC_OK : SUNMC_EDOM;
}

void lab_onboard_wrap_init(lab_onboard_wrap *w, lab_onboard *ob)
{
    w->lab = *ob->lab;
    w->ob = ob;
    w->lab.reading_check = wrap_check;
    w->lab.compensate = wrap_compensate;
}
