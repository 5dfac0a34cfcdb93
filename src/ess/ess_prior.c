/* ess_prior.c - the ESS calibration's priors from a noise-free pilot. */
#include "ess_prior.h"
#include "prior_cache.h"
#include "ess_config.h"
#include "ess_sensor.h"
#include "ess_unit.h"
#include "rng.h"
#include "status.h"
#include "units.h"

#include <math.h>
#include <string.h>

double ess_reading_noise_arcsec(const sunmc_config *c)
{
    const ess_config *e = ess_cfg(c);
    double phase = e->design.theta0_deg * ARCSEC_PER_DEG / (2 * M_PI) *
                   e->noise.row_current_pct * FRACTION_PER_PCT / M_SQRT2;
    return hypot(phase, c->encoder_arcsec) / sqrt((double)c->cal_repeats);
}

/* Pilot unit u of c0 read at pw's table angles and fitted without priors:
 * its fit vector into x.  SUNMC_OK when the fit converged. */
static int pilot_unit(const sunmc_config *c0, uint64_t seed, long u, ess_calib_workspace *pw,
                      double *x)
{
    const ess_config *e = ess_cfg(c0);
    ess_deviations dev;
    ess_unit unit;
    ess_deviations_sample(c0, seed, u, &dev);
    ess_unit_build(c0, &dev, &unit);
    rng_stream r; /* no noise is drawn from it: c0 has none */
    rng_stream_init(&r, seed, (uint64_t)u, RNG_STREAM_CAL_NOISE);
    int gross;
    ess_campaign_read(c0, &unit, &r, pw, NULL, &gross);
    pw->sun_y_rad = ess_sun_y_measured_arcsec(c0, seed, u, &dev) * RAD_PER_ARCSEC;
    ess_model m;
    fit_result fr;
    int st = ess_calibrate(pw, e->design.theta0_deg * RAD_PER_DEG,
                           dev.roll_measured_arcsec * RAD_PER_ARCSEC, e->alias_threshold,
                           c0->max_iterations, &m, &fr);
    for (int j = 0; st == SUNMC_OK && j < pw->np_fit; j++)
        x[j] = m.p[ess_calib_param_of(pw, j)];
    return st;
}

/* The pilot's units of c0 on cw's campaign, fitted, added to p. */
typedef struct {
    const sunmc_config *c0;
    const ess_calib_workspace *cw;
} pilot_ctx;

static int pilot_add(void *ctx, calib_prior *p, char *err, size_t errlen)
{
    const sunmc_config *c0 = ((const pilot_ctx *)ctx)->c0;
    const ess_calib_workspace *cw = ((const pilot_ctx *)ctx)->cw;
    /* a hybrid's prior is its physics's: the paper model's */
    int kind = cw->kind == ESS_MODEL_EXTENDED ? ESS_MODEL_EXTENDED : ESS_MODEL_PAPER;
    ess_calib_workspace *pw = ess_calib_alloc_fix(cw->n, kind, cw->fix_sun_y);
    if (!pw)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the priors' pilot");
    memcpy(pw->alpha_rad, cw->alpha_rad, cw->n * sizeof *cw->alpha_rad);
    memcpy(pw->beta_rad, cw->beta_rad, cw->n * sizeof *cw->beta_rad);
    uint64_t seed = prior_pilot_seed(c0);
    for (long u = 0; u < c0->prior_units; u++) {
        double x[ESS_NP_MAX];
        if (pilot_unit(c0, seed, u, pw, x) == SUNMC_OK)
            calib_prior_add(p, x);
    }
    ess_calib_free(pw);
    return SUNMC_OK;
}

int ess_prior_pilot(const sunmc_config *c, const ess_calib_workspace *cw, calib_prior *p,
                    char *err, size_t errlen)
{
    sunmc_config c0 = *c; /* no noise, no pick-freeze: the pilot is no random input */
    memset(&c0.pick, 0, sizeof c0.pick);
    c0.no_systematic = 0;
    c0.encoder_arcsec = 0;
    ess_cfg(&c0)->noise.row_current_pct = 0;
    if (calib_prior_reset(p, cw->np_fit) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "prior: %d parameters", cw->np_fit);
    /* the pilot's inputs (prior_cache.h): made once per process */
    int layout[3] = {cw->kind == ESS_MODEL_EXTENDED ? ESS_MODEL_EXTENDED : ESS_MODEL_PAPER,
                     cw->fix_sun_y, cw->np_fit};
    const prior_key_part key[] = {{&c0, sizeof c0},
                                  {layout, sizeof layout},
                                  {&cw->n, sizeof cw->n},
                                  {cw->alpha_rad, cw->n * sizeof *cw->alpha_rad},
                                  {cw->beta_rad, cw->n * sizeof *cw->beta_rad}};
    pilot_ctx pc = {&c0, cw};
    int st = prior_cache_pilot(key, (int)(sizeof key / sizeof *key), p, pilot_add, &pc, err,
                               errlen);
    if (st != SUNMC_OK)
        return st;
    return calib_prior_finish(p, ess_reading_noise_arcsec(c) * RAD_PER_ARCSEC, err, errlen);
}

int ess_prior_apply(const sunmc_config *c, ess_calib_workspace *cw, calib_prior *p, char *err,
                    size_t errlen)
{
    fit_prior_clear(cw->fw);
    calib_prior_reset(p, 0);
    /* spline and table fit no physics: no prior */
    if (c->cal_priors != CONFIG_PRIORS_TOLERANCES || cw->kind == ESS_MODEL_SPLINE ||
        cw->kind == ESS_MODEL_TABLE)
        return SUNMC_OK;
    return calib_prior_install(cw->fw, p, ess_prior_pilot(c, cw, p, err, errlen), err, errlen);
}
