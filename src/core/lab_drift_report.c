/* lab_drift_report.c - calibrate's report of a file's campaigns: the
 * family's per-row errors into lab_drift, its finding into the report
 * (lab.h). */
#include "lab.h"
#include "lab_drift.h"

#include <math.h>
#include <stdlib.h>

void lab_drift_report(const family_lab *lab, const void *cal, const lab_columns *d,
                      calreport *rep)
{
    if (!lab->cal_row_error || d->n_sources < 2 || !rep->fit_ok)
        return;
    double *e = malloc((2 * d->n + 1) * sizeof *e);
    if (!e)
        return;
    for (size_t i = 0; i < d->n; i++)
        if (lab->cal_row_error(cal, i, e + 2 * i) != 0)
            e[2 * i] = e[2 * i + 1] = NAN;
    lab_drift_input in = {.n = d->n,
                          .angle_deg = {d->v[0], d->v[1]},
                          .error_rad = {e, e + 1},
                          .error_stride = 2,
                          .weight = NULL,
                          .source = d->source,
                          .n_sources = d->n_sources,
                          .source_name = (const char *const *)d->source_name};
    if (lab_drift_analyse(&in, &rep->drift) >= 2 && rep->drift.drift)
        calreport_warn(rep,
                       "calibrate on one campaign (cut the file at its \"# source:\" lines) "
                       "or find what moved (mount, lamp, table zero); no calibration removes "
                       "a change between campaigns, and the cross-validation shows its cost "
                       "(campaigns.tsv)",
                       "drift between campaigns: %s", rep->drift.note);
    free(e);
}
