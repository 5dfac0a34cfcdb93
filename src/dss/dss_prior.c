/* dss_prior.c - the DSS physical calibration's priors from a noise-free
 * pilot (prior.h). */
#include "dss_prior.h"
#include "prior_cache.h"
#include "dss_config.h"
#include "dss_sensor.h"
#include "dss_unit.h"
#include "family.h"
#include "rng.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

double dss_reading_noise_px(const sunmc_config *c)
{
    const dss_config *d = dss_cfg(c);
    double px_per_rad = d->design.h_mm / (d->design.pixel_um * MM_PER_UM);
    double encoder = c->encoder_arcsec * RAD_PER_ARCSEC * px_per_rad;
    return hypot(d->noise.centroid_px, encoder) / sqrt((double)c->cal_repeats);
}

void dss_campaign_angles(const sunmc_config *c, double *b1_rad, double *b2_rad)
{
    const dss_config *dc = dss_cfg(c);
    long nb = grid_count(dc->cal_b_min_deg, dc->cal_b_max_deg, dc->cal_b_step_deg, 0);
    size_t n = (size_t)nb * (size_t)nb;
    for (size_t i = 0; i < n; i++) {
        b1_rad[i] = (dc->cal_b_min_deg + (double)(i / (size_t)nb) * dc->cal_b_step_deg) * RAD_PER_DEG;
        b2_rad[i] = (dc->cal_b_min_deg + (double)(i % (size_t)nb) * dc->cal_b_step_deg) * RAD_PER_DEG;
    }
}

/* Pilot unit u of c0 read at pw's table angles and fitted without priors:
 * its fitted parameters into x.  SUNMC_OK when the fit converged. */
static int pilot_unit(const sunmc_config *c0, uint64_t seed, long u, dss_calib_workspace *pw,
                      double *x)
{
    dss_deviations dev;
    dss_unit unit;
    dss_deviations_sample(c0, seed, u, &dev);
    dss_unit_build(c0, &dev, &unit);
    dss_unit_set_pattern(c0, seed, u, &unit);
    rng_stream r; /* nothing is drawn from it that matters: c0 has no noise */
    rng_stream_init(&r, seed, (uint64_t)u, RNG_STREAM_CAL_NOISE);
    for (size_t i0 = 0; i0 < pw->n; i0 += DSS_CHUNK) {
        dss_campaign_point p[DSS_CHUNK];
        size_t k = pw->n - i0 < DSS_CHUNK ? pw->n - i0 : DSS_CHUNK;
        dss_campaign_batch(c0, &unit, &r, k, pw->b1_rad + i0, pw->b2_rad + i0, p);
        for (size_t q = 0; q < k; q++) {
            pw->x_px[i0 + q] = p[q].seen ? p[q].x_px : 0.0;
            pw->y_px[i0 + q] = p[q].seen ? p[q].y_px : 0.0;
            pw->weight[i0 + q] = p[q].seen ? 1.0 : 0.0;
        }
    }
    double sun[2];
    dss_sun_measured_arcsec(c0, seed, u, &dev, sun);
    pw->sun_rad[0] = sun[0] * RAD_PER_ARCSEC;
    pw->sun_rad[1] = sun[1] * RAD_PER_ARCSEC;
    dss_calibration cal;
    fit_result fr;
    int st = dss_calibrate(pw, c0->max_iterations, &cal, &fr);
    for (int j = 0; st == SUNMC_OK && j < pw->n_free; j++)
        x[j] = cal.phys.p[pw->free_idx[j]];
    return st;
}

static int fits_index(const dss_calib_workspace *cw)
{
    for (int j = 0; j < cw->n_free; j++)
        if (cw->free_idx[j] == DSS_P_N)
            return 1;
    return 0;
}

/* The pilot's units of c0 on cw's campaign, fitted, added to p. */
typedef struct {
    const sunmc_config *c0;
    const dss_calib_workspace *cw;
} pilot_ctx;

static int pilot_add(void *ctx, calib_prior *p, char *err, size_t errlen)
{
    const sunmc_config *c0 = ((const pilot_ctx *)ctx)->c0;
    const dss_calib_workspace *cw = ((const pilot_ctx *)ctx)->cw;
    /* a hybrid's prior is its physical part's */
    dss_calib_workspace *pw = dss_calib_alloc_fix(&cw->design, cw->n, DSS_MODEL_PHYSICAL, cw->poly_order,
                                                  fits_index(cw), cw->fix_sun);
    if (!pw)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the priors' pilot");
    memcpy(pw->b1_rad, cw->b1_rad, cw->n * sizeof *cw->b1_rad);
    memcpy(pw->b2_rad, cw->b2_rad, cw->n * sizeof *cw->b2_rad);
    uint64_t seed = prior_pilot_seed(c0);
    for (long u = 0; u < c0->prior_units; u++) {
        double x[DSS_NP];
        if (pilot_unit(c0, seed, u, pw, x) == SUNMC_OK)
            calib_prior_add(p, x);
    }
    dss_calib_free(pw);
    return SUNMC_OK;
}

static int pilot(const sunmc_config *c, const dss_calib_workspace *cw, calib_prior *p, char *err,
                 size_t errlen)
{
    sunmc_config c0 = *c; /* no noise, no pick-freeze: the pilot is no random input */
    memset(&c0.pick, 0, sizeof c0.pick);
    c0.no_systematic = 0;
    c0.encoder_arcsec = 0;
    dss_cfg(&c0)->noise.centroid_px = 0;
    if (calib_prior_reset(p, cw->n_free) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "prior: %d parameters", cw->n_free);
    /* the pilot's inputs (prior_cache.h): made once per process */
    int layout[5] = {DSS_MODEL_PHYSICAL, cw->poly_order, fits_index(cw), cw->fix_sun, cw->n_free};
    const prior_key_part key[] = {{&c0, sizeof c0},
                                  {&cw->design, sizeof cw->design},
                                  {layout, sizeof layout},
                                  {&cw->n, sizeof cw->n},
                                  {cw->b1_rad, cw->n * sizeof *cw->b1_rad},
                                  {cw->b2_rad, cw->n * sizeof *cw->b2_rad}};
    pilot_ctx pc = {&c0, cw};
    int st = prior_cache_pilot(key, (int)(sizeof key / sizeof *key), p, pilot_add, &pc, err,
                               errlen);
    if (st != SUNMC_OK)
        return st;
    return calib_prior_finish(p, dss_reading_noise_px(c), err, errlen);
}

int dss_prior_apply(const sunmc_config *c, dss_calib_workspace *cw, calib_prior *p, char *err,
                    size_t errlen)
{
    calib_prior_reset(p, 0);
    if (!DSS_MODEL_HAS_PHYSICS(cw->kind))
        return SUNMC_OK;
    fit_prior_clear(cw->fw);
    if (c->cal_priors != CONFIG_PRIORS_TOLERANCES)
        return SUNMC_OK;
    return calib_prior_install(cw->fw, p, pilot(c, cw, p, err, errlen), err, errlen);
}
