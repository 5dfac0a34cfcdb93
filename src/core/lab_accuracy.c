/* lab_accuracy.c - what compensate achieved against the truth (lab_accuracy.h). */
#include "lab_accuracy.h"

#include "bands.h"
#include "output.h"
#include "status.h"
#include "verdict.h"
#include "rotation.h"
#include "tsvnum.h"
#include "units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const one_angle[] = {"alpha"};
static const char *const two_angles[] = {"alpha", "beta", "total"};

int lab_accuracy_init(lab_accuracy *a, const sensor_family *fam, const sunmc_config *c,
                      int n_comp, char *err, size_t errlen)
{
    memset(a, 0, sizeof *a);
    if (n_comp != 1 && n_comp != 2)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "accuracy: %d compensated angles (1 or 2 can be scored)", n_comp);
    a->n_comp = n_comp;
    a->n_angles = n_comp == 1 ? 1 : LAB_ACC_ANGLES;
    for (int k = 0; k < a->n_angles; k++)
        a->angle[k] = fam->angle_names && fam->angle_names[k]
                          ? fam->angle_names[k]
                          : (n_comp == 1 ? one_angle : two_angles)[k];
    a->unit = fam->rms_unit;
    a->per_deg = ARCSEC_PER_DEG / fam->arcsec_per_rms_unit;
    a->statistic = VERDICT_RMS;
    a->spec = NAN;
    if (c) {
        a->bands = c->bands_deg;
        a->have_spec = 1;
        a->statistic = c->spec_statistic;
        a->spec = c->spec_arcsec / fam->arcsec_per_rms_unit;
    }
    return SUNMC_OK;
}

/* The errors of one row (rms unit) and its band value (deg). */
static void row_errors(const lab_accuracy *a, const double *comp, const double *truth,
                       double *e, double *band_deg)
{
    if (a->n_comp == 1) {
        e[0] = (comp[0] - truth[0]) * DEG_PER_RAD * a->per_deg;
        *band_deg = fabs(truth[0]) * DEG_PER_RAD;
        return;
    }
    double uc[3], ut[3];
    sun_vector_of(comp[0], comp[1], uc);
    sun_vector_of(truth[0], truth[1], ut);
    e[0] = (comp[0] - truth[0]) * DEG_PER_RAD * a->per_deg;
    e[1] = (comp[1] - truth[1]) * DEG_PER_RAD * a->per_deg;
    e[2] = angle_between(uc, ut) * DEG_PER_RAD * a->per_deg;
    *band_deg = acos(fmin(ut[2], 1.0)) * DEG_PER_RAD;
}

int lab_accuracy_add(lab_accuracy *a, const double *comp_rad, const double *truth_rad)
{
    a->rows++;
    for (int k = 0; k < a->n_comp; k++)
        if (!isfinite(comp_rad[k]) || !isfinite(truth_rad[k])) {
            a->missing++;
            return SUNMC_OK;
        }
    if (a->used == a->cap) {
        size_t cap = a->cap ? 2 * a->cap : 1024;
        double *e = realloc(a->err, cap * LAB_ACC_ANGLES * sizeof *e);
        if (e)
            a->err = e;
        double *b = e ? realloc(a->band_deg, cap * sizeof *b) : NULL;
        if (!b)
            return SUNMC_ENOMEM;
        a->band_deg = b;
        a->cap = cap;
    }
    row_errors(a, comp_rad, truth_rad, a->err + a->used * LAB_ACC_ANGLES, &a->band_deg[a->used]);
    a->used++;
    return SUNMC_OK;
}

static int cmp_double(const void *x, const void *y)
{
    double u = *(const double *)x, v = *(const double *)y;
    return (u > v) - (u < v);
}

