/* dss_grid.c - the DSS campaign and validation grids as table positions. */
#include "dss_grid.h"
#include "dss_config.h"
#include "family.h"

static const char *const dss_table_axis_names[2] = {"b2", "b1"};

static long dss_table_grid(const sunmc_config *c, int which, double *axis0_deg, double *axis1_deg,
                    long max)
{
    const dss_config *dc = dss_cfg(c);
    int val = which == FAMILY_GRID_VALIDATION;
    double step = val ? dc->val_b_step_deg : dc->cal_b_step_deg;
    double lo = val ? dc->val_b_min_deg + dc->val_b_offset_deg : dc->cal_b_min_deg;
    long nb = val ? grid_count(dc->val_b_min_deg, dc->val_b_max_deg, step, dc->val_b_offset_deg)
                  : grid_count(dc->cal_b_min_deg, dc->cal_b_max_deg, step, 0);
    long i = 0;
    for (long j1 = 0; j1 < nb; j1++)
        for (long j2 = 0; j2 < nb; j2++, i++)
            if (i < max) {
                axis0_deg[i] = lo + (double)j2 * step;
                axis1_deg[i] = lo + (double)j1 * step;
            }
    return i;
}

const family_grid dss_grid = {
    .points = dss_table_grid,
    .axis_names = dss_table_axis_names,
    .design_step_key = "campaign.b_step_deg",
    .design_lines_key = NULL,
};
