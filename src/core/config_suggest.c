/* config_suggest.c - "did you mean ...?" for a mistyped config key: the
 * nearest key of any family by case-blind edit distance on its name, one
 * more when it sits in another section. */
#include "config.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

/* Largest edit distance still offered as a suggestion. */
#define SUGGEST_MAX_DISTANCE 2
#define SUGGEST_NAME_MAX 64

/* Levenshtein distance of a and b ignoring case (both shorter than
 * SUGGEST_NAME_MAX; longer names are never suggested). */
static int distance_ci(const char *a, const char *b)
{
    size_t na = strlen(a), nb = strlen(b);
    if (na >= SUGGEST_NAME_MAX || nb >= SUGGEST_NAME_MAX)
        return SUGGEST_NAME_MAX;
    int prev[SUGGEST_NAME_MAX + 1], cur[SUGGEST_NAME_MAX + 1];
    for (size_t j = 0; j <= nb; j++)
        prev[j] = (int)j;
    for (size_t i = 1; i <= na; i++) {
        cur[0] = (int)i;
        for (size_t j = 1; j <= nb; j++) {
            int same = tolower((unsigned char)a[i - 1]) == tolower((unsigned char)b[j - 1]);
            int best = prev[j - 1] + !same;
            if (prev[j] + 1 < best)
                best = prev[j] + 1;
            if (cur[j - 1] + 1 < best)
                best = cur[j - 1] + 1;
            cur[j] = best;
        }
        memcpy(prev, cur, sizeof cur);
    }
    return prev[nb];
}

void config_suggest(const char *section, const char *name, char *buf, size_t len)
{
    const config_key *keys[CONFIG_KEYS_MAX];
    const struct sensor_family *owners[CONFIG_KEYS_MAX];
    size_t n = config_list_keys(NULL, keys, owners, CONFIG_KEYS_MAX);
    const config_key *best = NULL;
    int best_d = SUGGEST_MAX_DISTANCE + 1;
    for (size_t i = 0; i < n; i++) {
        int d = distance_ci(name, keys[i]->name) + (strcmp(section, keys[i]->section) != 0);
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
