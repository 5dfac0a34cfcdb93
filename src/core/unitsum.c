/* unitsum.c - checksums of units.bin records (FNV-1a 64, leaves and nodes). */
#include "unitsum.h"
#include "params_io.h"
#include "status.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

void unitsum_init(unitsum_acc *a, long leaf_units)
{
    memset(a, 0, sizeof *a);
    a->leaf_units = leaf_units > 0 ? leaf_units : 1;
    a->cur = PARAMS_FNV1A64_INIT;
}

int unitsum_add(unitsum_acc *a, const void *record, size_t bytes)
{
    if (a->n + 1 >= a->cap) {
        long cap = a->cap ? 2 * a->cap : 64;
        unsigned long long *p = realloc(a->leaf, (size_t)cap * sizeof *p);
        if (!p)
            return SUNMC_ENOMEM;
        a->leaf = p;
        a->cap = cap;
    }
    a->cur = params_fnv1a64(a->cur, record, bytes);
    if (++a->in_leaf == a->leaf_units) {
        a->leaf[a->n++] = a->cur;
        a->cur = PARAMS_FNV1A64_INIT;
        a->in_leaf = 0;
    }
    return SUNMC_OK;
}

const unsigned long long *unitsum_leaves(unitsum_acc *a, long *n)
{
    *n = a->n;
    if (a->in_leaf > 0 && a->leaf) {
        a->leaf[a->n] = a->cur;
        (*n)++;
    }
    return a->leaf;
}

/* One level up, in place: n nodes become (n + 1) / 2. */
static long reduce(unsigned long long *h, long n)
{
    long m = 0;
    for (long i = 0; i < n; i += 2) {
        unsigned long long pair[2] = {h[i], i + 1 < n ? h[i + 1] : 0};
        h[m++] = i + 1 < n ? params_fnv1a64(PARAMS_FNV1A64_INIT, pair, sizeof pair) : h[i];
    }
    return m;
}

void unitsum_finish(unitsum_acc *a, unsigned long long *out, int *nout, long *node_units)
{
    long n;
    unsigned long long *h = (unsigned long long *)unitsum_leaves(a, &n);
    long units = a->leaf_units;
    while (n > UNITSUM_MAX) {
        n = reduce(h, n);
        units *= 2;
    }
    for (long i = 0; i < n; i++)
        out[i] = h[i];
    *nout = (int)n;
    *node_units = units;
}

void unitsum_free(unitsum_acc *a)
{
    free(a->leaf);
    a->leaf = NULL;
    a->n = a->cap = 0;
}

/* The leaves of the records of [first, end) in f (after its header). */
static int file_leaves(FILE *f, const char *path, const unitfile_layout *l, long units,
                       unitsum_acc *a, char *err, size_t errlen)
{
    size_t bytes = (size_t)unitfile_record_bytes(l);
    unsigned char *rec = malloc(bytes);
    int st = rec ? SUNMC_OK : sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    for (long u = 0; st == SUNMC_OK && u < units; u++) {
        if (fread(rec, bytes, 1, f) != 1)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: truncated record (ends after %ld of its %ld records)",
                            path, u, units);
        else if (unitsum_add(a, rec, bytes) != SUNMC_OK)
            st = sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    }
    free(rec);
    return st;
}

int unitsum_verify(const char *path, const unitfile_layout *l, long first, long end,
                   long leaf_units, long node_units, const unsigned long long *want, long nwant,
                   const char *source, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s", path, strerror(errno));
    unitsum_acc a;
    unitsum_init(&a, leaf_units);
    int st = unitfile_read_header(f, path, l, err, errlen);
    if (st == SUNMC_OK)
        st = file_leaves(f, path, l, end - first, &a, err, errlen);
    fclose(f);
    long n = 0, units = leaf_units;
    unsigned long long *h = (unsigned long long *)unitsum_leaves(&a, &n);
    while (st == SUNMC_OK && units < node_units && n > 1) {
        n = reduce(h, n);
        units *= 2;
    }
    if (st == SUNMC_OK && (n != nwant || (units != node_units && n > 1)))
        st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                        "%s: %ld checksums of %ld units for units %ld:%ld do not fit the %ld of "
                        "%ld units in %s",
                        path, n, units, first, end, nwant, node_units, source);
    for (long i = 0; st == SUNMC_OK && i < n; i++)
        if (h[i] != want[i]) {
            long a0 = first + i * node_units, a1 = a0 + node_units < end ? a0 + node_units : end;
            st = sunmc_fail(err, errlen, SUNMC_EINPUT,
                            "%s: the records of units %ld:%ld do not match their checksum in %s "
                            "(a flipped bit or an edited file); refused",
                            path, a0, a1, source);
        }
    unitsum_free(&a);
    return st;
}

int unitsum_add_results(unitsum_acc *a, const unitfile_layout *l, const unit_result *r, long n)
{
    uint64_t w[UNITFILE_MAX_WORDS];
    for (long u = 0; u < n; u++) {
        unitfile_pack(l, &r[u], w);
        if (unitsum_add(a, w, (size_t)unitfile_record_bytes(l)) != SUNMC_OK)
            return SUNMC_ENOMEM;
    }
    return SUNMC_OK;
}
