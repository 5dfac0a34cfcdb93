/* ess_keys.c - the ESS family's configuration keys, its defaults of shared
 * keys and its cross-key checks.
 *
 * Defaults are those of product type A in Fan et al., "Error Modeling and
 * Calibration for Encoded Sun Sensors", Sensors 2013 (the "ESS paper");
 * configs/ess_type_b.ini overrides what differs for type B.
 */
#include "ess_calib.h"
#include "ess_config.h"
#include "ess_model.h"
#include "family.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <stddef.h>

#define OFF(field) offsetof(ess_config, field)
#define NONE CONFIG_PHYSICAL_NONE
_Static_assert(sizeof(ess_config) <= sizeof(family_config), "ess_config must fit family_config");

const config_key ess_keys[] = {
    /* [design] */
    {"design", "H_mm", KEY_DOUBLE, "mm", "4.124", 0.5, 50, NULL, OFF(design.H_mm),
     "nominal slit-to-code-dial distance H (ESS paper sec. 3.1: 4.124 type A, 6.584 type B)"},
    {"design", "theta0_deg", KEY_DOUBLE, "deg", "2", 0.1, 10, NULL, OFF(design.theta0_deg),
     "fine-code period theta0 (ESS paper sec. 3.3: usually 2 deg)"},
    {"design", "coarse_resolution_deg", KEY_DOUBLE, "deg", "1", 0.05, 5, NULL,
     OFF(design.coarse_resolution_deg),
     "coarse-code cell width; the coarse reading picks the fine period (7 Gray rows x 1 deg "
     "cover +-64 deg)"},
    {"design", "coarse_rows_x_mm", KEY_LIST, "mm", "-4.2, -3.6, -3.0, -2.4, -1.8, -1.2, -0.6",
     -20, 20, NULL, OFF(design.coarse_rows_x_mm),
     "x position (across the rows) of each coarse row, most significant Gray bit first; "
     "7 rows as in the ESS paper"},
    {"design", "fine_rows_x_mm", KEY_LIST, "mm", "0.6, 1.2, 1.8, 2.4", -20, 20, NULL,
     OFF(design.fine_rows_x_mm),
     "x position of the 4 fine rows F1..F4 (quarter-period steps)"},
    {"design", "tilt_pivot_mm", KEY_DOUBLE, "mm", "0", -20, 20, NULL,
     OFF(design.tilt_pivot_mm),
     "x position about which the slit's tilt dphi turns: each row reads (x_row - pivot) "
     "tan(dphi) off; 0 = the dial's centre line (the slit's middle), 1.5 = the fine rows' "
     "centre, where the tilt leaves only their alternation (docs/ess.md)"},
    {"design", "slit_width_um", KEY_DOUBLE, "um", "20", 0, 500, NULL, OFF(design.slit_width_um),
     "entrance slit width; with the sun's diameter it sets the fine-code harmonics (derived "
     "mode); chosen so type A's error before compensation has the paper's size"},
    {"design", "dial_duty", KEY_DOUBLE, "", "0.5", 0.05, 0.95, NULL, OFF(design.dial_duty),
     "transparent fraction of one fine-code period on the dial"},
    {"design", "sun_diameter_deg", KEY_DOUBLE, "deg", "0.53", 0, 2, NULL,
     OFF(design.sun_diameter_deg),
     "angular diameter of the sun (ESS paper sec. 3.3: 0.53 deg)"},
    {"design", "harmonics", KEY_ENUM, "", "derived", 0, 0, "derived|given", OFF(design.harmonics),
     "fine-code harmonics: derived from slit width, duty and sun diameter, or given by "
     "a3_ratio/a5_ratio"},
    {"design", "a3_ratio", KEY_DOUBLE, "", "-0.1", -0.5, 0.5, NULL, OFF(design.a3_ratio),
     "a3/a1 when harmonics = given (ESS paper eq. 2, 7)"},
    {"design", "a5_ratio", KEY_DOUBLE, "", "0", -0.5, 0.5, NULL, OFF(design.a5_ratio),
     "a5/a1 when harmonics = given"},
    {"design", "fov_deg", KEY_DOUBLE, "deg", "62", 1, 80, NULL, OFF(design.fov_deg),
     "half field of view in alpha (ESS paper: +-62 deg)"},

    /* [tolerance]: one pair of keys per line of ESS_DEVIATIONS */
    ESS_DEVIATIONS(DEVIATION_X_KEYS)

    /* [noise] */
    {"noise", "row_current_pct", KEY_DOUBLE, "%", "1.5", 0, 100, NULL, OFF(noise.row_current_pct),
     "sigma of each fine-row current, % of the fundamental a1 at normal incidence; chosen so "
     "the after-compensation RMS has the ESS paper's Table 1 size"},

    /* [campaign] */
    {"campaign", "alpha_min_deg", KEY_DOUBLE, "deg", "-61.95", -89, 89, NULL,
     OFF(cal_alpha_min_deg),
     "first turntable inner-frame angle (ESS paper: +-62 deg); -61.95..61.95 is 177 steps of "
     "0.7 and ends on the validation's outermost angles"},
    {"campaign", "alpha_max_deg", KEY_DOUBLE, "deg", "61.95", -89, 89, NULL,
     OFF(cal_alpha_max_deg), "last turntable inner-frame angle"},
    {"campaign", "alpha_step_deg", KEY_DOUBLE, "deg", "0.7", 0.001, 90, NULL,
     OFF(cal_alpha_step_deg),
     "inner-frame step; 0.7 = 0.5 x 7/5 samples 5 phases of the 0.5-deg fine-code term (ESS "
     "paper Table 2: 1 and 0.25 alias it) and resolves harmonics 1, 2 and 4 of the 2-deg fine "
     "period (0.8 samples the 1st as the 4th); 0.7 x beta -30, 0, 30 is the shipped configs' "
     "campaign, chosen by `sunmc design` for both calibration models"},
    {"campaign", "beta_deg", KEY_LIST, "deg", "-30, 0, 30", -89, 89, NULL, OFF(cal_beta_deg),
     "outer-frame angles, one alpha scan each; +-30 covers the validation's beta +-25 (no "
     "extrapolation)"},

    /* [calibration] */
    {"calibration", "roll_sigma_arcsec", KEY_DOUBLE, "arcsec", "5", 0, 3600, NULL,
     OFF(roll_sigma_arcsec),
     "sigma of the roll (install_x) alignment measurement; the fit fixes the roll at the "
     "measured value because turntable data cannot separate it from (b, c)"},
    {"calibration", "roll_measured_arcsec", KEY_DOUBLE, "arcsec", "0", -36000, 36000, NULL,
     OFF(roll_measured_arcsec),
     "`calibrate` only: the measured installation roll of a real sensor"},
    {"calibration", "sun_y", KEY_ENUM, "", "fitted", 0, 0, "fitted|measured", OFF(sun_y_mode),
     "the sun simulator's tilt toward Y: fitted with the other parameters, or measured and "
     "fixed like the roll (one parameter fewer); turntable data separate it from eq. 12's b, c "
     "only by 1 - cos(beta) (|r| ~ 0.99 on +-30 deg lines), so the fitted tilt lets the "
     "campaign's noise into b and c"},
    {"calibration", "sun_y_sigma_arcsec", KEY_DOUBLE, "arcsec", "5", 0, 3600, NULL,
     OFF(sun_y_sigma_arcsec),
     "calibration.sun_y = measured: sigma of the sun simulator's tilt measurement (Monte "
     "Carlo; its own random stream)"},
    {"calibration", "sun_y_measured_arcsec", KEY_DOUBLE, "arcsec", "0", -36000, 36000, NULL,
     OFF(sun_y_measured_arcsec),
     "`calibrate` with calibration.sun_y = measured: the measured tilt of the sun simulator "
     "toward Y"},
    {"calibration", "alias_threshold", KEY_DOUBLE, "", "0.2", 0, 1, NULL, OFF(alias_threshold),
     "smallest normalised eigenvalue of the fine-code (sin, cos) columns below which the "
     "campaign cannot resolve that direction; it is then regularised to 0"},
    {"calibration", "model", KEY_ENUM, "", "paper", 0, 0,
     "paper|extended|spline|hybrid|table", OFF(cal_model),
     "ESS calibration model: paper (eq. 12 + k sin(4 pi alpha + t), 8 parameters), extended "
     "(18: the fine period's 1st, 2nd harmonics, the 4th's incidence dependence, eq. 7 "
     "exact; src/ess/ess_model_ext.c), spline (the true angle as a penalised B-spline of "
     "the measured one), hybrid (paper + a spline of its residual) or table (a look-up "
     "table of the spline); docs/calibration.md"},

    /* [validation] */
    {"validation", "alpha_min_deg", KEY_DOUBLE, "deg", "-62", -89, 89, NULL, OFF(val_alpha_min_deg),
     "first validation incidence angle"},
    {"validation", "alpha_max_deg", KEY_DOUBLE, "deg", "62", -89, 89, NULL, OFF(val_alpha_max_deg),
     "last validation incidence angle"},
    {"validation", "alpha_step_deg", KEY_DOUBLE, "deg", "0.13", 0.001, 90, NULL,
     OFF(val_alpha_step_deg),
     "validation step (not a divisor of the fine-code period)"},
    {"validation", "alpha_offset_deg", KEY_DOUBLE, "deg", "0.05", -10, 10, NULL,
     OFF(val_alpha_offset_deg),
     "offset of the validation grid from alpha_min_deg"},
    {"validation", "beta_deg", KEY_LIST, "deg", "-25, -10, 10, 25", -89, 89, NULL,
     OFF(val_beta_deg),
     "outer-frame angles of the validation scans (not the campaign's)"},
    {NULL} /* end */
};

