/* lab_export_form.c - what `sunmc export` says of a model it writes as its
 * table form only (lab_export.h: model_form): the empirical models of
 * issue 39. */
#include "lab_export.h"
#include "status.h"

int lab_export_table_only(const char *family, const char *model, const char *axes, char *err,
                          size_t errlen)
{
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "the %s_%s model holds a spline or a look-up table of its readings, "
                      "which has no closed form sunmc writes as C: export its compensated "
                      "angles as a table with --form table:STEP (STEP in %s), or calibrate the "
                      "physical model to export its model form",
                      family, model, axes);
}
