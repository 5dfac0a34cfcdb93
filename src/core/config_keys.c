/* config_keys.c - THE table of configuration keys, and the cross-key checks.
 *
 * Every key of every family is one row here: section, name (unit in the
 * name), type, families, unit, default (ESS or both), DSS default when it
 * differs, allowed range, enum choices, where it lives in sunmc_config, and a
 * one-line help that says where the default comes from.
 *
 * ESS defaults are those of product type A in Fan et al., "Error Modeling and
 * Calibration for Encoded Sun Sensors", Sensors 2013 (the "ESS paper");
 * configs/ess_type_b.ini overrides what differs for type B.  DSS defaults are
 * from Wei et al., "System modeling based measurement error analysis of
 * digital sun sensors" (the "DSS paper").
 */
#include "config.h"
#include "status.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#define OFF(field) offsetof(sunmc_config, field)
#define E FAMILY_ESS
#define D FAMILY_DSS
#define B FAMILY_BOTH
#define BIG 1e9

#define DIST_CHOICES "fixed|uniform|normal|truncnormal"

/* A tolerance is two keys: its magnitude and its distribution. */
#define TOL(fam, fld, name, unit, defv, defdist, maxv, help)                                      \
    {"tolerance", name, KEY_DOUBLE, fam, unit, defv, NULL, 0, maxv, NULL, OFF(fld.value), help},  \
    {"tolerance", name "_dist", KEY_ENUM, fam, "", defdist, NULL, 0, 0, DIST_CHOICES,             \
     OFF(fld.dist), "distribution of " name ": fixed (the value), uniform (+-value), normal "     \
                    "(sigma = value), truncnormal (sigma = value, cut at truncation_sigmas)"}

