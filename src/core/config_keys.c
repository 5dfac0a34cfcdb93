/* config_keys.c - the shared configuration keys (every family's), the
 * section order and the shared cross-key checks.
 *
 * Each row: section, name (unit in the name), type, unit, default, allowed
 * range, enum choices, where it lives in sunmc_config, and a one-line help
 * that says where the default comes from.  A family's own keys are in its
 * folder (its *_keys.c), reached through the registry; a family
 * may give its own default for a shared key (sensor_family.defaults).
 */
#include "sampling.h"
#include "config.h"
#include "status.h"
#include "tolerance.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#define OFF(field) offsetof(sunmc_config, field)

/* Sections in the order files, dumps and the reference list them. */
const char *const config_sections[] = {"sensor",   "design",      "tolerance",
                                       "noise",    "campaign",    "calibration",
                                       "validation", "environment", "run", "report"};
const size_t config_section_count = sizeof config_sections / sizeof config_sections[0];

const config_key config_keys[] = {
    /* [sensor] */
    {"sensor", "family", KEY_FAMILY, "", NULL, 0, 0, NULL, OFF(family),
     "sensor family" /* + each family's name and description, from the registry */},
    {"sensor", "product", KEY_STRING, "", "sensor", 0, 0, NULL, OFF(product),
     "product label printed in reports and summary.tsv"},

    /* [tolerance] */
    {"tolerance", "truncation_sigmas", KEY_DOUBLE, "", "3", 0.5, 10, NULL, OFF(truncation_sigmas),
     "truncnormal tolerances are cut at this many sigma"},

    /* [noise] */
    {"noise", "encoder_arcsec", KEY_DOUBLE, "arcsec", "1", 0, 3600, NULL, OFF(encoder_arcsec),
     "sigma of each turntable axis reading"},

    /* [campaign] */
    {"campaign", "repeats", KEY_INT, "", "1", 1, 1000, NULL, OFF(cal_repeats),
     "readings averaged at each campaign point"},
    {"campaign", "dwell_s", KEY_DOUBLE, "s", "1", 0, 3600, NULL, OFF(dwell_s),
     "campaign cost: time to take one reading (integration and readout), per repeat"},
    {"campaign", "point_settle_s", KEY_DOUBLE, "s", "1", 0, 3600, NULL, OFF(point_settle_s),
     "campaign cost: settling time of the table after each step along a line"},
    {"campaign", "line_settle_s", KEY_DOUBLE, "s", "30", 0, 36000, NULL, OFF(line_settle_s),
     "campaign cost: settling time after a move of the slow axis (a new beta line) and "
     "before the first point"},
    {"campaign", "slew_deg_per_s", KEY_DOUBLE, "deg/s", "5", 0.001, 1000, NULL,
     OFF(slew_deg_per_s),
     "campaign cost: table rate; both axes move at once, the longer travel sets the time"},
    {"campaign", "search_steps_deg", KEY_LIST, "deg", "0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 1",
     0.001, 90, NULL, OFF(search_steps_deg),
     "`design`: fast-axis steps tried (ESS alpha, DSS b); steps that alias are run, marked "
     "and never chosen"},
    {"campaign", "search_max_lines", KEY_INT, "", "5", 1, 7, NULL, OFF(search_max_lines),
     "`design`: symmetric slow-axis line sets of 1 to this many evenly spaced lines (ESS beta)"},
    {"campaign", "search_beta_max_deg", KEY_DOUBLE, "deg", "40", 0, 89, NULL,
     OFF(search_beta_max_deg), "`design`: largest |beta| of a line set"},
    {"campaign", "search_beta_step_deg", KEY_DOUBLE, "deg", "10", 0.1, 89, NULL,
     OFF(search_beta_step_deg),
     "`design`: line sets span +-B for B in steps of this up to search_beta_max_deg"},
    {"campaign", "search_repeats", KEY_LIST, "", "1, 2", 1, 1000, NULL, OFF(search_repeats),
     "`design`: readings per point tried (campaign.repeats)"},
    {"campaign", "search_screen_units", KEY_LONG, "", "64", 10, 100000, NULL,
     OFF(search_screen_units),
     "`design`: units of the screen; a candidate whose yield's upper bound is then below "
     "report.yield_target is dropped"},
    {"campaign", "search_max_units", KEY_LONG, "", "4096", 10, 10000000, NULL,
     OFF(search_max_units),
     "`design`: most units a candidate runs (blocks of run.block_units) while its yield's "
     "bound has not settled against report.yield_target"},
    {"campaign", "search_shortlist", KEY_INT, "", "5", 1, 100, NULL, OFF(search_shortlist),
     "`design`: stop after this many candidates, cheapest first, settled as meeting the target"},
    {"campaign", "search_max_extrapolation_deg", KEY_DOUBLE, "deg", "0.5", 0, 90, NULL,
     OFF(search_max_extrapolation_deg),
     "`design`: candidates whose validation angles lie further than this beyond the "
     "campaign's span (campaign.h) are not tried: a calibration is not trusted where it "
     "extrapolates"},

    /* [calibration] */
    {"calibration", "max_iterations", KEY_INT, "", "100", 5, 10000, NULL, OFF(max_iterations),
     "most Levenberg-Marquardt iterations per fit"},
    {"calibration", "max_dropped_fraction", KEY_DOUBLE, "", "0.05", 0, 1, NULL,
     OFF(max_dropped_fraction),
     "`calibrate`: a fit that had to drop more than this fraction of the rows as gross errors "
     "is refused (the data are not this sensor's, or not in its units)"},
    {"calibration", "max_residual_ratio", KEY_DOUBLE, "", "10", 1, 1e6, NULL,
     OFF(max_residual_ratio),
     "`calibrate`: a fit whose residual exceeds this many times the reading noise of the "
     "config (at least 1 arcsec) is refused"},
    {"calibration", "priors", KEY_ENUM, "", "tolerances", 0, 0, "off|tolerances", OFF(cal_priors),
     "Gaussian priors on the fitted parameters: off, or tolerances (each parameter's mean and "
     "sigma over a pilot of calibration.prior_units units drawn from the tolerances and "
     "fitted without noise: what the lab knows before the campaign), as extra residual rows "
     "weighted by the reading noise"},
    {"calibration", "outlier_campaigns", KEY_ENUM, "", "drop", 0, 0, "keep|drop",
     OFF(cal_outlier_campaigns),
     "`calibrate`, data of repeat campaigns (single-axis sweeps, each table line swept "
     "again and again): a campaign the others predict more than 2 times worse than the median "
     "one (at most a quarter of them) is named and dropped from the calibration (drop), or "
     "kept in it and left out of the accuracy estimate only (keep)"},
    {"calibration", "prior_units", KEY_INT, "", "48", 8, 100000, NULL, OFF(prior_units),
     "calibration.priors = tolerances: units of the pilot that sets the priors (drawn from "
     "run.seed's own pilot stream, the same in every shard and thread)"},
    {"calibration", "onboard", KEY_STRING, "", "double", 0, 0, NULL, OFF(onboard),
     "the arithmetic each unit is validated through: double (the model), float (`sunmc "
     "export`'s code built with -DSUNMC_FLOAT; PSD: physical and polynomial models) or table:STEP (its table form, STEP in "
     "the reading axes' unit: ESS output_deg, DSS px, PSD channel ratio; at most 10^6 nodes); "
     "Table 1, the yield and `budget` (its ONBOARD_ part) then include the on-board error"},

    /* [environment] */
    {"environment", "calibration_temp_c", KEY_DOUBLE, "C", "20", -100, 150, NULL,
     OFF(cal_temp_c), "the lab's temperature: the campaign is simulated and fitted at it"},
    {"environment", "operating_temp_c", KEY_LIST, "C", "20", -100, 150, NULL, OFF(op_temps_c),
     "the temperatures of the validation (in orbit): a list, items START:STOP:STEP included "
     "(e.g. -30, 0, 30, 60 or -30:60:30); each unit is calibrated once at calibration_temp_c "
     "and validated at the lab's temperature and at each of these, the materials below moving "
     "it by (operating - calibration); the yield over the range counts a unit passing at every "
     "one; just calibration_temp_c: the lab's validation alone, as without these keys "
     "(docs/temperature.md)"},
    {"environment", "spacer_cte_ppm_k", KEY_DOUBLE, "ppm/K", "23.1", -50, 100, NULL,
     OFF(spacer_cte_ppm_k),
     "expansion of the spacer that sets the ESS slit-to-dial distance H and the DSS pinhole "
     "height h; 23.1 = aluminium (6061-T6; ASM Handbook vol. 2)"},
    {"environment", "mask_cte_ppm_k", KEY_DOUBLE, "ppm/K", "7.1", -50, 100, NULL,
     OFF(mask_cte_ppm_k),
     "expansion of the ESS code dial (its code pitch); 7.1 = N-BK7 (Schott data sheet)"},
    {"environment", "detector_cte_ppm_k", KEY_DOUBLE, "ppm/K", "2.6", -50, 100, NULL,
     OFF(detector_cte_ppm_k),
     "expansion of the DSS detector (its pixel pitch); 2.6 = silicon at 20 C (Okada & "
     "Tokumaru 1984, J. Appl. Phys. 56)"},
    {"environment", "glass_cte_ppm_k", KEY_DOUBLE, "ppm/K", "7.1", -50, 100, NULL,
     OFF(glass_cte_ppm_k), "expansion of the DSS cover glass (its thickness); 7.1 = N-BK7"},
    {"environment", "glass_dn_dt_ppm_k", KEY_DOUBLE, "ppm/K", "1.6", -50, 50, NULL,
     OFF(glass_dn_dt_ppm_k),
     "the DSS cover glass's index change per kelvin (absolute dn/dT, 1e-6/K); 1.6 = N-BK7 "
     "near 20 C in the visible to near infrared (Schott data sheet, 1.1-1.6)"},

    /* [run] */
    {"run", "units", KEY_LONG, "", "1000", 1, 100000000, NULL, OFF(units),
     "number of simulated units (--units N or --units FIRST:END)"},
    {"run", "seed", KEY_LONG, "", "1", 0, 2147483647, NULL, OFF(seed),
     "random seed; unit u's draws depend only on (seed, u)"},
    {"run", "threads", KEY_INT, "", "0", 0, 1024, NULL, OFF(threads),
     "OpenMP threads, 0 = all cores; results do not depend on it"},
    {"run", "lot_size", KEY_LONG, "", "100", 1, 100000000, NULL, OFF(lot_size),
     "units per production lot: units u and v share a lot when u / lot_size = v / lot_size "
     "(integer division); a tolerance's NAME_lot share of its variance is common to its lot"},
    {"run", "sampling", KEY_ENUM, "", "random", 0, 0, "random|lhs|sobol", OFF(sampling),
     "design of the tolerance draws (noise stays random): random (independent units), lhs "
     "(Latin hypercube) or sobol (digitally shifted Sobol' points), each randomised anew per "
     "block of run.sampling_block units; intervals come from the block totals "
     "(docs/statistics.md)"},
    {"run", "sampling_block", KEY_LONG, "", "64", 2, SAMPLING_BLOCK_MAX, NULL, OFF(sampling_block),
     "`run.sampling = lhs | sobol`: units per randomised design (a power of 2 keeps a Sobol' "
     "block a net); fewer units per block give more blocks, so a surer interval"},
    {"run", "block_units", KEY_LONG, "", "256", 1, 1000000, NULL, OFF(block_units),
     "units per block, each written and checkpointed as it ends; `run --until` checks between blocks"},

    /* [report] */
    {"report", "bands_deg", KEY_BANDS, "deg", "0:30, 30:60, 0:62", 0, 90, NULL, OFF(bands_deg),
     "RMS bands on |alpha| (ESS; ESS paper Table 1) or on the field angle (DSS)"},
    {"report", "spec_arcsec", KEY_DOUBLE, "arcsec", "54", 0, 36000, NULL, OFF(spec_arcsec),
     "the accuracy a unit must meet after calibration (report.spec_statistic of its error, in "
     "every band of report.spec_bands) to pass; 54\" = 0.015 deg"},
    {"report", "spec_statistic", KEY_ENUM, "", "rms", 0, 0, "rms|p99.7|max", OFF(spec_statistic),
     "what of a unit's error over a band's validation points the spec bounds: rms (an RMS "
     "over the field, as most datasheets), p99.7 (the 99.73 % quantile of |error|, a "
     "datasheet's \"3 sigma\" without assuming a normal law; the nearest-rank order statistic, "
     "which is the max below 370 points) or max (a bound, \"+-0.1 deg\")"},
    {"report", "spec_bands", KEY_STRING, "", "all", 0, 0, NULL, OFF(spec_bands),
     "the bands of report.bands_deg the spec holds in: all (the whole field), or a list of "
     "them as written there (\"0:25, 25:50\"); a unit passes only in every one"},
    {"report", "min_coverage", KEY_DOUBLE, "", "1", 0, 1, NULL, OFF(min_coverage),
     "share of each spec band's validation points a unit must read (sun seen, spot on the "
     "detector, no gross error); below it the unit fails: a sensor blind over part of its "
     "field does not meet a spec over that field"},
    {"report", "yield_target", KEY_DOUBLE, "", "0.95", 0.01, 1, NULL, OFF(yield_target),
     "`budget`, `design`, `allocate`: the yield (fraction of units meeting the spec: "
     "report.spec_statistic, spec_bands, min_coverage) each inverse tolerance limit, chosen "
     "campaign and allocation must keep"},
    {"report", "budget_units", KEY_LONG, "", "100", 10, 1000000, NULL, OFF(budget_units),
     "`budget`: units per Monte Carlo step of the inverse-limit bisection"},
    {"report", "budget_steps", KEY_INT, "", "5", 1, 40, NULL, OFF(budget_steps),
     "`budget`: bisection steps per source for the inverse limit"},
    {"report", "confidence", KEY_DOUBLE, "", "0.95", 0.5, 0.999, NULL, OFF(confidence),
     "two-sided level of every confidence interval in summary.tsv, sweep.tsv and Table 1"},
    {"report", "yield_interval", KEY_ENUM, "", "wilson", 0, 0,
     "wilson|clopper_pearson|clopper_pearson_lower", OFF(yield_interval),
     "the yield's interval: wilson (two-sided score interval, coverage near nominal, may "
     "under-cover very close to 100 %), clopper_pearson (two-sided, exact: coverage at least "
     "report.confidence) or clopper_pearson_lower (one-sided: the yield is at least the lower "
     "bound with confidence report.confidence, upper bound 1); design and budget compare the "
     "lower bound with report.yield_target"},
    {"report", "model_form_every", KEY_LONG, "", "10", 0, 100000000, NULL, OFF(model_form_every),
     "every N-th unit (unit mod N = 0) is calibrated a second time on its campaign without "
     "noise and read without noise: its after-RMS is the model-form part of Table 1 (what "
     "the calibration model cannot represent of the simulated sensor; docs/statistics.md); "
     "0 = none, 1 = every unit (a second fit each)"},
    {"report", "cost_exponent", KEY_DOUBLE, "", "1", 0.1, 10, NULL, OFF(cost_exponent),
     "`allocate`: k of the cost model, a tolerance at value v costs tolerance.NAME_cost * "
     "(today / v)^k (halving a tolerance costs 2^k times as much)"},
};

