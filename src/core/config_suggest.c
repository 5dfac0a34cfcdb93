/* config_suggest.c - "did you mean ...?" for a mistyped config key: the
 * nearest key of the config's family (of any family when it is not known
 * yet) by case-blind edit distance on its name, one more when it sits in
 * another section. */
#include "config.h"
#include "suggest.h"

#include <stdio.h>
#include <string.h>

void config_suggest(const struct sensor_family *fam, const char *section, const char *name,
                    char *buf, size_t len)
{
    const config_key *keys[CONFIG_KEYS_MAX];
    const struct sensor_family *owners[CONFIG_KEYS_MAX];
    size_t n = config_list_keys(fam, keys, owners, CONFIG_KEYS_MAX);
    const config_key *best = NULL;
    int best_d = SUGGEST_MAX_DISTANCE + 1;
    for (size_t i = 0; i < n; i++) {
        int d = suggest_distance(name, keys[i]->name) + (strcmp(section, keys[i]->section) != 0);
        if (d < best_d && 2 * d < (int)strlen(name)) {
            best = keys[i];
            best_d = d;
        }
    }
    if (best)
        snprintf(buf, len, " (did you mean %s.%s?)", best->section, best->name);
    else if (len)
        buf[0] = '\0';
}

void config_suggest_section(const char *section, char *buf, size_t len)
{
    const char *best = suggest_nearest(section, config_sections, config_section_count);
    if (best)
        snprintf(buf, len, " (did you mean [%s]?)", best);
    else if (len)
        buf[0] = '\0';
}