const config_key config_keys[] = {
    /* [sensor] */
    {"sensor", "family", KEY_ENUM, B, "", "ess", NULL, 1, 0, "ess|dss", OFF(family),
     "sensor family: ess (encoded sun sensor) or dss (pinhole digital sun sensor)"},
    {"sensor", "product", KEY_STRING, B, "", "ESS type A", "DSS", 0, 0, NULL, OFF(product),
     "product label printed in reports and summary.tsv"},

    /* [design] ESS */
    {"design", "H_mm", KEY_DOUBLE, E, "mm", "4.124", NULL, 0.5, 50, NULL, OFF(ess.H_mm),
     "nominal slit-to-code-dial distance H (ESS paper sec. 3.1: 4.124 type A, 6.584 type B)"},
    {"design", "theta0_deg", KEY_DOUBLE, E, "deg", "2", NULL, 0.1, 10, NULL, OFF(ess.theta0_deg),
     "fine-code period theta0 (ESS paper sec. 3.3: usually 2 deg)"},
    {"design", "coarse_resolution_deg", KEY_DOUBLE, E, "deg", "1", NULL, 0.05, 5, NULL,
     OFF(ess.coarse_resolution_deg),
     "coarse-code cell width; the coarse reading picks the fine period (7 Gray rows x 1 deg "
     "cover +-64 deg)"},
    {"design", "coarse_rows_x_mm", KEY_LIST, E, "mm", "-4.2, -3.6, -3.0, -2.4, -1.8, -1.2, -0.6",
     NULL, -20, 20, NULL, OFF(ess.coarse_rows_x_mm),
     "x position (across the rows) of each coarse row, most significant Gray bit first; "
     "7 rows as in the ESS paper"},
    {"design", "fine_rows_x_mm", KEY_LIST, E, "mm", "0.6, 1.2, 1.8, 2.4", NULL, -20, 20, NULL,
     OFF(ess.fine_rows_x_mm), "x position of the 4 fine rows F1..F4 (quarter-period steps)"},
    {"design", "slit_width_um", KEY_DOUBLE, E, "um", "20", NULL, 0, 500, NULL,
     OFF(ess.slit_width_um),
     "entrance slit width; with the sun's diameter it sets the fine-code harmonics (derived "
     "mode); chosen so type A's error before compensation has the paper's size"},
    {"design", "dial_duty", KEY_DOUBLE, E, "", "0.5", NULL, 0.05, 0.95, NULL, OFF(ess.dial_duty),
     "transparent fraction of one fine-code period on the dial"},
    {"design", "sun_diameter_deg", KEY_DOUBLE, E, "deg", "0.53", NULL, 0, 2, NULL,
     OFF(ess.sun_diameter_deg), "angular diameter of the sun (ESS paper sec. 3.3: 0.53 deg)"},
    {"design", "harmonics", KEY_ENUM, E, "", "derived", NULL, 0, 0, "derived|given",
     OFF(ess.harmonics),
     "fine-code harmonics: derived from slit width, duty and sun diameter, or given by "
     "a3_ratio/a5_ratio"},
    {"design", "a3_ratio", KEY_DOUBLE, E, "", "-0.1", NULL, -0.5, 0.5, NULL, OFF(ess.a3_ratio),
     "a3/a1 when harmonics = given (ESS paper eq. 2, 7)"},
    {"design", "a5_ratio", KEY_DOUBLE, E, "", "0", NULL, -0.5, 0.5, NULL, OFF(ess.a5_ratio),
     "a5/a1 when harmonics = given"},
    {"design", "fov_deg", KEY_DOUBLE, E, "deg", "62", NULL, 1, 80, NULL, OFF(ess.fov_deg),
     "half field of view in alpha (ESS paper: +-62 deg)"},

    /* [design] DSS */
    {"design", "h_mm", KEY_DOUBLE, D, "mm", "3", NULL, 0.2, 50, NULL, OFF(dss.h_mm),
     "nominal pinhole-to-detector height h"},
    {"design", "pixel_um", KEY_DOUBLE, D, "um", "5.5", NULL, 0.5, 100, NULL, OFF(dss.pixel_um),
     "detector pixel pitch"},
    {"design", "detector_px", KEY_INT, D, "px", "2048", NULL, 16, 100000, NULL,
     OFF(dss.detector_px), "detector side length in pixels (square detector)"},
    {"design", "pinhole_um", KEY_DOUBLE, D, "um", "60", NULL, 1, 5000, NULL, OFF(dss.pinhole_um),
     "pinhole diameter (sets the spot size for the S-curve bias)"},
    {"design", "glass_thickness_mm", KEY_DOUBLE, D, "mm", "0.4", NULL, 0, 5, NULL,
     OFF(dss.glass_thickness_mm), "detector cover-glass thickness"},
    {"design", "glass_index", KEY_DOUBLE, D, "", "1.52", NULL, 1, 3, NULL, OFF(dss.glass_index),
     "cover-glass refractive index"},
    {"design", "dss_fov_deg", KEY_DOUBLE, D, "deg", "60", NULL, 1, 80, NULL, OFF(dss.fov_deg),
     "half field of view per axis"},

    /* [tolerance] ESS */
    TOL(E, ess_tol.dH_um, "dH_um", "um", "2", "uniform", 1000,
        "slit-to-dial distance error dH (ESS paper sec. 3.1: +-2 um)"),
    TOL(E, ess_tol.dd_um, "dd_um", "um", "1", "uniform", 1000,
        "slit offset dd from the dial's centre line (ESS paper sec. 3.2: +-1 um)"),
    TOL(E, ess_tol.dphi_deg, "dphi_deg", "deg", "0.01", "uniform", 10,
        "slit tilt dphi against the dial's centre line (ESS paper sec. 3.2: +-0.01 deg)"),
    TOL(E, ess_tol.slit_width_um, "slit_width_um", "um", "1", "uniform", 100,
        "slit width error (changes the derived fine-code harmonics)"),
    TOL(E, ess_tol.harmonic_phase_deg, "harmonic_phase_deg", "deg", "180", "uniform", 180,
        "phase of the 3rd harmonic against the fundamental, from etched-edge asymmetry "
        "(ESS paper Tables 3-4 show t far from 0)"),
    TOL(E, ess_tol.gain_pct, "gain_pct", "%", "1", "uniform", 50,
        "per-row photocell gain error (ESS paper sec. 3.4: within +-1%)"),
    TOL(E, ess_tol.etch_um, "etch_um", "um", "0.2", "uniform", 50,
        "per-row etching position error of the fine-code pattern (ESS paper sec. 3.4)"),
    TOL(E, ess_tol.install_x_arcsec, "install_x_arcsec", "arcsec", "60", "uniform", 36000,
        "ESS-to-turntable rotation about X (roll in the sensing plane; measured, not fitted)"),
    TOL(E, ess_tol.install_y_arcsec, "install_y_arcsec", "arcsec", "300", "uniform", 36000,
        "ESS-to-turntable rotation about Y (ESS paper Table 3: up to 5')"),
    TOL(E, ess_tol.install_z_arcsec, "install_z_arcsec", "arcsec", "90", "uniform", 36000,
        "ESS-to-turntable rotation about Z (ESS paper Table 3: up to 1'8\")"),
    TOL(E, ess_tol.sun_x_arcsec, "sun_x_arcsec", "arcsec", "60", "uniform", 36000,
        "sun-simulator direction tilt toward X (the V0 of ESS paper eq. 14)"),
    TOL(E, ess_tol.sun_y_arcsec, "sun_y_arcsec", "arcsec", "60", "uniform", 36000,
        "sun-simulator direction tilt toward Y"),

    /* [tolerance] DSS */
    TOL(D, dss_tol.dh_px, "dh_px", "px", "0.2", "uniform", 1000,
        "pinhole height error dh (DSS paper Fig. 2: 0.2 pixel)"),
    TOL(D, dss_tol.dx_px, "dx_px", "px", "0.1", "uniform", 1000,
        "principal point error dx (DSS paper Fig. 3: 0.1 pixel)"),
    TOL(D, dss_tol.dy_px, "dy_px", "px", "0.1", "uniform", 1000,
        "principal point error dy (DSS paper Fig. 3: 0.1 pixel)"),
    TOL(D, dss_tol.c1_arcsec, "c1_arcsec", "arcsec", "10", "uniform", 36000,
        "installation rotation c1 about X (DSS paper sec. 3: c1, c2 about X, Y, c3 about the "
        "principal axis, composed in zxy order; Fig. 4: 10\")"),
    TOL(D, dss_tol.c2_arcsec, "c2_arcsec", "arcsec", "10", "uniform", 36000,
        "installation rotation c2 about Y (DSS paper Fig. 4: 10\")"),
    TOL(D, dss_tol.c3_arcsec, "c3_arcsec", "arcsec", "10", "uniform", 36000,
        "installation rotation c3 about Z, the principal axis (DSS paper Fig. 4: 10\")"),
    TOL(D, dss_tol.glass_thickness_um, "glass_thickness_um", "um", "10", "uniform", 1000,
        "cover-glass thickness error"),
    TOL(D, dss_tol.glass_index, "glass_index", "", "0.005", "uniform", 0.5,
        "cover-glass refractive index error"),

    {"tolerance", "truncation_sigmas", KEY_DOUBLE, B, "", "3", NULL, 0.5, 10, NULL,
     OFF(truncation_sigmas), "truncnormal tolerances are cut at this many sigma"},

    /* [noise] */
    {"noise", "row_current_pct", KEY_DOUBLE, E, "%", "1.5", NULL, 0, 100, NULL,
     OFF(ess_noise.row_current_pct),
     "sigma of each fine-row current, % of the fundamental a1 at normal incidence; chosen so "
     "the after-compensation RMS has the ESS paper's Table 1 size"},
    {"noise", "encoder_arcsec", KEY_DOUBLE, B, "arcsec", "1", NULL, 0, 3600, NULL,
     OFF(encoder_arcsec), "sigma of each turntable axis reading"},
    {"noise", "centroid_px", KEY_DOUBLE, D, "px", "0.01", NULL, 0, 10, NULL,
     OFF(dss_noise.centroid_px), "sigma of the measured spot centre, per axis"},
    {"noise", "s_curve", KEY_ENUM, D, "", "off", NULL, 0, 0, "off|on", OFF(dss_noise.s_curve),
     "add the pixel-phase (S-curve) centroid bias of a finite spot"},

    /* [campaign] */
    {"campaign", "alpha_min_deg", KEY_DOUBLE, E, "deg", "-62", NULL, -89, 89, NULL,
     OFF(cal_alpha_min_deg), "first turntable inner-frame angle (ESS paper: +-62 deg)"},
    {"campaign", "alpha_max_deg", KEY_DOUBLE, E, "deg", "62", NULL, -89, 89, NULL,
     OFF(cal_alpha_max_deg), "last turntable inner-frame angle"},
    {"campaign", "alpha_step_deg", KEY_DOUBLE, E, "deg", "0.2", NULL, 0.001, 90, NULL,
     OFF(cal_alpha_step_deg),
     "inner-frame step (ESS paper Table 2: 1 and 0.25; both alias the 0.5-deg fine-code term)"},
    {"campaign", "beta_deg", KEY_LIST, E, "deg", "-20, 0, 20", NULL, -89, 89, NULL,
     OFF(cal_beta_deg), "outer-frame angles, one alpha scan each"},
    {"campaign", "b_min_deg", KEY_DOUBLE, D, "deg", "-60", NULL, -89, 89, NULL, OFF(cal_b_min_deg),
     "first rotary-table angle of the b1 x b2 grid"},
    {"campaign", "b_max_deg", KEY_DOUBLE, D, "deg", "60", NULL, -89, 89, NULL, OFF(cal_b_max_deg),
     "last rotary-table angle of the b1 x b2 grid"},
    {"campaign", "b_step_deg", KEY_DOUBLE, D, "deg", "5", NULL, 0.01, 90, NULL, OFF(cal_b_step_deg),
     "rotary-table step, both axes"},
    {"campaign", "repeats", KEY_INT, B, "", "1", NULL, 1, 1000, NULL, OFF(cal_repeats),
     "readings averaged at each campaign point"},

    /* [calibration] */
    {"calibration", "model", KEY_ENUM, D, "", "physical", NULL, 0, 0, "physical|polynomial",
     OFF(cal_model), "DSS calibration model: physical (dx, dy, h, refraction, c1-c3) or a 2-D "
                     "polynomial of the angle errors"},
    {"calibration", "poly_order", KEY_INT, D, "", "3", NULL, 1, 7, NULL, OFF(poly_order),
     "order of the 2-D polynomial model"},
    {"calibration", "fit_glass_index", KEY_ENUM, D, "", "on", NULL, 0, 0, "off|on",
     OFF(fit_glass_index),
     "physical model: fit the cover-glass index too (height, thickness and index are nearly "
     "collinear, |corr| ~0.99, yet fitting all three predicts the spots best; off holds the "
     "index at design; see dss_calib.h)"},
    {"calibration", "roll_sigma_arcsec", KEY_DOUBLE, E, "arcsec", "5", NULL, 0, 3600, NULL,
     OFF(roll_sigma_arcsec),
     "sigma of the roll (install_x) alignment measurement; the fit fixes the roll at the "
     "measured value because turntable data cannot separate it from (b, c)"},
    {"calibration", "roll_measured_arcsec", KEY_DOUBLE, E, "arcsec", "0", NULL, -36000, 36000, NULL,
     OFF(roll_measured_arcsec), "`calibrate` only: the measured installation roll of a real sensor"},
    {"calibration", "alias_threshold", KEY_DOUBLE, E, "", "0.2", NULL, 0, 1, NULL,
     OFF(alias_threshold),
     "smallest normalised eigenvalue of the fine-code (sin, cos) columns below which the "
     "campaign cannot resolve that direction; it is then regularised to 0"},
    {"calibration", "max_iterations", KEY_INT, B, "", "100", NULL, 5, 10000, NULL,
     OFF(max_iterations), "most Levenberg-Marquardt iterations per fit"},

    /* [validation] */
    {"validation", "alpha_min_deg", KEY_DOUBLE, E, "deg", "-62", NULL, -89, 89, NULL,
     OFF(val_alpha_min_deg), "first validation incidence angle"},
    {"validation", "alpha_max_deg", KEY_DOUBLE, E, "deg", "62", NULL, -89, 89, NULL,
     OFF(val_alpha_max_deg), "last validation incidence angle"},
    {"validation", "alpha_step_deg", KEY_DOUBLE, E, "deg", "0.13", NULL, 0.001, 90, NULL,
     OFF(val_alpha_step_deg), "validation step (not a divisor of the fine-code period)"},
    {"validation", "alpha_offset_deg", KEY_DOUBLE, E, "deg", "0.05", NULL, -10, 10, NULL,
     OFF(val_alpha_offset_deg), "offset of the validation grid from alpha_min_deg"},
    {"validation", "beta_deg", KEY_LIST, E, "deg", "-25, -10, 10, 25", NULL, -89, 89, NULL,
     OFF(val_beta_deg), "outer-frame angles of the validation scans (not the campaign's)"},
    {"validation", "b_min_deg", KEY_DOUBLE, D, "deg", "-60", NULL, -89, 89, NULL,
     OFF(val_b_min_deg), "first validation rotary-table angle"},
    {"validation", "b_max_deg", KEY_DOUBLE, D, "deg", "60", NULL, -89, 89, NULL,
     OFF(val_b_max_deg), "last validation rotary-table angle"},
    {"validation", "b_step_deg", KEY_DOUBLE, D, "deg", "4.1", NULL, 0.01, 90, NULL,
     OFF(val_b_step_deg), "validation rotary-table step"},
    {"validation", "b_offset_deg", KEY_DOUBLE, D, "deg", "1.3", NULL, -10, 10, NULL,
     OFF(val_b_offset_deg), "offset of the validation grid from b_min_deg"},

    /* [run] */
    {"run", "units", KEY_LONG, B, "", "1000", NULL, 1, 100000000, NULL, OFF(units),
     "number of simulated units (--units N or --units FIRST:END)"},
    {"run", "seed", KEY_LONG, B, "", "1", NULL, 0, 2147483647, NULL, OFF(seed),
     "random seed; unit u's draws depend only on (seed, u)"},
    {"run", "threads", KEY_INT, B, "", "0", NULL, 0, 1024, NULL, OFF(threads),
     "OpenMP threads, 0 = all cores; results do not depend on it"},

    /* [report] */
    {"report", "bands_deg", KEY_BANDS, B, "deg", "0:30, 30:60, 0:62", "0:20, 20:40, 0:60", 0, 90,
     NULL, OFF(bands_deg),
     "RMS bands on |alpha| (ESS; ESS paper Table 1) or on the field angle (DSS)"},
    {"report", "spec_arcsec", KEY_DOUBLE, B, "arcsec", "54", "10", 0, 36000, NULL, OFF(spec_arcsec),
     "after-calibration RMS a unit must meet per band (yield); 54\" = 0.015 deg"},
    {"report", "yield_target", KEY_DOUBLE, B, "", "0.95", NULL, 0.01, 1, NULL, OFF(yield_target),
     "`budget`: the yield (fraction of units meeting spec_arcsec in the widest band) each "
     "inverse tolerance limit must keep"},
    {"report", "budget_units", KEY_LONG, B, "", "100", NULL, 10, 1000000, NULL,
     OFF(budget_units), "`budget`: units per Monte Carlo step of the inverse-limit bisection"},
    {"report", "budget_steps", KEY_INT, B, "", "5", NULL, 1, 40, NULL, OFF(budget_steps),
     "`budget`: bisection steps per source for the inverse limit"},
};

