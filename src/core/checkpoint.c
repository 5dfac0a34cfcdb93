/* checkpoint.c - completed blocks of a run, committed atomically, for
 * run --resume. */
#include "checkpoint.h"
#include "params_io.h"
#include "unitsum.h"
#include "status.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define PROGRESS_NAME "progress"
#define SUM_LINE_BYTES 17 /* "%016llx\n" */

int checkpoint_path(const char *out, char *buf, size_t len)
{
    char norm[PATH_MAX];
    size_t n = strlen(out);
    while (n > 1 && out[n - 1] == '/')
        n--;
    if (n >= sizeof norm)
        return SUNMC_EINPUT;
    memcpy(norm, out, n);
    norm[n] = '\0';
    const char *slash = strrchr(norm, '/');
    int w = slash ? snprintf(buf, len, "%.*s/.%s.resume", (int)(slash - norm), norm, slash + 1)
                  : snprintf(buf, len, ".%s.resume", norm);
    return w > 0 && (size_t)w < len ? SUNMC_OK : SUNMC_EINPUT;
}

static void join(char *buf, size_t len, const char *dir, const char *name)
{
    snprintf(buf, len, "%s/%s", dir, name);
}

void checkpoint_units_path(const checkpoint *k, char *buf, size_t len)
{
    join(buf, len, k->dir, UNITFILE_NAME);
}

static int sync_dir(const char *dir)
{
    int fd = open(dir, O_RDONLY | O_DIRECTORY);
    if (fd < 0)
        return -1;
    int r = fsync(fd);
    close(fd);
    return r;
}

/* Write the progress file atomically: temporary, sync, rename, sync dir. */
static int write_progress(const checkpoint *k, char *err, size_t errlen)
{
    char tmp[PATH_MAX + 16], path[PATH_MAX + 16];
    join(tmp, sizeof tmp, k->dir, PROGRESS_NAME ".tmp");
    join(path, sizeof path, k->dir, PROGRESS_NAME);
    FILE *f = fopen(tmp, "w");
    int ok = f && fprintf(f, "units_done %ld\nblock_units %ld\n", k->done, k->block_units) > 0 &&
             fflush(f) == 0 && fsync(fileno(f)) == 0;
    if (f && fclose(f) != 0)
        ok = 0;
    if (!ok || rename(tmp, path) != 0 || sync_dir(k->dir) != 0)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: cannot write the checkpoint: %s", path,
                          strerror(errno));
    return SUNMC_OK;
}

static int write_manifest(const char *dir, const run_manifest *m, char *err, size_t errlen)
{
    char path[PATH_MAX + 16];
    join(path, sizeof path, dir, MANIFEST_NAME);
    FILE *f = fopen(path, "w");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", path, strerror(errno));
    int st = manifest_write(f, m, err, errlen);
    if ((fflush(f) != 0 || fsync(fileno(f)) != 0) && st == SUNMC_OK)
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", path, strerror(errno));
    fclose(f);
    return st;
}

void checkpoint_remove(const char *out, long *removed_units)
{
    char dir[PATH_MAX], path[PATH_MAX + 16];
    if (removed_units)
        *removed_units = -1;
    if (checkpoint_path(out, dir, sizeof dir) != SUNMC_OK)
        return;
    join(path, sizeof path, dir, PROGRESS_NAME);
    FILE *f = fopen(path, "r");
    if (f) {
        long done = 0;
        if (removed_units && fscanf(f, "units_done %ld", &done) == 1)
            *removed_units = done;
        fclose(f);
    }
    static const char *const names[] = {PROGRESS_NAME, PROGRESS_NAME ".tmp", MANIFEST_NAME,
                                        UNITFILE_NAME, UNITSUM_NAME};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        join(path, sizeof path, dir, names[i]);
        unlink(path);
    }
    rmdir(dir);
}

