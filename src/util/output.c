/* output.c - a command's output directory, written all or nothing: files go
 * to a temporary directory beside the target, which replaces the target
 * whole at the end (see output.h). */
#include "output.h"
#include "outlock.h"
#include "status.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#ifndef RENAME_EXCHANGE
#define RENAME_EXCHANGE (1 << 1)
#endif

#define OUT_MARKER_TEXT \
    "sunmc output directory: the next sunmc command writing here replaces it whole\n" \
    "(only while it holds nothing but the files listed below)\n"
/* Each file the command wrote is listed in the marker on a line of its own. */
#define OUT_MARKER_FILE "file\t"
/* Largest marker read back (a listing of OUT_MAX_FILES names). */
#define OUT_MARKER_READ_MAX 8192
/* Names of foreign entries shown in a message. */
#define OUT_FOREIGN_SHOWN 8

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
static char guard_note[OUT_NOTE_MAX]; /* written to stderr by the handler */

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
        out_lock_drop_on_signal();
        size_t len = strlen(guard_note);
        if (len && write(STDERR_FILENO, guard_note, len) < 0)
            guard_note[0] = '\0';
    } else if (expected == GUARD_MAIN) {
        guard_pending = sig;
        return;
    } else if (expected == GUARD_CLEANING) {
        return; /* another thread is cleaning up and ends the process */
    }
    sigaction(sig, &guard_default, NULL);
    raise(sig);
}

void out_signal_note(const char *note)
{
    snprintf(guard_note, sizeof guard_note, "%s", note ? note : "");
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
    guard_note[0] = '\0';
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

/* 1 when the marker text lists file name. */
static int marker_lists(const char *text, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = text; (p = strstr(p, OUT_MARKER_FILE)) != NULL; p++) {
        const char *q = p + strlen(OUT_MARKER_FILE);
        if ((p == text || p[-1] == '\n') && strncmp(q, name, n) == 0 && q[n] == '\n')
            return 1;
    }
    return 0;
}

/* The marker of directory path into text; 0 when it has none. */
static int marker_read(const char *path, char *text, size_t len)
{
    char m[OUT_PATH_MAX];
    struct stat st;
    snprintf(m, sizeof m, "%s/%s", path, OUT_MARKER);
    FILE *f = lstat(m, &st) == 0 && S_ISREG(st.st_mode) ? fopen(m, "r") : NULL;
    if (!f)
        return 0;
    size_t n = fread(text, 1, len - 1, f);
    text[n] = '\0';
    fclose(f);
    return 1;
}

/* The entries of directory path that sunmc did not write: not the marker,
 * not a file the marker lists (every entry when there is no marker).  Their
 * names into list ("a, b, ..."); the count, -1 when path cannot be read. */
static int foreign_entries(const char *path, char *list, size_t len, int *has_marker)
{
    static char text[OUT_MARKER_READ_MAX];
    *has_marker = marker_read(path, text, sizeof text);
    DIR *d = opendir(path);
    if (!d)
        return -1;
    int n = 0;
    size_t used = 0;
    if (len)
        list[0] = '\0';
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        const char *name = e->d_name;
        if (strcmp(name, ".") == 0 || strcmp(name, "..") == 0 ||
            (*has_marker && (strcmp(name, OUT_MARKER) == 0 || marker_lists(text, name))))
            continue;
        if (n < OUT_FOREIGN_SHOWN && used < len)
            used += (size_t)snprintf(list + used, len - used, "%s%s", n ? ", " : "", name);
        else if (n == OUT_FOREIGN_SHOWN && used < len)
            used += (size_t)snprintf(list + used, len - used, ", ...");
        n++;
    }
    closedir(d);
    return n;
}

/* 1 when directory path is empty or holds only what sunmc wrote there. */
static int dir_replaceable(const char *path)
{
    int marker;
    return foreign_entries(path, NULL, 0, &marker) == 0;
}

/* Refusal of an existing directory that holds files sunmc did not write. */
static int refuse_foreign(const char *dir, const char *norm, char *err, size_t errlen)
{
    char list[512];
    int marker;
    int n = foreign_entries(norm, list, sizeof list, &marker);
    if (n < 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %s: cannot read it: %s", dir,
                          strerror(errno));
    if (!marker)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--out %s: the directory holds files sunmc did not write (no %s "
                          "marker: %s); sunmc replaces its output directory whole, so give a "
                          "new or empty directory",
                          dir, OUT_MARKER, list);
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "--out %s: holds %d file%s sunmc did not write there (%s); sunmc replaces "
                      "its output directory whole, so move %s or give another --out",
                      dir, n, n == 1 ? "" : "s", list, n == 1 ? "it" : "them");
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
            return refuse_foreign(dir, norm, err, errlen);
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

