/* psd_export.h - the four-channel sensor's models as C code for `sunmc
 * export` (lab_export.h). */
#ifndef SUNMC_PSD_EXPORT_H
#define SUNMC_PSD_EXPORT_H

struct lab_export;
extern const struct lab_export psd_export;

#endif
