/* psd_keys.c - the four-channel analog sun sensor's configuration keys,
 * its defaults of shared keys and its cross-key checks.
 *
 * Default design: a CubeSat fine sun sensor on a Hamamatsu S5991-01
 * improved tetra-lateral PSD (9 x 9 mm active area) under a 0.5 mm
 * aperture about 4 mm above it, 12-bit ADC (docs/psd.md, Sources).
 */
#include "psd_config.h"
#include "psd_model.h"
#include "family.h"
#include "status.h"
#include "tolerance.h"
#include "units.h"

#include <math.h>
#include <stddef.h>

#define OFF(field) offsetof(psd_config, field)
#define NONE CONFIG_PHYSICAL_NONE
_Static_assert(sizeof(psd_config) <= sizeof(family_config), "psd_config must fit family_config");

const config_key psd_keys[] = {
    /* [design] */
    {"design", "detector", KEY_ENUM, "", "lateral", 0, 0, "lateral|quadrant", OFF(design.detector),
     "lateral-effect PSD (the light's centroid) or quadrant photodiode (four overlap areas)"},
    {"design", "lateral", KEY_ENUM, "", "tetra", 0, 0, "duo|tetra", OFF(design.lateral),
     "lateral PSD: duo-lateral (x from i1, i2 and y from i3, i4) or tetra-lateral (corner "
     "electrodes, with the pincushion distortion)"},
    {"design", "h_mm", KEY_DOUBLE, "mm", "4", 0.2, 100, NULL, OFF(design.h_mm),
     "aperture height above the detector"},
    {"design", "active_mm", KEY_DOUBLE, "mm", "9", 0.1, 100, NULL, OFF(design.active_mm),
     "side of the square active area (S5991-01: 9 mm; S5990-01: 4.5 mm)"},
    {"design", "aperture_um", KEY_DOUBLE, "um", "500", 1, 20000, NULL, OFF(design.aperture_um),
     "aperture diameter"},
    {"design", "gap_um", KEY_DOUBLE, "um", "40", 0, 2000, NULL, OFF(design.gap_um),
     "quadrant photodiode: gap between the quadrants"},
    {"design", "pincushion", KEY_DOUBLE, "", "0.04", -1, 1, NULL, OFF(design.pincushion),
     "tetra-lateral: pincushion coefficient k of x' = x (1 + k y^2) (x, y in half sides)"},
    {"design", "glass_thickness_mm", KEY_DOUBLE, "mm", "0", 0, 10, NULL,
     OFF(design.glass_thickness_mm), "cover-glass thickness under the aperture (0: none)"},
    {"design", "glass_index", KEY_DOUBLE, "", "1.5", 1, 3, NULL, OFF(design.glass_index),
     "cover-glass refractive index"},
    {"design", "psd_fov_deg", KEY_DOUBLE, "deg", "45", 1, 80, NULL, OFF(design.fov_deg),
     "half field of view per axis (grids must stay within it)"},
    {"design", "polarity", KEY_ENUM, "", "positive", 0, 0, "positive|inverted",
     OFF(design.polarity),
     "channel output rises (positive) or falls (inverted: an inverting amplifier) with light"},
    {"design", "signal_fs", KEY_DOUBLE, "", "0.6", 0.001, 1, NULL, OFF(design.signal_fs),
     "sun signal of the four channels together at normal incidence, fraction of the ADC's "
     "full scale"},
    {"design", "dark_fs", KEY_DOUBLE, "", "0.02", 0, 1, NULL, OFF(design.dark_fs),
     "nominal dark signal of each channel, fraction of full scale"},

    /* [tolerance]: one pair of keys per line of PSD_DEVIATIONS */
    PSD_DEVIATIONS(DEVIATION_X_KEYS)

    /* [noise] */
    {"environment", "dark_doubling_k", KEY_DOUBLE, "K", "0", 0, 100, NULL, OFF(dark_doubling_k),
     "the channels' dark signals double every this many kelvin away from calibration_temp_c "
     "(silicon photodiodes: roughly every 5 to 10 K); 0: no drift (no stated source for this "
     "sensor's amplifier offsets)"},
    {"environment", "responsivity_tc_ppm_k", KEY_DOUBLE, "ppm/K", "0", -10000, 10000, NULL,
     OFF(responsivity_tc_ppm_k),
     "the channels' gains per kelvin (photodiode responsivity; common to the four, it "
     "cancels in the ratios but for the dark signals); 0: none stated"},
    {"noise", "channel_pct", KEY_DOUBLE, "%", "0.05", 0, 10, NULL, OFF(noise_fs_pct),
     "sigma of each channel's noise, % of the ADC's full scale"},
    {"noise", "lamp_pct", KEY_DOUBLE, "%", "0", 0, 50, NULL, OFF(lamp_pct),
     "the sun simulator's light at the sensor, changing from one reading to the next (lamp "
     "drift, a beam not uniform over the table's travel): each reading's light times 1 + "
     "N(0, lamp_pct); the dark-corrected ratios do not see it, the raw ones do"},
    {"noise", "common_pct", KEY_DOUBLE, "%", "0", 0, 10, NULL, OFF(common_pct),
     "sigma of a noise the four channels share in a reading, % of the ADC's full scale: "
     "each reading adds common_pct * n * w_k to channel k (one N(0, 1) draw n, weights "
     "noise.common_signs): a shared supply or amplifier reference, whose noise the ratios "
     "partly cancel; the spread of a point's repeats shows it as correlated channels"},
    {"noise", "common_signs", KEY_LIST, "", "1, 1, 1, 1", -1, 1, NULL, OFF(common_signs),
     "noise.common_pct's weight on channels 1-4 (four values): 1, 1, 1, 1 a common mode "
     "(the ratios cancel it); 1, 1, -1, -1 two channel pairs on opposite references"},
    {"noise", "table_line_arcsec", KEY_DOUBLE, "arcsec", "0", 0, 3600, NULL,
     OFF(table_line_arcsec),
     "the turntable's setting error per scan line: after each move of the slow axis the table "
     "stands off its recorded angles by N(0, sigma) in each axis, the same for every point of "
     "the line (repeats do not average it); the campaign's lines and the validation's (whose "
     "scoring then includes the lab's error, as a lab's held-out lines do); 0: none"},
    {"noise", "adc_bits", KEY_INT, "", "12", 4, 24, NULL, OFF(adc_bits),
     "ADC resolution (quantisation of each channel)"},

    /* [campaign]: the lab's table and its grid */
    {"campaign", "table_order", KEY_ENUM, "", "beta_outer", 0, 0,
     "projected|alpha_outer|beta_outer", OFF(table_order),
     "how the table's (alpha, beta) put the sun in the table top: projected (tan alpha = "
     "u_x/u_z, tan beta = u_y/u_z), alpha_outer or beta_outer (a two-axis gimbal, that axis "
     "carrying the other; psd_config.h)"},
    {"campaign", "table_alpha_sign", KEY_ENUM, "", "plus", 0, 0, "plus|minus",
     OFF(table_alpha_sign), "plus: table alpha > 0 moves the sun toward the sensor's +X"},
    {"campaign", "table_beta_sign", KEY_ENUM, "", "plus", 0, 0, "plus|minus", OFF(table_beta_sign),
     "plus: table beta > 0 moves the sun toward the sensor's +Y"},
    {"campaign", "alpha_max_deg", KEY_DOUBLE, "deg", "20", 0.5, 80, NULL, OFF(cal_alpha_max_deg),
     "campaign alpha from -alpha_max_deg to +alpha_max_deg"},
    {"campaign", "alpha_step_deg", KEY_DOUBLE, "deg", "5", 0.05, 80, NULL, OFF(cal_alpha_step_deg),
     "campaign alpha step (the fast axis)"},
    {"campaign", "beta_deg", KEY_LIST, "deg", "-20, -10, 0, 10, 20", -80, 80, NULL,
     OFF(cal_beta_deg), "campaign beta lines (the slow axis), one alpha scan each"},

    /* [calibration] */
    {"calibration", "model", KEY_ENUM, "", "physical", 0, 0, "physical|polynomial|spline|hybrid|table",
     OFF(cal_model),
     "physical (aperture offsets and height, mount, channel gains and darks; psd_model.h), "
     "the field's polynomial in the raw ratios, spline (a penalised B-spline of the angles "
     "in the raw ratios), hybrid (physical + a spline of its residual) or table (a look-up "
     "table of the spline); docs/calibration.md"},
    {"calibration", "poly_order", KEY_INT, "", "5", 1, PSD_POLY_MAX_ORDER, NULL, OFF(poly_order),
     "polynomial model: total degree in (x, y)"},
    {"calibration", "poly_form", KEY_ENUM, "", "full", 0, 0, "full|fss20", OFF(poly_form),
     "polynomial model: every term of the degree, or fss20 (order 5 less x^2 y^2: the 20 "
     "terms of aeroztark's FSScalibration)"},

    {"calibration", "fit_tilt", KEY_ENUM, "", "off", 0, 0, "off|on", OFF(fit_tilt),
     "physical model: fit the mount's tilts about X and Y too (off: they stay 0 and the "
     "aperture offsets dx, dy take them up, exactly at the normal and to first order across "
     "a campaign of a few tens of degrees; on: separable only through the optics' "
     "nonlinearity, |corr| ~ 1 with dx, dy)"},

    /* [validation] */
    {"validation", "alpha_max_deg", KEY_DOUBLE, "deg", "20", 0.5, 80, NULL,
     OFF(val_alpha_max_deg), "validation alpha within +-alpha_max_deg"},
    {"validation", "alpha_step_deg", KEY_DOUBLE, "deg", "2.3", 0.05, 80, NULL,
     OFF(val_alpha_step_deg), "validation alpha step"},
    {"validation", "alpha_offset_deg", KEY_DOUBLE, "deg", "0.7", -10, 10, NULL,
     OFF(val_alpha_offset_deg), "offset of the validation alphas from -alpha_max_deg"},
    {"validation", "beta_deg", KEY_LIST, "deg", "-17, -7, 3, 13", -80, 80, NULL,
     OFF(val_beta_deg), "validation beta lines"},
    {NULL}};

