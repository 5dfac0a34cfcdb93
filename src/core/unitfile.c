/* unitfile.c - units.bin (per-unit results, lossless) and manifest.ini. */
#include "unitfile.h"
#include "thermal.h"
#include "vmath.h"
#include "ini.h"
#include "status.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* 2: the verdict's statistic, points read and band points (verdict.h) */
#define UNITFILE_MAGIC "SUNMCUB3"
#define UNITFILE_ORDER 0x0102030405060708ULL
#define UNITFILE_INT_WORDS 7

void unitfile_layout_of(const sunmc_config *c, unitfile_layout *l)
{
    const sensor_family *fam = c->family;
    const char *names[UNIT_MAX_PAR];
    l->nd = fam->dev_columns(c, names, UNIT_MAX_DEV);
    l->np = fam->par_columns(c, names, UNIT_MAX_PAR);
    l->na = fam->n_angles(c);
    l->nb = c->bands_deg.n;
    l->nt = thermal_n_temps(c);
    l->words = UNITFILE_INT_WORDS + l->nd + l->np + 1 + (4L + 2L * l->nt) * l->na * l->nb + l->nb +
               2L * (1L + l->nt) * l->na * l->nb;
}

long unitfile_header_bytes(void)
{
    return UNITFILE_HEADER_WORDS * 8;
}

long unitfile_record_bytes(const unitfile_layout *l)
{
    return l->words * 8;
}

int unitfile_write_header(FILE *f, const unitfile_layout *l, char *err, size_t errlen)
{
    uint64_t w[UNITFILE_HEADER_WORDS] = {0, UNITFILE_ORDER, (uint64_t)l->words, (uint64_t)l->nd,
                                         (uint64_t)l->np, (uint64_t)l->na, (uint64_t)l->nb,
                                         (uint64_t)l->nt};
    memcpy(&w[0], UNITFILE_MAGIC, 8);
    if (fwrite(w, sizeof w, 1, f) != 1)
        return sunmc_fail(err, errlen, SUNMC_EIO, "%s: write error: %s", UNITFILE_NAME,
                          strerror(errno));
    return SUNMC_OK;
}

/* The verdict's cells (after the RMS cells): the band points, then per
 * set (the lab's, each temperature) the statistic and the points read,
 * every angle and band, as doubles (the counts exactly). */
static void pack_verdict(const unitfile_layout *l, const unit_result *r, double *d)
{
    for (int b = 0; b < l->nb; b++)
        *d++ = r->points[b];
    for (int t = -1; t < l->nt; t++)
        for (int a = 0; a < l->na; a++)
            for (int b = 0; b < l->nb; b++) {
                *d++ = t < 0 ? r->stat_after[a][b] : r->stat_after_t[t][a][b];
                *d++ = t < 0 ? r->read_after[a][b] : r->read_after_t[t][a][b];
            }
}

static void unpack_verdict(const unitfile_layout *l, const double *d, unit_result *r)
{
    for (int b = 0; b < l->nb; b++)
        r->points[b] = (int)*d++;
    for (int t = -1; t < l->nt; t++)
        for (int a = 0; a < l->na; a++)
            for (int b = 0; b < l->nb; b++) {
                double s = *d++, n = *d++;
                if (t < 0) {
                    r->stat_after[a][b] = s;
                    r->read_after[a][b] = (int)n;
                } else {
                    r->stat_after_t[t][a][b] = s;
                    r->read_after_t[t][a][b] = (int)n;
                }
            }
}

/* One record into w (words): the integers, then the doubles in order. */
void unitfile_pack(const unitfile_layout *l, const unit_result *r, uint64_t *w)
{
    int64_t ints[UNITFILE_INT_WORDS] = {r->unit,        r->fit_status, r->fit_gsl_status,
                                        r->fit_iterations, r->alias_weak, r->gross_cal,
                                        r->gross_val};
    memcpy(w, ints, sizeof ints);
    double *d = (double *)(void *)(w + UNITFILE_INT_WORDS);
    memcpy(d, r->dev, (size_t)l->nd * sizeof *d);
    d += l->nd;
    memcpy(d, r->par, (size_t)l->np * sizeof *d);
    d += l->np;
    *d++ = r->fit_rms;
    const double(*m[4])[CONFIG_BANDS_MAX] = {r->rms_before, r->rms_after, r->rms_after_sys,
                                             r->rms_after_mf};
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < l->na; a++) {
            memcpy(d, m[k][a], (size_t)l->nb * sizeof *d);
            d += l->nb;
        }
    for (int t = 0; t < l->nt; t++)
        for (int k = 0; k < 2; k++)
            for (int a = 0; a < l->na; a++) {
                memcpy(d, k == 0 ? r->rms_before_t[t][a] : r->rms_after_t[t][a],
                       (size_t)l->nb * sizeof *d);
                d += l->nb;
            }
    pack_verdict(l, r, d);
}