const size_t config_key_count = sizeof config_keys / sizeof config_keys[0];

int config_check_grid(double lo, double hi, double step, double fov, const char *what, char *err,
                      size_t errlen)
{
    if (!(hi > lo))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: min must be below max (%g >= %g)", what,
                          lo, hi);
    if (fabs(lo) > fov + 1e-9 || fabs(hi) > fov + 1e-9)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: range %g..%g deg leaves the field of view +-%g deg", what, lo, hi,
                          fov);
    if ((hi - lo) / step > 100000)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: more than 100000 steps", what);
    return SUNMC_OK;
}

static double fam_double(const sunmc_config *c, size_t offset)
{
    double v;
    memcpy(&v, c->fam.bytes + offset, sizeof v);
    return v;
}

static int check_one_physical(const sunmc_config *c, const config_physical *p, char *err,
                              size_t errlen)
{
    const tolerance *t = (const tolerance *)(const void *)(c->fam.bytes + p->tol_offset);
    double design = p->design_offset == CONFIG_PHYSICAL_NONE ? p->design_fixed
                                                             : fam_double(c, p->design_offset);
    double scale = p->scale * (p->scale_offset == CONFIG_PHYSICAL_NONE
                                   ? 1.0
                                   : fam_double(c, p->scale_offset));
    double lo, hi;
    tolerance_range(t, c->truncation_sigmas, &lo, &hi);
    double q = design + scale * lo;
    if (p->strict ? q > p->floor : q >= p->floor)
        return SUNMC_OK;
    char range[96];
    tolerance_range_text(t, c->truncation_sigmas, range, sizeof range);
    const char *sp = p->unit[0] ? " " : "";
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "%s = %g (%s) can make %s %s %g%s%s: with %s = %g the draws reach %g%s%s; "
                      "lower the tolerance or change the design value%s",
                      p->tol_key, t->value, range, p->quantity, p->strict ? "<=" : "<", p->floor,
                      sp, p->unit, p->design_key, design, q, sp, p->unit,
                      t->dist == DIST_NORMAL ? ", or bound the draws (truncnormal)" : "");
}

int config_check_physical(const sunmc_config *c, const config_physical *list, char *err,
                          size_t errlen)
{
    for (const config_physical *p = list; p->quantity; p++) {
        int s = check_one_physical(c, p, err, errlen);
        if (s != SUNMC_OK)
            return s;
    }
    return SUNMC_OK;
}