const config_default psd_defaults[] = {
    {"sensor", "product", "PSD"},
    {"report", "bands_deg", "0:10, 10:20, 0:28"},
    {"report", "spec_arcsec", "360"},
    {"campaign", "search_steps_deg", "1, 2, 2.5, 4, 5, 10"},
    {NULL}};

static const config_physical psd_physical[] = {
    {"the aperture height h + dh", "mm", "design.h_mm", OFF(design.h_mm), 0, "tolerance.dh_um",
     OFF(tol.dh_um), MM_PER_UM, NONE, 0, 1},
    {"the aperture diameter", "um", "design.aperture_um", OFF(design.aperture_um), 0,
     "tolerance.aperture_um", OFF(tol.aperture_um), 1, NONE, 0, 1},
    {NULL}};

/* The aperture must stay above the detector (and above the glass) at the
 * tolerances' extreme draws. */
static int physical_check(const sunmc_config *c, char *err, size_t errlen)
{
    const psd_config *p = psd_cfg(c);
    int s = config_check_physical(c, psd_physical, err, errlen);
    if (s == SUNMC_OK && !(p->design.glass_thickness_mm < p->design.h_mm))
        s = sunmc_fail(err, errlen, SUNMC_EINPUT,
                       "design.glass_thickness_mm = %g must be below design.h_mm = %g",
                       p->design.glass_thickness_mm, p->design.h_mm);
    return s;
}

