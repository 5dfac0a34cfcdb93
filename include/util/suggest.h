/* suggest.h - "did you mean ...?": the nearest of a set of names to a
 * mistyped one, by case-blind edit distance. */
#ifndef SUNMC_SUGGEST_H
#define SUNMC_SUGGEST_H

#include <stddef.h>

/* Longest name compared; longer names are never suggested. */
#define SUGGEST_NAME_MAX 64
/* Largest edit distance still offered as a suggestion. */
#define SUGGEST_MAX_DISTANCE 2

/* Edit distance of a and b ignoring case, a swap of two neighbouring
 * characters counting as one edit ("rnu" is one from "run"; optimal string
 * alignment); SUGGEST_NAME_MAX when either is SUGGEST_NAME_MAX long or
 * longer. */
int suggest_distance(const char *a, const char *b);

/* The name of names[n] nearest to word, when at most SUGGEST_MAX_DISTANCE
 * edits away and fewer than half the length of the longer of the two
 * ("rn" -> "run"); NULL otherwise. */
const char *suggest_nearest(const char *word, const char *const *names, size_t n);

/* " (did you mean NAME?)" for the nearest to word of the names in list
 * (separated by '|', ',' or blanks, as messages list choices), or "". */
void suggest_hint(const char *word, const char *list, char *buf, size_t len);

#endif
