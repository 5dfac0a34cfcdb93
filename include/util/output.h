/* output.h - a command's output directory, written all or nothing.
 *
 * Guarantee: after a command that writes to --out DIR, DIR is either exactly
 * what it was before (the command failed or was interrupted) or holds exactly
 * the files of this command, complete (it succeeded).  Never a mix of old and
 * new files, never a half-written file, never a file left from an earlier
 * command.
 *
 * How:
 *   - out_check, before any work: DIR must be creatable (its nearest existing
 *     ancestor is a directory we can create entries in), must not be an
 *     existing file, and when it exists it must be empty or hold the marker
 *     file OUT_MARKER that every sunmc output directory holds and nothing but
 *     the files that marker lists (so sunmc never replaces a directory it did
 *     not write, such as a home directory, nor a user's file put into one);
 *     out_check_inputs: nor one that holds an input of the command.
 *   - out_begin removes what a killed run into DIR left beside it (its
 *     .NAME.tmp.HOST-PID.* directories; a .NAME.old.* is put back as DIR when
 *     DIR is missing), then creates a temporary directory beside DIR
 *     (.NAME.tmp.HOST-PID.XXXXXX in DIR's parent); every file is written
 *     there (out_open).
 *   - out_commit flushes and syncs every file (any write error, e.g. a full
 *     disk, is an error: nothing is moved), lists them in the marker, then
 *     exchanges the temporary directory and an existing DIR in one step
 *     (renameat2 RENAME_EXCHANGE) and removes the old one; where the file
 *     system cannot exchange, DIR is moved aside (.NAME.old.HOST-PID.*) and
 *     the new one renamed into place.
 *   - out_abort (any error) removes the temporary directory.
 *   - Between out_begin and out_commit/out_abort, SIGINT, SIGTERM and SIGHUP
 *     remove the temporary directory (async-signal-safe: unlink and rmdir of
 *     recorded paths) and then end the process by the same signal; during the
 *     renames of out_commit the signal is held back until DIR is complete.
 *     The previous handlers are restored afterwards.
 *
 * One output set is open at a time in a process.  Modules still never print:
 * every function returns a status and fills err.
 */
#ifndef SUNMC_OUTPUT_H
#define SUNMC_OUTPUT_H

#include <stdio.h>

#define OUT_MAX_FILES 16
#define OUT_PATH_MAX 4096
#define OUT_NAME_MAX 64

/* Marker file written into every output directory. */
#define OUT_MARKER ".sunmc"

typedef struct {
    int n;
    FILE *f[OUT_MAX_FILES];
    char name[OUT_MAX_FILES][OUT_NAME_MAX];
    char dir[OUT_PATH_MAX];    /* the target, without trailing slashes */
    char tmpdir[OUT_PATH_MAX]; /* where the files are written */
} out_set;

/* Can dir be written as an output directory?  SUNMC_EINPUT with a message
 * starting "--out DIR: " when it is empty, ".", "..", "/", an existing file,
 * under a file, in a directory where nothing can be created, or an existing
 * directory that is neither empty nor a sunmc output directory.  Creates
 * nothing (a probe directory is made and removed at once). */
int out_check(const char *dir, char *err, size_t errlen);

/* Before any work: SUNMC_EINPUT naming them when dir (existing) holds any
 * of the n paths inputs (compared by real path; NULL entries skipped) or is
 * one of them: replacing dir would destroy an input of the command. */
int out_check_inputs(const char *dir, const char *const *inputs, int n, char *err,
                     size_t errlen);

/* Start writing the files of dir: creates its parents if missing and the
 * temporary directory beside it, and installs the signal handlers. */
int out_begin(out_set *o, const char *dir, char *err, size_t errlen);

/* Open file `name` (a plain file name) of the set; *f is the stream. */
int out_open(out_set *o, const char *name, FILE **f, char *err, size_t errlen);

/* Open names[k] for k < n into files[k] (out_open for each, stopping at the
 * first error). */
int out_open_all(out_set *o, const char *const *names, FILE **files, int n, char *err,
                 size_t errlen);

/* Close every stream, check for write errors, and replace dir whole by the
 * new files (see above).  On error nothing is moved (out_abort is done). */
int out_commit(out_set *o, char *err, size_t errlen);

/* Text (up to OUT_NOTE_MAX) the signal handler writes to stderr after it
 * removed the temporary directory: what was kept and how to resume.  NULL
 * or "" for none. */
#define OUT_NOTE_MAX 2048
void out_signal_note(const char *note);

/* Close every stream and remove the temporary directory. */
void out_abort(out_set *o);

/* mkdir -p. */
int out_mkdirs(const char *dir, char *err, size_t errlen);

#endif