static long alpha_count(double amax, double step, double offset)
{
    return grid_count(-amax, amax, step, offset);
}

/* Every report band holds a validation point (field angle of the truth). */
static int band_check(const sunmc_config *c, char *err, size_t errlen)
{
    const psd_config *p = psd_cfg(c);
    band_acc acc;
    band_acc_reset(&acc);
    double max_abs = 0;
    long na = alpha_count(p->val_alpha_max_deg, p->val_alpha_step_deg, p->val_alpha_offset_deg);
    for (int j = 0; j < p->val_beta_deg.n; j++)
        for (long i = 0; i < na; i++) {
            double a = -p->val_alpha_max_deg + p->val_alpha_offset_deg +
                       (double)i * p->val_alpha_step_deg, u[3];
            psd_table_sun(p, a * RAD_PER_DEG, p->val_beta_deg.v[j] * RAD_PER_DEG, u);
            double f = acos(fmin(u[2], 1.0)) * DEG_PER_RAD;
            band_acc_add(&acc, &c->bands_deg, f, 0);
            max_abs = fmax(max_abs, f);
        }
    double fov_field = atan(M_SQRT2 * tan(p->design.fov_deg * RAD_PER_DEG)) * DEG_PER_RAD;
    return band_check_coverage(&c->bands_deg, &acc, max_abs, fov_field,
                               "design.psd_fov_deg per axis, its corners", "field angle",
                               "validation.alpha_max_deg, validation.alpha_step_deg, "
                               "validation.alpha_offset_deg, validation.beta_deg",
                               err, errlen);
}

