/* fuzz_argv.c - libFuzzer harness: the command line (issue 22).  The first
 * byte picks a command's option list, the rest is split at NUL bytes into
 * up to 32 arguments and parsed as that command's (cli_parse): every
 * argument must be consumed or refused, never hang (a bare `--` did) or
 * overflow a buffer (--space was cut at 127 characters).  The resume
 * command line is rebuilt from the same arguments. */
#include "fuzz_util.h"

#include "cli.h"
#include "suggest.h"

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>

#define FUZZ_MAX_ARGS 32

static const struct {
    const char *command, *allowed;
} commands[] = {
    {"run", "CONFIG units seed threads set out quiet profile until shard resume isa"},
    {"config", "CONFIG? set reference"},
    {"sweep", "CONFIG units seed threads set out quiet vary"},
    {"design", "CONFIG units seed threads set space out quiet"},
    {"budget", "CONFIG units seed threads set out quiet"},
    {"curve", "CONFIG seed set out quiet unit only"},
    {"simulate", "CONFIG unit seed set out quiet"},
    {"calibrate", "sensor config set out quiet duplicates FILES1"},
    {"compensate", "quiet FILES2"},
};
#define N_COMMANDS (sizeof commands / sizeof commands[0])

/* The refusals print to stderr: sent to /dev/null around the parse, so
 * that libFuzzer's own lines (and a sanitizer's report) stay readable. */
static int quiet_stderr(void)
{
    static int null_fd = -1;
    if (null_fd < 0)
        null_fd = open("/dev/null", O_WRONLY);
    fflush(stderr);
    int saved = dup(STDERR_FILENO);
    if (null_fd >= 0)
        dup2(null_fd, STDERR_FILENO);
    return saved;
}

static void restore_stderr(int saved)
{
    fflush(stderr);
    if (saved >= 0) {
        dup2(saved, STDERR_FILENO);
        close(saved);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    size_t c = data[0] % N_COMMANDS;
    char *text = malloc(size);
    if (!text)
        return 0;
    memcpy(text, data + 1, size - 1);
    text[size - 1] = '\0';
    char *argv[FUZZ_MAX_ARGS + 3] = {"sunmc", (char *)commands[c].command};
    int argc = 2;
    for (char *p = text; argc < FUZZ_MAX_ARGS + 2 && p < text + size;) {
        argv[argc++] = p;
        p += strlen(p) + 1;
    }
    argv[argc] = NULL;
    static cli_options o; /* large (its --space buffers) */
    int saved = quiet_stderr();
    cli_parse(argc, argv, 2, commands[c].command, commands[c].allowed, &o);
    restore_stderr(saved);
    char cmd[1536];
    cli_resume_command(argc, argv, cmd, sizeof cmd);
    const char *names[FUZZ_MAX_ARGS + 2];
    for (int i = 0; i < argc; i++)
        names[i] = argv[i];
    suggest_nearest(argv[argc - 1], names, (size_t)argc);
    free(text);
    return 0;
}
