/* modelform.h - the model-form part of a unit's error after calibration.
 *
 * A unit's after-calibration error has three parts: the noise of the
 * validation reading, the calibration's estimation error (the campaign's
 * noise carried through the fit into the parameters) and model form (what
 * the calibration model cannot represent of the simulated truth: the
 * omitted physics, whatever the campaign's noise).  The systematic pass
 * (rms_after_sys: the same validation points read without noise) removes
 * the first; the model-form pass removes both: the same unit (the same
 * tolerance draws: streams are per tolerance) calibrated on a campaign with
 * every noise key of its family 0 and read without noise.  Its after-RMS
 * is the model-form part, rms_after_mf.
 *
 * The pass costs a second fit, so it runs on every report.model_form_every-th
 * unit (unit % N == 0; 0: none), and never when the caller reads no
 * systematic part (c->no_systematic: budget, design, sensitivity runs).
 * Which units get it depends on the unit number alone, so results stay the
 * same for any thread count, shard split or rank count.
 */
#ifndef SUNMC_MODELFORM_H
#define SUNMC_MODELFORM_H

#include "config.h"
#include "family.h"

/* 1 when unit `unit` of c gets the model-form pass. */
int modelform_due(const sunmc_config *c, long unit);

/* 1 when any unit of c gets it (report.model_form_every > 0 and the
 * systematic pass on). */
int modelform_on(const sunmc_config *c);

/* Into out: c with every noise key of its family (sensor_family.noise) 0,
 * no model-form pass of its own and no systematic pass.  SUNMC_EINPUT
 * (message in err) when a noise key is not a number key of the family. */
int modelform_config(const sunmc_config *c, sunmc_config *out, char *err, size_t errlen);

/* c's noise-free config into storage and *mf = storage, or *mf = NULL
 * when the pass is off for c (modelform_on); the error of
 * modelform_config. */
int modelform_setup(const sunmc_config *c, sunmc_config *storage, const sunmc_config **mf,
                    char *err, size_t errlen);

/* One thread's pass: the shared noise-free config (NULL: off), its own
 * workspace of it and a result to run the unit into, allocated once and
 * reused for every unit the thread runs. */
typedef struct {
    const sunmc_config *mf;
    void *ws;
    unit_result *scratch;
} modelform_pass;

/* p for config mf (from modelform_setup; NULL: p off, nothing allocated).
 * SUNMC_ENOMEM (message in err) when the workspace or the result cannot
 * be had: p is then off and holds nothing. */
int modelform_pass_init(modelform_pass *p, const sunmc_config *mf, char *err, size_t errlen);
void modelform_pass_free(modelform_pass *p);

/* Unit `unit` of config c: its model-form pass into r when p is on and the
 * unit is due (modelform_due); SUNMC_OK and r untouched otherwise. */
int modelform_pass_run(modelform_pass *p, const sunmc_config *c, long unit, unit_result *r);

/* Unit `unit` of the noise-free config mf (modelform_config) run in
 * workspace ws (a workspace of mf) into scratch; its after-RMS copied into
 * r->rms_after_mf (NaN where its fit failed or a band is empty).  Returns
 * the unit run's status. */
int modelform_unit(const sunmc_config *mf, long unit, void *ws, unit_result *scratch,
                   unit_result *r);

#endif
