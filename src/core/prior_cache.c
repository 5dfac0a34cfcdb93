/* prior_cache.c - a process's priors' pilots, each made once (prior_cache.h). */
#include "prior_cache.h"
#include "status.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    unsigned char *key; /* the parts' bytes, concatenated */
    size_t bytes;
    calib_prior prior;
    int status;
    char err[SUNMC_ERRLEN];
} cache_entry;

static cache_entry cache[PRIOR_CACHE_SIZE];
static int cache_next; /* the entry the next keep replaces */

static size_t key_bytes(const prior_key_part *key, int n)
{
    size_t b = 0;
    for (int i = 0; i < n; i++)
        b += key[i].bytes;
    return b;
}

/* 1 when entry e holds exactly the bytes of key. */
static int entry_is(const cache_entry *e, const prior_key_part *key, int n, size_t bytes)
{
    if (!e->key || e->bytes != bytes)
        return 0;
    size_t off = 0;
    for (int i = 0; i < n; i++) {
        if (key[i].bytes && memcmp(e->key + off, key[i].p, key[i].bytes) != 0)
            return 0;
        off += key[i].bytes;
    }
    return 1;
}

int prior_cache_find(const prior_key_part *key, int n, calib_prior *p, int *status, char *err,
                     size_t errlen)
{
    size_t bytes = key_bytes(key, n);
    int found = 0;
#pragma omp critical(prior_cache)
    for (int k = 0; k < PRIOR_CACHE_SIZE && !found; k++)
        if (entry_is(&cache[k], key, n, bytes)) {
            *p = cache[k].prior;
            *status = cache[k].status;
            if (cache[k].status != SUNMC_OK && err && errlen)
                snprintf(err, errlen, "%s", cache[k].err);
            found = 1;
        }
    return found;
}

void prior_cache_keep(const prior_key_part *key, int n, const calib_prior *p, int status,
                      const char *err)
{
    if (status != SUNMC_OK && status != SUNMC_EINPUT)
        return;
    size_t bytes = key_bytes(key, n);
    unsigned char *copy = malloc(bytes ? bytes : 1);
    if (!copy)
        return;
    for (size_t off = 0, i = 0; i < (size_t)n; off += key[i].bytes, i++)
        if (key[i].bytes)
            memcpy(copy + off, key[i].p, key[i].bytes);
#pragma omp critical(prior_cache)
    {
        int have = 0;
        for (int k = 0; k < PRIOR_CACHE_SIZE && !have; k++)
            have = entry_is(&cache[k], key, n, bytes);
        if (have) {
            free(copy);
        } else {
            cache_entry *e = &cache[cache_next];
            cache_next = (cache_next + 1) % PRIOR_CACHE_SIZE;
            free(e->key);
            e->key = copy;
            e->bytes = bytes;
            e->prior = *p;
            e->status = status;
            snprintf(e->err, sizeof e->err, "%s", status == SUNMC_OK || !err ? "" : err);
        }
    }
}

int prior_cache_pilot(const prior_key_part *key, int n, calib_prior *p, prior_pilot_fn add,
                      void *ctx, char *err, size_t errlen)
{
    int st = SUNMC_OK;
    if (prior_cache_find(key, n, p, &st, NULL, 0))
        return SUNMC_OK;
    if ((st = add(ctx, p, err, errlen)) == SUNMC_OK)
        prior_cache_keep(key, n, p, SUNMC_OK, NULL);
    return st;
}

void prior_cache_clear(void)
{
#pragma omp critical(prior_cache)
    {
        for (int k = 0; k < PRIOR_CACHE_SIZE; k++) {
            free(cache[k].key);
            cache[k].key = NULL;
            cache[k].bytes = 0;
        }
        cache_next = 0;
    }
}
