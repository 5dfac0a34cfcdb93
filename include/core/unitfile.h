/* unitfile.h - the per-unit results of a run at full precision (units.bin)
 * and the run's manifest (manifest.ini): what `sunmc merge` and
 * `run --resume` read back.
 *
 * units.bin is binary so that every double comes back to the last bit
 * (units.tsv rounds to 6-10 digits for people).  Layout, all in the
 * writing machine's byte order (a reader on another order refuses it):
 *   header, 8 words of 8 bytes: the magic "SUNMCUB3", the byte-order check
 *     0x0102030405060708, words per record, then nd, np, na, nb (columns
 *     of the family and config: deviations, parameters, angles, bands) and
 *     nt, the operating temperatures (thermal.h; 0 without them);
 *   one record per unit, in unit order, each word 8 bytes: unit,
 *     fit_status, fit_gsl_status, fit_iterations, alias_weak, gross_cal,
 *     gross_val as int64, then as IEEE doubles dev[nd], par[np], fit_rms,
 *     rms_before[na][nb], rms_after[na][nb], rms_after_sys[na][nb],
 *     rms_after_mf[na][nb] (modelform.h), then
 *     for each operating temperature t < nt rms_before_t[t][na][nb] and
 *     rms_after_t[t][na][nb].
 * The profile times are not stored.
 *
 * manifest.ini (INI, section [manifest]): format, sunmc_version, family,
 * config_fnv1a64 (config_hash), seed, first_unit, end_unit (the units
 * [first_unit, end_unit) that units.bin holds), units_file, kernel_isa,
 * build, units_sum_units and units_fnv1a64 (the checksums of units.bin's
 * records, unitsum.h).
 */
#ifndef SUNMC_UNITFILE_H
#define SUNMC_UNITFILE_H

#include "config.h"
#include "family.h"

#include <stdint.h>
#include <stdio.h>

#define UNITFILE_NAME "units.bin"
#define MANIFEST_NAME "manifest.ini"
#define MANIFEST_FORMAT 3 /* 3: units_sum_units, units_fnv1a64 */
#define MANIFEST_SUM_MAX 32
#define UNITFILE_HEADER_WORDS 8
#define UNITFILE_INT_WORDS 7
#define UNITFILE_MAX_WORDS                                                                       \
    (UNITFILE_INT_WORDS + UNIT_MAX_DEV + UNIT_MAX_PAR + 1 +                                       \
     (3 + 2 * UNIT_MAX_TEMPS) * UNIT_MAX_ANGLES * CONFIG_BANDS_MAX + CONFIG_BANDS_MAX +           \
     2 * (1 + UNIT_MAX_TEMPS) * UNIT_MAX_ANGLES * CONFIG_BANDS_MAX)

typedef struct {
    int nd, np, na, nb;
    int nt;     /* operating temperatures (thermal.h); 0: none */
    long words; /* per record */
} unitfile_layout;

void unitfile_layout_of(const sunmc_config *c, unitfile_layout *l);

/* Write the header; then records[n] (SUNMC_EIO on a write error). */
int unitfile_write_header(FILE *f, const unitfile_layout *l, char *err, size_t errlen);
int unitfile_write(FILE *f, const unitfile_layout *l, const unit_result *r, long n, char *err,
                   size_t errlen);

/* One record as written: w[l->words] (UNITFILE_MAX_WORDS suffice). */
void unitfile_pack(const unitfile_layout *l, const unit_result *r, uint64_t *w);

/* Read and check the header of path against the layout the config expects
 * (SUNMC_EINPUT naming what differs). */
int unitfile_read_header(FILE *f, const char *path, const unitfile_layout *l, char *err,
                         size_t errlen);
/* Read up to max records into r; *got is the number read (0 at the end).
 * A partial record at the end is SUNMC_EINPUT. */
int unitfile_read(FILE *f, const char *path, const unitfile_layout *l, unit_result *r, long max,
                  long *got, char *err, size_t errlen);

/* Bytes of the header and of one record. */
long unitfile_header_bytes(void);
long unitfile_record_bytes(const unitfile_layout *l);

typedef struct {
    int format;
    char version[32];
    char family[CONFIG_STR_MAX];
    unsigned long long config_hash;
    long seed;
    long first, end;
    char isa[16];    /* kernel path run: "avx2" or "baseline" (vm_isa) */
    char build[160]; /* compiler and flags (vm_build_id) */
    long sum_units;  /* units of one checksum of units.bin (unitsum.h) */
    int nsum;
    unsigned long long sum[MANIFEST_SUM_MAX];
} run_manifest;

/* The manifest of units [first, end) of st's config. */
void manifest_of(const config_state *st, long first, long end, run_manifest *m);
int manifest_write(FILE *f, const run_manifest *m, char *err, size_t errlen);
/* Read path; SUNMC_EINPUT with "PATH:LINE: message" for a missing or bad
 * key, SUNMC_EIO when it cannot be opened. */
int manifest_read(const char *path, run_manifest *m, char *err, size_t errlen);
/* SUNMC_EINPUT when a and b are not of the same version, family, config
 * and seed, with a message naming the field and both values (a_name and
 * b_name say where each came from). */
int manifest_compatible(const run_manifest *a, const char *a_name, const run_manifest *b,
                        const char *b_name, char *err, size_t errlen);

#endif