static void unpack(const unitfile_layout *l, const uint64_t *w, unit_result *r)
{
    int64_t ints[UNITFILE_INT_WORDS];
    memset(r, 0, sizeof *r);
    memcpy(ints, w, sizeof ints);
    r->unit = (long)ints[0];
    r->fit_status = (int)ints[1];
    r->fit_gsl_status = (int)ints[2];
    r->fit_iterations = (int)ints[3];
    r->alias_weak = (int)ints[4];
    r->gross_cal = (int)ints[5];
    r->gross_val = (int)ints[6];
    const double *d = (const double *)(const void *)(w + UNITFILE_INT_WORDS);
    memcpy(r->dev, d, (size_t)l->nd * sizeof *d);
    d += l->nd;
    memcpy(r->par, d, (size_t)l->np * sizeof *d);
    d += l->np;
    r->fit_rms = *d++;
    double(*m[4])[CONFIG_BANDS_MAX] = {r->rms_before, r->rms_after, r->rms_after_sys,
                                       r->rms_after_mf};
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < l->na; a++) {
            memcpy(m[k][a], d, (size_t)l->nb * sizeof *d);
            d += l->nb;
        }
    for (int t = 0; t < l->nt; t++)
        for (int k = 0; k < 2; k++)
            for (int a = 0; a < l->na; a++) {
                memcpy(k == 0 ? r->rms_before_t[t][a] : r->rms_after_t[t][a], d,
                       (size_t)l->nb * sizeof *d);
                d += l->nb;
            }
    unpack_verdict(l, d, r);
}

int unitfile_write(FILE *f, const unitfile_layout *l, const unit_result *r, long n, char *err,
                   size_t errlen)
{
    uint64_t w[UNITFILE_MAX_WORDS];
    for (long u = 0; u < n; u++) {
        unitfile_pack(l, &r[u], w);
        if (fwrite(w, 8, (size_t)l->words, f) != (size_t)l->words)
            return sunmc_fail(err, errlen, SUNMC_EIO, "%s: write error: %s", UNITFILE_NAME,
                              strerror(errno));
    }
    return SUNMC_OK;
}

