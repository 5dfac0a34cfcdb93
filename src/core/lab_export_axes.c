/* lab_export_axes.c - the reading axes of `sunmc export` and the on-board
 * table (lab_export.h): the family's hooks, or, for a family whose axes are
 * its raw columns (lab_export.axes_are_raw: the ESS's output_deg, the
 * DSS's x_px, y_px), the identity, written once here. */
#include "lab_export.h"
#include "status.h"

void lab_export_raw_at(const lab_export *x, const void *model, const double *q, double *raw)
{
    if (!x->axes_are_raw) {
        x->raw_at(model, q, raw);
        return;
    }
    for (int a = 0; a < x->n_axes; a++)
        raw[a] = q[a];
}

int lab_export_axes_at(const lab_export *x, const void *model, const double *raw, double *q)
{
    if (!x->axes_are_raw)
        return x->axes_at(model, raw, q);
    for (int a = 0; a < x->n_axes; a++)
        q[a] = raw[a];
    return SUNMC_OK;
}

void lab_export_emit_axes(const lab_export *x, const void *model, FILE *f)
{
    if (!x->axes_are_raw) {
        x->emit_axes(model, f);
        return;
    }
    for (int a = 0; a < x->n_axes; a++)
        fprintf(f, "    q[%d] = raw[%d];\n", a, a);
}

int lab_export_has_axes(const lab_export *x)
{
    return x->axes_are_raw || x->axes_at != NULL;
}