const config_default ess_defaults[] = {
    {"sensor", "product", "ESS type A"},
    {"report", "bands_deg", "0:30, 30:60, 0:62"},
    {"report", "spec_arcsec", "54"},
    {NULL} /* end */
};

/* Draws that would build an impossible sensor: a slit at or below the dial,
 * a negative slit width, a dead or inverted photocell. */
static const config_physical ess_physical[] = {
    {"the slit-to-dial height H + dH", "mm", "design.H_mm", OFF(design.H_mm), 0,
     "tolerance.dH_um", OFF(tol.dH_um), MM_PER_UM, NONE, 0, 1},
    {"the slit width", "um", "design.slit_width_um", OFF(design.slit_width_um), 0,
     "tolerance.slit_width_um", OFF(tol.slit_width_um), 1, NONE, 0, 0},
    {"the fine-row photocell gain 1 + gain_pct/100", "%", "the nominal gain (100%)", NONE, 100,
     "tolerance.gain_pct", OFF(tol.gain_pct), 1, NONE, 0, 1},
    {NULL}};

static int physical_check(const sunmc_config *c, char *err, size_t errlen)
{
    return config_check_physical(c, ess_physical, err, errlen);
}

/* Every report band must hold validation points (|alpha| of the grid). */
static int band_check(const sunmc_config *c, char *err, size_t errlen)
{
    const ess_config *e = ess_cfg(c);
    band_acc acc;
    band_acc_reset(&acc);
    double max_abs = 0;
    long n = grid_count(e->val_alpha_min_deg, e->val_alpha_max_deg, e->val_alpha_step_deg,
                        e->val_alpha_offset_deg);
    for (long i = 0; i < n; i++) {
        double a = fabs(e->val_alpha_min_deg + e->val_alpha_offset_deg +
                        (double)i * e->val_alpha_step_deg);
        band_acc_add(&acc, &c->bands_deg, a, 0);
        max_abs = fmax(max_abs, a);
    }
    return band_check_coverage(&c->bands_deg, &acc, max_abs, e->design.fov_deg, "design.fov_deg",
                               "alpha",
                               "validation.alpha_min_deg, validation.alpha_max_deg, "
                               "validation.alpha_step_deg, validation.alpha_offset_deg",
                               err, errlen);
}

