/* ess_lab.h - the ESS's lab hooks (`simulate`, `calibrate`, `compensate`;
 * lab.h), reached as ess_family.lab. */
#ifndef SUNMC_ESS_LAB_H
#define SUNMC_ESS_LAB_H

#include "lab.h"

extern const family_lab ess_lab;

#endif
