/* psd_export.h - the four-channel sensor's models as C code for `sunmc
 * export` (lab_export.h). */
#ifndef SUNMC_PSD_EXPORT_H
#define SUNMC_PSD_EXPORT_H

struct lab_export;
extern const struct lab_export psd_export;

/* The exported function's check and model with -DSUNMC_FLOAT, in process
 * (lab_export.eval_float; psd_export_float.c): enum lab_reading, the
 * angles in rad. */
int psd_export_eval_float(const void *model, const float *raw, float *ang_rad);

#endif
