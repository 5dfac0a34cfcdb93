/* main.c - sunmc: Monte Carlo tolerance, calibration and design trades for
 * satellite sun sensors.  Dispatches to one command per file (cmd_*.c). */
#include "cli.h"
#include "outlock.h"
#include "ranks.h"
#include "status.h"
#include "suggest.h"
#include "vmath.h"

#include <gsl/gsl_errno.h>
#include <limits.h>
#include <errno.h>
#include <omp.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

static void usage(FILE *f)
{
    fprintf(f,
            "sunmc %s - Monte Carlo tolerance, calibration and design trades for sun sensors\n"
            "\n"
            "usage: sunmc COMMAND [options]\n"
            "  run CONFIG         simulate, calibrate and validate many units; print Table 1\n"
            "  config [CONFIG]    print the effective config (--reference: every key, commented)\n"
            "  sweep CONFIG       --vary KEY=LIST|START:STOP:STEP (1 or 2 axes): Monte Carlo per point\n"
            "  design CONFIG      the cheapest calibration campaign meeting the yield target\n"
            "  budget CONFIG      error budget: floor, each tolerance and noise source, inverse limits\n"
            "  allocate CONFIG    the cheapest joint tolerances whose confirmed yield meets the target\n"
            "  sensitivity CONFIG Sobol indices (first order, total) of the unit RMS per random input\n"
            "  curve CONFIG       one unit's (--unit U) or one source's (--only KEY=V) error curves\n"
            "  simulate CONFIG    --unit U: one unit's campaign as a lab records it (CSV)\n"
            "  calibrate          --config CONFIG DATA.csv: fit a real sensor (family from CONFIG)\n"
            "  compensate         PARAMS.ini RAW.csv: apply a calibration\n"
            "  export             PARAMS.ini --out DIR: the calibration as C99 flight code\n"
            "  merge OUT DIR...   the shards (run --shard K/N --out DIR) of one run into OUT\n"
            "\n"
            "common options:\n"
            "  --units N | FIRST:END   units 0..N-1, or FIRST..END-1 (same rows as in a whole run)\n"
            "  --seed S                random seed (run.seed)\n"
            "  --threads T             OpenMP threads (results do not depend on it)\n"
            "  --set SECTION.KEY=VALUE override a config key (repeatable)\n"
            "  --out DIR               write the command's files there (all or nothing; one\n"
            "                          live command per DIR: a second one is refused)\n"
            "  --quiet                 no progress or timing on stderr\n"
            "  each option once (--set and the others shown as [...]... add up); numbers are\n"
            "  plain decimal (no 0x, inf, nan; whole numbers without '+' or exponent)\n"
            "  sunmc COMMAND --help    the command's own help; sunmc --version\n"
            "  sunmc --help --family NAME   the keys of one family (default: the first)\n"
            "\n",
            SUNMC_VERSION);
}

/* 1 when argv holds --help or -h. */
static int asks_help(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return 1;
    return 0;
}

static int dispatch(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return EXIT_BAD_INPUT;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0 ||
        (strcmp(cmd, "--family") == 0 && asks_help(argc, argv))) {
        usage(stdout);
        return cli_help_keys(stdout, argc, argv);
    }
    if (strcmp(cmd, "--version") == 0) {
        printf("sunmc %s\n", SUNMC_VERSION);
#ifdef SUNMC_MPI
        printf("built with MPI: %s\n", ranks_library());
#endif
        return 0;
    }
    static const struct {
        const char *name;
        int (*fn)(int, char **);
    } commands[] = {{"run", cmd_run},           {"config", cmd_config},
                    {"sweep", cmd_sweep},       {"budget", cmd_budget},
                    {"design", cmd_design},     {"allocate", cmd_allocate},
                    {"sensitivity", cmd_sensitivity},
                    {"curve", cmd_curve},       {"simulate", cmd_simulate},
                    {"calibrate", cmd_calibrate}, {"compensate", cmd_compensate},
                    {"export", cmd_export},
                    {"merge", cmd_merge}};
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (strcmp(cmd, commands[i].name) == 0)
            return commands[i].fn(argc, argv);
    const char *names[sizeof commands / sizeof commands[0]];
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        names[i] = commands[i].name;
    const char *near = suggest_nearest(cmd, names, sizeof names / sizeof names[0]);
    fprintf(stderr, "sunmc: unknown command '%s'%s%s%s (see sunmc --help)\n", cmd,
            near ? " (did you mean " : "", near ? near : "", near ? "?)" : "");
    return EXIT_BAD_INPUT;
}

/* Smallest OpenMP thread stack sunmc runs on: the DSS kernels need 48 KiB
 * (measured: 32 KiB crashes), taken four times over. */
#define MIN_THREAD_STACK_BYTES (256.0 * 1024)

/* Bytes of an OMP_STACKSIZE / GOMP_STACKSIZE text ("16K", "4M", "65536B";
 * a bare number is KiB); < 0 when malformed. */
