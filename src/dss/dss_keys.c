/* dss_keys.c - the DSS family's configuration keys, its defaults of shared
 * keys and its cross-key checks.
 *
 * Defaults are from Wei et al., "System modeling based measurement error
 * analysis of digital sun sensors" (the "DSS paper").
 */
#include "dss_calib.h"
#include "dss_config.h"
#include "dss_model.h"
#include "dss_poly.h"
#include "rotation.h"
#include "dss_unit.h"
#include "family.h"
#include "status.h"
#include "tolerance.h"
#include "units.h"

#include <math.h>

#include <stddef.h>

#define OFF(field) offsetof(dss_config, field)
#define NONE CONFIG_PHYSICAL_NONE
_Static_assert(sizeof(dss_config) <= sizeof(family_config), "dss_config must fit family_config");

const config_key dss_keys[] = {
    /* [design] */
    {"design", "h_mm", KEY_DOUBLE, "mm", "3", 0.2, 50, NULL, OFF(design.h_mm),
     "nominal pinhole-to-detector height h"},
    {"design", "pixel_um", KEY_DOUBLE, "um", "5.5", 0.5, 100, NULL, OFF(design.pixel_um),
     "detector pixel pitch"},
    {"design", "detector_px", KEY_INT, "px", "2048", 16, 100000, NULL, OFF(design.detector_px),
     "detector side length in pixels (square detector)"},
    {"design", "pinhole_um", KEY_DOUBLE, "um", "60", 1, 5000, NULL, OFF(design.pinhole_um),
     "pinhole diameter (sets the spot size for the S-curve bias)"},
    {"design", "wavelength_nm", KEY_DOUBLE, "nm", "650", 0, 2000, NULL, OFF(design.wavelength_nm),
     "effective wavelength of the sunlight the detector sees: the pinhole's diffraction blurs "
     "the spot (cut-off d / (lambda h)) and sets the S-curve with the centroid window "
     "(docs/dss.md); 650 = the middle of a silicon detector's response to sunlight "
     "(400-900 nm); 0 = no diffraction, the geometric disc's S-curve"},
    {"design", "mask_thickness_um", KEY_DOUBLE, "um", "0", 0, 1000, NULL,
     OFF(design.mask_thickness_um),
     "thickness of the mask around the pinhole: the hole becomes a tube whose light is the "
     "overlap of its two openings, centred at its mid-plane (h is to the lower face; the spot "
     "sits as if the pinhole were T / 2 higher), and no light passes beyond "
     "tan(theta) = pinhole / T; 0 = a thin film (a chrome mask on glass, ~0.1 um)"},
    {"design", "centroid_window_px", KEY_INT, "px", "0", 0, 64, NULL,
     OFF(design.centroid_window_px),
     "half-width m of a fixed centroid window without threshold (2 m + 1 pixels about the "
     "pixel nearest the spot): it cuts the spot's diffraction tails, an S-curve of 0.031 px "
     "rms at m = 10 for configs/dss.ini (noise.s_curve = on; docs/dss.md); 0 = the whole "
     "spot (a thresholded centroid: no truncation), the fixed pattern summed over "
     "ceil(2.5 sigma)"},
    {"design", "glass_thickness_mm", KEY_DOUBLE, "mm", "0.4", 0, 5, NULL,
     OFF(design.glass_thickness_mm),
     "detector cover-glass thickness"},
    {"design", "glass_index", KEY_DOUBLE, "", "1.52", 1, 3, NULL, OFF(design.glass_index),
     "cover-glass refractive index"},
    {"design", "dss_fov_deg", KEY_DOUBLE, "deg", "60", 1, 80, NULL, OFF(design.fov_deg),
     "half field of view per axis"},
    {"design", "sun_disc_deg", KEY_DOUBLE, "deg", "0", 0, 2, NULL, OFF(design.sun_disc_deg),
     "the sun's apparent diameter: the spot is the pinhole's image of the disc, whose centroid "
     "sits (R^2/4) tan(theta) farther out than the centre's image (~1.1 arcsec tan(theta); "
     "docs/dss.md); 0.533 = the sun's mean diameter over the year (0.524-0.542; 1 AU, solar "
     "radius 695,700 km, IAU 2015 B3; configs/dss.ini, in orbit); 0 = a point sun"},
    {"design", "limb_darkening", KEY_DOUBLE, "", "0.6", 0, 1, NULL, OFF(design.limb_darkening),
     "linear limb-darkening coefficient u of the sun's disc, I(mu) = 1 - u (1 - mu): 0.6 = the "
     "visible value (Eddington grey atmosphere; Neckel & Labs 1994, Sol. Phys. 153, give "
     "0.55-0.65 over 500-600 nm, ~0.45 at 900 nm); 0 = a uniform disc"},
    {"design", "onboard_refraction", KEY_ENUM, "", "corrected", 0, 0, "corrected|ignored",
     OFF(design.onboard_refraction),
     "on-board formula: corrected = exact inverse of the nominal geometry, cover glass "
     "included; ignored = the DSS paper's eq. 9-10 (its Fig. 5 refraction error stays)"},
    {"design", "principal_point", KEY_ENUM, "", "physical", 0, 0, "physical|paper_eq6",
     OFF(design.principal_point),
     "how tolerance.dx_px, dy_px enter: physical = the pinhole displaced from where the "
     "on-board formula assumes it; paper_eq6 = the DSS paper's eq. 5-6 literally, the sun at "
     "the table's zero along S_b0 = (dx, dy, -h), rotated with the table, and eq. 9-10 "
     "subtracting (dx, dy): no error at the centre (docs/dss.md)"},

    /* [tolerance]: one pair of keys per line of DSS_DEVIATIONS */
    DSS_DEVIATIONS(DEVIATION_X_KEYS)

    /* [noise] */
    {"noise", "centroid_px", KEY_DOUBLE, "px", "0.01", 0, 10, NULL, OFF(noise.centroid_px),
     "sigma of the measured spot centre, per axis"},
    {"noise", "s_curve", KEY_ENUM, "", "off", 0, 0, "off|on", OFF(noise.s_curve),
     "add the pixel-phase (S-curve) centroid bias of a finite spot"},

    /* [campaign] */
    {"campaign", "b_min_deg", KEY_DOUBLE, "deg", "-60", -89, 89, NULL, OFF(cal_b_min_deg),
     "first rotary-table angle of the b1 x b2 grid"},
    {"campaign", "b_max_deg", KEY_DOUBLE, "deg", "60", -89, 89, NULL, OFF(cal_b_max_deg),
     "last rotary-table angle of the b1 x b2 grid"},
    {"campaign", "b_step_deg", KEY_DOUBLE, "deg", "5", 0.01, 90, NULL, OFF(cal_b_step_deg),
     "rotary-table step, both axes"},
    {"campaign", "mount", KEY_ENUM, "", "as_mounted", 0, 0, "aligned|as_mounted",
     OFF(design.mount),
     "as_mounted: sun_sensor = C R(b) v_sun, the mount C (c1-c3) and the sun simulator v_sun "
     "(sun_b1, sun_b2) as they are; aligned: the DSS paper's eq. 6, the lab aligns the sun to "
     "the detector normal at table zero (v_sun = C^T z)"},

    /* [calibration] */
    {"calibration", "model", KEY_ENUM, "", "physical", 0, 0,
     "physical|polynomial|spline|hybrid|table", OFF(cal_model),
     "DSS calibration model: physical (dx, dy, h, refraction, c1-c3), a 2-D polynomial of the "
     "angle errors, spline (a penalised B-spline of alpha, beta over the spot x, y), hybrid "
     "(physical + a spline of its residual) or table (a look-up table of the spline); "
     "docs/calibration.md"},
    {"calibration", "poly_order", KEY_INT, "", "3", 1, 7, NULL, OFF(poly_order),
     "order of the 2-D polynomial model"},
    {"calibration", "fit_glass_index", KEY_ENUM, "", "on", 0, 0, "off|on", OFF(fit_glass_index),
     "physical model: fit the cover-glass index too (height, thickness and index are nearly "
     "collinear, |corr| ~0.99, yet fitting all three predicts the spots best; off holds the "
     "index at design; see dss_calib.h)"},
    {"calibration", "fit_detector_tilt", KEY_ENUM, "", "off", 0, 0, "off|on",
     OFF(design.fit_tilt),
     "physical model: extend it by the detector plane's tilt against the mask (two angles, "
     "fit_detector_tilt_x_arcsec, fit_detector_tilt_y_arcsec, the geometry of "
     "tolerance.detector_tilt_x_arcsec); off (the DSS paper's model) leaves the tilt in the "
     "after-calibration error"},
    {"calibration", "sun", KEY_ENUM, "", "fitted", 0, 0, "fitted|measured", OFF(sun_mode),
     "campaign.mount = as_mounted: the sun simulator's direction (sun_b1, sun_b2) fitted with "
     "the other parameters, or measured and fixed (two parameters fewer); on a narrow campaign "
     "it and the mount's tilt c1, c2 stop separating, so the fitted direction lets the "
     "campaign's noise into c1, c2"},
    {"calibration", "sun_sigma_arcsec", KEY_DOUBLE, "arcsec", "5", 0, 3600, NULL,
     OFF(sun_sigma_arcsec),
     "calibration.sun = measured: sigma of the measurement of each of sun_b1, sun_b2 (Monte "
     "Carlo; its own random stream)"},
    {"calibration", "sun_b1_measured_arcsec", KEY_DOUBLE, "arcsec", "0", -36000, 36000, NULL,
     OFF(sun_b1_measured_arcsec),
     "`calibrate` with calibration.sun = measured: the sun simulator's measured direction, the "
     "table angle about X it equals"},
    {"calibration", "sun_b2_measured_arcsec", KEY_DOUBLE, "arcsec", "0", -36000, 36000, NULL,
     OFF(sun_b2_measured_arcsec),
     "`calibrate` with calibration.sun = measured: the same about Y"},

    /* [validation] */
    {"validation", "b_min_deg", KEY_DOUBLE, "deg", "-60", -89, 89, NULL, OFF(val_b_min_deg),
     "first validation rotary-table angle"},
    {"validation", "b_max_deg", KEY_DOUBLE, "deg", "60", -89, 89, NULL, OFF(val_b_max_deg),
     "last validation rotary-table angle"},
    {"validation", "b_step_deg", KEY_DOUBLE, "deg", "4.1", 0.01, 90, NULL, OFF(val_b_step_deg),
     "validation rotary-table step"},
    {"validation", "b_offset_deg", KEY_DOUBLE, "deg", "1.3", -10, 10, NULL, OFF(val_b_offset_deg),
     "offset of the validation grid from b_min_deg"},
    {NULL} /* end */
};

