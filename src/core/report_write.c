/* report_write.c - summary.tsv and units.tsv (report.h). */
#include "report.h"
#include "thermal.h"
#include "verdict.h"
#include "status.h"
#include "tsvnum.h"

#include <math.h>
#include <string.h>

/* report.yield_interval's values, for summary.tsv. */
static const char *const yield_interval_key[] = {"wilson", "clopper_pearson",
                                                 "clopper_pearson_lower"};

static void summary_header(FILE *f, int n_lead, const char *const *lead_names, int thermal)
{
    for (int i = 0; i < n_lead; i++)
        fprintf(f, "%s\t", lead_names[i]);
    fprintf(f, "product\tfamily\tangle\tband\tband_lo_deg\tband_hi_deg\tunits\trms_unit\t"
               "rms_before_mean\trms_before_mean_ci_lo\trms_before_mean_ci_hi\t"
               "rms_after_mean\trms_after_mean_ci_lo\trms_after_mean_ci_hi\t"
               "rms_after_sys_mean\trms_after_sys_mean_ci_lo\trms_after_sys_mean_ci_hi\t"
               "rms_after_max\trms_after_min\t"
               "rms_after_p95\trms_after_p95_ci_lo\trms_after_p95_ci_hi\t"
               "improvement_mean\timprovement_mean_ci_lo\timprovement_mean_ci_hi\t"
               "improvement_max\timprovement_min\tyield\tyield_ci_lo\tyield_ci_hi\tspec_arcsec\t"
               "confidence\tstat_units\tfit_failures\tgross_errors\talias_units\tmodel\t"
               "campaign_points\tcampaign_hours\textrapolation_deg\tno_reading_units\t"
               "worse\tworse_ci_lo\tworse_ci_hi\tyield_interval\t"
               "spec_yield\tspec_yield_ci_lo\tspec_yield_ci_hi\tspec_statistic\tspec_bands\t"
               "min_coverage\tband_points\t"
               "rms_after_mf_mean\trms_after_mf_mean_ci_lo\trms_after_mf_mean_ci_hi\tmf_units\t"
               "share_noise\tshare_noise_ci_lo\tshare_noise_ci_hi\t"
               "share_estimation\tshare_estimation_ci_lo\tshare_estimation_ci_hi\t"
               "share_model_form\tshare_model_form_ci_lo\tshare_model_form_ci_hi");
    fprintf(f, "%s\n", thermal ? "\tcondition\ttemp_c" : "");
}

void report_write_summary_header(FILE *f, int n_lead, const char *const *lead_names)
{
    summary_header(f, n_lead, lead_names, 0);
}

void report_write_summary_header_of(FILE *f, const sunmc_config *c, int n_lead,
                                    const char *const *lead_names)
{
    summary_header(f, n_lead, lead_names, thermal_n_temps(c) > 0);
}

/* summary.tsv's condition column. */
static const char *const condition_key[] = {"lab", "operating", "worst"};

/* n numbers with fmt, each followed by a tab (tsvnum.h: "-" for NaN, no
 * "-0"). */
static void write_nums(FILE *f, const char *fmt, int n, const double *v)
{
    for (int i = 0; i < n; i++) {
        tsv_num_put(f, fmt, v[i]);
        fputc('\t', f);
    }
}

/* "\t" then v with fmt. */
static void put_field(FILE *f, const char *fmt, double v)
{
    fputc('\t', f);
    tsv_num_put(f, fmt, v);
}

/* "S\tS_ci_lo\tS_ci_hi\t" */
static void write_estimate(FILE *f, double v, stats_interval ci)
{
    write_nums(f, "%.6g", 3, (double[]){v, ci.lo, ci.hi});
}

void report_write_summary_rows(FILE *f, const sunmc_config *c,
                               const summary_row *rows, int n_lead, const char *const *lead_values)
{
    const sensor_family *fam = c->family;
    int n = report_n_rows(c);
    char model[256];
    fam->model_label(c, model, sizeof model);
    for (int i = 0; i < n; i++) {
        const summary_row *r = &rows[i];
        char band[32];
        report_band_label(c, r->band, band, sizeof band);
        for (int j = 0; j < n_lead; j++)
            fprintf(f, "%s\t", lead_values[j]);
        fprintf(f, "%s\t%s\t%s\t%s\t", c->product, fam->name, fam->angle_names[r->angle],
                band);
        write_nums(f, "%g", 2, (double[]){c->bands_deg.lo[r->band], c->bands_deg.hi[r->band]});
        fprintf(f, "%ld\t%s\t", r->units, fam->rms_unit);
        write_estimate(f, r->rms_before_mean, r->rms_before_mean_ci);
        write_estimate(f, r->rms_after_mean, r->rms_after_mean_ci);
        write_estimate(f, r->rms_after_sys_mean, r->rms_after_sys_mean_ci);
        write_nums(f, "%.6g", 2, (double[]){r->rms_after_max, r->rms_after_min});
        write_estimate(f, r->rms_after_p95, r->rms_after_p95_ci);
        write_estimate(f, r->improvement_mean, r->improvement_mean_ci);
        write_nums(f, "%.6g", 2, (double[]){r->improvement_max, r->improvement_min});
        write_estimate(f, r->yield, r->yield_ci);
        write_nums(f, "%g", 2, (double[]){c->spec_arcsec, r->confidence});
        fprintf(f, "%ld\t%ld\t%ld\t%ld\t%s\t%ld\t", r->stat_units, r->fit_failures,
                r->gross_errors, r->alias_units, model, r->campaign_points);
        write_nums(f, "%.6g", 2, (double[]){r->campaign_hours, r->extrapolation_deg});
        fprintf(f, "%ld\t", r->no_reading_units);
        write_nums(f, "%.6g", 3, (double[]){r->worse, r->worse_ci.lo, r->worse_ci.hi});
        fprintf(f, "%s\t", yield_interval_key[c->yield_interval]);
        write_nums(f, "%.6g", 3, (double[]){r->spec_yield, r->spec_yield_ci.lo, r->spec_yield_ci.hi});
        fprintf(f, "%s\t%s\t", verdict_statistic_name(c), c->spec_bands[0] ? c->spec_bands : "all");
        tsv_num_put(f, "%g", c->min_coverage);
        fprintf(f, "\t%ld\t", r->band_points);
        write_estimate(f, r->rms_after_mf_mean, r->rms_after_mf_mean_ci);
        fprintf(f, "%ld\t", r->mf_units);
        write_estimate(f, r->share_noise, r->share_noise_ci);
        write_estimate(f, r->share_estimation, r->share_estimation_ci);
        write_nums(f, "%.6g", 2, (double[]){r->share_model_form, r->share_model_form_ci.lo});
        tsv_num_put(f, "%.6g", r->share_model_form_ci.hi);
        if (thermal_n_temps(c) > 0) {
            fprintf(f, "\t%s", condition_key[r->condition]);
            put_field(f, "%g", r->temp_c);
        }
        fputc('\n', f);
    }
}

