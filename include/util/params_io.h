/* params_io.h - params.ini: a calibration as `sunmc calibrate` writes it and
 * `sunmc compensate` (and a person) reads it.
 *
 * An INI file (the dialect of ini.h) of sections and `key = value` lines,
 * each optionally followed by `# comment` (the unit and the standard error,
 * for the reader).  Keys
 * carry their unit in their name (_deg, _arcsec, _px).  Numbers are written
 * with 17 significant digits so that a write/read round trip is exact.
 *
 * Typical content ([calibration] is common to every family):
 *     [calibration]
 *     sunmc_version = 0.1.0
 *     sensor = ess
 *     model = ess_eq12_finecode
 *     data_file = runs/u3/campaign.csv
 *     data_fnv1a64 = 3f2a...          (FNV-1a 64 of the data file's bytes)
 *     [design]  ...  [parameters]  ...
 */
#ifndef SUNMC_PARAMS_IO_H
#define SUNMC_PARAMS_IO_H

#include <stddef.h>
#include <stdio.h>

#define PARAMS_MAX_ENTRIES 160
#define PARAMS_SECTION_MAX 32
#define PARAMS_KEY_MAX 64
#define PARAMS_VALUE_MAX 512
#define PARAMS_COMMENT_MAX 160
#define PARAMS_PATH_MAX 1024

typedef struct {
    char section[PARAMS_SECTION_MAX];
    char key[PARAMS_KEY_MAX];
    char value[PARAMS_VALUE_MAX];
    char comment[PARAMS_COMMENT_MAX];  /* written after '#', may be empty */
    int line;                          /* line in the file it was read from; 0 when built */
} params_entry;

typedef struct {
    char path[PARAMS_PATH_MAX];        /* file read from ("" when built) */
    int n;
    params_entry e[PARAMS_MAX_ENTRIES];
} params_file;

/* Empty set. */
void params_init(params_file *p);

/* Add section.key = text (or a double, %.17g) with an optional comment (NULL:
 * none).  SUNMC_EINPUT when full, a name is too long or the key exists. */
int params_set_text(params_file *p, const char *section, const char *key, const char *text,
                    const char *comment);
int params_set_double(params_file *p, const char *section, const char *key, double v,
                      const char *comment);

/* Write every entry, grouped by section in order of first appearance, after
 * the header comment `title` (may hold several lines; each gets "# "). */
int params_write(FILE *f, const params_file *p, const char *title);

/* Read path (ini.h: its syntax errors are "FILE:LINE: message").
 * SUNMC_EIO when unreadable. */
int params_read(const char *path, params_file *p, char *err, size_t errlen);

/* The entry section.key, or NULL. */
const params_entry *params_find(const params_file *p, const char *section, const char *key);
/* A key's earlier name: entry section.from becomes section.to, its value
 * and line kept, when the file has from and not to.  Returns 1 when it
 * renamed, 0 otherwise. */
int params_rename(params_file *p, const char *section, const char *from, const char *to);

/* Value of section.key as text / as a finite double.  Messages:
 * "FILE: missing key section.key" and "FILE:LINE: key section.key: 'x' is not
 * a number". */
int params_get_text(const params_file *p, const char *section, const char *key,
                    const char **out, char *err, size_t errlen);
int params_get_double(const params_file *p, const char *section, const char *key, double *out,
                      char *err, size_t errlen);

/* Value of section.key as a whole number: decimal digits with an optional
 * '-' (numtext.h: "3.0", "+3", "3e0" are not), within an int, else
 * "FILE:LINE: key section.key: 'x' is not a whole number". */
int params_get_int(const params_file *p, const char *section, const char *key, int *out,
                   char *err, size_t errlen);

/* A range check on a value read from section.key: SUNMC_OK when ok, else
 * "FILE:LINE: key section.key must be WHAT" at the key's line. */
/* A range check of one number read from p: lo <= v <= hi, else
 * "FILE:LINE: section.key = V is out of range: allowed LO to HI UNIT (why)"
 * (why says where the range comes from; may be NULL). */
typedef struct {
    const char *section, *key;
    double lo, hi;
    const char *unit, *why;
} params_range;

/* Read and check each of ranges[n] (params_get_double, then the range);
 * the first failure is the status. */
int params_check_ranges(const params_file *p, const params_range *ranges, int n, char *err,
                        size_t errlen);

int params_require(const params_file *p, const char *section, const char *key, int ok,
                   const char *what, char *err, size_t errlen);

/* The first entry of `section` whose key is none of names[n], or NULL. */
const params_entry *params_unknown_key(const params_file *p, const char *section,
                                       const char *const *names, int n);
/* Every key of `section` must be one of names[n] (NULL-free), else
 * "FILE:LINE: unknown key section.key" and " (did you mean NAME?)" when
 * one of names is near (suggest.h). */
int params_check_keys(const params_file *p, const char *section, const char *const *names,
                      int n, char *err, size_t errlen);

/* FNV-1a 64-bit hash of n bytes, continuing from h (start with
 * PARAMS_FNV1A64_INIT); and of a whole file's bytes. */
#define PARAMS_FNV1A64_INIT 0xcbf29ce484222325ULL
unsigned long long params_fnv1a64(unsigned long long h, const void *data, size_t n);
int params_file_fnv1a64(const char *path, unsigned long long *hash, char *err, size_t errlen);

#endif
