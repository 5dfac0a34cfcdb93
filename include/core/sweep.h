/* sweep.h - design trades: one or two config keys varied over a list or a
 * range of values, the full grid of points for two.
 *
 * An axis is written KEY=LIST, KEY=START:STOP:STEP or KEY=ALT|ALT|..., KEY
 * being "section.key" of the key table:
 *     campaign.alpha_step_deg=1,0.5,0.3,0.25,0.2   a number key: a list
 *     design.H_mm=3:8:0.5          (3, 3.5, ..., 8; STOP included when hit)
 *     campaign.beta_deg=-20,0,20|-30,0,30|-30,-10,10,30
 *                                  any key but sensor.family and report.bands_deg
 *                                  (list, choice, text, number): alternatives, each
 *                                  a value as it would be written in a file
 * Each point's values are applied with config_set_value, then the config is
 * re-validated, so a value is checked exactly as it would be in a file.
 */
#ifndef SUNMC_SWEEP_H
#define SUNMC_SWEEP_H

#include "family.h"

#include <stddef.h>

#define SWEEP_MAX_AXES 2
#define SWEEP_MAX_VALUES 256      /* most values on one axis */
#define SWEEP_VALUE_TEXT 160      /* a value as text: "%.10g", or an alternative */
#define SWEEP_LABEL_MAX (SWEEP_MAX_AXES * (SWEEP_VALUE_TEXT + 4))

typedef struct {
    char section[CONFIG_STR_MAX];
    char name[CONFIG_STR_MAX];
    char dotted[2 * CONFIG_STR_MAX + 2]; /* "section.key": column name in sweep.tsv */
    int numeric;                         /* 1: every value is a number, in v[] */
    int n;                               /* number of values */
    double v[SWEEP_MAX_VALUES];          /* in the unit of the key's name; NaN if not numeric */
    char text[SWEEP_MAX_VALUES][SWEEP_VALUE_TEXT]; /* each value as config text */
} sweep_axis;

/* Parse one --vary spec for a config of family `family`.  SUNMC_EINPUT
 * with a message naming the spec for an unknown key, a key that cannot be
 * varied (sensor.family, report.bands_deg), a key of another family, a
 * malformed list or range, a zero or wrong-signed step, an empty or too long
 * alternative, a non-number key without '|' alternatives, or more than
 * SWEEP_MAX_VALUES values. */
int sweep_axis_parse(const char *spec, const sensor_family *family, sweep_axis *ax, char *err,
                     size_t errlen);

/* Number of points of the grid of axes[n_axes] (product of the counts). */
long sweep_n_points(const sweep_axis *axes, int n_axes);

/* Values of point p (0 <= p < sweep_n_points): the first axis is the outer
 * (slowest) one.  values[n_axes] receives them (NaN on a non-numeric axis). */
void sweep_point_values(const sweep_axis *axes, int n_axes, long p, double *values);

/* The same as text: texts[n_axes] point into the axes. */
void sweep_point_text(const sweep_axis *axes, int n_axes, long p, const char **texts);

/* Point p's label for plots: its values' texts joined by "; ". */
void sweep_point_label(const sweep_axis *axes, int n_axes, long p, char *buf, size_t len);

/* Apply point p to st (config_set_value with origin "--vary section.key",
 * then config_validate).  SUNMC_EINPUT with the key and value on error. */
int sweep_apply(config_state *st, const sweep_axis *axes, int n_axes, long p, char *err,
                size_t errlen);

#endif
