/* dss_grid.h - the DSS rotary-table grids (campaign and validation) as table
 * positions, for the family's table_grid hook (family.h, campaign.h). */
#ifndef SUNMC_DSS_GRID_H
#define SUNMC_DSS_GRID_H

#include "config.h"

/* Axis 0 = b2 (fast), axis 1 = b1 (one row per b1), in the order the unit
 * pipeline visits them. */
extern const char *const dss_table_axis_names[2];
long dss_table_grid(const sunmc_config *c, int which, double *axis0_deg, double *axis1_deg,
                    long max);

#endif
