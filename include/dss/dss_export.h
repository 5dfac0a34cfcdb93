/* dss_export.h - the DSS's model as C code for `sunmc export` (lab_export.h). */
#ifndef SUNMC_DSS_EXPORT_H
#define SUNMC_DSS_EXPORT_H

/* The field angle's Newton steps of the export (dss_export.c says why). */
#define DSS_EXPORT_NEWTON_STEPS 10

struct lab_export;
extern const struct lab_export dss_export;

/* The exported function's check and model with -DSUNMC_FLOAT, in process
 * (lab_export.eval_float; dss_export_float.c): enum lab_reading, the
 * angles in rad. */
int dss_export_eval_float(const void *model, const float *raw, float *ang_rad);

#endif
