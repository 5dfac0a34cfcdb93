/* ess_grid.h - the ESS turntable grids (campaign and validation) as table
 * positions, the family's family_grid (family.h, campaign.h). */
#ifndef SUNMC_ESS_GRID_H
#define SUNMC_ESS_GRID_H

#include "family.h"

/* Axis 0 = inner frame alpha (fast), axis 1 = outer frame beta (one line
 * per beta), in the order the unit pipeline visits them; design searches
 * campaign.alpha_step_deg and campaign.beta_deg. */
extern const family_grid ess_grid;

#endif