int unitfile_read_header(FILE *f, const char *path, const unitfile_layout *l, char *err,
                         size_t errlen)
{
    uint64_t w[UNITFILE_HEADER_WORDS];
    if (fread(w, sizeof w, 1, f) != 1 || memcmp(&w[0], UNITFILE_MAGIC, 8) != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: not a sunmc units file (no %s header)",
                          path, UNITFILE_MAGIC);
    /* word 8: the operating temperatures, 0 without them (thermal.h) */
    if (w[7] != 0 && (l->nt == 0 || w[7] > UNIT_MAX_TEMPS))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: header word 8 is not zero (a flipped "
                          "bit or an edited file, or a run with operating temperatures)", path);
    if (w[1] != UNITFILE_ORDER)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: written on a machine of another byte order", path);
    uint64_t want[6] = {(uint64_t)l->words, (uint64_t)l->nd, (uint64_t)l->np, (uint64_t)l->na,
                        (uint64_t)l->nb, (uint64_t)l->nt};
    if (memcmp(&w[2], want, sizeof want) != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: records of %llu words (%llu deviations, %llu parameters, %llu "
                          "angles, %llu bands, %llu operating temperatures); this config's have "
                          "%ld (%d, %d, %d, %d, %d)",
                          path, (unsigned long long)w[2], (unsigned long long)w[3],
                          (unsigned long long)w[4], (unsigned long long)w[5],
                          (unsigned long long)w[6], (unsigned long long)w[7], l->words, l->nd,
                          l->np, l->na, l->nb, l->nt);
    return SUNMC_OK;
}

int unitfile_read(FILE *f, const char *path, const unitfile_layout *l, unit_result *r, long max,
                  long *got, char *err, size_t errlen)
{
    uint64_t w[UNITFILE_MAX_WORDS];
    *got = 0;
    while (*got < max) {
        size_t k = fread(w, 8, (size_t)l->words, f);
        if (k == 0 && !ferror(f))
            break;
        if (k != (size_t)l->words)
            return sunmc_fail(err, errlen, ferror(f) ? SUNMC_EIO : SUNMC_EINPUT,
                              "%s: %s after %ld records of this block", path,
                              ferror(f) ? strerror(errno) : "truncated record", *got);
        unpack(l, w, &r[(*got)++]);
    }
    return SUNMC_OK;
}

/* ---- manifest.ini ---- */

void manifest_of(const config_state *st, long first, long end, run_manifest *m)
{
    memset(m, 0, sizeof *m);
    m->format = MANIFEST_FORMAT;
    snprintf(m->version, sizeof m->version, "%s", SUNMC_VERSION);
    snprintf(m->family, sizeof m->family, "%s", st->cfg.family->name);
    m->config_hash = config_hash(st);
    m->seed = st->cfg.seed;
    m->first = first;
    m->end = end;
    snprintf(m->isa, sizeof m->isa, "%s", vm_isa());
    snprintf(m->build, sizeof m->build, "%s", vm_build_id());
}

int manifest_write(FILE *f, const run_manifest *m, char *err, size_t errlen)
{
    fprintf(f,
            "# sunmc run manifest: what `sunmc merge` and `run --resume` check\n"
            "[manifest]\nformat = %d\nsunmc_version = %s\nfamily = %s\nconfig_fnv1a64 = %016llx\n"
            "seed = %ld\nfirst_unit = %ld\nend_unit = %ld\nunits_file = %s\nkernel_isa = %s\n"
            "build = %s\nunits_sum_units = %ld\nunits_fnv1a64 =",
            m->format, m->version, m->family, m->config_hash, m->seed, m->first, m->end,
            UNITFILE_NAME, m->isa, m->build, m->sum_units);
    for (int i = 0; i < m->nsum; i++)
        fprintf(f, " %016llx", m->sum[i]);
    fputc('\n', f);
    return ferror(f) ? sunmc_fail(err, errlen, SUNMC_EIO, "%s: write error", MANIFEST_NAME)
                     : SUNMC_OK;
}

/* units_fnv1a64: up to MANIFEST_SUM_MAX hashes of 16 hex digits. */
static int manifest_sums(const ini_entry *e, const char *path, run_manifest *m, char *err,
                         size_t errlen)
{
    const char *p = e->value;
    m->nsum = 0;
    while (*p) {
        char *end;
        errno = 0;
        unsigned long long h = strtoull(p, &end, 16);
        if (end - p != 16 || errno || (*end && *end != ' ') || m->nsum == MANIFEST_SUM_MAX)
            return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: units_fnv1a64 = %s: not a list "
                              "of at most %d hashes of 16 hex digits", path, e->line, e->value,
                              MANIFEST_SUM_MAX);
        m->sum[m->nsum++] = h;
        p = *end ? end + 1 : end;
    }
    return SUNMC_OK;
}