static int grid_check(const psd_config *p, char *err, size_t errlen)
{
    double fov = p->design.fov_deg;
    if (p->cal_alpha_max_deg > fov || p->val_alpha_max_deg > fov)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "campaign.alpha_max_deg = %g or validation.alpha_max_deg = %g is "
                          "beyond design.psd_fov_deg = %g",
                          p->cal_alpha_max_deg, p->val_alpha_max_deg, fov);
    for (int j = 0; j < p->cal_beta_deg.n; j++)
        if (fabs(p->cal_beta_deg.v[j]) > fov)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "campaign.beta_deg holds %g, beyond design.psd_fov_deg = %g",
                              p->cal_beta_deg.v[j], fov);
    for (int j = 0; j < p->val_beta_deg.n; j++)
        if (fabs(p->val_beta_deg.v[j]) > fov)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "validation.beta_deg holds %g, beyond design.psd_fov_deg = %g",
                              p->val_beta_deg.v[j], fov);
    long n = alpha_count(p->cal_alpha_max_deg, p->cal_alpha_step_deg, 0) * p->cal_beta_deg.n;
    psd_poly q;
    int fr[PSD_NP];
    int phys = PSD_MODEL_HAS_PHYSICS(p->cal_model);
    int np = phys ? psd_phys_free(&p->design, p->fit_tilt, fr)
             : p->cal_model == PSD_MODEL_SPLINE || p->cal_model == PSD_MODEL_TABLE ? PSD_SPLINE_MIN_ROWS
                                                : psd_poly_init(&q, p->poly_order, p->poly_form);
    long nr = phys ? 2 * n : n;
    if (p->cal_beta_deg.n < 2 || nr <= np)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "campaign: %ld points on %d beta lines, too few for the %s model's %d "
                          "parameters (campaign.alpha_max_deg, campaign.alpha_step_deg, "
                          "campaign.beta_deg: at least 2 lines)",
                          n, p->cal_beta_deg.n,
                          psd_model_names[p->cal_model], np);
    if (p->poly_form == PSD_POLY_FSS20 && p->poly_order != 5)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "calibration.poly_form = fss20 is the 5th-order form: set "
                          "calibration.poly_order = 5 (it is %d)", p->poly_order);
    return SUNMC_OK;
}

int psd_validate(const sunmc_config *c, char *err, size_t errlen)
{
    const psd_config *p = psd_cfg(c);
    if (p->common_signs.n != PSD_CHANNELS)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "noise.common_signs: %d values, the sensor has %d channels",
                          p->common_signs.n, PSD_CHANNELS);
    int s = physical_check(c, err, errlen);
    if (s == SUNMC_OK)
        s = grid_check(p, err, errlen);
    if (s == SUNMC_OK)
        s = band_check(c, err, errlen);
    return s;
}
