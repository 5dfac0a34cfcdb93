/* dss_lab.h - the DSS's lab hooks (`simulate`, `calibrate`, `compensate`;
 * lab.h), reached as dss_family.lab. */
#ifndef SUNMC_DSS_LAB_H
#define SUNMC_DSS_LAB_H

#include "lab.h"

extern const family_lab dss_lab;

#endif
