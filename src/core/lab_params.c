/* lab_params.c - compensate's strict reading of a params.ini, the part
 * every family shares: version, [calibration] keys, model line against the
 * sections, [prior] keys (lab_params.h). */
#include "lab_params.h"
#include "status.h"
#include "suggest.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const lab_params_header_keys[] = {
    "sunmc_version", "sensor", "model", "data_file", "data_fnv1a64", "data_rows", "config",
    "residual_sigma_arcsec", "crossval_rms_arcsec"};
const int lab_params_n_header_keys =
    (int)(sizeof lab_params_header_keys / sizeof lab_params_header_keys[0]);

/* Hex digits of data_fnv1a64: a 64-bit hash written %016llx. */
#define LAB_FNV_HEX_DIGITS 16

int lab_version_parse(const char *s, long v[3])
{
    for (int k = 0; k < 3; k++) {
        int n = 0;
        long x = 0;
        for (; isdigit((unsigned char)s[n]); n++)
            x = 10 * x + (s[n] - '0');
        if (n == 0 || n > LAB_VERSION_MAX_DIGITS)
            return -1;
        v[k] = x;
        s += n;
        if (k < 2 && *s++ != '.')
            return -1;
    }
    return *s == '\0' ? 0 : -1;
}

int lab_params_version(const params_file *p, const char *mine, char *warn, size_t warnlen,
                       char *err, size_t errlen)
{
    if (warnlen)
        warn[0] = '\0';
    const params_entry *e = params_find(p, "calibration", "sunmc_version");
    if (!e)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s: missing key calibration.sunmc_version: every params.ini sunmc "
                          "calibrate writes names the version that wrote it; without it this "
                          "sunmc %s cannot tell whether it reads the file as it was meant",
                          p->path, mine);
    long v[3], me[3];
    if (lab_version_parse(e->value, v) != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: calibration.sunmc_version '%s' is not a version "
                          "MAJOR.MINOR.PATCH (e.g. %s)",
                          p->path, e->line, e->value, mine);
    if (lab_version_parse(mine, me) != 0)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "this build's version '%s' is malformed",
                          mine);
    if (v[0] > me[0])
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: written by sunmc %s, newer than this %s: a newer major version "
                          "may hold what this one would read otherwise; compensate with sunmc "
                          "%ld or later",
                          p->path, e->line, e->value, mine, v[0]);
    int newer = v[0] == me[0] && (v[1] > me[1] || (v[1] == me[1] && v[2] > me[2]));
    if (newer)
        snprintf(warn, warnlen,
                 "%s:%d: written by sunmc %s, newer than this %s: read as this version reads "
                 "it (the same major version; a key it does not know is refused)",
                 p->path, e->line, e->value, mine);
    return SUNMC_OK;
}

static int has_sig(const params_file *p, const lab_params_model *m)
{
    return m->sig_key && params_find(p, m->sig_section, m->sig_key);
}

/* Is word one of the blank-separated words of list? */
static int in_list(const char *word, const char *list)
{
    size_t n = strlen(word);
    for (const char *s = list; (s = strstr(s, word)) != NULL; s += n)
        if ((s == list || s[-1] == ' ') && (s[n] == ' ' || s[n] == '\0'))
            return 1;
    return 0;
}

/* Does m extend o (its file holds o's sections and signature too)? */
static int extends(const lab_params_model *m, const lab_params_model *o)
{
    return m->extends && strcmp(m->extends, o->name) == 0;
}

/* "a, b, c": the models' names. */
static void model_names(const lab_params_model *ms, char *buf, size_t len)
{
    size_t at = 0;
    buf[0] = '\0';
    for (int i = 0; ms[i].name && at < len; i++)
        at += (size_t)snprintf(buf + at, len - at, "%s%s", i ? ", " : "", ms[i].name);
}

int lab_params_model_of(const family_lab *lab, const params_file *p,
                        const lab_params_model **model, char *err, size_t errlen)
{
    const char *name;
    int st = params_get_text(p, "calibration", "model", &name, err, errlen);
    if (st != SUNMC_OK)
        return st;
    const params_entry *e = params_find(p, "calibration", "model");
    const lab_params_model *ms = lab->params_models, *m = NULL;
    for (int i = 0; ms[i].name && !m; i++)
        if (strcmp(ms[i].name, name) == 0)
            m = &ms[i];
    if (!m) {
        char names[256], hint[128];
        model_names(ms, names, sizeof names);
        suggest_hint(name, names, hint, sizeof hint);
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: model '%s' is not one this sensor's params.ini can hold (%s)%s",
                          p->path, e->line, name, names, hint);
    }
    for (int i = 0; ms[i].name; i++) {
        if (&ms[i] == m || !has_sig(p, &ms[i]) || extends(m, &ms[i]))
            continue;
        const params_entry *s = params_find(p, ms[i].sig_section, ms[i].sig_key);
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: model = %s, but the file holds the %s model (%s.%s at line %d)",
                          p->path, e->line, name, ms[i].name, ms[i].sig_section, ms[i].sig_key,
                          s->line);
    }
    if (m->sig_key && !has_sig(p, m))
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: model = %s, but the file has no %s.%s, which every %s "
                          "params.ini has: its sections hold another model",
                          p->path, e->line, name, m->sig_section, m->sig_key, name);
    *model = m;
    return SUNMC_OK;
}

