/* output.c - a command's output directory, written all or nothing: files go
 * to a temporary directory beside the target, which replaces the target
 * whole at the end (see output.h). */
#include "output.h"
#include "status.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define OUT_MARKER_TEXT \
    "sunmc output directory: the next sunmc command writing here replaces it whole\n"

/* ---- the signal guard: one output set at a time ---- */

enum { GUARD_IDLE, GUARD_WRITING, GUARD_MAIN, GUARD_CLEANING };

_Static_assert(ATOMIC_INT_LOCK_FREE == 2, "the signal guard needs a lock-free atomic int");

static atomic_int guard_state = GUARD_IDLE;
static char guard_tmpdir[OUT_PATH_MAX];
static char guard_paths[OUT_MAX_FILES + 1][OUT_PATH_MAX]; /* marker + files */
static volatile sig_atomic_t guard_n;
static volatile sig_atomic_t guard_pending;
static const int guard_signals[] = {SIGINT, SIGTERM, SIGHUP};
#define GUARD_NSIG ((int)(sizeof guard_signals / sizeof guard_signals[0]))
static struct sigaction guard_old[GUARD_NSIG];
static struct sigaction guard_default;

/* While files are being written: remove them and the temporary directory,
 * then end by the same signal.  While the main thread moves or removes them
 * (GUARD_MAIN): note the signal; guard_release raises it afterwards.  Only
 * async-signal-safe calls. */
static void guard_on_signal(int sig)
{
    int expected = GUARD_WRITING;
    if (atomic_compare_exchange_strong(&guard_state, &expected, GUARD_CLEANING)) {
        int n = guard_n;
        for (int i = 0; i < n; i++)
            unlink(guard_paths[i]);
        rmdir(guard_tmpdir);
    } else if (expected == GUARD_MAIN) {
        guard_pending = sig;
        return;
    } else if (expected == GUARD_CLEANING) {
        return; /* another thread is cleaning up and ends the process */
    }
    sigaction(sig, &guard_default, NULL);
    raise(sig);
}

static void guard_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = guard_on_signal;
    sigemptyset(&sa.sa_mask);
    memset(&guard_default, 0, sizeof guard_default);
    guard_default.sa_handler = SIG_DFL;
    sigemptyset(&guard_default.sa_mask);
    guard_pending = 0;
    for (int i = 0; i < GUARD_NSIG; i++)
        sigaction(guard_signals[i], &sa, &guard_old[i]);
}

/* The main thread takes the files over from the handler; 0 when a handler
 * is already removing them (the process is ending). */
static int guard_take(void)
{
    int expected = GUARD_WRITING;
    return atomic_compare_exchange_strong(&guard_state, &expected, GUARD_MAIN);
}

/* Back to idle, the previous handlers restored; a signal held back while the
 * main thread had the files is raised now. */
static void guard_release(void)
{
    guard_n = 0;
    guard_tmpdir[0] = '\0';
    for (int i = 0; i < GUARD_NSIG; i++)
        sigaction(guard_signals[i], &guard_old[i], NULL);
    atomic_store(&guard_state, GUARD_IDLE);
    if (guard_pending)
        raise(guard_pending);
}

/* ---- paths ---- */

/* Split dir into parent and last component, without trailing slashes;
 * refuses "", "/", "." and "..". */
