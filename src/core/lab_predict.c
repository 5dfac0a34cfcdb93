/* lab_predict.c - what a unit within the config's tolerances can read at
 * given table angles, from the family's deviation list alone (lab.h). */
#include "family.h"
#include "lab.h"
#include "status.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The nominal unit, then for each entry of the deviation list the unit
 * with that entry alone at -reach and at +reach. */
struct lab_predictor {
    const family_lab *lab;
    const sunmc_config *c;
    int n_units;
    size_t stride;
    unsigned char *units;
    int n_out;                      /* output columns: between the inputs and "weight" */
    double margin[LAB_MAX_COLUMNS]; /* the family's, per output */
};

static void *unit_at(const lab_predictor *p, int k)
{
    return p->units + (size_t)k * p->stride;
}

lab_predictor *lab_predict_alloc(const family_lab *lab, const sunmc_config *c, char *err,
                                 size_t errlen)
{
    const sensor_family *fam = c->family;
    if (!lab || !lab->cal_unit_build || !lab->cal_unit_read || !lab->cal_predict_margin ||
        lab->cal_n_inputs < 1 || !fam->deviations) {
        sunmc_fail(err, errlen, SUNMC_EINPUT, "the %s family has no lab prediction", fam->name);
        return NULL;
    }
    if (lab->cal_unit_bytes > LAB_UNIT_MAX_BYTES) {
        sunmc_fail(err, errlen, SUNMC_EINPUT, "a %s unit takes %zu bytes, more than %d",
                   fam->name, lab->cal_unit_bytes, LAB_UNIT_MAX_BYTES);
        return NULL;
    }
    lab_predictor *p = calloc(1, sizeof *p);
    int n = fam->n_deviations;
    double *values = calloc(UNIT_MAX_DEV, sizeof *values);
    if (p) {
        p->stride = (lab->cal_unit_bytes + 15) / 16 * 16;
        p->n_units = 1 + 2 * n;
        p->units = malloc((size_t)p->n_units * p->stride);
    }
    if (!p || !p->units || !values) {
        free(values);
        lab_predict_free(p);
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the lab prediction");
        return NULL;
    }
    p->lab = lab;
    p->c = c;
    while (lab->cal_columns[lab->cal_n_inputs + p->n_out] &&
           strcmp(lab->cal_columns[lab->cal_n_inputs + p->n_out], "weight") != 0)
        p->n_out++;
    for (int j = 0; j < p->n_out; j++)
        p->margin[j] = lab->cal_predict_margin[j];
    lab->cal_unit_build(c, values, unit_at(p, 0));
    int k0 = 0;
    for (int e = 0; e < n; e++) {
        const deviation_spec *d = &fam->deviations[e];
        double r = deviations_reach(d, c);
        for (int s = 0; s < 2; s++) {
            for (int i = 0; i < d->count; i++)
                values[k0 + i] = s ? r : -r;
            lab->cal_unit_build(c, values, unit_at(p, 1 + 2 * e + s));
        }
        for (int i = 0; i < d->count; i++)
            values[k0 + i] = 0;
        k0 += d->count;
    }
    free(values);
    return p;
}

int lab_predict(const lab_predictor *p, const double *in_deg, double *out, double *allowed)
{
    const family_lab *lab = p->lab;
    int no = p->n_out;
    int st = lab->cal_unit_read(p->c, unit_at(p, 0), in_deg, out);
    if (st != SUNMC_OK)
        return st;
    for (int j = 0; j < no; j++)
        allowed[j] = p->margin[j];
    double o[LAB_MAX_COLUMNS];
    for (int e = 0; e < p->c->family->n_deviations; e++) {
        double worst[LAB_MAX_COLUMNS] = {0};
        for (int s = 0; s < 2; s++) {
            /* A unit at one end of a tolerance that sees no sun here says
             * nothing of the spread: the other units still bound it. */
            if (lab->cal_unit_read(p->c, unit_at(p, 1 + 2 * e + s), in_deg, o) != SUNMC_OK)
                continue;
            for (int j = 0; j < no; j++)
                worst[j] = fmax(worst[j], fabs(o[j] - out[j]));
        }
        for (int j = 0; j < no; j++)
            allowed[j] += worst[j];
    }
    return SUNMC_OK;
}

void lab_predict_free(lab_predictor *p)
{
    if (!p)
        return;
    free(p->units);
    free(p);
}
