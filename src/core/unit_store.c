/* unit_store.c - units' validation readings kept between runs of configs
 * that share them (unit_store.h). */
#include "unit_store.h"
#include "family.h"
#include "rng.h"
#include "status.h"

#include <stdlib.h>
#include <string.h>

/* Slots start on this boundary (vector loads of the family's arrays). */
#define STORE_ALIGN 64
/* Longest formatted key value: a full list of shortest doubles. */
#define STORE_VALUE_TEXT (CONFIG_LIST_MAX * 32)

struct unit_store {
    sunmc_config cfg;     /* the config whose readings the slots hold */
    long capacity;
    size_t slot_bytes;    /* readings_bytes(cfg), rounded up to STORE_ALIGN */
    unsigned char *data;  /* capacity slots */
    long *unit;           /* unit whose readings slot i holds; -1: none */
    long reads;           /* units read into a slot */
};

static int splits(const sensor_family *fam)
{
    return fam->readings_bytes && fam->unit_read && fam->unit_finish;
}

/* 1 when key k is one whose value the family's readings ignore. */
static int ignored(const sensor_family *fam, const config_key *k)
{
    for (const char *const *n = fam->readings_ignore; n && *n; n++) {
        size_t ls = strlen(k->section);
        if (strcmp(*n, k->section) == 0 ||
            (strncmp(*n, k->section, ls) == 0 && (*n)[ls] == '.' && strcmp(*n + ls + 1, k->name) == 0))
            return 1;
    }
    return 0;
}

/* 1 when the readings of fam's units never draw from stream id: a noise
 * stream of the campaign alone (family_noise.campaign_only), or the stream
 * of a tolerance whose key the readings ignore. */
static int stream_unread(const sensor_family *fam, uint32_t id)
{
    for (const family_noise *nz = fam->noise; nz && nz->name; nz++)
        if (nz->stream == id)
            return nz->campaign_only;
    for (int e = 0; e < fam->n_deviations; e++) {
        const deviation_spec *d = &fam->deviations[e];
        if (RNG_STREAM_TOLERANCE + d->stream != id)
            continue;
        const config_key *k = config_find_in(fam, "tolerance", d->name);
        return k && ignored(fam, k);
    }
    return 0;
}

/* The pick-freeze streams of c that its readings draw from into out (in
 * c's order); their count. */
static int read_picks(const sunmc_config *c, uint32_t *out)
{
    int n = 0;
    for (int i = 0; i < c->pick.n; i++)
        if (!stream_unread(c->family, c->pick.stream[i]))
            out[n++] = c->pick.stream[i];
    return n;
}

/* The same streams of the readings taken from the same pick seed: a pick
 * of a stream only the campaign draws from changes no reading. */
static int same_pick(const sunmc_config *a, const sunmc_config *b)
{
    uint32_t sa[CONFIG_PICK_MAX], sb[CONFIG_PICK_MAX];
    int na = read_picks(a, sa), nb = read_picks(b, sb);
    if (na != nb || (na > 0 && a->pick.seed != b->pick.seed))
        return 0;
    for (int i = 0; i < na; i++)
        if (sa[i] != sb[i])
            return 0;
    return 1;
}

int unit_readings_same(const sunmc_config *a, const sunmc_config *b)
{
    const sensor_family *fam = a->family;
    if (fam != b->family || !splits(fam) || !same_pick(a, b))
        return 0;
    const config_key *keys[CONFIG_KEYS_MAX];
    const sensor_family *owners[CONFIG_KEYS_MAX];
    size_t n = config_list_keys(fam, keys, owners, CONFIG_KEYS_MAX);
    for (size_t i = 0; i < n; i++) {
        if (ignored(fam, keys[i]))
            continue;
        char va[STORE_VALUE_TEXT], vb[STORE_VALUE_TEXT];
        config_format_value(keys[i], a, va, sizeof va);
        config_format_value(keys[i], b, vb, sizeof vb);
        if (strcmp(va, vb) != 0)
            return 0;
    }
    return 1;
}

static size_t slot_bytes(const sunmc_config *c)
{
    size_t b = c->family->readings_bytes(c);
    return (b + STORE_ALIGN - 1) / STORE_ALIGN * STORE_ALIGN;
}

double unit_store_bytes(const sunmc_config *c, long capacity)
{
    if (!splits(c->family) || capacity <= 0)
        return 0.0;
    return (double)capacity * ((double)slot_bytes(c) + (double)sizeof(long));
}

int unit_store_alloc(const sunmc_config *c, long capacity, unit_store **out, char *err,
                     size_t errlen)
{
    *out = NULL;
    if (!splits(c->family) || capacity <= 0)
        return SUNMC_OK;
    unit_store *s = calloc(1, sizeof *s);
    if (s) {
        s->cfg = *c;
        s->capacity = capacity;
        s->slot_bytes = slot_bytes(c);
        s->data = aligned_alloc(STORE_ALIGN, (size_t)capacity * s->slot_bytes);
        s->unit = malloc((size_t)capacity * sizeof *s->unit);
    }
    if (!s || !s->data || !s->unit) {
        unit_store_free(s);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM,
                          "out of memory for the validation readings of %ld units (%.0f MB)",
                          capacity, unit_store_bytes(c, capacity) / 1e6);
    }
    for (long i = 0; i < capacity; i++)
        s->unit[i] = -1;
    *out = s;
    return SUNMC_OK;
}

int unit_store_alloc_upto(const sunmc_config *c, long capacity, double max_bytes,
                          unit_store **out, char *err, size_t errlen)
{
    *out = NULL;
    double bytes = unit_store_bytes(c, capacity);
    if (!(bytes > 0) || bytes > max_bytes)
        return SUNMC_OK;
    return unit_store_alloc(c, capacity, out, err, errlen);
}

void unit_store_free(unit_store *s)
{
    if (!s)
        return;
    free(s->data);
    free(s->unit);
    free(s);
}

static int fits(const unit_store *s, const sunmc_config *c, long first, long end)
{
    return s && splits(c->family) && end - first <= s->capacity && slot_bytes(c) <= s->slot_bytes;
}

int unit_store_serves(const unit_store *s, const sunmc_config *c, long first, long end)
{
    return fits(s, c, first, end) && unit_readings_same(&s->cfg, c);
}

int unit_store_bind(unit_store *s, const sunmc_config *c, long first, long end)
{
    if (!fits(s, c, first, end))
        return 0;
    if (!unit_readings_same(&s->cfg, c)) {
        s->cfg = *c;
        for (long i = 0; i < s->capacity; i++)
            s->unit[i] = -1;
    }
    return 1;
}

void *unit_store_slot(unit_store *s, long u, int *held)
{
    long i = u % s->capacity;
    *held = s->unit[i] == u;
    return s->data + (size_t)i * s->slot_bytes;
}

void unit_store_fill(unit_store *s, long u)
{
    s->unit[u % s->capacity] = u;
#pragma omp atomic
    s->reads++;
}

long unit_store_reads(const unit_store *s)
{
    return s ? s->reads : 0;
}
