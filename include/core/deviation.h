/* deviation.h - a family's deviation list, and drawing one unit's
 * deviations from it.
 *
 * Each family keeps ONE list of its tolerances, an X-macro (ESS_DEVIATIONS
 * in ess_deviations.h, DSS_DEVIATIONS in dss_deviations.h); one line per
 * tolerance gives its name, unit, draws per unit, random stream, units.tsv
 * columns and its config key's default, distribution, maximum and help.
 * From that line come the tolerance's two config keys (NAME, NAME_dist), its
 * `tolerance` in the family's config, its entry in the table below, its
 * units.tsv columns and its draws.
 *
 * Random streams: entry i draws from stream RNG_STREAM_TOLERANCE + its
 * stream id, written in the list and never renumbered, so a new tolerance
 * (any place in the list, with a new id) leaves every other draw unchanged.
 */
#ifndef SUNMC_DEVIATION_H
#define SUNMC_DEVIATION_H

#include "config.h"

#include <stddef.h>
#include <stdint.h>

typedef struct {
    const char *name;             /* tolerance key: "dH_um" */
    int count;                    /* draws per unit (e.g. one per fine row) */
    uint32_t stream;              /* RNG_STREAM_TOLERANCE + stream */
    size_t tol_offset;            /* its `tolerance` in the family's config */
    size_t dev_offset;            /* its first double in the family's deviations struct */
    const char *const *columns;   /* count column names for units.tsv */
} deviation_spec;

/* Draw unit `unit`'s deviations for seed (a stream that c->pick lists draws
 * from c->pick.seed instead, family.h) into dev (the family's deviations
 * struct): entry e's count values from its own stream, with the tolerances
 * of the family's config `fam_cfg` (c->fam) and c->truncation_sigmas. */
void deviations_sample(const deviation_spec *list, int n, const sunmc_config *c, uint64_t seed,
                       long unit, void *dev);

/* The values of dev in list order (count of each entry), into out[max];
 * returns how many there are. */
int deviations_values(const deviation_spec *list, int n, const void *dev, double *out, int max);

/* The column names in the same order, into names[max]; returns the count. */
int deviations_columns(const deviation_spec *list, int n, const char **names, int max);

/* Multiply every deviation of the list in dev by s (all count values of
 * each entry): s = -1 makes the mirror unit of `sunmc curve`, a fixed
 * tolerance of -V.  A field of the family's deviations struct that is not
 * in the list (a derived measurement) is the family's to scale. */
void deviations_scale(const deviation_spec *list, int n, void *dev, double s);

/* The inverse of deviations_values: dev's listed fields from values (in
 * list order, deviations_values' count of them); other fields untouched. */
void deviations_set_values(const deviation_spec *list, int n, const double *values, void *dev);

/* The largest |draw| of entry spec's tolerance in c (its distribution's
 * bound, or truncation_sigmas sigmas for a normal one). */
double deviations_reach(const deviation_spec *spec, const sunmc_config *c);

/* X-macro helpers: pass them to a family's list, whose lines are
 *   X(name, unit, count, stream, columns, default, dist, max, help)
 * with `columns` count strings (no braces).  The family's config struct
 * holds the tolerances as a member `tol`.
 *   DEVIATION_X_TOLERANCE  a `tolerance name;` member (the tol struct)
 *   DEVIATION_X_KEYS       its two config rows; needs OFF(field), the
 *                          offset in the family's config, where expanded
 *   DEVIATION_X_COLUMNS    static name##_columns[], for DEVIATION_SPEC
 *   DEVIATION_X_NAMES      its column names, for a flat table of names
 *   DEVIATION_X_ONE, _COUNT  +1 per line, +count per line (enum counts)
 * and DEVIATION_SPEC(cfg_type, dev_type, name, count, stream) is the line's
 * deviation_spec (a family wraps it in its own X with its two types). */
#define DEVIATION_X_TOLERANCE(name, ...) tolerance name;
#define DEVIATION_X_KEYS(name, unit, count, stream, columns, def, dist, max, help)                \
    CONFIG_TOLERANCE_KEYS(OFF(tol.name), #name, unit, def, dist, max, help),
#define DEVIATION_X_COLUMNS(name, unit, count, stream, columns, ...)                              \
    static const char *const name##_columns[count] = {columns};
#define DEVIATION_X_NAMES(name, unit, count, stream, columns, ...) columns,
#define DEVIATION_X_ONE(...) +1
#define DEVIATION_X_COUNT(name, unit, count, ...) +(count)
#define DEVIATION_SPEC(cfg_type, dev_type, name, count, stream)                                  \
    {#name, count, stream, offsetof(cfg_type, tol.name), offsetof(dev_type, name),                \
     name##_columns}

#endif
