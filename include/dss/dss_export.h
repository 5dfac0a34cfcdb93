/* dss_export.h - the DSS's model as C code for `sunmc export` (lab_export.h). */
#ifndef SUNMC_DSS_EXPORT_H
#define SUNMC_DSS_EXPORT_H

struct lab_export;
extern const struct lab_export dss_export;

#endif