int checkpoint_create(checkpoint *k, const char *out, const run_manifest *m, long block_units,
                      const unitfile_layout *l, char *err, size_t errlen)
{
    char path[PATH_MAX + 16];
    memset(k, 0, sizeof *k);
    if (checkpoint_path(out, k->dir, sizeof k->dir) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %s: path too long", out);
    checkpoint_remove(out, NULL);
    k->layout = *l;
    k->first = m->first;
    k->block_units = block_units;
    if (mkdir(k->dir, 0777) != 0)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", k->dir, strerror(errno));
    run_manifest mk = *m; /* the checksums are in units.sum, a block each */
    mk.sum_units = block_units;
    mk.nsum = 0;
    int st = write_manifest(k->dir, &mk, err, errlen);
    checkpoint_units_path(k, path, sizeof path);
    if (st == SUNMC_OK && !(k->bin = fopen(path, "wb")))
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", path, strerror(errno));
    join(path, sizeof path, k->dir, UNITSUM_NAME);
    if (st == SUNMC_OK && !(k->sum = fopen(path, "w")))
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", path, strerror(errno));
    if (st == SUNMC_OK)
        st = unitfile_write_header(k->bin, l, err, errlen);
    if (st == SUNMC_OK)
        st = checkpoint_append(k, NULL, 0, err, errlen);
    if (st != SUNMC_OK)
        checkpoint_close(k);
    return st;
}

/* The progress file's counts; SUNMC_EINPUT when unreadable. */
static int read_progress(const char *dir, long *done, long *block_units, char *err, size_t errlen)
{
    char path[PATH_MAX + 16];
    join(path, sizeof path, dir, PROGRESS_NAME);
    FILE *f = fopen(path, "r");
    int n = f ? fscanf(f, "units_done %ld\nblock_units %ld", done, block_units) : 0;
    if (f)
        fclose(f);
    if (n != 2 || *done < 0 || *block_units < 1)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: not a checkpoint's progress file "
                          "(remove %s to start over)", path, dir);
    return SUNMC_OK;
}

/* The checkpoint run_manifest ck against this run's m. */
static int same_run(const checkpoint *k, const run_manifest *ck, const run_manifest *m,
                    long ck_block, char *err, size_t errlen)
{
    char here[64];
    snprintf(here, sizeof here, "this run");
    int st = manifest_compatible(ck, k->dir, m, here, err, errlen);
    if (st == SUNMC_OK && (ck->first != m->first || ck->end != m->end))
        st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s is of units %ld:%ld, this run of %ld:%ld",
                        k->dir, ck->first, ck->end, m->first, m->end);
    if (st == SUNMC_OK && ck_block != k->block_units)
        st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                        "%s ran blocks of %ld units, this run of %ld (run.block_units)", k->dir,
                        ck_block, k->block_units);
    return st;
}

/* The checksums of units.sum for the k->done committed units: *n of them
 * into a new array (NULL and SUNMC_EINPUT when there are fewer). */
static unsigned long long *read_sums(checkpoint *k, const char *path, long *n, char *err,
                                     size_t errlen)
{
    *n = (k->done + k->block_units - 1) / k->block_units;
    unsigned long long *h = malloc((size_t)(*n > 0 ? *n : 1) * sizeof *h);
    FILE *f = fopen(path, "r");
    long i = 0;
    char line[SUM_LINE_BYTES + 2];
    while (h && f && i < *n && fgets(line, sizeof line, f) && strlen(line) == SUM_LINE_BYTES &&
           sscanf(line, "%16llx", &h[i]) == 1)
        i++;
    if (f)
        fclose(f);
    if (h && i == *n)
        return h;
    free(h);
    sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: holds %ld of the %ld block checksums its progress "
               "file needs (remove %s to start over)", path, i, *n, k->dir);
    return NULL;
}

/* Every committed block against its checksum; units.sum then appends. */
static int check_sums(checkpoint *k, const run_manifest *m, char *err, size_t errlen)
{
    char path[PATH_MAX + 16], bin[PATH_MAX + 16], hint[2 * PATH_MAX + 64];
    join(path, sizeof path, k->dir, UNITSUM_NAME);
    checkpoint_units_path(k, bin, sizeof bin);
    long n = 0;
    unsigned long long *h = read_sums(k, path, &n, err, errlen);
    if (!h)
        return SUNMC_EINPUT;
    int st = unitsum_verify(bin, &k->layout, m->first, m->first + k->done, k->block_units,
                            k->block_units, h, n, path, hint, sizeof hint);
    free(h);
    if (st != SUNMC_OK)
        return sunmc_fail(err, errlen, st, "%s (remove %s to start over)", hint, k->dir);
    if (st == SUNMC_OK && (truncate(path, (off_t)n * SUM_LINE_BYTES) != 0 ||
                           !(k->sum = fopen(path, "a"))))
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", path, strerror(errno));
    return st;
}

