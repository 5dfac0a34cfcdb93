/* outlock.c - one live command per output directory (outlock.h). */
#include "outlock.h"
#include "output.h"
#include "status.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

/* Tries to open a lock file that its holder removed meanwhile. */
#define LOCK_TRIES 8
/* Parent directories made for the lock file (and removed at the end). */
#define LOCK_MADE_MAX 16

static int lock_fd = -1;
static char lock_path[OUT_PATH_MAX];
static char lock_made[LOCK_MADE_MAX][OUT_PATH_MAX];
static int lock_n_made;

/* The lock file of dir (PARENT/.NAME.lock) into path, its parent into parent. */
static int lock_file_of(const char *dir, char *path, char *parent, char *err, size_t errlen)
{
    char norm[OUT_PATH_MAX];
    size_t len = strlen(dir);
    if (len == 0 || len >= sizeof norm - 64)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %.64s: not a directory name", dir);
    memcpy(norm, dir, len + 1);
    while (len > 1 && norm[len - 1] == '/')
        norm[--len] = '\0';
    char *slash = strrchr(norm, '/');
    const char *base = slash ? slash + 1 : norm;
    if (!slash)
        strcpy(parent, ".");
    else if (slash == norm)
        strcpy(parent, "/");
    else
        snprintf(parent, OUT_PATH_MAX, "%.*s", (int)(slash - norm), norm);
    if (snprintf(path, OUT_PATH_MAX, "%s/.%s%s", parent, base, OUT_LOCK_SUFFIX) >= OUT_PATH_MAX)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %.64s...: path too long", dir);
    return SUNMC_OK;
}

/* mkdir -p parent, recording each directory made (deepest last). */
static int make_parents(const char *parent, char *err, size_t errlen)
{
    char p[OUT_PATH_MAX];
    snprintf(p, sizeof p, "%s", parent);
    for (char *s = p + 1;; s++) {
        if (*s != '/' && *s != '\0')
            continue;
        char c = *s;
        *s = '\0';
        if (mkdir(p, 0777) == 0 && lock_n_made < LOCK_MADE_MAX)
            snprintf(lock_made[lock_n_made++], OUT_PATH_MAX, "%s", p);
        else if (errno != EEXIST)
            return sunmc_fail(err, errlen, SUNMC_EIO, "--out: cannot create %s: %s", p,
                              strerror(errno));
        *s = c;
        if (c == '\0')
            return SUNMC_OK;
    }
}

/* The PID written in the lock file fd (0 when none yet). */
static long holder_pid(int fd)
{
    char text[32] = "";
    ssize_t n = pread(fd, text, sizeof text - 1, 0);
    long pid = 0;
    if (n > 0) {
        text[n] = '\0';
        if (sscanf(text, "%ld", &pid) != 1)
            pid = 0;
    }
    return pid;
}

/* 1 when fd is still the file at path (its holder did not remove it). */
static int still_there(int fd, const char *path)
{
    struct stat a, b;
    return fstat(fd, &a) == 0 && stat(path, &b) == 0 && a.st_ino == b.st_ino &&
           a.st_dev == b.st_dev;
}

static int refuse_busy(const char *dir, int fd, char *err, size_t errlen)
{
    long pid = holder_pid(fd);
    char who[48] = "another sunmc";
    if (pid > 0)
        snprintf(who, sizeof who, "another sunmc (PID %ld)", pid);
    return sunmc_fail(err, errlen, SUNMC_EINPUT,
                      "--out %s: %s is writing it (lock %s); wait for it to end, or give "
                      "another --out",
                      dir, who, lock_path);
}

int out_lock(const char *dir, char *err, size_t errlen)
{
    if (lock_fd >= 0)
        return SUNMC_OK;
    char parent[OUT_PATH_MAX];
    int st = lock_file_of(dir, lock_path, parent, err, errlen);
    if (st == SUNMC_OK && access(parent, F_OK) != 0)
        st = make_parents(parent, err, errlen);
    for (int t = 0; st == SUNMC_OK && t < LOCK_TRIES; t++) {
        int fd = open(lock_path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0)
            return sunmc_fail(err, errlen, SUNMC_EIO, "--out %s: cannot create the lock %s: %s",
                              dir, lock_path, strerror(errno));
        if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
            st = errno == EWOULDBLOCK ? refuse_busy(dir, fd, err, errlen)
                                      : sunmc_fail(err, errlen, SUNMC_EIO,
                                                   "--out %s: cannot lock %s: %s", dir,
                                                   lock_path, strerror(errno));
            close(fd);
            break;
        }
        if (!still_there(fd, lock_path)) { /* its holder removed it as we opened it */
            close(fd);
            continue;
        }
        char pid[32];
        int n = snprintf(pid, sizeof pid, "%ld\n", (long)getpid());
        if (ftruncate(fd, 0) != 0 || pwrite(fd, pid, (size_t)n, 0) != n) {
            /* a full disk: the lock holds all the same, the PID is unknown */
        }
        lock_fd = fd;
        return SUNMC_OK;
    }
    if (st == SUNMC_OK)
        st = sunmc_fail(err, errlen, SUNMC_EIO, "--out %s: the lock %s keeps changing", dir,
                        lock_path);
    lock_path[0] = '\0';
    for (int i = lock_n_made - 1; i >= 0; i--)
        rmdir(lock_made[i]);
    lock_n_made = 0;
    return st;
}

void out_unlock(void)
{
    if (lock_fd >= 0) {
        unlink(lock_path); /* still holding it: no one else has it open locked */
        close(lock_fd);
    }
    lock_fd = -1;
    lock_path[0] = '\0';
    for (int i = lock_n_made - 1; i >= 0; i--)
        rmdir(lock_made[i]); /* fails, leaving it, when a run put files there */
    lock_n_made = 0;
}

void out_lock_drop_on_signal(void)
{
    if (lock_fd >= 0)
        unlink(lock_path);
}