int out_check_inputs(const char *dir, const char *const *inputs, int n, char *err,
                     size_t errlen)
{
    char rd[PATH_MAX], ri[PATH_MAX], list[512] = "";
    if (!realpath(dir, rd))
        return SUNMC_OK; /* a new directory holds nothing */
    size_t len = strlen(rd), used = 0;
    int hits = 0;
    for (int k = 0; k < n; k++) {
        if (!inputs[k] || !realpath(inputs[k], ri))
            continue;
        if (strncmp(ri, rd, len) != 0 || (ri[len] != '/' && ri[len] != '\0' && len > 1))
            continue;
        if (used < sizeof list)
            used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", hits ? ", " : "",
                                     inputs[k]);
        hits++;
    }
    if (hits)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "--out %s: holds %s of this command (%s); sunmc replaces its output "
                          "directory whole, so write to another directory",
                          dir, hits == 1 ? "an input" : "inputs", list);
    return SUNMC_OK;
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

static int remove_tree(const char *path);

/* "HOST-PID" of this process, naming its temporary and old directories
 * so that a later run can tell a dead run's litter from a live run's. */
static void owner_tag(char *buf, size_t len)
{
    char host[65] = "";
    if (gethostname(host, sizeof host - 1) != 0 || !host[0])
        strcpy(host, "host");
    host[strcspn(host, ".-/")] = '\0';
    snprintf(buf, len, "%.32s-%ld", host, (long)getpid());
}

/* 1 when a litter name's tag ("HOST-PID.XXXXXX") is of a process of this
 * host that no longer runs, or is of the older tagless form ("XXXXXX"). */
static int litter_dead(const char *tag)
{
    const char *dot = strrchr(tag, '.');
    if (!dot)
        return 1;
    char mine[96], host[96];
    owner_tag(mine, sizeof mine);
    size_t n = (size_t)(dot - tag);
    if (n >= sizeof host)
        return 0;
    memcpy(host, tag, n);
    host[n] = '\0';
    char *dash = strrchr(host, '-');
    if (!dash)
        return 0;
    long pid = strtol(dash + 1, NULL, 10);
    *dash = '\0';
    char *mdash = strrchr(mine, '-');
    *mdash = '\0';
    if (strcmp(host, mine) != 0 || pid <= 0)
        return 0;
    return kill((pid_t)pid, 0) != 0 && errno == ESRCH;
}

/* Clean up what a killed run into parent/base left: its temporary
 * directories are removed; an old directory moved aside is put back when
 * base is missing (a kill between two renames), else removed.  Live runs'
 * directories (this host, process still running) are left alone. */
static void clean_litter(const char *parent, const char *base)
{
    char tmp_pre[OUT_NAME_MAX * 2 + 8], old_pre[OUT_NAME_MAX * 2 + 8], target[OUT_PATH_MAX];
    snprintf(tmp_pre, sizeof tmp_pre, ".%s.tmp.", base);
    snprintf(old_pre, sizeof old_pre, ".%s.old.", base);
    if (snprintf(target, sizeof target, "%s/%s", parent, base) >= (int)sizeof target)
        return;
    DIR *d = opendir(parent);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        int is_tmp = strncmp(e->d_name, tmp_pre, strlen(tmp_pre)) == 0;
        int is_old = strncmp(e->d_name, old_pre, strlen(old_pre)) == 0;
        if (!is_tmp && !is_old)
            continue;
        if (!litter_dead(e->d_name + strlen(is_tmp ? tmp_pre : old_pre)))
            continue;
        char path[OUT_PATH_MAX];
        struct stat st;
        if (snprintf(path, sizeof path, "%s/%s", parent, e->d_name) >= (int)sizeof path)
            continue;
        if (is_old && lstat(target, &st) != 0 && errno == ENOENT && rename(path, target) == 0)
            continue;
        remove_tree(path);
    }
    closedir(d);
}

/* The temporary directory beside the target, with the usual permissions
 * (mkdtemp makes it private). */
