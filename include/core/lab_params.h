/* lab_params.h - `sunmc compensate`'s strict reading of a params.ini, the
 * part every family shares (issue 36): what the file says about itself
 * ([calibration]: who wrote it, which model it holds), which sections it
 * may have, and its [prior]; the family's params_load then reads its own
 * sections, every key known or refused.  Messages "FILE:LINE: ...". */
#ifndef SUNMC_LAB_PARAMS_H
#define SUNMC_LAB_PARAMS_H

#include "lab.h"
#include "params_io.h"

#include <stddef.h>

/* The keys of [calibration] (lab_params_header writes them). */
extern const char *const lab_params_header_keys[];
extern const int lab_params_n_header_keys;

/* "MAJOR.MINOR.PATCH", each decimal digits (at most
 * LAB_VERSION_MAX_DIGITS), nothing else: v[0..2] and 0; -1 otherwise. */
#define LAB_VERSION_MAX_DIGITS 9
int lab_version_parse(const char *s, long v[3]);

/* calibration.sunmc_version of p against `mine` (this build's
 * SUNMC_VERSION): an older or equal version is read; a newer MAJOR is
 * refused ("FILE:LINE: written by sunmc 9.9.9, newer than this 0.1.0:
 * ..."); a newer minor or patch of the same major is read with a warning
 * into warn (else warn is ""); a missing or malformed version is refused. */
int lab_params_version(const params_file *p, const char *mine, char *warn, size_t warnlen,
                       char *err, size_t errlen);

/* The model of lab->params_models that p's model line names, when the
 * file holds that model (its signature key present, no other model's):
 * into *model; else refused at the model line. */
int lab_params_model_of(const family_lab *lab, const params_file *p,
                        const lab_params_model **model, char *err, size_t errlen);

/* p read as compensate reads it, into model (lab->model_size bytes): its
 * version (lab_params_version against SUNMC_VERSION), every [calibration]
 * key known and data_rows whole, its model (lab_params_model_of), no
 * section beyond [calibration], [prior] and the model's, every [prior] key
 * pilot_units (whole) or NAME_mean / NAME_sigma of a key of the model's
 * sections; then lab->params_load.  warn as lab_params_version's. */
int lab_params_load(const family_lab *lab, const params_file *p, void *model, char *warn,
                    size_t warnlen, char *err, size_t errlen);

#endif