/* RMS, nearest-rank p99.7 and max of |e| over the rows of band b. */
static void band_stats(lab_accuracy *a, int k, int b, double *abs_e)
{
    long n = 0;
    double s2 = 0;
    for (size_t i = 0; i < a->used; i++)
        if (band_holds(&a->bands, b, a->band_deg[i])) {
            double e = a->err[i * LAB_ACC_ANGLES + (size_t)k];
            abs_e[n++] = fabs(e);
            s2 += e * e;
        }
    a->n[k][b] = n;
    a->rms[k][b] = a->p997[k][b] = a->max[k][b] = NAN;
    if (n == 0)
        return;
    qsort(abs_e, (size_t)n, sizeof *abs_e, cmp_double);
    long rank = (long)ceil(VERDICT_P997_LEVEL * (double)n);
    a->rms[k][b] = sqrt(s2 / (double)n);
    a->p997[k][b] = abs_e[(rank < 1 ? 1 : rank) - 1];
    a->max[k][b] = abs_e[n - 1];
}

int lab_accuracy_finish(lab_accuracy *a)
{
    if (!a->have_spec) {
        double hi = 0;
        for (size_t i = 0; i < a->used; i++)
            hi = fmax(hi, a->band_deg[i]);
        a->bands.n = 1;
        a->bands.lo[0] = 0;
        a->bands.hi[0] = hi;
    }
    double *abs_e = malloc((a->used + 1) * sizeof *abs_e);
    if (!abs_e)
        return SUNMC_ENOMEM;
    for (int k = 0; k < a->n_angles; k++)
        for (int b = 0; b < a->bands.n; b++)
            band_stats(a, k, b, abs_e);
    free(abs_e);
    return SUNMC_OK;
}

double lab_accuracy_stat(const lab_accuracy *a, int k, int b)
{
    return a->statistic == VERDICT_P997  ? a->p997[k][b]
           : a->statistic == VERDICT_MAX ? a->max[k][b]
                                         : a->rms[k][b];
}

static const char *const stat_names[] = {"rms", "p99.7", "max"};

const char *lab_accuracy_stat_name(const lab_accuracy *a)
{
    return a->statistic >= VERDICT_RMS && a->statistic <= VERDICT_MAX ? stat_names[a->statistic]
                                                                      : "?";
}

/* "yes", "no", or "-" without a spec or points */
const char *lab_accuracy_meets(const lab_accuracy *a, int k, int b)
{
    double s = lab_accuracy_stat(a, k, b);
    if (!a->have_spec || !(s == s))
        return "-";
    return s <= a->spec ? "yes" : "no";
}

/* "v" or "-" for NaN */
static void put(FILE *f, const char *sep, double v)
{
    char num[64];
    tsv_num_fmt(num, sizeof num, "%.6g", v);
    fprintf(f, "%s%s", sep, num);
}

void lab_accuracy_write(const lab_accuracy *a, FILE *f)
{
    fprintf(f, "angle\tband\tband_lo_deg\tband_hi_deg\tpoints\tunit\trms\tp99_7\tmax\t"
               "spec_statistic\tspec\tmeets_spec\n");
    for (int k = 0; k < a->n_angles; k++)
        for (int b = 0; b < a->bands.n; b++) {
            fprintf(f, "%s\t%g:%g", a->angle[k], a->bands.lo[b], a->bands.hi[b]);
            put(f, "\t", a->bands.lo[b]);
            put(f, "\t", a->bands.hi[b]);
            fprintf(f, "\t%ld\t%s", a->n[k][b], a->unit);
            put(f, "\t", a->rms[k][b]);
            put(f, "\t", a->p997[k][b]);
            put(f, "\t", a->max[k][b]);
            fprintf(f, "\t%s", a->have_spec ? lab_accuracy_stat_name(a) : "-");
            put(f, "\t", a->have_spec ? a->spec : NAN);
            fprintf(f, "\t%s\n", lab_accuracy_meets(a, k, b));
        }
}

void lab_accuracy_free(lab_accuracy *a)
{
    free(a->err);
    free(a->band_deg);
    a->err = a->band_deg = NULL;
    a->used = a->cap = 0;
}

int lab_accuracy_save(const lab_accuracy *a, out_set *os, char *err, size_t errlen)
{
    FILE *f = NULL;
    int st = out_open(os, LAB_ACC_FILE, &f, err, errlen);
    if (st == SUNMC_OK) {
        lab_accuracy_write(a, f);
        return out_commit(os, err, errlen);
    }
    out_abort(os);
    return st;
}
