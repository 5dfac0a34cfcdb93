/* cmd_merge.c - `sunmc merge OUT SHARD_DIR...`: shards of one run into the
 * run's files. */
#include "cli.h"
#include "summary_print.h"
#include "merge.h"
#include "outlock.h"
#include "runner.h"
#include "status.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

static const char merge_help[] =
    "usage: sunmc merge OUT SHARD_DIR... [--quiet]\n"
    "Merges the output directories of `run --units FIRST:END --out DIR` or `run --shard K/N\n"
    "--out DIR` of one run (same sunmc version, config and seed; their unit ranges must tile\n"
    "one range with no gap or overlap) into OUT: every statistic is recomputed in unit order\n"
    "from the shards' units.bin, so OUT holds the files of the single run of that range.\n";

static void merged_units_line(FILE *m, long first, long end, long units)
{
    if (first == 0)
        fprintf(m, "units = %ld  # sunmc merge of units 0:%ld (the shards' run.units: %ld)\n", end,
                end, units);
    else
        fprintf(m, "units = %ld  # sunmc merge of units %ld:%ld: run it with --units %ld:%ld\n",
                end, first, end, first, end);
}

/* The shard's config.ini without its "# units" line: the merged file's
 * body.  When the merged units [first, end) are not the whole run of
 * `units` (run.units), its units line says end, so that running the merged
 * config.ini (with --units first:end when first > 0) reproduces the merge. */
static char *config_body(const char *dir, long first, long end, long units, char *err,
                         size_t errlen)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/config.ini", dir);
    FILE *f = fopen(path, "r");
    if (!f) {
        sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: %s", path, strerror(errno));
        return NULL;
    }
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    char line[4096];
    /* a shard that is itself a merge has its own units line */
    int top = 1, in_run = 0, whole = first == 0 && end == units;
    while (m && fgets(line, sizeof line, f)) {
        if (line[0] == '[')
            in_run = strncmp(line, "[run]", 5) == 0;
        if (in_run && strncmp(line, "units = ", 8) == 0 &&
            (!whole || atol(line + 8) != units || strstr(line, "# sunmc merge")))
            merged_units_line(m, first, end, units);
        else if (!(top && strncmp(line, "# units ", 8) == 0))
            fputs(line, m);
        top = 0;
    }
    fclose(f);
    if (m)
        fclose(m);
    if (!buf)
        sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    return buf;
}

/* The config of the shards, from the first one's config.ini, checked
 * against its manifest's hash. */
static int shard_config(const merge_shard *s, config_state *st, char *err, size_t errlen)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/config.ini", s->dir);
    int rc = config_build(st, path, NULL, 0, err, errlen);
    if (rc != SUNMC_OK)
        return rc;
    if (config_hash(st) != s->m.config_hash) {
        config_state_free(st);
        return sunmc_fail(err, errlen, SUNMC_EINPUT,
                          "%s does not match its manifest's config_fnv1a64 (edited?)", path);
    }
    return SUNMC_OK;
}

/* Replay every shard's units through r in unit order. */
static int replay_shards(run_sink *r, const merge_shard *s, int n, char *err, size_t errlen)
{
    char path[PATH_MAX], man[PATH_MAX];
    int st = SUNMC_OK;
    for (int i = 0; i < n && st == SUNMC_OK; i++) {
        snprintf(path, sizeof path, "%s/%s", s[i].dir, UNITFILE_NAME);
        snprintf(man, sizeof man, "%s/%s", s[i].dir, MANIFEST_NAME);
        st = unitsum_verify(path, &r->layout, s[i].m.first, s[i].m.end, UNITSUM_LEAF_UNITS,
                            s[i].m.sum_units, s[i].m.sum, s[i].m.nsum, man, err, errlen);
        if (st == SUNMC_OK)
            st = run_replay(r, path, s[i].m.first, s[i].m.end, NULL, err, errlen);
    }
    return st;
}

static int merge_into(const char *out, const merge_shard *s, int n, const config_state *st,
                      char *err, size_t errlen)
{
    const sunmc_config *c = &st->cfg;
    summary_row *rows = calloc((size_t)report_n_rows(c), sizeof *rows);
    char *body = config_body(s[0].dir, s[0].m.first, s[n - 1].m.end, c->units, err, errlen);
    cli_run_files rf;
    run_sink r;
    int rc = rows && body ? cli_run_files_begin(&rf, out, err, errlen) : SUNMC_ENOMEM;
    if (rc == SUNMC_OK && (rc = run_sink_init(&r, c, rf.f[RUN_FILE_UNITS],
                                              rf.f[RUN_FILE_BIN], err, errlen)))
        cli_run_files_abort(&rf);
    if (rc == SUNMC_OK) {
        if ((rc = replay_shards(&r, s, n, err, errlen)) == SUNMC_OK) {
            run_manifest m = s[0].m;
            m.end = s[n - 1].m.end;
            run_sink_sums(&r, &m);
            report_acc_rows(r.acc, rows);
            summary_print(stdout, c, rows);
            printf("merged units %ld:%ld from %d shard%s into %s\n", m.first, m.end, n,
                   n == 1 ? "" : "s", out);
            fflush(stdout);
            fprintf(rf.f[RUN_FILE_CONFIG], "# units %ld:%ld of this config\n%s", m.first, m.end,
                    body);
            rc = cli_run_files_commit(&rf, c, rows, &m, err, errlen);
        } else {
            cli_run_files_abort(&rf);
        }
        run_sink_free(&r);
    }
    free(rows);
    free(body);
    return rc;
}

int cmd_merge(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, merge_help))
        return 0;
    const char **dirs = calloc((size_t)argc, sizeof *dirs);
    const char *out = NULL;
    int n = 0;
    char err[SUNMC_ERRLEN];
    int options_done = 0;
    for (int i = 2; dirs && i < argc; i++) {
        if (!options_done && strcmp(argv[i], "--") == 0) {
            options_done = 1;
            continue;
        }
        if (!options_done && strcmp(argv[i], "--quiet") == 0)
            continue; /* merge prints no progress; accepted like the other commands */
        if (!options_done && argv[i][0] == '-' && argv[i][1] != '\0') {
            fprintf(stderr, "sunmc merge: unknown option %s (see sunmc merge --help)\n", argv[i]);
            free(dirs);
            return EXIT_BAD_INPUT;
        }
        if (!out)
            out = argv[i];
        else
            dirs[n++] = argv[i];
    }
    if (!out || n == 0) {
        fprintf(stderr, "sunmc merge: needs OUT and at least one SHARD_DIR (see sunmc merge "
                        "--help)\n");
        free(dirs);
        return EXIT_BAD_INPUT;
    }
    merge_shard *s = calloc((size_t)n, sizeof *s);
    config_state st;
    int rc = s ? out_check(out, err, sizeof err) : SUNMC_ENOMEM;
    if (rc == SUNMC_OK)
        rc = out_check_inputs(out, dirs, n, err, sizeof err);
    if (rc == SUNMC_OK)
        rc = out_lock(out, err, sizeof err); /* held until main's out_unlock */
    if (rc == SUNMC_OK)
        rc = merge_plan(dirs, n, s, err, sizeof err);
    if (rc == SUNMC_OK && (rc = shard_config(&s[0], &st, err, sizeof err)) == SUNMC_OK) {
        rc = merge_into(out, s, n, &st, err, sizeof err);
        config_state_free(&st);
    }
    if (rc != SUNMC_OK)
        fprintf(stderr, "sunmc merge: %s\n", rc == SUNMC_ENOMEM ? "out of memory" : err);
    free(s);
    free(dirs);
    return cli_exit_code(rc);
}