int checkpoint_open(checkpoint *k, const char *out, const run_manifest *m, long block_units,
                    const unitfile_layout *l, int *found, char *err, size_t errlen)
{
    char path[PATH_MAX + 16];
    struct stat sb;
    memset(k, 0, sizeof *k);
    *found = 0;
    if (checkpoint_path(out, k->dir, sizeof k->dir) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "--out %s: path too long", out);
    if (stat(k->dir, &sb) != 0)
        return SUNMC_OK;
    /* Killed before its first commit (no progress file): a checkpoint of
     * 0 units, whatever else it holds; started afresh. */
    join(path, sizeof path, k->dir, PROGRESS_NAME);
    if (stat(path, &sb) != 0 && errno == ENOENT) {
        checkpoint_remove(out, NULL);
        return SUNMC_OK;
    }
    *found = 1;
    k->layout = *l;
    k->first = m->first;
    k->block_units = block_units;
    run_manifest ck;
    long ck_block = 0;
    join(path, sizeof path, k->dir, MANIFEST_NAME);
    int st = manifest_read(path, &ck, err, errlen);
    if (st == SUNMC_OK)
        st = read_progress(k->dir, &k->done, &ck_block, err, errlen);
    if (st == SUNMC_OK)
        st = same_run(k, &ck, m, ck_block, err, errlen);
    if (st != SUNMC_OK)
        return st;
    /* Records past the committed count are a block cut short: dropped. */
    checkpoint_units_path(k, path, sizeof path);
    off_t size = unitfile_header_bytes() + (off_t)k->done * unitfile_record_bytes(l);
    if (stat(path, &sb) != 0 || sb.st_size < size)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: holds fewer than the %ld units its "
                          "progress file counts (remove %s to start over)", path, k->done, k->dir);
    if (truncate(path, size) != 0 || !(k->bin = fopen(path, "ab")))
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", path, strerror(errno));
    return check_sums(k, m, err, errlen);
}

/* The block's checksum, a line of units.sum, synced. */
static int append_sum(checkpoint *k, const unit_result *r, long n, char *err, size_t errlen)
{
    uint64_t w[UNITFILE_MAX_WORDS];
    unsigned long long h = PARAMS_FNV1A64_INIT;
    for (long u = 0; u < n; u++) {
        unitfile_pack(&k->layout, &r[u], w);
        h = params_fnv1a64(h, w, (size_t)unitfile_record_bytes(&k->layout));
    }
    if (fprintf(k->sum, "%016llx\n", h) != SUM_LINE_BYTES || fflush(k->sum) != 0 ||
        fsync(fileno(k->sum)) != 0)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s/%s: %s", k->dir, UNITSUM_NAME,
                          strerror(errno));
    return SUNMC_OK;
}

int checkpoint_append(checkpoint *k, const unit_result *r, long n, char *err, size_t errlen)
{
    char path[PATH_MAX + 16];
    checkpoint_units_path(k, path, sizeof path);
    int st = n > 0 ? unitfile_write(k->bin, &k->layout, r, n, err, errlen) : SUNMC_OK;
    if (st == SUNMC_OK && (fflush(k->bin) != 0 || fsync(fileno(k->bin)) != 0))
        st = sunmc_fail(err, errlen, SUNMC_EIO, "%s: %s", path, strerror(errno));
    if (st == SUNMC_OK && n > 0)
        st = append_sum(k, r, n, err, errlen);
    if (st != SUNMC_OK)
        return st;
    k->done += n;
    return write_progress(k, err, errlen);
}

void checkpoint_close(checkpoint *k)
{
    if (k->bin)
        fclose(k->bin);
    if (k->sum)
        fclose(k->sum);
    k->bin = NULL;
    k->sum = NULL;
}
