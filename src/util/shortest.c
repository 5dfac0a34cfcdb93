/* shortest.c - the shortest round-trip decimal text of a double. */
#include "shortest.h"

#include <stdio.h>
#include <stdlib.h>

int shortest_double(double v, char *buf, size_t len)
{
    char t[SHORTEST_TEXT_MAX];
    for (int digits = 15; digits < 17; digits++) {
        snprintf(t, sizeof t, "%.*g", digits, v);
        if (strtod(t, NULL) == v || v != v)
            return snprintf(buf, len, "%s", t);
    }
    return snprintf(buf, len, "%.17g", v);
}
