/* fuzz_config.c - libFuzzer harness: any bytes as a config file
 * (config_build: the INI lexer, the key tables, values, cross-key checks),
 * and the effective config written back when it builds. */
#include "fuzz_util.h"

#include "config.h"
#include "status.h"

#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[64], err[SUNMC_ERRLEN];
    int fd = fuzz_file(data, size, path, sizeof path);
    if (fd < 0)
        return 0;
    config_state st;
    if (config_build(&st, path, NULL, 0, err, sizeof err) == SUNMC_OK) {
        FILE *null = fopen("/dev/null", "w");
        if (null) {
            config_write(null, &st);
            fclose(null);
        }
        config_state_free(&st);
    }
    close(fd);
    return 0;
}
