/* report.c - statistics over units and the TSV / table writers. */
#include "report.h"
#include "status.h"

#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define REPORT_PERCENTILE 0.95

int report_n_rows(const sunmc_config *c, const sensor_family *fam)
{
    return fam->n_angles(c) * c->bands_deg.n;
}

void report_band_label(const sunmc_config *c, int i, char *buf, size_t len)
{
    snprintf(buf, len, "%g:%g", c->bands_deg.lo[i], c->bands_deg.hi[i]);
}

int report_summarize(const sunmc_config *c, const sensor_family *fam, const unit_result *results,
                     long n, summary_row *rows)
{
    double *after = malloc((size_t)(n > 0 ? n : 1) * sizeof *after);
    if (!after)
        return SUNMC_ENOMEM;
    double spec = c->spec_arcsec / fam->arcsec_per_rms_unit;
    int na = fam->n_angles(c), nb = c->bands_deg.n;
    long gross = 0, alias = 0;
    for (long u = 0; u < n; u++) {
        gross += results[u].gross_val;
        alias += results[u].alias_weak > 0;
    }
    for (int a = 0; a < na; a++)
        for (int b = 0; b < nb; b++) {
            summary_row *r = &rows[a * nb + b];
            memset(r, 0, sizeof *r);
            r->angle = a;
            r->band = b;
            r->units = n;
            r->gross_errors = gross;
            r->alias_units = alias;
            double sb = 0, sa = 0, si = 0;
            double amax = -INFINITY, amin = INFINITY, imax = -INFINITY, imin = INFINITY;
            long k = 0, pass = 0;
            for (long u = 0; u < n; u++) {
                const unit_result *ur = &results[u];
                if (ur->fit_status != UNIT_FIT_OK) {
                    r->fit_failures++;
                    continue;
                }
                double bef = ur->rms_before[a][b], aft = ur->rms_after[a][b];
                if (!isfinite(bef) || !isfinite(aft))
                    continue;
                double imp = bef / aft;
                sb += bef;
                sa += aft;
                si += imp;
                amax = fmax(amax, aft);
                amin = fmin(amin, aft);
                imax = fmax(imax, imp);
                imin = fmin(imin, imp);
                after[k++] = aft;
                pass += aft <= spec;
            }
            if (k == 0) {
                r->rms_before_mean = r->rms_after_mean = r->rms_after_max = r->rms_after_min =
                    r->rms_after_p95 = r->improvement_mean = r->improvement_max =
                        r->improvement_min = NAN;
            } else {
                r->rms_before_mean = sb / (double)k;
                r->rms_after_mean = sa / (double)k;
                r->rms_after_max = amax;
                r->rms_after_min = amin;
                r->improvement_mean = si / (double)k;
                r->improvement_max = imax;
                r->improvement_min = imin;
                gsl_sort(after, 1, (size_t)k);
                r->rms_after_p95 = gsl_stats_quantile_from_sorted_data(after, 1, (size_t)k,
                                                                       REPORT_PERCENTILE);
            }
            r->yield = n > 0 ? (double)pass / (double)n : NAN;
        }
    free(after);
    return SUNMC_OK;
}

void report_print_table(FILE *f, const sunmc_config *c, const sensor_family *fam,
                        const summary_row *rows)
{
    int na = fam->n_angles(c), nb = c->bands_deg.n;
    const char *u = fam->rms_unit;
    const int prec = strcmp(u, "deg") == 0 ? 4 : 2;
    char model[256];
    fam->model_label(c, model, sizeof model);
    fprintf(f, "\n%s (%s): %ld units, seed %ld, spec %g arcsec\ncalibration model: %s\n",
            c->product, fam->name, rows[0].units, c->seed, c->spec_arcsec, model);
    fprintf(f, "%-6s %-9s | %-19s | %-20s | %-19s | %9s %6s\n", "angle", "band", "RMS after [" ,
            "times improvement", "mean RMS [", "p95 after", "yield");
    fprintf(f, "%-6s %-9s | %9s %9s | %6s %6s %6s | %9s %9s | %9s %6s\n", "", "|x| deg", "max",
            "min", "mean", "max", "min", "before", "after", u, "");
    for (int a = 0; a < na; a++)
        for (int b = 0; b < nb; b++) {
            const summary_row *r = &rows[a * nb + b];
            char band[32];
            report_band_label(c, b, band, sizeof band);
            fprintf(f, "%-6s %-9s | %9.*f %9.*f | %6.2f %6.2f %6.2f | %9.*f %9.*f | %9.*f %5.1f%%\n",
                    fam->angle_names[a], band, prec, r->rms_after_max, prec, r->rms_after_min,
                    r->improvement_mean, r->improvement_max, r->improvement_min, prec,
                    r->rms_before_mean, prec, r->rms_after_mean, prec, r->rms_after_p95,
                    100.0 * r->yield);
        }
    fprintf(f, "RMS in %s.  fit failures: %ld   gross errors (validation readings): %ld", u,
            rows[0].fit_failures, rows[0].gross_errors);
    if (fam->alias_term)
        fprintf(f, "   units whose campaign aliases %s: %ld", fam->alias_term, rows[0].alias_units);
    fputc('\n', f);
}

