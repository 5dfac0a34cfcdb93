/* h5out.h - a run's tables as one HDF5 file (sunmc run --format hdf5).
 *
 * h5out_write reads the TSV tables of a run (units.tsv, summary.tsv; header
 * line then one row per line, tab-separated) and config.ini, and writes
 * path as:
 *   /units/COLUMN    one 1-D dataset per units.tsv column, in unit order
 *   /summary/COLUMN  one 1-D dataset per summary.tsv column, one row per band
 *   attributes of /: config (config.ini's text), family, product, seed,
 *                    units, first, end
 * A column whose every value is a whole number is int64, else one whose
 * every value is a number (nan and inf included) is float64, else a
 * fixed-length string (null-padded, the longest value's length); a cell
 * "-" (a number the tool could not form) is nan in a numeric column, which
 * is then float64.  Each group's attribute "columns" lists the table's
 * header in order, tab-separated.  The values
 * are those the TSV prints, so the file equals the TSV to its printed
 * precision.  No timestamps are stored: the same tables give the same bytes.
 * Modules never print: a status, and err names what was wrong.
 */
#ifndef SUNMC_H5OUT_H
#define SUNMC_H5OUT_H

#include <stddef.h>

/* The run's identity, stored as attributes of the root group. */
typedef struct {
    const char *family;
    const char *product;
    long seed;
    long units;       /* run.units */
    long first, end;  /* the units the file holds: [first, end) */
} h5out_meta;

/* Name of the file in a run directory. */
#define H5OUT_NAME "results.h5"
/* A number the tool could not form, in a TSV cell (nan in the file). */
#define H5OUT_MISSING "-"

/* Load the HDF5 library (dlopen: sunmc does not link it, which would slow
 * every process's start; its name is the build's, or the environment's
 * SUNMC_HDF5_LIB).  SUNMC_EINPUT when it cannot be loaded or lacks a
 * function h5out needs, err saying which and how to install it.  Called
 * by h5out_write; a run asking for results.h5 calls it before its units,
 * so a missing library refuses the run and writes nothing. */
int h5out_load(char *err, size_t errlen);

int h5out_write(const char *path, const char *units_tsv, const char *summary_tsv,
                const char *config_ini, const h5out_meta *meta, char *err, size_t errlen);

#endif