const size_t config_key_count = sizeof config_keys / sizeof config_keys[0];

static int check_grid(double lo, double hi, double step, double fov, const char *what, char *err,
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

int config_validate(const sunmc_config *c, char *err, size_t errlen)
{
    int s;
    if (c->family == FAMILY_ESS) {
        const ess_design *d = &c->ess;
        if (d->fine_rows_x_mm.n != 4)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "design.fine_rows_x_mm must list exactly 4 rows, has %d",
                              d->fine_rows_x_mm.n);
        double cover = ldexp(d->coarse_resolution_deg, d->coarse_rows_x_mm.n);
        if (cover < 2 * d->fov_deg + 2 * d->coarse_resolution_deg)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "design: %d coarse rows of %g deg cover %g deg, less than the "
                              "field of view +-%g deg",
                              d->coarse_rows_x_mm.n, d->coarse_resolution_deg, cover, d->fov_deg);
        if (d->coarse_resolution_deg > d->theta0_deg / 2)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "design.coarse_resolution_deg = %g must be at most half of "
                              "theta0_deg = %g to pick the fine period",
                              d->coarse_resolution_deg, d->theta0_deg);
        if ((s = check_grid(c->cal_alpha_min_deg, c->cal_alpha_max_deg, c->cal_alpha_step_deg,
                            d->fov_deg, "campaign.alpha", err, errlen)) != SUNMC_OK)
            return s;
        if ((s = check_grid(c->val_alpha_min_deg, c->val_alpha_max_deg, c->val_alpha_step_deg,
                            d->fov_deg, "validation.alpha", err, errlen)) != SUNMC_OK)
            return s;
    } else {
        if ((s = check_grid(c->cal_b_min_deg, c->cal_b_max_deg, c->cal_b_step_deg, c->dss.fov_deg,
                            "campaign.b", err, errlen)) != SUNMC_OK)
            return s;
        if ((s = check_grid(c->val_b_min_deg, c->val_b_max_deg, c->val_b_step_deg, c->dss.fov_deg,
                            "validation.b", err, errlen)) != SUNMC_OK)
            return s;
    }
    return SUNMC_OK;
}