void report_write_summary_header(FILE *f, int n_lead, const char *const *lead_names)
{
    for (int i = 0; i < n_lead; i++)
        fprintf(f, "%s\t", lead_names[i]);
    fprintf(f, "product\tfamily\tangle\tband\tband_lo_deg\tband_hi_deg\tunits\trms_unit\t"
               "rms_before_mean\trms_after_mean\trms_after_max\trms_after_min\trms_after_p95\t"
               "improvement_mean\timprovement_max\timprovement_min\tyield\tspec_arcsec\t"
               "fit_failures\tgross_errors\talias_units\tmodel\n");
}

void report_write_summary_rows(FILE *f, const sunmc_config *c, const sensor_family *fam,
                               const summary_row *rows, int n_lead, const double *lead_values)
{
    int n = report_n_rows(c, fam);
    char model[256];
    fam->model_label(c, model, sizeof model);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        char band[32];
        report_band_label(c, r->band, band, sizeof band);
        for (int j = 0; j < n_lead; j++)
            fprintf(f, "%.10g\t", lead_values[j]);
        fprintf(f, "%s\t%s\t%s\t%s\t%g\t%g\t%ld\t%s\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t"
                   "%.6g\t%g\t%ld\t%ld\t%ld\t%s\n",
                c->product, fam->name, fam->angle_names[r->angle], band, c->bands_deg.lo[r->band],
                c->bands_deg.hi[r->band], r->units, fam->rms_unit, r->rms_before_mean,
                r->rms_after_mean, r->rms_after_max, r->rms_after_min, r->rms_after_p95,
                r->improvement_mean, r->improvement_max, r->improvement_min, r->yield,
                c->spec_arcsec, r->fit_failures, r->gross_errors, r->alias_units, model);
    }
}

void report_write_units(FILE *f, const sunmc_config *c, const sensor_family *fam,
                        const unit_result *results, long n)
{
    const char *dev[UNIT_MAX_DEV], *par[UNIT_MAX_PAR];
    int nd = fam->dev_columns(c, dev, UNIT_MAX_DEV);
    int np = fam->par_columns(c, par, UNIT_MAX_PAR);
    int na = fam->n_angles(c), nb = c->bands_deg.n;
    fprintf(f, "unit\tfit_status\tfit_gsl_status\tfit_iterations\talias_weak\tgross_cal\tgross_val");
    for (int i = 0; i < nd; i++)
        fprintf(f, "\t%s", dev[i]);
    for (int i = 0; i < np; i++)
        fprintf(f, "\t%s", par[i]);
    fprintf(f, "\tfit_rms_%s", fam->rms_unit);
    const char *which[2] = {"before", "after"};
    for (int w = 0; w < 2; w++)
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                fprintf(f, "\trms_%s_%s_%g_%g_%s", which[w], fam->angle_names[a],
                        c->bands_deg.lo[b], c->bands_deg.hi[b], fam->rms_unit);
    fputc('\n', f);
    for (long u = 0; u < n; u++) {
        const unit_result *r = &results[u];
        fprintf(f, "%ld\t%s\t%d\t%d\t%d\t%d\t%d", r->unit,
                r->fit_status == UNIT_FIT_OK ? "ok" : "failed", r->fit_gsl_status,
                r->fit_iterations, r->alias_weak, r->gross_cal, r->gross_val);
        for (int i = 0; i < nd; i++)
            fprintf(f, "\t%.10g", r->dev[i]);
        for (int i = 0; i < np; i++)
            fprintf(f, "\t%.10g", r->par[i]);
        fprintf(f, "\t%.6g", r->fit_rms);
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                fprintf(f, "\t%.6g", r->rms_before[a][b]);
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                fprintf(f, "\t%.6g", r->rms_after[a][b]);
        fputc('\n', f);
    }
}
