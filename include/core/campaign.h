/* campaign.h - what a calibration campaign costs in turntable time and
 * which table angles it covers, for every family (through its family_grid
 * hook, family.h) and for a real campaign's data (`sunmc calibrate`).
 *
 * Cost model (keys in [campaign], each with its unit in the name): the
 * table visits the campaign's positions in order; a move takes the larger
 * of the two axes' travel over campaign.slew_deg_per_s (both axes move at
 * once); the table then settles, campaign.line_settle_s after a move of
 * the slow axis (a new beta line, ESS; a new b1 row, DSS) -- and before the
 * first point -- else campaign.point_settle_s; at each position it takes
 * campaign.repeats readings of campaign.dwell_s each.  So
 *   hours = [sum over moves of max |travel| / rate
 *            + lines * line_settle + (points - lines) * point_settle
 *            + points * repeats * dwell] / 3600.
 * Mounting, warm-up and the sun simulator's own time are not in it.
 *
 * Span: the campaign calibrates the table angles between its extreme
 * positions on each axis; a validation angle beyond them is an
 * extrapolation of the fitted model, and how far (deg) is reported.
 */
#ifndef SUNMC_CAMPAIGN_H
#define SUNMC_CAMPAIGN_H

#include "config.h"

#include <stddef.h>

#define CAMPAIGN_AXES 2

typedef struct {
    int known;                          /* 0: the family has no table grid (nothing below) */
    long points;                        /* table positions */
    long lines;                         /* positions reached by a move of the slow axis */
    long readings;                      /* points x repeats */
    double slew_deg;                    /* summed travel (the longer axis of each move) */
    double hours;                       /* estimated turntable time */
    double cal_lo[CAMPAIGN_AXES], cal_hi[CAMPAIGN_AXES]; /* campaign span per axis, deg */
    double val_lo[CAMPAIGN_AXES], val_hi[CAMPAIGN_AXES]; /* validation span, deg */
    double outside_deg[CAMPAIGN_AXES];  /* validation beyond the campaign span, 0 when inside */
    double extrapolation_deg;           /* the larger of outside_deg */
} campaign_info;

/* The cost of visiting the n table positions (a0[i], a1[i]) in order,
 * a0 the fast axis, values times to_deg in deg, under c's cost keys; fills
 * every field but the validation span (val_*, outside_deg = 0). */
void campaign_cost(const sunmc_config *c, const double *a0, const double *a1, long n,
                   double to_deg, campaign_info *out);

/* Cost and span of c's own campaign and validation grids (the family's
 * family_grid); out->known = 0 when the family has none.
 * SUNMC_ENOMEM. */
int campaign_describe(const sunmc_config *c, campaign_info *out, char *err, size_t errlen);

/* "validation beta reaches -25..25 deg, beyond the campaign's -20..20 deg
 * (extrapolated by up to 5 deg)" for each axis that leaves the span, joined
 * by "; "; "" when nothing does.  axis_names: the family's table axes. */
void campaign_extrapolation_text(const campaign_info *ci, const char *const *axis_names,
                                 char *buf, size_t len);

#endif
