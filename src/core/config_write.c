/* config_write.c - the effective config (`sunmc config`, config.ini) and the
 * commented reference of every key (configs/reference.ini). */
#include "config.h"
#include "ini.h"
#include "params_io.h"
#include "registry.h"
#include "status.h"

#include <ctype.h>
#include <string.h>


int config_write(FILE *f, const config_state *st)
{
    const sunmc_config *c = &st->cfg;
    const char *cur = "";
    char buf[INI_LINE_MAX];
    fprintf(f, "# sunmc effective configuration (%s); the comment names each value's origin\n",
            c->family->name);
    for (size_t i = 0; i < st->n_keys; i++) {
        const config_key *k = st->keys[i];
        if (strcmp(cur, k->section) != 0) {
            fprintf(f, "\n[%s]\n", k->section);
            cur = k->section;
        }
        config_format_value(k, c, buf, sizeof buf);
        if (st->origins)
            fprintf(f, "%s = %s  # %s\n", k->name, buf, st->origins[i].origin);
        else
            fprintf(f, "%s = %s\n", k->name, buf);
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}

unsigned long long config_hash(const config_state *st)
{
    static const char *const skip[] = {"units", "threads", "block_units"};
    unsigned long long h = PARAMS_FNV1A64_INIT;
    char buf[INI_LINE_MAX], line[INI_LINE_MAX + 2 * CONFIG_STR_MAX];
    for (size_t i = 0; i < st->n_keys; i++) {
        const config_key *k = st->keys[i];
        int skipped = 0;
        for (size_t j = 0; j < sizeof skip / sizeof skip[0]; j++)
            skipped |= strcmp(k->section, "run") == 0 && strcmp(k->name, skip[j]) == 0;
        if (skipped)
            continue;
        config_format_value(k, &st->cfg, buf, sizeof buf);
        int n = snprintf(line, sizeof line, "%s.%s=%s\n", k->section, k->name, buf);
        h = params_fnv1a64(h, line, (size_t)n < sizeof line ? (size_t)n : sizeof line - 1);
    }
    return h;
}

void config_key_help(const config_key *k, char *buf, size_t len)
{
    if (k->type != KEY_FAMILY) {
        snprintf(buf, len, "%s", k->help);
        return;
    }
    /* "sensor family: a (its description), b (...) or c (...)" */
    int n = sensor_family_count();
    size_t used = (size_t)snprintf(buf, len, "%s:", k->help);
    for (int i = 0; i < n && used < len; i++) {
        const sensor_family *f = sensor_family_at(i);
        const char *sep = i == 0 ? " " : i == n - 1 ? " or " : ", ";
        used += (size_t)snprintf(buf + used, len - used, "%s%s (%s)", sep, f->name, f->description);
    }
}

/* "ESS" for the family named "ess". */
static void upper_name(const sensor_family *f, char *buf, size_t len)
{
    size_t i = 0;
    for (; f->name[i] && i + 1 < len; i++)
        buf[i] = (char)toupper((unsigned char)f->name[i]);
    buf[i] = '\0';
}

static void write_reference_header(FILE *f)
{
    char first[CONFIG_STR_MAX], others[256] = "", up[CONFIG_STR_MAX];
    size_t used = 0;
    upper_name(sensor_family_at(0), first, sizeof first);
    for (int i = 1; i < sensor_family_count() && used < sizeof others; i++) {
        upper_name(sensor_family_at(i), up, sizeof up);
        used += (size_t)snprintf(others + used, sizeof others - used, "%s%s", i > 1 ? " or " : "",
                                 up);
    }
    fprintf(f,
            "# sunmc reference configuration: every key, generated from the key table\n"
            "# (`sunmc config --reference`).  Values shown are the %s defaults; where the\n"
            "# %s default differs it is given in the comment.  Units are in the key names.\n"
            "# Tolerances: KEY = magnitude and KEY_dist = fixed|uniform|normal|truncnormal\n"
            "# (uniform: +-magnitude; normal, truncnormal: sigma = magnitude).\n",
            first, others);
}

/* "#   families: ...; allowed: ...[; F default: X]..." for key k of owner
 * (NULL: a shared key, every family's). */
static void write_reference_scope(FILE *f, const config_key *k, const sensor_family *owner)
{
    char r[128];
    config_range_text(k, r, sizeof r);
    fprintf(f, "#   families: ");
    if (owner)
        fprintf(f, "%s", owner->name);
    else
        for (int i = 0, shown = 0; i < sensor_family_count(); i++)
            if (!config_family_omits(sensor_family_at(i), k))
                fprintf(f, "%s%s", shown++ ? ", " : "", sensor_family_at(i)->name);
    fprintf(f, "; allowed: %s", r);
    if (!owner && k->type != KEY_FAMILY) {
        const char *shown = config_key_default(k, NULL);
        for (int i = 1; i < sensor_family_count(); i++) {
            if (config_family_omits(sensor_family_at(i), k))
                continue;
            const char *d = config_key_default(k, sensor_family_at(i));
            if (strcmp(d, shown) != 0)
                fprintf(f, "; %s default: %s", sensor_family_at(i)->name, d);
        }
    }
    fputc('\n', f);
}

int config_write_reference(FILE *f)
{
    const config_key *keys[CONFIG_KEYS_MAX];
    const sensor_family *owners[CONFIG_KEYS_MAX];
    size_t n = config_list_keys(NULL, keys, owners, CONFIG_KEYS_MAX);
    const char *cur = "";
    char help[512];
    write_reference_header(f);
    for (size_t i = 0; i < n; i++) {
        const config_key *k = keys[i];
        if (strcmp(cur, k->section) != 0) {
            fprintf(f, "\n[%s]\n", k->section);
            cur = k->section;
        }
        config_key_help(k, help, sizeof help);
        fprintf(f, "# %s\n", help);
        write_reference_scope(f, k, owners[i]);
        fprintf(f, "# %s = %s\n", k->name,
                config_key_default(k, owners[i] ? owners[i] : NULL));
    }
    return ferror(f) ? SUNMC_EIO : SUNMC_OK;
}
