/* output.h - all-or-nothing output files.
 *
 * Every file of a command is written under a temporary name in the output
 * directory and renamed into place only when all of them are complete
 * (out_commit).  On any error out_abort removes the temporaries, so a failed
 * run leaves no half-written file.
 */
#ifndef SUNMC_OUTPUT_H
#define SUNMC_OUTPUT_H

#include <stdio.h>

#define OUT_MAX_FILES 16
#define OUT_PATH_MAX 4096

typedef struct {
    int n;
    FILE *f[OUT_MAX_FILES];
    char tmp[OUT_MAX_FILES][OUT_PATH_MAX];
    char final[OUT_MAX_FILES][OUT_PATH_MAX];
} out_set;

/* Start a set of files in dir (created, with parents, if missing). */
int out_begin(out_set *o, const char *dir, char *err, size_t errlen);

/* Open dir/name for writing under a temporary name; *f is the stream. */
int out_open(out_set *o, const char *dir, const char *name, FILE **f, char *err, size_t errlen);

/* Open dir/names[k] for k < n into files[k] (out_open for each, stopping at
 * the first error). */
int out_open_all(out_set *o, const char *dir, const char *const *names, FILE **files, int n,
                 char *err, size_t errlen);

/* Close every stream, check for write errors, rename all into place. */
int out_commit(out_set *o, char *err, size_t errlen);

/* Close and remove every temporary. */
void out_abort(out_set *o);

/* mkdir -p. */
int out_mkdirs(const char *dir, char *err, size_t errlen);

#endif