int ess_config_validate(const sunmc_config *c, char *err, size_t errlen)
{
    const ess_config *e = ess_cfg(c);
    const ess_design *d = &e->design;
    int s;
    if (d->fine_rows_x_mm.n != 4)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "design.fine_rows_x_mm must list exactly 4 rows, has %d",
                          d->fine_rows_x_mm.n);
    double cover = ldexp(d->coarse_resolution_deg, d->coarse_rows_x_mm.n);
    if (cover < 2 * d->fov_deg + 2 * d->coarse_resolution_deg)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "design: %d coarse rows of %g deg cover %g deg, less than the "
                          "field of view +-%g deg (design.coarse_rows_x_mm, "
                          "design.coarse_resolution_deg, design.fov_deg)",
                          d->coarse_rows_x_mm.n, d->coarse_resolution_deg, cover, d->fov_deg);
    if (d->coarse_resolution_deg > d->theta0_deg / 2)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "design.coarse_resolution_deg = %g must be at most half of "
                          "design.theta0_deg = %g to pick the fine period",
                          d->coarse_resolution_deg, d->theta0_deg);
    if ((s = physical_check(c, err, errlen)) != SUNMC_OK)
        return s;
    if ((s = config_check_grid(e->cal_alpha_min_deg, e->cal_alpha_max_deg, e->cal_alpha_step_deg,
                               d->fov_deg, "campaign.alpha", err, errlen)) != SUNMC_OK)
        return s;
    /* The fit needs more campaign points than parameters. */
    long na = grid_count(e->cal_alpha_min_deg, e->cal_alpha_max_deg, e->cal_alpha_step_deg, 0);
    long points = na * e->cal_beta_deg.n;
    int np = ess_model_np(e->cal_model) - (e->sun_y_mode == ESS_SUN_Y_MEASURED);
    if (ESS_MODEL_HAS_SPLINE(e->cal_model) && np < ESS_SPLINE_MIN_ROWS - 1)
        np = ESS_SPLINE_MIN_ROWS - 1;
    if (points <= np)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "campaign: %ld alpha x %d beta_deg = %ld points, fewer than the %d the "
                          "fit of %d parameters needs (campaign.alpha_min_deg, "
                          "campaign.alpha_max_deg, campaign.alpha_step_deg, campaign.beta_deg)",
                          na, e->cal_beta_deg.n, points, np + 1, np);
    if ((s = config_check_grid(e->val_alpha_min_deg, e->val_alpha_max_deg, e->val_alpha_step_deg,
                               d->fov_deg, "validation.alpha", err, errlen)) != SUNMC_OK)
        return s;
    return band_check(c, err, errlen);
}