static int split_dir(const char *dir, char *norm, char *parent, char *base, char *err,
                     size_t errlen)
{
    size_t len = strlen(dir);
    if (len == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out needs a directory name");
    if (len >= OUT_PATH_MAX - 64)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %.64s...: path too long", dir);
    memcpy(norm, dir, len + 1);
    while (len > 1 && norm[len - 1] == '/')
        norm[--len] = '\0';
    char *slash = strrchr(norm, '/');
    const char *b = slash ? slash + 1 : norm;
    if (strcmp(norm, "/") == 0 || strcmp(b, ".") == 0 || strcmp(b, "..") == 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--out %s: name a directory of its own (not /, . or ..)", dir);
    if (strlen(b) >= OUT_NAME_MAX * 2)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %s: name too long", dir);
    strcpy(base, b);
    if (!slash)
        strcpy(parent, ".");
    else if (slash == norm)
        strcpy(parent, "/");
    else {
        memcpy(parent, norm, (size_t)(slash - norm));
        parent[slash - norm] = '\0';
    }
    return SUNMC_OK;
}

/* 1 when directory path is empty or holds the sunmc marker. */
static int dir_replaceable(const char *path)
{
    DIR *d = opendir(path);
    if (!d)
        return 0;
    int empty = 1;
    struct dirent *e;
    while (empty && (e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0)
            empty = 0;
    closedir(d);
    if (empty)
        return 1;
    char m[OUT_PATH_MAX];
    struct stat st;
    snprintf(m, sizeof m, "%s/%s", path, OUT_MARKER);
    return lstat(m, &st) == 0 && S_ISREG(st.st_mode);
}

/* Create and remove a directory in dir: can we make entries there? */
static int probe_dir(const char *shown, const char *dir, char *err, size_t errlen)
{
    char probe[OUT_PATH_MAX];
    snprintf(probe, sizeof probe, "%s/.sunmc-probe.XXXXXX", dir);
    if (!mkdtemp(probe))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %s: cannot create anything in %s: %s",
                          shown, dir, strerror(errno));
    rmdir(probe);
    return SUNMC_OK;
}

/* The nearest existing ancestor of path (which does not exist) into anc. */
static int existing_ancestor(const char *shown, const char *path, char *anc, char *err,
                             size_t errlen)
{
    snprintf(anc, OUT_PATH_MAX, "%s", path);
    for (;;) {
        char *slash = strrchr(anc, '/');
        if (!slash)
            strcpy(anc, ".");
        else if (slash == anc)
            anc[1] = '\0';
        else
            *slash = '\0';
        struct stat st;
        if (stat(anc, &st) == 0) {
            if (!S_ISDIR(st.st_mode))
                return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %s: %s is not a directory",
                                  shown, anc);
            return SUNMC_OK;
        }
        if (errno != ENOENT)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %s: %s: %s", shown, anc,
                              strerror(errno));
        if (strcmp(anc, ".") == 0 || strcmp(anc, "/") == 0)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %s: no existing parent", shown);
    }
}

int out_check(const char *dir, char *err, size_t errlen)
{
    char norm[OUT_PATH_MAX], parent[OUT_PATH_MAX], base[OUT_NAME_MAX * 2];
    int st = split_dir(dir, norm, parent, base, err, errlen);
    if (st != SUNMC_OK)
        return st;
    struct stat sb;
    if (lstat(norm, &sb) == 0) {
        if (S_ISLNK(sb.st_mode))
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "--out %s: is a symbolic link; give the directory itself", dir);
        if (!S_ISDIR(sb.st_mode))
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "--out %s: exists and is not a directory", dir);
        if (!dir_replaceable(norm))
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "--out %s: the directory holds files sunmc did not write (no %s "
                              "marker); sunmc replaces its output directory whole, so give a "
                              "new or empty directory",
                              dir, OUT_MARKER);
        return probe_dir(dir, parent, err, errlen);
    }
    if (errno == ENOTDIR)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--out %s: a parent on the path is a file, not a directory", dir);
    if (errno != ENOENT)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %s: %s", dir, strerror(errno));
    char anc[OUT_PATH_MAX];
    if ((st = existing_ancestor(dir, norm, anc, err, errlen)) != SUNMC_OK)
        return st;
    return probe_dir(dir, anc, err, errlen);
}

int out_mkdirs(const char *dir, char *err, size_t errlen)
{
    char path[OUT_PATH_MAX];
    if (snprintf(path, sizeof path, "%s", dir) >= (int)sizeof path)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: path too long", dir);
    for (char *p = path + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(path, 0777) != 0 && errno != EEXIST)
            return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot create directory: %s", path,
                              strerror(errno));
        *p = '/';
    }
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot create directory: %s", path,
                          strerror(errno));
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: not a directory", path);
    return SUNMC_OK;
}

