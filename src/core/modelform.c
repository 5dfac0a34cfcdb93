/* modelform.c - the model-form pass of a unit (see modelform.h). */
#include "modelform.h"
#include "status.h"

#include <math.h>
#include <string.h>

int modelform_on(const sunmc_config *c)
{
    return c->model_form_every > 0 && !c->no_systematic;
}

int modelform_due(const sunmc_config *c, long unit)
{
    return modelform_on(c) && unit % c->model_form_every == 0;
}

int modelform_config(const sunmc_config *c, sunmc_config *out, char *err, size_t errlen)
{
    *out = *c;
    out->model_form_every = 0;
    out->no_systematic = 1;
    for (const family_noise *nz = c->family->noise; nz && nz->name; nz++)
        for (const char *const *dotted = nz->keys; *dotted; dotted++) {
            const config_key *k = config_find_dotted(c->family, *dotted);
            if (!k || k->type != KEY_DOUBLE)
                return sunmc_fail(err, errlen, SUNMC_EINPUT,
                                  "family %s: noise key %s is not a number key",
                                  c->family->name, *dotted);
            *(double *)config_value_ptr(k, out) = 0.0;
        }
    return SUNMC_OK;
}

int modelform_unit(const sunmc_config *mf, long unit, void *ws, unit_result *scratch,
                   unit_result *r)
{
    memset(scratch->phase_s, 0, sizeof scratch->phase_s);
    int st = mf->family->unit_run(mf, unit, ws, scratch);
    int ok = st == SUNMC_OK && scratch->fit_status == UNIT_FIT_OK;
    for (int a = 0; a < UNIT_MAX_ANGLES; a++)
        for (int b = 0; b < CONFIG_BANDS_MAX; b++)
            r->rms_after_mf[a][b] = ok ? scratch->rms_after[a][b] : NAN;
    for (int p = 0; p < UNIT_PHASES; p++)
        r->phase_s[p] += scratch->phase_s[p];
    return st;
}
