/* fuzz_params.c - libFuzzer harness: any bytes as a params.ini (params_read,
 * then compensate's strict reading, lab_params_load: version, model line,
 * sections, every key, then the family's loader with its physical
 * ranges), and a loaded
 * calibration applied as `sunmc compensate` applies it: the ESS to raw
 * outputs across +-90 deg, the DSS to spots across its detector, the PSD
 * to channels through its reading check.  A
 * calibration that loads must compensate without crashing; readings it
 * cannot invert are counted, not fatal. */
#include "fuzz_util.h"

#include "dss_labfit.h"
#include "dss_calib.h"
#include "ess_labfit.h"
#include "ess_model.h"
#include "lab.h"
#include "lab_params.h"
#include "registry.h"
#include "psd_unit.h"
#include "params_io.h"
#include "status.h"
#include "units.h"

#include <stdlib.h>
#include <string.h>

static void compensate_ess(const params_file *pf)
{
    char err[SUNMC_ERRLEN];
    ess_model m;
    if (ess_params_load(pf, &m, err, sizeof err) != SUNMC_OK)
        return;
    for (int i = -90; i <= 90; i += 3) {
        double a;
        ess_model_compensate(&m, i * RAD_PER_DEG, &a);
    }
}

static void compensate_dss(const params_file *pf)
{
    char err[SUNMC_ERRLEN];
    dss_calibration cal;
    if (dss_params_load(pf, &cal, err, sizeof err) != SUNMC_OK)
        return;
    for (int i = -1024; i <= 1024; i += 256)
        for (int j = -1024; j <= 1024; j += 256) {
            double a, b;
            dss_compensate(&cal, i, j, &a, &b);
        }
}

/* The PSD through its family_lab hooks, as compensate calls them: the
 * reading check, then the inverse, over channels from below 0 to 1. */
static void compensate_psd(const params_file *pf)
{
    char err[SUNMC_ERRLEN];
    void *model = malloc(psd_lab.model_size);
    if (model && psd_lab.params_load(pf, model, err, sizeof err) == SUNMC_OK)
        for (int i = -1; i <= 4; i++)
            for (int j = 0; j <= 4; j++) {
                double raw[6] = {0.25 * i, 0.25 * j, 0.1, 0.05, NAN, NAN}, comp[4];
                if (psd_lab.reading_check(model, raw) == LAB_READING_OK)
                    psd_lab.compensate(model, raw, comp);
            }
    free(model);
}

/* compensate's strict reading of the whole file (lab_params_load). */
static int strict_ok(const params_file *pf, const char *sensor)
{
    char err[SUNMC_ERRLEN], warn[SUNMC_ERRLEN];
    const sensor_family *fam = sensor_family_find(sensor);
    if (!fam || !fam->lab)
        return 0;
    void *model = malloc(fam->lab->model_size);
    int ok = model && lab_params_load(fam->lab, pf, model, warn, sizeof warn, err,
                                      sizeof err) == SUNMC_OK;
    free(model);
    return ok;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[64], err[SUNMC_ERRLEN];
    int fd = fuzz_file(data, size, path, sizeof path);
    if (fd < 0)
        return 0;
    params_file *pf = malloc(sizeof *pf);
    const char *sensor = NULL;
    if (pf && params_read(path, pf, err, sizeof err) == SUNMC_OK &&
        params_get_text(pf, "calibration", "sensor", &sensor, err, sizeof err) == SUNMC_OK &&
        strict_ok(pf, sensor)) {
        if (strcmp(sensor, "ess") == 0)
            compensate_ess(pf);
        else if (strcmp(sensor, "dss") == 0)
            compensate_dss(pf);
        else if (strcmp(sensor, "psd") == 0)
            compensate_psd(pf);
    }
    free(pf);
    close(fd);
    return 0;
}
