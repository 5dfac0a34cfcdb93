/* dss_stub.c - placeholder DSS family until the DSS model lands. */
#include "family.h"
#include "status.h"

#include <stdlib.h>

static const char *const dss_angle_names[] = {"alpha", "beta", "total"};
static int dss_n_angles(const sunmc_config *c) { return 3; }
static int dss_cols(const sunmc_config *c, const char **names, int max) { return 0; }
static void *dss_ws_alloc(const sunmc_config *c, char *err, size_t errlen)
{
    sunmc_fail(err, errlen, SUNMC_EINPUT, "the dss family is not implemented yet");
    return NULL;
}
static void dss_ws_free(void *ws) { free(ws); }
static int dss_unit_run(const sunmc_config *c, long unit, void *ws, unit_result *r)
{
    return SUNMC_EINPUT;
}

const sensor_family dss_family = {
    .name = "dss", .rms_unit = "arcsec", .arcsec_per_rms_unit = 1.0,
    .n_angles = dss_n_angles, .angle_names = dss_angle_names,
    .dev_columns = dss_cols, .par_columns = dss_cols,
    .workspace_alloc = dss_ws_alloc, .workspace_free = dss_ws_free, .unit_run = dss_unit_run,
};
