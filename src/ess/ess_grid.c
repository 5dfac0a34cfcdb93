/* ess_grid.c - the ESS campaign and validation grids as table positions. */
#include "ess_grid.h"
#include "ess_config.h"
#include "family.h"

static const char *const ess_table_axis_names[2] = {"alpha", "beta"};

static long ess_table_grid(const sunmc_config *c, int which, double *axis0_deg, double *axis1_deg,
                    long max)
{
    const ess_config *ec = ess_cfg(c);
    int val = which == FAMILY_GRID_VALIDATION;
    double lo = val ? ec->val_alpha_min_deg + ec->val_alpha_offset_deg : ec->cal_alpha_min_deg;
    double step = val ? ec->val_alpha_step_deg : ec->cal_alpha_step_deg;
    const double_list *beta = val ? &ec->val_beta_deg : &ec->cal_beta_deg;
    long na = val ? grid_count(ec->val_alpha_min_deg, ec->val_alpha_max_deg, step,
                               ec->val_alpha_offset_deg)
                  : grid_count(ec->cal_alpha_min_deg, ec->cal_alpha_max_deg, step, 0);
    long i = 0;
    for (int k = 0; k < beta->n; k++)
        for (long j = 0; j < na; j++, i++)
            if (i < max) {
                axis0_deg[i] = lo + (double)j * step;
                axis1_deg[i] = beta->v[k];
            }
    return i;
}

const family_grid ess_grid = {
    .points = ess_table_grid,
    .axis_names = ess_table_axis_names,
    .design_step_key = "campaign.alpha_step_deg",
    .design_lines_key = "campaign.beta_deg",
};
