/* shortest.h - a double as the shortest decimal text that reads back as the
 * same double (15, 16 or 17 significant digits): what sunmc writes wherever
 * a value is recorded or compared (config echoes, hashes, best.ini). */
#ifndef SUNMC_SHORTEST_H
#define SUNMC_SHORTEST_H

#include <stddef.h>

/* Longest text shortest_double writes, with its '\0'. */
#define SHORTEST_TEXT_MAX 32

/* v into buf ("%.15g" when that reads back as v, else 16, else 17
 * digits); returns the length written (as snprintf). */
int shortest_double(double v, char *buf, size_t len);

#endif