/* One key of the manifest into m; bit `seen` of *mask marks it read. */
static int manifest_key(const ini_entry *e, const char *path, run_manifest *m, unsigned *mask,
                        char *err, size_t errlen)
{
    static const char *const keys[] = {"format",     "sunmc_version", "family",
                                       "config_fnv1a64", "seed",      "first_unit",
                                       "end_unit",   "units_file",    "kernel_isa",
                                       "build",      "units_sum_units", "units_fnv1a64"};
    int k = -1;
    for (int i = 0; i < 12; i++)
        if (strcmp(e->key, keys[i]) == 0)
            k = i;
    char *end = NULL;
    errno = 0;
    long v = k == 0 || (k >= 4 && k <= 6) || k == 10 ? strtol(e->value, &end, 10) : 0;
    if (k < 0 || strcmp(e->section, "manifest") != 0 ||
        (end && (end == e->value || *end != '\0' || errno || v < 0)))
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s:%d: unexpected %s.%s = %s", path, e->line,
                          e->section, e->key, e->value);
    *mask |= 1u << k;
    if (k == 0)
        m->format = (int)v;
    else if (k == 1)
        snprintf(m->version, sizeof m->version, "%.31s", e->value);
    else if (k == 2)
        snprintf(m->family, sizeof m->family, "%.*s", (int)sizeof m->family - 1, e->value);
    else if (k == 3)
        m->config_hash = strtoull(e->value, NULL, 16);
    else if (k == 4)
        m->seed = v;
    else if (k == 5)
        m->first = v;
    else if (k == 6)
        m->end = v;
    else if (k == 8)
        snprintf(m->isa, sizeof m->isa, "%.*s", (int)sizeof m->isa - 1, e->value);
    else if (k == 9)
        snprintf(m->build, sizeof m->build, "%.*s", (int)sizeof m->build - 1, e->value);
    else if (k == 10)
        m->sum_units = v;
    else if (k == 11)
        return manifest_sums(e, path, m, err, errlen);
    return SUNMC_OK;
}

int manifest_read(const char *path, run_manifest *m, char *err, size_t errlen)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s (not a sunmc run directory?)", path,
                          strerror(errno));
    memset(m, 0, sizeof *m);
    ini_reader r;
    ini_begin(&r, f, path);
    ini_entry e;
    int item, st;
    unsigned mask = 0;
    while ((st = ini_next(&r, &item, &e, err, errlen)) == SUNMC_OK && item != INI_END)
        if (item == INI_KEY && (st = manifest_key(&e, path, m, &mask, err, errlen)) != SUNMC_OK)
            break;
    ini_end(&r);
    fclose(f);
    if (st == SUNMC_OK && m->format != MANIFEST_FORMAT)
        st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: manifest format %d; this sunmc reads %d",
                        path, m->format, MANIFEST_FORMAT);
    if (st == SUNMC_OK && mask != 0xfffu)
        st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: incomplete manifest (keys missing)", path);
    if (st == SUNMC_OK && m->sum_units < 1)
        st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: units_sum_units = %ld: must be at least 1",
                        path, m->sum_units);
    if (st == SUNMC_OK && m->end <= m->first)
        st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: empty unit range %ld:%ld", path, m->first,
                        m->end);
    return st;
}

int manifest_compatible(const run_manifest *a, const char *a_name, const run_manifest *b,
                        const char *b_name, char *err, size_t errlen)
{
    const char *what = NULL;
    char va[64], vb[64];
    if (strcmp(a->version, b->version) != 0) {
        what = "sunmc version";
        snprintf(va, sizeof va, "%s", a->version);
        snprintf(vb, sizeof vb, "%s", b->version);
    } else if (strcmp(a->family, b->family) != 0) {
        what = "sensor family";
        snprintf(va, sizeof va, "%s", a->family);
        snprintf(vb, sizeof vb, "%s", b->family);
    } else if (a->seed != b->seed) {
        what = "seed";
        snprintf(va, sizeof va, "%ld", a->seed);
        snprintf(vb, sizeof vb, "%ld", b->seed);
    } else if (a->config_hash != b->config_hash) {
        what = "config (config_fnv1a64)";
        snprintf(va, sizeof va, "%016llx", a->config_hash);
        snprintf(vb, sizeof vb, "%016llx", b->config_hash);
    } else if (strcmp(a->isa, b->isa) != 0) {
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s and %s ran different kernel paths: kernel_isa %s against %s (their "
                          "last bits differ); run every part on one path: `sunmc run --isa "
                          "baseline` (or SUNMC_ISA=baseline) runs the baseline on every CPU",
                          a_name, b_name, a->isa, b->isa);
    } else if (strcmp(a->build, b->build) != 0) {
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s and %s are of different builds: build '%s' against '%s' (their "
                          "last bits may differ); run every part with one sunmc binary",
                          a_name, b_name, a->build, b->build);
    }
    if (!what)
        return SUNMC_OK;
    return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s and %s are of different runs: %s %s against %s",
                      a_name, b_name, what, va, vb);
}