static double stack_bytes(const char *v)
{
    char *end;
    double n = strtod(v, &end);
    while (*end == ' ')
        end++;
    double unit = 1024;
    switch (*end) {
    case 'b': case 'B': unit = 1; end++; break;
    case 'k': case 'K': unit = 1024; end++; break;
    case 'm': case 'M': unit = 1024.0 * 1024; end++; break;
    case 'g': case 'G': unit = 1024.0 * 1024 * 1024; end++; break;
    default: break;
    }
    while (*end == ' ')
        end++;
    return end == v || *end || !(n >= 0) ? -1 : n * unit;
}

/* The OpenMP runtime sized its threads' stacks from the environment before
 * main: one too small for the kernels would crash a worker (a segfault, no
 * message), so it is refused up front. */
static int check_thread_stack(void)
{
    static const char *const vars[] = {"OMP_STACKSIZE", "GOMP_STACKSIZE"};
    for (int i = 0; i < 2; i++) {
        const char *v = getenv(vars[i]);
        if (!v)
            continue;
        double b = stack_bytes(v);
        if (b >= 0 && b < MIN_THREAD_STACK_BYTES) {
            fprintf(stderr, "sunmc: %s=%s gives OpenMP threads stacks smaller than the %.0fK "
                            "sunmc needs; unset it or set %s=%.0fK or more\n",
                    vars[i], v, MIN_THREAD_STACK_BYTES / 1024, vars[i],
                    MIN_THREAD_STACK_BYTES / 1024);
            return EXIT_BAD_INPUT;
        }
    }
    return 0;
}

/* A failed write to stdout (a closed pipe, a full disk) is said, with what
 * was kept: the files of --out are complete all the same.  Without --out
 * stdout was the result, so the exit status is 1. */
static int check_stdout(int argc, char **argv, int rc)
{
    if (fflush(stdout) == 0 && !ferror(stdout))
        return rc;
    const char *out = NULL;
    for (int i = 2; i + 1 < argc; i++)
        if (strcmp(argv[i], "--out") == 0)
            out = argv[i + 1];
    int e = errno;
    if (out && rc == 0)
        fprintf(stderr, "sunmc: standard output failed (%s): the printed table is cut; kept: "
                        "the files of --out %s, complete\n", strerror(e), out);
    else
        fprintf(stderr, "sunmc: standard output failed (%s): the printed result is cut\n",
                strerror(e));
    return rc ? rc : out ? 0 : 1;
}

/* The binary beside this one whose kernels run the baseline on every CPU. */
#define BASELINE_BINARY "sunmc-baseline"

/* --isa baseline (`run`) or SUNMC_ISA=baseline (any command) on a binary
 * whose kernels have an AVX2 clone: the loader picked the clone before
 * main, so the command is run again by sunmc-baseline (same arguments),
 * before MPI starts.  Returns only on an error (an exit code) or when
 * nothing is to be done (0). */
static int isa_reexec(int argc, char **argv)
{
    const char *want = NULL, *env = getenv("SUNMC_ISA");
    for (int i = 2; argc >= 2 && strcmp(argv[1], "run") == 0 && i < argc; i++) {
        if (strcmp(argv[i], "--") == 0)
            break;
        if (strcmp(argv[i], "--isa") == 0 && i + 1 < argc)
            want = argv[i + 1];
        else if (strncmp(argv[i], "--isa=", 6) == 0)
            want = argv[i] + 6;
    }
    if (!want && env && env[0])
        want = env;
    if (!want || strcmp(want, "baseline") != 0 || vm_forced_baseline())
        return 0;
    char self[PATH_MAX], path[PATH_MAX + 32];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0)
        return 0; /* cmd_run says the path cannot be forced */
    self[n] = '\0';
    char *slash = strrchr(self, '/');
    snprintf(path, sizeof path, "%.*s/%s", slash ? (int)(slash - self) : 1,
             slash ? self : ".", BASELINE_BINARY);
    if (access(path, X_OK) != 0) {
        fprintf(stderr, "sunmc: --isa baseline: %s is missing (`make` builds it beside sunmc, "
                        "`make install` installs it)\n", path);
        return EXIT_BAD_INPUT;
    }
    argv[0] = path;
    execv(path, argv);
    fprintf(stderr, "sunmc: --isa baseline: cannot run %s: %s\n", path, strerror(errno));
    return EXIT_BAD_INPUT;
}

/* Under mpirun every rank runs `run` (its units split across the ranks);
 * any other command runs on rank 0 alone. */
int main(int argc, char **argv)
{
    gsl_set_error_handler_off();
    /* A closed pipe (`sunmc ... | head`) must not end the process before
     * --out is committed: writes to it fail with EPIPE instead. */
    signal(SIGPIPE, SIG_IGN);
    char err[SUNMC_ERRLEN];
    int xrc = isa_reexec(argc, argv);
    if (xrc)
        return xrc;
    if (ranks_init(&argc, &argv, err, sizeof err) != SUNMC_OK) {
        fprintf(stderr, "sunmc: %s\n", err);
        return 1;
    }
    int rc = check_thread_stack();
    if (rc == 0 && (ranks_rank() == 0 || (argc >= 2 && strcmp(argv[1], "run") == 0)))
        rc = dispatch(argc, argv);
    rc = check_stdout(argc, argv, rc);
    out_unlock(); /* the --out DIR this command held (outlock.h) */
    ranks_finalize();
    return rc;
}
