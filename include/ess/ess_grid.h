/* ess_grid.h - the ESS turntable grids (campaign and validation) as table
 * positions, for the family's table_grid hook (family.h, campaign.h). */
#ifndef SUNMC_ESS_GRID_H
#define SUNMC_ESS_GRID_H

#include "config.h"

/* Axis 0 = inner frame alpha (fast), axis 1 = outer frame beta (one line
 * per beta), in the order the unit pipeline visits them. */
extern const char *const ess_table_axis_names[2];
long ess_table_grid(const sunmc_config *c, int which, double *axis0_deg, double *axis1_deg,
                    long max);

#endif