/* Every entry in [calibration], [prior] or a section of m. */
static int check_sections(const params_file *p, const lab_params_model *m, char *err,
                          size_t errlen)
{
    char list[256], hint[128];
    snprintf(list, sizeof list, "calibration %s prior", m->sections);
    for (int i = 0; i < p->n; i++) {
        if (in_list(p->e[i].section, list))
            continue;
        suggest_hint(p->e[i].section, list, hint, sizeof hint);
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s:%d: unknown section [%s] (key %s): a %s params.ini has the "
                          "sections %s%s",
                          p->path, p->e[i].line, p->e[i].section, p->e[i].key, m->name, list,
                          hint);
    }
    return SUNMC_OK;
}

/* [calibration]: every key known, data_rows whole, data_fnv1a64 a hash. */
static int check_header(const params_file *p, char *err, size_t errlen)
{
    int st = params_check_keys(p, "calibration", lab_params_header_keys,
                               lab_params_n_header_keys, err, errlen);
    int rows = 0;
    if (st == SUNMC_OK && params_find(p, "calibration", "data_rows"))
        st = params_get_int(p, "calibration", "data_rows", &rows, err, errlen);
    if (st == SUNMC_OK && rows < 0)
        st = params_require(p, "calibration", "data_rows", 0, ">= 0", err, errlen);
    const params_entry *h = params_find(p, "calibration", "data_fnv1a64");
    if (st == SUNMC_OK && h) {
        int ok = strlen(h->value) == LAB_FNV_HEX_DIGITS;
        for (int k = 0; ok && h->value[k]; k++)
            ok = isxdigit((unsigned char)h->value[k]);
        st = params_require(p, "calibration", "data_fnv1a64", ok,
                            "16 hex digits (the FNV-1a 64 of the data file)", err, errlen);
    }
    return st;
}

/* [prior]: pilot_units (whole, >= 1) and NAME_mean, NAME_sigma (numbers)
 * for keys NAME of the model's sections. */
static int check_prior(const params_file *p, char *err, size_t errlen)
{
    enum { MAX = 2 * PARAMS_MAX_ENTRIES + 1 };
    static const char *const sfx[2] = {"_mean", "_sigma"};
    int any = 0;
    for (int i = 0; i < p->n; i++)
        any |= strcmp(p->e[i].section, "prior") == 0;
    if (!any)
        return SUNMC_OK;
    char(*buf)[PARAMS_KEY_MAX + 8] = malloc(MAX * sizeof *buf);
    const char **names = malloc(MAX * sizeof *names);
    if (!buf || !names) {
        free(buf);
        free(names);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "%s: out of memory", p->path);
    }
    int n = 0;
    names[n++] = "pilot_units";
    for (int i = 0; i < p->n; i++) {
        const char *s = p->e[i].section;
        if (strcmp(s, "prior") == 0 || strcmp(s, "calibration") == 0)
            continue;
        for (int k = 0; k < 2; k++, n++) {
            snprintf(buf[n], sizeof buf[n], "%s%s", p->e[i].key, sfx[k]);
            names[n] = buf[n];
        }
    }
    int st = params_check_keys(p, "prior", names, n, err, errlen);
    free(buf);
    free(names);
    int units = 1;
    if (st == SUNMC_OK && params_find(p, "prior", "pilot_units"))
        st = params_get_int(p, "prior", "pilot_units", &units, err, errlen);
    if (st == SUNMC_OK && units < 1)
        st = params_require(p, "prior", "pilot_units", 0, ">= 1", err, errlen);
    for (int i = 0; i < p->n && st == SUNMC_OK; i++) {
        double v;
        if (strcmp(p->e[i].section, "prior") == 0 && strcmp(p->e[i].key, "pilot_units") != 0)
            st = params_get_double(p, "prior", p->e[i].key, &v, err, errlen);
    }
    return st;
}

int lab_params_load(const family_lab *lab, const params_file *p, void *model, char *warn,
                    size_t warnlen, char *err, size_t errlen)
{
    const lab_params_model *m = NULL;
    int st = lab_params_version(p, SUNMC_VERSION, warn, warnlen, err, errlen);
    if (st == SUNMC_OK)
        st = check_header(p, err, errlen);
    if (st == SUNMC_OK && lab->params_models) {
        st = lab_params_model_of(lab, p, &m, err, errlen);
        if (st == SUNMC_OK)
            st = check_sections(p, m, err, errlen);
    }
    if (st == SUNMC_OK)
        st = lab->params_load(p, model, err, errlen);
    if (st == SUNMC_OK)
        st = check_prior(p, err, errlen);
    return st;
}