const config_default dss_defaults[] = {
    {"sensor", "product", "DSS"},
    {"report", "bands_deg", "0:20, 20:40, 0:60"},
    {"report", "spec_arcsec", "10"},
    {"campaign", "search_steps_deg", "2, 3, 4, 5, 6, 8, 10"},
    {NULL} /* end */
};

/* `sunmc config` lists noise.encoder_arcsec before the DSS's own noise keys. */
const char *const dss_sections_after_shared[] = {"noise", NULL};

/* Readings the fit needs: more residuals than free parameters (the
 * physical model has two per reading, the polynomial one per axis). */
static int campaign_size_check(const dss_config *d, char *err, size_t errlen)
{
    long nb = grid_count(d->cal_b_min_deg, d->cal_b_max_deg, d->cal_b_step_deg, 0);
    long n = nb * nb;
    int phys = d->cal_model == DSS_MODEL_PHYSICAL || d->cal_model == DSS_MODEL_HYBRID;
    int np = phys ? dss_calib_free_params(&d->design, d->fit_glass_index,
                                                d->sun_mode == DSS_SUN_MEASURED, NULL)
                  : dss_poly_n_terms(d->poly_order);
    if (d->cal_model != DSS_MODEL_POLYNOMIAL && !phys)
        np = DSS_SPLINE_MIN_ROWS - 1;
    if ((phys ? 2 * n : n) > np && (!DSS_MODEL_HAS_SPLINE(d->cal_model) || n >= DSS_SPLINE_MIN_ROWS))
        return SUNMC_OK;
    if (DSS_MODEL_HAS_SPLINE(d->cal_model))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "campaign: %ld x %ld b grid = %ld readings, too few for the %s model: "
                          "it needs at least %d (campaign.b_min_deg, campaign.b_max_deg, "
                          "campaign.b_step_deg)",
                          nb, nb, n, dss_model_names[d->cal_model], DSS_SPLINE_MIN_ROWS);
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "campaign: %ld x %ld b grid = %ld readings, too few for the %s model's %d "
                      "parameters (campaign.b_min_deg, campaign.b_max_deg, campaign.b_step_deg, "
                      "calibration.model, calibration.poly_order, calibration.fit_glass_index, "
                      "calibration.fit_detector_tilt, calibration.sun)",
                      nb, nb, n, phys ? "physical" : "polynomial", np);
}