/* ---- writing ---- */

/* Record path for the signal handler, then create it. */
static FILE *guarded_fopen(const char *path)
{
    int i = guard_n;
    snprintf(guard_paths[i], OUT_PATH_MAX, "%s", path);
    guard_n = i + 1;
    return fopen(path, "w");
}

/* The temporary directory beside the target, with the usual permissions
 * (mkdtemp makes it private). */
static int make_tmpdir(out_set *o, const char *parent, const char *base, char *err,
                       size_t errlen)
{
    if (snprintf(o->tmpdir, OUT_PATH_MAX, "%s/.%s.tmp.XXXXXX", parent, base) >= OUT_PATH_MAX)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: path too long", o->dir);
    if (!mkdtemp(o->tmpdir)) {
        int e = errno;
        o->tmpdir[0] = '\0';
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot create a directory beside it: %s",
                          o->dir, strerror(e));
    }
    mode_t mask = umask(0);
    umask(mask);
    chmod(o->tmpdir, 0777 & ~mask);
    return SUNMC_OK;
}

int out_begin(out_set *o, const char *dir, char *err, size_t errlen)
{
    memset(o, 0, sizeof *o);
    if (atomic_load(&guard_state) != GUARD_IDLE)
        return sunmc_fail(err, errlen, SUNMC_EIO, "internal: an output set is already open");
    char parent[OUT_PATH_MAX], base[OUT_NAME_MAX * 2];
    int st = split_dir(dir, o->dir, parent, base, err, errlen);
    if (st == SUNMC_OK)
        st = out_mkdirs(parent, err, errlen);
    if (st == SUNMC_OK)
        st = make_tmpdir(o, parent, base, err, errlen);
    if (st != SUNMC_OK)
        return st;
    snprintf(guard_tmpdir, sizeof guard_tmpdir, "%s", o->tmpdir);
    guard_n = 0;
    guard_install();
    atomic_store(&guard_state, GUARD_WRITING);

    char marker[OUT_PATH_MAX];
    FILE *f = NULL;
    if (snprintf(marker, sizeof marker, "%s/%s", o->tmpdir, OUT_MARKER) < (int)sizeof marker)
        f = guarded_fopen(marker);
    int bad = !f || fputs(OUT_MARKER_TEXT, f) == EOF;
    if ((f && fclose(f) != 0) || bad) {
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot write: %s", marker, strerror(errno));
        out_abort(o);
    }
    return st;
}

int out_open(out_set *o, const char *name, FILE **f, char *err, size_t errlen)
{
    if (!o->tmpdir[0])
        return sunmc_fail(err, errlen, SUNMC_EIO, "internal: output set not begun");
    if (o->n >= OUT_MAX_FILES)
        return sunmc_fail(err, errlen, SUNMC_EIO, "too many output files");
    if (strlen(name) >= OUT_NAME_MAX || strchr(name, '/') || strcmp(name, OUT_MARKER) == 0)
        return sunmc_fail(err, errlen, SUNMC_EIO, "internal: bad output file name '%s'", name);
    char path[OUT_PATH_MAX];
    if (snprintf(path, sizeof path, "%s/%s", o->tmpdir, name) >= (int)sizeof path)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s/%s: path too long", o->dir, name);
    int i = o->n;
    o->f[i] = guarded_fopen(path);
    if (!o->f[i])
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s/%s: cannot write: %s", o->dir, name,
                          strerror(errno));
    snprintf(o->name[i], OUT_NAME_MAX, "%s", name);
    o->n++;
    *f = o->f[i];
    return SUNMC_OK;
}

int out_open_all(out_set *o, const char *const *names, FILE **files, int n, char *err,
                 size_t errlen)
{
    int st = SUNMC_OK;
    for (int k = 0; k < n && st == SUNMC_OK; k++)
        st = out_open(o, names[k], &files[k], err, errlen);
    return st;
}

