/* ess_export.h - the ESS's model as C code for `sunmc export` (lab_export.h). */
#ifndef SUNMC_ESS_EXPORT_H
#define SUNMC_ESS_EXPORT_H

struct lab_export;
extern const struct lab_export ess_export;

#endif