void report_write_units_header(FILE *f, const sunmc_config *c)
{
    const sensor_family *fam = c->family;
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
    const char *which[4] = {"before", "after", "after_sys", "after_mf"};
    for (int w = 0; w < 4; w++)
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                fprintf(f, "\trms_%s_%s_%g_%g_%s", which[w], fam->angle_names[a],
                        c->bands_deg.lo[b], c->bands_deg.hi[b], fam->rms_unit);
    /* at each operating temperature, then the worst over them (thermal.h) */
    int nt = thermal_n_temps(c);
    for (int t = 0; t <= nt && nt > 0; t++)
        for (int w = 0; w < 2; w++)
            for (int a = 0; a < na; a++)
                for (int b = 0; b < nb; b++) {
                    double lo = c->bands_deg.lo[b], hi = c->bands_deg.hi[b];
                    fprintf(f, "\trms_%s_%s_%g_%g_%s", which[w], fam->angle_names[a], lo, hi,
                            fam->rms_unit);
                    if (t < nt)
                        fprintf(f, "_at_%gC", thermal_temp_c(c, t));
                    else
                        fprintf(f, "_worst");
                }
    /* the spec's verdict for the studies' angle, at the worst condition */
    fprintf(f, "\tpass\tverdict\tverdict_band\tverdict_stat_%s\tverdict_coverage", fam->rms_unit);
    fputc('\n', f);
}

/* units.tsv's verdict columns of unit r: pass (1/0), why, the deciding
 * band, its statistic and coverage ("-" where none). */
static void write_verdict(FILE *f, const sunmc_config *c, const unit_result *r)
{
    verdict v;
    verdict_unit(c, r, verdict_angle(c), VERDICT_WORST, &v);
    char band[32] = "-";
    if (v.band >= 0)
        report_band_label(c, v.band, band, sizeof band);
    fprintf(f, "\t%d\t%s\t%s", v.pass, verdict_why_name(v.why), band);
    put_field(f, "%.6g", v.stat);
    put_field(f, "%.4g", v.coverage);
}

void report_write_unit_rows(FILE *f, const sunmc_config *c,
                            const unit_result *results, long n)
{
    const sensor_family *fam = c->family;
    const char *names[UNIT_MAX_PAR];
    int nd = fam->dev_columns(c, names, UNIT_MAX_DEV);
    int np = fam->par_columns(c, names, UNIT_MAX_PAR);
    int na = fam->n_angles(c), nb = c->bands_deg.n;
    for (long u = 0; u < n; u++) {
        const unit_result *r = &results[u];
        fprintf(f, "%ld\t%s\t%d\t%d\t%d\t%d\t%d", r->unit,
                r->fit_status == UNIT_FIT_OK ? "ok" : "failed", r->fit_gsl_status,
                r->fit_iterations, r->alias_weak, r->gross_cal, r->gross_val);
        for (int i = 0; i < nd; i++)
            put_field(f, "%.10g", r->dev[i]);
        for (int i = 0; i < np; i++)
            put_field(f, "%.10g", r->par[i]);
        put_field(f, "%.6g", r->fit_rms);
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                put_field(f, "%.6g", r->rms_before[a][b]);
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                put_field(f, "%.6g", r->rms_after[a][b]);
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                put_field(f, "%.6g", r->rms_after_sys[a][b]);
        for (int a = 0; a < na; a++)
            for (int b = 0; b < nb; b++)
                put_field(f, "%.6g", r->rms_after_mf[a][b]);
        int nt = thermal_n_temps(c);
        for (int t = 0; t <= nt && nt > 0; t++)
            for (int w = 0; w < 2; w++) {
                const double(*v)[UNIT_MAX_ANGLES][CONFIG_BANDS_MAX] =
                    w == 0 ? r->rms_before_t : r->rms_after_t;
                for (int a = 0; a < na; a++)
                    for (int b = 0; b < nb; b++)
                        put_field(f, "%.6g", t < nt ? v[t][a][b] : thermal_worst(v, nt, a, b));
            }
        write_verdict(f, c, r);
        fputc('\n', f);
    }
}

void report_write_units(FILE *f, const sunmc_config *c,
                        const unit_result *results, long n)
{
    report_write_units_header(f, c);
    report_write_unit_rows(f, c, results, n);
}
