/* modelform.c - the model-form pass of a unit (see modelform.h). */
#include "modelform.h"
#include "status.h"

#include <math.h>
#include <stdlib.h>
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

int modelform_setup(const sunmc_config *c, sunmc_config *storage, const sunmc_config **mf,
                    char *err, size_t errlen)
{
    *mf = NULL;
    if (!modelform_on(c))
        return SUNMC_OK;
    int st = modelform_config(c, storage, err, errlen);
    if (st == SUNMC_OK)
        *mf = storage;
    return st;
}

void modelform_pass_free(modelform_pass *p)
{
    if (p->ws)
        p->mf->family->workspace_free(p->ws);
    free(p->scratch);
    p->mf = NULL;
    p->ws = NULL;
    p->scratch = NULL;
}

int modelform_pass_init(modelform_pass *p, const sunmc_config *mf, char *err, size_t errlen)
{
    p->mf = mf;
    p->ws = NULL;
    p->scratch = NULL;
    if (!mf)
        return SUNMC_OK;
    p->ws = mf->family->workspace_alloc(mf, err, errlen);
    p->scratch = p->ws ? malloc(sizeof *p->scratch) : NULL;
    if (p->scratch)
        return SUNMC_OK;
    if (p->ws)
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the model-form pass");
    modelform_pass_free(p);
    return SUNMC_ENOMEM;
}

int modelform_pass_run(modelform_pass *p, const sunmc_config *c, long unit, unit_result *r)
{
    if (!p->mf || !modelform_due(c, unit))
        return SUNMC_OK;
    return modelform_unit(p->mf, unit, p->ws, p->scratch, r);
}
