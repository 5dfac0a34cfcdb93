/* suggest.c - the nearest name to a mistyped one (suggest.h). */
#include "suggest.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

/* 1 when a[0..1] is b[0..1] with its two characters swapped ("nu", "un"). */
static int swapped(const char *a, const char *b)
{
    return tolower((unsigned char)a[0]) == tolower((unsigned char)b[1]) &&
           tolower((unsigned char)a[1]) == tolower((unsigned char)b[0]);
}

int suggest_distance(const char *a, const char *b)
{
    size_t na = strlen(a), nb = strlen(b);
    if (na >= SUGGEST_NAME_MAX || nb >= SUGGEST_NAME_MAX)
        return SUGGEST_NAME_MAX;
    /* rows i-2, i-1 and i of the table (a swap looks two rows back) */
    int prev2[SUGGEST_NAME_MAX + 1] = {0}, prev[SUGGEST_NAME_MAX + 1], cur[SUGGEST_NAME_MAX + 1];
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
            if (i > 1 && j > 1 && swapped(a + i - 2, b + j - 2) && prev2[j - 2] + 1 < best)
                best = prev2[j - 2] + 1;
            cur[j] = best;
        }
        memcpy(prev2, prev, sizeof prev);
        memcpy(prev, cur, sizeof cur);
    }
    return prev[nb];
}

const char *suggest_nearest(const char *word, const char *const *names, size_t n)
{
    const char *best = NULL;
    int best_d = SUGGEST_MAX_DISTANCE + 1;
    for (size_t i = 0; i < n; i++) {
        int d = suggest_distance(word, names[i]);
        size_t longer = strlen(word) > strlen(names[i]) ? strlen(word) : strlen(names[i]);
        if (d < best_d && 2 * d < (int)longer) {
            best = names[i];
            best_d = d;
        }
    }
    return best;
}

void suggest_hint(const char *word, const char *list, char *buf, size_t len)
{
    char copy[512], *names[64], *save = NULL;
    size_t n = 0;
    snprintf(copy, sizeof copy, "%s", list);
    for (char *t = strtok_r(copy, "|, ", &save); t && n < 64; t = strtok_r(NULL, "|, ", &save))
        if (strcmp(t, "or") != 0)
            names[n++] = t;
    const char *near = suggest_nearest(word, (const char *const *)names, n);
    if (near && len > 0)
        snprintf(buf, len, " (did you mean %s?)", near);
    else if (len > 0)
        buf[0] = '\0';
}
