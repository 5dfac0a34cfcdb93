/* merge.c - shard directories checked to be parts of one run. */
#include "merge.h"
#include "status.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int by_first(const void *a, const void *b)
{
    const merge_shard *x = a, *y = b;
    return (x->m.first > y->m.first) - (x->m.first < y->m.first);
}

/* The same directory given twice (by any path)? */
static int same_dir(const char *a, const char *b)
{
    char ra[PATH_MAX], rb[PATH_MAX];
    return realpath(a, ra) && realpath(b, rb) && strcmp(ra, rb) == 0;
}

/* Shards sorted by first unit: each starts where the one before ends. */
static int check_tiling(const merge_shard *s, int n, char *err, size_t errlen)
{
    for (int i = 1; i < n; i++) {
        const merge_shard *p = &s[i - 1], *q = &s[i];
        if (same_dir(p->dir, q->dir))
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s and %s are the same directory (units %ld:%ld twice)", p->dir,
                              q->dir, q->m.first, q->m.end);
        if (q->m.first > p->m.end)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "units %ld:%ld are missing: %s ends at %ld, %s starts at %ld",
                              p->m.end, q->m.first, p->dir, p->m.end, q->dir, q->m.first);
        if (q->m.first < p->m.end)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "units %ld:%ld are in both %s and %s",
                              q->m.first, p->m.end < q->m.end ? p->m.end : q->m.end, p->dir,
                              q->dir);
    }
    return SUNMC_OK;
}

/* A config.ini line without its origin comment and end of line. */
static void strip_origin(char *line)
{
    char *c = strstr(line, "  #");
    if (c)
        *c = '\0';
    line[strcspn(line, "\n")] = '\0';
}

/* The first key whose value differs between a/config.ini and b/config.ini,
 * as " (first difference: [section] key = va against vb)"; "" if none. */
static void first_config_difference(const char *a, const char *b, char *buf, size_t len)
{
    char pa[PATH_MAX], pb[PATH_MAX], la[1024], lb[1024], section[128] = "";
    snprintf(pa, sizeof pa, "%s/config.ini", a);
    snprintf(pb, sizeof pb, "%s/config.ini", b);
    FILE *fa = fopen(pa, "r"), *fb = fopen(pb, "r");
    buf[0] = '\0';
    while (fa && fb && fgets(la, sizeof la, fa) && fgets(lb, sizeof lb, fb)) {
        strip_origin(la);
        strip_origin(lb);
        if (la[0] == '[')
            snprintf(section, sizeof section, "%.127s", la);
        if (la[0] != '#' && strcmp(la, lb) != 0) {
            snprintf(buf, len, " (first difference: %.100s %.160s against %.160s)", section, la, lb);
            break;
        }
    }
    if (fa)
        fclose(fa);
    if (fb)
        fclose(fb);
}

int merge_plan(const char *const *dirs, int n, merge_shard *shards, char *err, size_t errlen)
{
    char path[PATH_MAX];
    if (n < 1)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "no shard directory to merge");
    for (int i = 0; i < n; i++) {
        shards[i].dir = dirs[i];
        snprintf(path, sizeof path, "%s/%s", dirs[i], MANIFEST_NAME);
        int st = manifest_read(path, &shards[i].m, err, errlen);
        if (st != SUNMC_OK)
            return st;
        if (i > 0 && (st = manifest_compatible(&shards[0].m, shards[0].dir, &shards[i].m, dirs[i],
                                               err, errlen)) != SUNMC_OK) {
            char diff[512];
            size_t used = strlen(err);
            first_config_difference(shards[0].dir, dirs[i], diff, sizeof diff);
            if (shards[0].m.config_hash != shards[i].m.config_hash && used < errlen)
                snprintf(err + used, errlen - used, "%s", diff);
            return st;
        }
    }
    qsort(shards, (size_t)n, sizeof *shards, by_first);
    return check_tiling(shards, n, err, errlen);
}