static const config_physical dss_physical[] = {
    {"the pinhole height h + dh", "mm", "design.h_mm", OFF(design.h_mm), 0, "tolerance.dh_px",
     OFF(tol.dh_px), MM_PER_UM, OFF(design.pixel_um), 0, 1},
    {"the cover-glass thickness", "mm", "design.glass_thickness_mm",
     OFF(design.glass_thickness_mm), 0, "tolerance.glass_thickness_um",
     OFF(tol.glass_thickness_um), MM_PER_UM, NONE, 0, 0},
    {"the cover-glass index", "", "design.glass_index", OFF(design.glass_index), 0,
     "tolerance.glass_index", OFF(tol.glass_index), 1, NONE, 1, 0},
    {NULL}};

/* Draws that would build an impossible sensor: the pinhole at or below the
 * detector, a negative glass thickness, glass touching the pinhole, an
 * index below 1. */
static int physical_check(const sunmc_config *c, char *err, size_t errlen)
{
    const dss_config *d = dss_cfg(c);
    const dss_design *g = &d->design;
    double ts = c->truncation_sigmas, pixel_mm = g->pixel_um * MM_PER_UM;
    int s = config_check_physical(c, dss_physical, err, errlen);
    if (s != SUNMC_OK)
        return s;
    /* The gap between the glass and the pinhole: lowest pinhole, thickest glass. */
    double hlo, hhi, tlo, thi;
    tolerance_range(&d->tol.dh_px, ts, &hlo, &hhi);
    tolerance_range(&d->tol.glass_thickness_um, ts, &tlo, &thi);
    double gap = (g->h_mm + hlo * pixel_mm) - (g->glass_thickness_mm + thi * MM_PER_UM);
    if (gap > 0)
        return SUNMC_OK;
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "tolerance.dh_px = %g and tolerance.glass_thickness_um = %g can put the "
                      "cover glass at or above the pinhole: design.h_mm = %g and "
                      "design.glass_thickness_mm = %g leave a gap of %g mm at their extreme "
                      "draws; lower the tolerances or widen the gap",
                      d->tol.dh_px.value, d->tol.glass_thickness_um.value, g->h_mm,
                      g->glass_thickness_mm, gap);
}

