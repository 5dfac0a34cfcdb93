/* sweep.h - design trades: one or two config keys varied over a list or a
 * range of values, the full grid of points for two.
 *
 * An axis is written KEY=LIST or KEY=START:STOP:STEP, KEY being
 * "section.key" of the key table (numeric keys only):
 *     campaign.alpha_step_deg=1,0.5,0.3,0.25,0.2
 *     design.H_mm=3:8:0.5          (3, 3.5, ..., 8; STOP included when hit)
 * Each point's values are applied with config_set_value, then the config is
 * re-validated, so a value is checked exactly as it would be in a file.
 */
#ifndef SUNMC_SWEEP_H
#define SUNMC_SWEEP_H

#include "family.h"

#include <stddef.h>

#define SWEEP_MAX_AXES 2
#define SWEEP_MAX_VALUES 256      /* most values on one axis */
#define SWEEP_VALUE_TEXT 64       /* a value as text, "%.10g" */

typedef struct {
    char section[CONFIG_STR_MAX];
    char name[CONFIG_STR_MAX];
    char dotted[2 * CONFIG_STR_MAX + 2]; /* "section.key": column name in sweep.tsv */
    int n;                               /* number of values */
    double v[SWEEP_MAX_VALUES];          /* in the unit of the key's name */
} sweep_axis;

/* Parse one --vary spec for a config of family `family`.  SUNMC_EINPUT
 * with a message naming the spec for an unknown or non-numeric key, a key of
 * another family, a malformed list or range, a zero or wrong-signed step, or
 * more than SWEEP_MAX_VALUES values. */
int sweep_axis_parse(const char *spec, const sensor_family *family, sweep_axis *ax, char *err,
                     size_t errlen);

/* Number of points of the grid of axes[n_axes] (product of the counts). */
long sweep_n_points(const sweep_axis *axes, int n_axes);

/* Values of point p (0 <= p < sweep_n_points): the first axis is the outer
 * (slowest) one.  values[n_axes] receives them. */
void sweep_point_values(const sweep_axis *axes, int n_axes, long p, double *values);

/* Apply point p to st (config_set_value with origin "--vary section.key",
 * then config_validate).  SUNMC_EINPUT with the key and value on error. */
int sweep_apply(config_state *st, const sweep_axis *axes, int n_axes, long p, char *err,
                size_t errlen);

#endif
