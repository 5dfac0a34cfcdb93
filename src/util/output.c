/* output.c - temporary names, then rename: no partial output files. */
#include "output.h"
#include "status.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

int out_begin(out_set *o, const char *dir, char *err, size_t errlen)
{
    memset(o, 0, sizeof *o);
    return out_mkdirs(dir, err, errlen);
}

int out_open(out_set *o, const char *dir, const char *name, FILE **f, char *err, size_t errlen)
{
    if (o->n >= OUT_MAX_FILES)
        return sunmc_fail(err, errlen, SUNMC_EIO, "too many output files");
    int i = o->n;
    if (snprintf(o->final[i], OUT_PATH_MAX, "%s/%s", dir, name) >= OUT_PATH_MAX ||
        snprintf(o->tmp[i], OUT_PATH_MAX, "%s/.%s.tmp.%ld", dir, name, (long)getpid()) >=
            OUT_PATH_MAX)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s/%s: path too long", dir, name);
    o->f[i] = fopen(o->tmp[i], "w");
    if (!o->f[i])
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot write: %s", o->tmp[i],
                          strerror(errno));
    o->n++;
    *f = o->f[i];
    return SUNMC_OK;
}

int out_open_all(out_set *o, const char *dir, const char *const *names, FILE **files, int n,
                 char *err, size_t errlen)
{
    int st = SUNMC_OK;
    for (int k = 0; k < n && st == SUNMC_OK; k++)
        st = out_open(o, dir, names[k], &files[k], err, errlen);
    return st;
}

int out_commit(out_set *o, char *err, size_t errlen)
{
    int status = SUNMC_OK;
    for (int i = 0; i < o->n; i++) {
        if (!o->f[i])
            continue;
        int bad = ferror(o->f[i]);
        if (fclose(o->f[i]) != 0 || bad)
            if (status == SUNMC_OK)
                status = sunmc_fail(err, errlen, SUNMC_EIO, "%s: write error", o->final[i]);
        o->f[i] = NULL;
    }
    if (status != SUNMC_OK) {
        out_abort(o);
        return status;
    }
    for (int i = 0; i < o->n; i++)
        if (rename(o->tmp[i], o->final[i]) != 0) {
            status = sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot rename into place: %s",
                                o->final[i], strerror(errno));
            out_abort(o);
            return status;
        }
    o->n = 0;
    return SUNMC_OK;
}

void out_abort(out_set *o)
{
    for (int i = 0; i < o->n; i++) {
        if (o->f[i])
            fclose(o->f[i]);
        o->f[i] = NULL;
        unlink(o->tmp[i]);
    }
    o->n = 0;
}