/* Every report band must hold validation points (field angle of the
 * table's truth on the grid). */
static int band_check(const sunmc_config *c, char *err, size_t errlen)
{
    const dss_config *d = dss_cfg(c);
    band_acc acc;
    band_acc_reset(&acc);
    double max_abs = 0;
    long nb = grid_count(d->val_b_min_deg, d->val_b_max_deg, d->val_b_step_deg,
                         d->val_b_offset_deg);
    for (long j1 = 0; j1 < nb; j1++)
        for (long j2 = 0; j2 < nb; j2++) {
            double b1 = d->val_b_min_deg + d->val_b_offset_deg + (double)j1 * d->val_b_step_deg;
            double b2 = d->val_b_min_deg + d->val_b_offset_deg + (double)j2 * d->val_b_step_deg;
            double a0, b0;
            table_truth(b1 * RAD_PER_DEG, b2 * RAD_PER_DEG, &a0, &b0);
            double f = dss_field_angle_deg(a0, b0);
            band_acc_add(&acc, &c->bands_deg, f, 0);
            max_abs = fmax(max_abs, f);
        }
    /* The field angle reaches beyond the per-axis half field of view in
     * the corners: atan(sqrt(2) tan fov). */
    double fov_field = atan(M_SQRT2 * tan(d->design.fov_deg * RAD_PER_DEG)) * DEG_PER_RAD;
    return band_check_coverage(&c->bands_deg, &acc, max_abs, fov_field,
                               "design.dss_fov_deg per axis, its corners", "field angle",
                               "validation.b_min_deg, validation.b_max_deg, "
                               "validation.b_step_deg, validation.b_offset_deg",
                               err, errlen);
}

int dss_config_validate(const sunmc_config *c, char *err, size_t errlen)
{
    const dss_config *d = dss_cfg(c);
    if (!(d->design.glass_thickness_mm < d->design.h_mm))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "design.glass_thickness_mm = %g must be below design.h_mm = %g (the "
                          "cover glass lies under the pinhole)",
                          d->design.glass_thickness_mm, d->design.h_mm);
    int s = physical_check(c, err, errlen);
    if (s == SUNMC_OK)
        s = config_check_grid(d->cal_b_min_deg, d->cal_b_max_deg, d->cal_b_step_deg,
                              d->design.fov_deg, "campaign.b", err, errlen);
    if (s == SUNMC_OK && d->sun_mode == DSS_SUN_MEASURED && d->design.mount == DSS_MOUNT_ALIGNED)
        s = sunmc_fail(err, errlen, SUNMC_EINPUT,
                       "calibration.sun = measured needs campaign.mount = as_mounted: an "
                       "aligned lab has no sun-simulator direction to fit or measure");
    if (s == SUNMC_OK)
        s = campaign_size_check(d, err, errlen);
    if (s == SUNMC_OK)
        s = config_check_grid(d->val_b_min_deg, d->val_b_max_deg, d->val_b_step_deg,
                              d->design.fov_deg, "validation.b", err, errlen);
    if (s == SUNMC_OK)
        s = band_check(c, err, errlen);
    return s;
}
