/* ess_export.h - the ESS's model as C code for `sunmc export` (lab_export.h). */
#ifndef SUNMC_ESS_EXPORT_H
#define SUNMC_ESS_EXPORT_H

/* The export's fixed loop counts and eq. 13's switch (ess_export.c says
 * why each; ess_export_float.c writes the same code in float). */
#define ESS_EXPORT_HALLEY_STEPS 8
#define ESS_EXPORT_BISECTIONS 64
#define ESS_EXPORT_NEWTON_STEPS 12
#define ESS_EXPORT_E_MAX 1e-2
#define ESS_EXPORT_AD_MAX 1.4

struct lab_export;
extern const struct lab_export ess_export;

/* The exported function's check and model with -DSUNMC_FLOAT, in process
 * (lab_export.eval_float): enum lab_reading, the angle in rad. */
int ess_export_eval_float(const void *model, const float *raw, float *ang_rad);

#endif
