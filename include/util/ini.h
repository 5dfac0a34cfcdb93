/* ini.h - the one INI dialect of sunmc: config files and params.ini.
 *
 * A line is blank, a comment (its first non-blank character is '#' or ';'),
 * a section header "[name]", or "key = value".  A '#' that starts a value or
 * follows white space starts a comment ("H_mm = 4.124  # type A"); its text
 * is kept with the entry.  White space around names and values is dropped.
 *
 * Errors, each "FILE:LINE: message": a line longer than INI_LINE_MAX
 * characters, a malformed section header, a line that is none of the above,
 * a key before any [section], an empty key, a name longer than
 * INI_NAME_MAX - 1 characters, and a key given twice in a section (the
 * message names the line it was first set on).
 *
 * The reader is a stream: the caller sees each section header and each key
 * in file order, so it can check names as it goes and report the first
 * error of the file.
 */
#ifndef SUNMC_INI_H
#define SUNMC_INI_H

#include <stddef.h>
#include <stdio.h>

#define INI_LINE_MAX 1024
#define INI_NAME_MAX 64

/* What ini_next found. */
enum ini_item { INI_END = 0, INI_SECTION, INI_KEY };

typedef struct {
    char section[INI_NAME_MAX];  /* the section header, or the key's section */
    char key[INI_NAME_MAX];      /* INI_KEY only */
    char value[INI_LINE_MAX];
    char comment[INI_LINE_MAX];  /* after '#', trimmed; "" when none */
    int line;                    /* 1-based line in the file */
} ini_entry;

typedef struct {
    char section[INI_NAME_MAX];
    char key[INI_NAME_MAX];
    int line;
} ini_seen;

typedef struct {
    FILE *f;
    const char *path;            /* for messages */
    int line;
    char section[INI_NAME_MAX];  /* current section, "" before the first */
    ini_seen *seen;              /* keys read so far (duplicates) */
    int n_seen, cap_seen;
} ini_reader;

/* Read the open file f, named path in messages. */
void ini_begin(ini_reader *r, FILE *f, const char *path);

/* The next section header or key into e; *item = INI_END at the end of the
 * file.  SUNMC_EINPUT with "FILE:LINE: message" for a syntax error,
 * SUNMC_EIO for a read error, SUNMC_ENOMEM. */
int ini_next(ini_reader *r, int *item, ini_entry *e, char *err, size_t errlen);

/* Release the reader (not the file). */
void ini_end(ini_reader *r);

/* Strip leading and trailing white space in place. */
char *ini_trim(char *s);

#endif