static int make_tmpdir(out_set *o, const char *parent, const char *base, char *err,
                       size_t errlen)
{
    char tag[96];
    owner_tag(tag, sizeof tag);
    if (snprintf(o->tmpdir, OUT_PATH_MAX, "%s/.%s.tmp.%s.XXXXXX", parent, base, tag) >=
        OUT_PATH_MAX)
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
    if (st == SUNMC_OK) {
        clean_litter(parent, base);
        st = make_tmpdir(o, parent, base, err, errlen);
    }
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

/* Swap the new directory and the old target in one step (Linux
 * renameat2 RENAME_EXCHANGE): the target is never missing.  0 on success;
 * -1 where the file system cannot (the caller renames twice). */
static int exchange_dirs(const char *a, const char *b)
{
#ifdef SYS_renameat2
    return (int)syscall(SYS_renameat2, AT_FDCWD, a, AT_FDCWD, b, RENAME_EXCHANGE);
#else
    (void)a;
    (void)b;
    errno = ENOSYS;
    return -1;
#endif
}

/* Where exchange_dirs cannot: move the target aside, the new directory
 * into place.  A kill between the two renames leaves the old directory
 * aside, which the next run into the target puts back (clean_litter). */
static int rename_twice(out_set *o, char *aside, char *err, size_t errlen)
{
    char parent[OUT_PATH_MAX], base[OUT_NAME_MAX * 2], norm[OUT_PATH_MAX], tag[96];
    split_dir(o->dir, norm, parent, base, NULL, 0);
    owner_tag(tag, sizeof tag);
    if (snprintf(aside, OUT_PATH_MAX, "%s/.%s.old.%s.XXXXXX", parent, base, tag) >=
            OUT_PATH_MAX ||
        !mkdtemp(aside))
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot make room beside it: %s", o->dir,
                          strerror(errno));
    if (rename(o->dir, aside) != 0) {
        int e = errno;
        rmdir(aside);
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot move the old directory aside: %s",
                          o->dir, strerror(e));
    }
    if (rename(o->tmpdir, o->dir) != 0) {
        int e = errno;
        rename(aside, o->dir);
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot move the new files into place: %s",
                          o->dir, strerror(e));
    }
    o->tmpdir[0] = '\0';
    return SUNMC_OK;
}

/* Put the new directory in place of the target (exchanged with an existing
 * one, else renamed) and remove the old one. */
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
        if (exchange_dirs(o->tmpdir, o->dir) == 0) {
            snprintf(aside, sizeof aside, "%s", o->tmpdir); /* now holds the old files */
            o->tmpdir[0] = '\0';
        } else {
            int st = rename_twice(o, aside, err, errlen);
            if (st != SUNMC_OK)
                return st;
        }
    } else if (errno != ENOENT) {
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", o->dir, strerror(errno));
    } else if (rename(o->tmpdir, o->dir) != 0) {
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot move the new files into place: %s",
                          o->dir, strerror(errno));
    } else {
        o->tmpdir[0] = '\0';
    }
    if (aside[0] && remove_tree(aside) != 0)
        return sunmc_fail(err, errlen, SUNMC_EIO,
                          "%s: written, but the previous contents (moved to %s) could not be "
                          "removed",
                          o->dir, aside);
    return SUNMC_OK;
}

/* List the set's files in its marker, so that the next command may replace
 * them (and only them). */
static int marker_list_files(out_set *o, char *err, size_t errlen)
{
    char m[OUT_PATH_MAX];
    if (snprintf(m, sizeof m, "%s/%s", o->tmpdir, OUT_MARKER) >= (int)sizeof m)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: path too long", o->dir);
    FILE *f = fopen(m, "a");
    int bad = !f;
    for (int i = 0; f && i < o->n; i++)
        bad |= fprintf(f, OUT_MARKER_FILE "%s\n", o->name[i]) < 0;
    if (f) {
        bad |= fflush(f) != 0;
        bad |= fsync(fileno(f)) != 0 && errno != EINVAL;
        bad |= fclose(f) != 0;
    }
    return bad ? sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot write: %s", m, strerror(errno))
               : SUNMC_OK;
}

int out_commit(out_set *o, char *err, size_t errlen)
{
    int status = close_all(o, err, errlen);
    if (status == SUNMC_OK)
        status = marker_list_files(o, err, errlen);
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
