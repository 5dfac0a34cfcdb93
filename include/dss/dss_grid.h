/* dss_grid.h - the DSS rotary-table grids (campaign and validation) as table
 * positions, the family's family_grid (family.h, campaign.h). */
#ifndef SUNMC_DSS_GRID_H
#define SUNMC_DSS_GRID_H

#include "family.h"

/* Axis 0 = b2 (fast), axis 1 = b1 (one row per b1), in the order the unit
 * pipeline visits them; design searches campaign.b_step_deg (both axes). */
extern const family_grid dss_grid;

#endif