/* Flush, sync and close every stream; the first write error is the status. */
static int close_all(out_set *o, char *err, size_t errlen)
{
    int status = SUNMC_OK;
    for (int i = 0; i < o->n; i++) {
        FILE *f = o->f[i];
        if (!f)
            continue;
        int e = 0, earlier = ferror(f);
        if (fflush(f) != 0)
            e = errno;
        else if (fsync(fileno(f)) != 0 && errno != EINVAL)
            e = errno;
        if (fclose(f) != 0 && !e)
            e = errno;
        o->f[i] = NULL;
        if ((e || earlier) && status == SUNMC_OK)
            status = sunmc_fail(err, errlen, SUNMC_EIO, "%s/%s: write error: %s", o->dir,
                                o->name[i], e ? strerror(e) : "disk full or I/O error");
    }
    return status;
}

/* Remove a directory tree (the old output directory). */
static int remove_tree(const char *path)
{
    DIR *d = opendir(path);
    if (!d)
        return -1;
    int bad = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        char sub[OUT_PATH_MAX];
        struct stat st;
        if (snprintf(sub, sizeof sub, "%s/%s", path, e->d_name) >= (int)sizeof sub ||
            lstat(sub, &st) != 0) {
            bad = 1;
            continue;
        }
        if (S_ISDIR(st.st_mode) ? remove_tree(sub) != 0 : unlink(sub) != 0)
            bad = 1;
    }
    closedir(d);
    return (rmdir(path) != 0 || bad) ? -1 : 0;
}

/* Move an existing target aside, the new directory into place, and remove
 * the old one. */
static int swap_into_place(out_set *o, char *err, size_t errlen)
{
    char aside[OUT_PATH_MAX] = "";
    struct stat sb;
    if (lstat(o->dir, &sb) == 0) {
        if (!S_ISDIR(sb.st_mode) || !dir_replaceable(o->dir))
            return sunmc_fail(err, errlen, SUNMC_EIO,
                              "%s: changed while sunmc ran (no longer empty or a sunmc output "
                              "directory): nothing written",
                              o->dir);
        char parent[OUT_PATH_MAX], base[OUT_NAME_MAX * 2], norm[OUT_PATH_MAX];
        split_dir(o->dir, norm, parent, base, NULL, 0);
        if (snprintf(aside, sizeof aside, "%s/.%s.old.XXXXXX", parent, base) >= (int)sizeof aside ||
            !mkdtemp(aside))
            return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot make room beside it: %s", o->dir,
                              strerror(errno));
        if (rename(o->dir, aside) != 0) {
            int e = errno;
            rmdir(aside);
            return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot move the old directory aside: %s",
                              o->dir, strerror(e));
        }
    } else if (errno != ENOENT) {
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", o->dir, strerror(errno));
    }
    if (rename(o->tmpdir, o->dir) != 0) {
        int e = errno;
        if (aside[0])
            rename(aside, o->dir);
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot move the new files into place: %s",
                          o->dir, strerror(e));
    }
    o->tmpdir[0] = '\0';
    if (aside[0] && remove_tree(aside) != 0)
        return sunmc_fail(err, errlen, SUNMC_EIO,
                          "%s: written, but the previous contents (moved to %s) could not be "
                          "removed",
                          o->dir, aside);
    return SUNMC_OK;
}

int out_commit(out_set *o, char *err, size_t errlen)
{
    int status = close_all(o, err, errlen);
    if (status != SUNMC_OK) {
        out_abort(o);
        return status;
    }
    if (!guard_take())
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: interrupted: nothing written", o->dir);
    status = swap_into_place(o, err, errlen);
    if (o->tmpdir[0])
        remove_tree(o->tmpdir);
    o->tmpdir[0] = '\0';
    o->n = 0;
    guard_release();
    return status;
}

void out_abort(out_set *o)
{
    for (int i = 0; i < o->n; i++) {
        if (o->f[i])
            fclose(o->f[i]);
        o->f[i] = NULL;
    }
    o->n = 0;
    if (!o->tmpdir[0] || !guard_take())
        return;
    remove_tree(o->tmpdir);
    o->tmpdir[0] = '\0';
    guard_release();
}
