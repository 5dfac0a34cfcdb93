/* calreport_models.c - the recommendation of a model comparison
 * (calreport.h): what the PSD and the DSS say of their models' held-out
 * errors, once. */
#include "calreport.h"

#include <stdio.h>

/* Does x replace b as the recommendation?  A simpler x when it is not
 * worse by more than gain; a more complex one when it is better by gain,
 * for a single reading or -- when both estimate it -- for the mean of a
 * point's readings: there the reading noise, common to every model, no
 * longer hides what the calibration itself leaves (a flight that averages
 * gets that gain; one that does not loses nothing by more than gain). */
static int beats(const calreport_model *x, const calreport_model *b, double gain)
{
    int means = x->per_point > 1 && b->per_point > 1 && x->rms_out_mean_arcsec > 0 &&
                b->rms_out_mean_arcsec > 0;
    if (x->np < b->np)
        return x->rms_out_arcsec < b->rms_out_arcsec * (1.0 + gain) &&
               (!means || x->rms_out_mean_arcsec < b->rms_out_mean_arcsec * (1.0 + gain));
    if (x->rms_out_arcsec < b->rms_out_arcsec * (1.0 - gain))
        return 1;
    return means && x->rms_out_mean_arcsec < b->rms_out_mean_arcsec * (1.0 - gain) &&
           !(x->rms_out_arcsec > b->rms_out_arcsec);
}

void calreport_models_recommend(calreport_models *cm, double gain, double far)
{
    int best = -1, emp = -1;
    for (int m = 0; m < cm->n; m++) {
        const calreport_model *x = &cm->m[m];
        if (!x->ok)
            continue;
        if (best < 0)
            best = m;
        /* the simpler of two, unless the other is clearly better */
        if (beats(x, &cm->m[best], gain))
            best = m;
        if (m != 0 && (emp < 0 || x->rms_out_arcsec < cm->m[emp].rms_out_arcsec))
            emp = m;
    }
    cm->best = best < 0 ? cm->used : best;
    size_t at = 0;
    const calreport_model *b = &cm->m[cm->best];
    if (best < 0) {
        snprintf(cm->note, sizeof cm->note, "no model could be refitted on every fold");
        return;
    }
    at += (size_t)snprintf(cm->note, sizeof cm->note,
                           "recommended %s: held out %.0f arcsec for a single reading",
                           b->name, b->rms_out_arcsec);
    if (b->per_point > 1 && at < sizeof cm->note)
        at += (size_t)snprintf(cm->note + at, sizeof cm->note - at, ", %.0f for the mean of %.3g",
                               b->rms_out_mean_arcsec, b->per_point);
    if (b->n_outliers > 0 && at < sizeof cm->note)
        at += (size_t)snprintf(cm->note + at, sizeof cm->note - at,
                               " (%d held-out part%s unlike the others left out; %.0f with %s)",
                               b->n_outliers, b->n_outliers > 1 ? "s" : "",
                               b->rms_out_all_arcsec, b->n_outliers > 1 ? "them" : "it");
    if (at < sizeof cm->note)
        at += (size_t)snprintf(cm->note + at, sizeof cm->note - at, "%s%s",
                               cm->best != cm->used ? ": calibrate with --set calibration.model="
                                                    : "",
                               cm->best != cm->used ? b->name : "");
    const calreport_model *ph = &cm->m[0];
    if (emp >= 0 && ph->ok && ph->rms_out_arcsec > far * cm->m[emp].rms_out_arcsec &&
        at < sizeof cm->note)
        snprintf(cm->note + at, sizeof cm->note - at,
                 "; the physics does not describe this sensor: the physical model's held-out "
                 "error is %.1f times the %s model's",
                 ph->rms_out_arcsec / cm->m[emp].rms_out_arcsec, cm->m[emp].name);
}
