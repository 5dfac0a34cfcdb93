/* summary_print.h - Table 1 and the tables after it, for people: the
 * run's summary rows (report.h) printed by the one table printer
 * (table.h).  `run` and `merge` print it. */
#ifndef SUNMC_SUMMARY_PRINT_H
#define SUNMC_SUMMARY_PRINT_H

#include "config.h"
#include "report.h"

#include <stdio.h>

/* The run's header (product, units, seed, spec, model, campaign), the
 * paper's Table 1 with p95, the means with their intervals, yield and
 * "made worse", the notes and warnings, and the operating temperatures'
 * table when there are any.  rows: report_n_rows(c) of them. */
void summary_print(FILE *f, const sunmc_config *c, const summary_row *rows);

/* The campaign's points, lines, readings and turntable hours, and a
 * warning where it extrapolates; nothing when it cannot be described. */
void summary_print_campaign(FILE *f, const sunmc_config *c);

#endif
