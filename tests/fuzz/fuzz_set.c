/* fuzz_set.c - libFuzzer harness: the command line's --set overrides.
 * The input is split at newlines into up to 16 "section.key=value"
 * strings (NUL bytes end a string early, as argv would), applied to the
 * shipped ESS or DSS config as the first byte picks. */
#include "fuzz_util.h"

#include "config.h"
#include "status.h"

#include <stdlib.h>
#include <string.h>

#define FUZZ_MAX_SETS 16

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    static const char *const configs[] = {"configs/ess_type_a.ini", "configs/dss.ini", NULL};
    const char *config = configs[data[0] % 3];
    char *text = malloc(size);
    if (!text)
        return 0;
    memcpy(text, data + 1, size - 1);
    text[size - 1] = '\0';
    const char *sets[FUZZ_MAX_SETS];
    int n = 0;
    for (char *p = text, *nl; n < FUZZ_MAX_SETS && p < text + size - 1; p = nl + 1) {
        nl = memchr(p, '\n', (size_t)(text + size - 1 - p));
        if (!nl)
            nl = text + size - 1;
        *nl = '\0';
        sets[n++] = p;
    }
    char err[SUNMC_ERRLEN];
    config_state st;
    if (config_build(&st, config, sets, n, err, sizeof err) == SUNMC_OK)
        config_state_free(&st);
    free(text);
    return 0;
}
