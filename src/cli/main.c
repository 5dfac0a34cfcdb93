/* main.c - sunmc: Monte Carlo tolerance, calibration and design trades for
 * satellite sun sensors.  Dispatches to one command per file (main_*.c). */
#include "cli.h"
#include "par.h"
#include "status.h"
#include "suggest.h"

#include <gsl/gsl_errno.h>
#include <omp.h>
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
            "  sensitivity CONFIG Sobol indices (first order, total) of the unit RMS per random input\n"
            "  curve CONFIG       one unit's (--unit U) or one source's (--only KEY=V) error curves\n"
            "  simulate CONFIG    --unit U: one unit's campaign as a lab records it (CSV)\n"
            "  calibrate          --config CONFIG DATA.csv: fit a real sensor (family from CONFIG)\n"
            "  compensate         PARAMS.ini RAW.csv: apply a calibration\n"
            "  merge OUT DIR...   the shards (run --shard K/N --out DIR) of one run into OUT\n"
            "\n"
            "common options:\n"
            "  --units N | FIRST:END   units 0..N-1, or FIRST..END-1 (same rows as in a whole run)\n"
            "  --seed S                random seed (run.seed)\n"
            "  --threads T             OpenMP threads (results do not depend on it)\n"
            "  --set SECTION.KEY=VALUE override a config key (repeatable)\n"
            "  --out DIR               write the command's files there (all or nothing)\n"
            "  --quiet                 no progress or timing on stderr\n"
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
        printf("built with MPI: %s\n", par_library());
#endif
        return 0;
    }
    static const struct {
        const char *name;
        int (*fn)(int, char **);
    } commands[] = {{"run", cmd_run},           {"config", cmd_config},
                    {"sweep", cmd_sweep},       {"budget", cmd_budget},
                    {"design", cmd_design},
                    {"sensitivity", cmd_sensitivity},
                    {"curve", cmd_curve},       {"simulate", cmd_simulate},
                    {"calibrate", cmd_calibrate}, {"compensate", cmd_compensate},
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

/* Under mpirun every rank runs `run` (its units split across the ranks);
 * any other command runs on rank 0 alone. */
int main(int argc, char **argv)
{
    gsl_set_error_handler_off();
    char err[SUNMC_ERRLEN];
    if (par_init(&argc, &argv, err, sizeof err) != SUNMC_OK) {
        fprintf(stderr, "sunmc: %s\n", err);
        return 1;
    }
    int rc = 0;
    if (par_rank() == 0 || (argc >= 2 && strcmp(argv[1], "run") == 0))
        rc = dispatch(argc, argv);
    par_finalize();
    return rc;
}
