/* cli_parse.c - a command's arguments: every one is consumed or refused
 * with the fix (exit 2).  `--` ends the options, `--name=value` is
 * `--name value`, a single-dash option or an extra argument is refused, a
 * mistyped option name gets a did-you-mean. */
#include "cli.h"
#include "numtext.h"
#include "outlock.h"
#include "output.h"
#include "ranks.h"
#include "status.h"
#include "suggest.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Longest option name (the allowed lists hold short words). */
#define OPT_NAME_MAX 32
#define OPT_NAMES_MAX 32
/* Longest --units / --seed text (a long's 19 digits and some zeros). */
#define CLI_WHOLE_DIGITS_MAX 32

static int bad(const char *command, const char *msg, const char *arg)
{
    fprintf(stderr, "sunmc %s: %s%s%s (see sunmc %s --help)\n", command, msg, arg ? ": " : "",
            arg ? arg : "", command);
    return EXIT_BAD_INPUT;
}

/* Options a command takes more than once (each adds to a list; their
 * --help shows them as [--set ...]...).  --units is checked by its form:
 * N (run.units) and FIRST:END (the range of that run) once each. */
#define REPEATABLE_OPTIONS "set vary space units"

/* The word opt in the space-separated list allowed (a pointer into it, the
 * same for every spelling), or NULL. */
static const char *allowed_find(const char *allowed, const char *opt)
{
    size_t n = strlen(opt);
    if (n == 0)
        return NULL;
    for (const char *p = allowed; (p = strstr(p, opt)) != NULL; p += n)
        if ((p == allowed || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return p;
    return NULL;
}

/* 1 when the space-separated list allowed holds the word opt. */
static int allowed_has(const char *allowed, const char *opt)
{
    return allowed_find(allowed, opt) != NULL;
}

/* Option name (its word in allowed) given once more: refused unless it is
 * repeatable, else recorded. */
static int given_once(cli_options *o, const char *command, const char *allowed,
                      const char *name)
{
    const char *word = allowed_find(allowed, name);
    if (allowed_has(REPEATABLE_OPTIONS, name))
        return 0;
    for (int i = 0; i < o->n_given; i++)
        if (o->given[i] == word) {
            char msg[OPT_NAME_MAX + 96];
            snprintf(msg, sizeof msg, "--%s given twice; give it once", name);
            return bad(command, msg, NULL);
        }
    if (o->n_given < CLI_MAX_GIVEN)
        o->given[o->n_given++] = word;
    return 0;
}

/* Sets of o whose key is section.key (blanks around it allowed). */
static int sets_of_key(const cli_options *o, const char *key)
{
    int n = 0;
    size_t len = strlen(key);
    for (int i = 0; i < o->n_sets; i++) {
        const char *s = o->sets[i];
        s += strspn(s, " \t");
        if (strncmp(s, key, len) != 0)
            continue;
        s += len;
        s += strspn(s, " \t");
        n += *s == '=';
    }
    return n;
}

/* --units N with --set run.units=M (or --seed with --set run.seed): two
 * values for one key, where one would silently win. */
static int one_value_per_key(const cli_options *o, const char *command)
{
    static const char *const opts[] = {"units", "seed"};
    for (int k = 0; k < 2; k++) {
        char key[16];
        snprintf(key, sizeof key, "run.%s", opts[k]);
        int from_option = k == 0 ? o->units_given : o->seed_given;
        if (from_option && sets_of_key(o, key) > 1) {
            char msg[128];
            snprintf(msg, sizeof msg, "--%s and --set %s both give %s; give one of them",
                     opts[k], key, key);
            return bad(command, msg, NULL);
        }
    }
    return 0;
}

/* Data files a command takes besides CONFIG: the N of a "FILES<N>" word. */
static int allowed_files(const char *allowed)
{
    const char *p = strstr(allowed, "FILES");
    return p ? atoi(p + strlen("FILES")) : 0;
}

static int takes_config(const char *allowed)
{
    return allowed_has(allowed, "CONFIG") || allowed_has(allowed, "CONFIG?");
}

/* A whole number in plain decimal (numtext.h: no '+', blanks, hex or
 * exponent); 0 on success. */
static int parse_long_arg(const char *s, long *out)
{
    return num_parse_long(s, out) == 0 ? 0 : -1;
}

/* The option names of allowed (its lower-case words, plus help). */
static size_t option_names(const char *allowed, char buf[][OPT_NAME_MAX], const char **names)
{
    size_t n = 0;
    for (const char *p = allowed; *p && n + 1 < OPT_NAMES_MAX;) {
        size_t len = strcspn(p, " ");
        if (len > 0 && len < OPT_NAME_MAX && p[0] >= 'a' && p[0] <= 'z') {
            memcpy(buf[n], p, len);
            buf[n][len] = '\0';
            names[n] = buf[n];
            n++;
        }
        p += len;
        p += strspn(p, " ");
    }
    names[n++] = "help";
    return n;
}

/* An option the command does not take: arg as typed, name without dashes
 * (and without =value).  Offers the nearest option, or for a single-dash
 * letter every option starting with it. */
static int unknown_option(const char *command, const char *allowed, const char *arg,
                          const char *name)
{
    char buf[OPT_NAMES_MAX][OPT_NAME_MAX], hint[256] = "";
    const char *names[OPT_NAMES_MAX];
    size_t n = option_names(allowed, buf, names);
    int single = arg[1] != '-';
    if (single && strlen(name) == 1) {
        size_t used = 0;
        for (size_t i = 0; i < n && used < sizeof hint - 40; i++)
            if (names[i][0] == name[0])
                used += (size_t)snprintf(hint + used, sizeof hint - used, "%s--%s",
                                         used ? " or " : " (did you mean ", names[i]);
        if (used)
            snprintf(hint + used, sizeof hint - used, "?)");
    } else {
        const char *near = NULL;
        for (size_t i = 0; i < n && !near; i++)
            if (strcmp(names[i], name) == 0)
                near = names[i];
        if (!near)
            near = suggest_nearest(name, names, n);
        if (near)
            snprintf(hint, sizeof hint, " (did you mean --%s?)", near);
    }
    fprintf(stderr, "sunmc %s: unknown option %s%s%s (see sunmc %s --help)\n", command, arg, hint,
            single ? "; options start with --" : "", command);
    return EXIT_BAD_INPUT;
}

/* A flag without a value (--quiet, --profile, --reference, --resume):
 * set it and return 1; 0 for any other name. */
static int set_flag(cli_options *o, const char *name)
{
    int *flag = strcmp(name, "quiet") == 0       ? &o->quiet
                : strcmp(name, "profile") == 0   ? &o->profile
                : strcmp(name, "reference") == 0 ? &o->reference
                : strcmp(name, "resume") == 0    ? &o->resume
                                                 : NULL;
    if (flag)
        *flag = 1;
    return flag != NULL;
}

/* The most units of a run (run.units' largest value): unit indices are
 * below it. */
static long units_most(void)
{
    const config_key *k = config_find("run", "units");
    return k ? (long)k->max : 100000000;
}

/* --units FIRST:END, both whole numbers within run.units' largest value. */
static int set_range(cli_options *o, const char *command, const char *v, const char *colon)
{
    char lo[64];
    size_t n = (size_t)(colon - v);
    long most = units_most();
    if (o->end >= 0)
        return bad(command, "--units FIRST:END given twice; give it once", v);
    if (n >= sizeof lo)
        return bad(command, "--units FIRST:END is malformed", v);
    memcpy(lo, v, n);
    lo[n] = '\0';
    if (parse_long_arg(lo, &o->first) != 0 || parse_long_arg(colon + 1, &o->end) != 0 ||
        o->first < 0 || o->end <= o->first)
        return bad(command, "--units FIRST:END needs whole numbers 0 <= FIRST < END", v);
    if (o->end > most) {
        char msg[128];
        snprintf(msg, sizeof msg, "--units FIRST:END needs END <= %ld (run.units' largest value)",
                 most);
        return bad(command, msg, v);
    }
    return 0;
}

/* --seed S, --units N or --units FIRST:END: a run.* override, or the range. */
static int set_run_key(cli_options *o, const char *command, const char *name, const char *v)
{
    const char *colon = strchr(v, ':');
    if (strcmp(name, "units") == 0 && colon)
        return set_range(o, command, v, colon);
    long whole;
    if (strcmp(name, "units") == 0 && o->units_given)
        return bad(command, "--units N given twice; give it once", v);
    if (strlen(v) > CLI_WHOLE_DIGITS_MAX) {
        char msg[96];
        snprintf(msg, sizeof msg, "--%s is too long for a whole number", name);
        return bad(command, msg, v);
    }
    if (parse_long_arg(v, &whole) != 0) {
        char msg[96];
        snprintf(msg, sizeof msg, "--%s needs a whole number%s", name,
                 strcmp(name, "units") == 0 ? " (e.g. 1000, not 1e3) or FIRST:END" : "");
        return bad(command, msg, v);
    }
    const config_key *k = config_find("run", name);
    if (k && (whole < k->min || whole > k->max)) {
        char msg[128];
        snprintf(msg, sizeof msg, "--%s needs a whole number from %.0f to %.0f", name, k->min,
                 k->max);
        return bad(command, msg, v);
    }
    if (o->n_sets >= CLI_MAX_SETS)
        return bad(command, "too many options", v);
    *(strcmp(name, "units") == 0 ? &o->units_given : &o->seed_given) = 1;
    snprintf(o->set_buf[o->n_sets], sizeof o->set_buf[0], "run.%s=%ld", name, whole);
    o->sets[o->n_sets] = o->set_buf[o->n_sets];
    o->n_sets++;
    return 0;
}

static int set_shard(cli_options *o, const char *command, const char *v)
{
    const char *slash = strchr(v, '/');
    char k[CLI_WHOLE_DIGITS_MAX + 1];
    size_t n = slash ? (size_t)(slash - v) : 0;
    o->shard_k = o->shard_n = 0;
    if (slash && n < sizeof k) {
        memcpy(k, v, n);
        k[n] = '\0';
        if (parse_long_arg(k, &o->shard_k) != 0 || parse_long_arg(slash + 1, &o->shard_n) != 0)
            o->shard_n = 0;
    }
    if (o->shard_n < 1 || o->shard_n > 1000000 || o->shard_k < 0 || o->shard_k >= o->shard_n)
        return bad(command, "--shard K/N needs 0 <= K < N (e.g. 0/4 .. 3/4)", v);
    return 0;
}

/* --space KEY=LIST: the campaign.search_KEY override, refused when it does
 * not fit whole (never cut). */
static int set_space(cli_options *o, const char *command, const char *v)
{
    if (o->n_sets >= CLI_MAX_SETS)
        return bad(command, "too many options", v);
    if (snprintf(o->set_buf[o->n_sets], sizeof o->set_buf[0], "campaign.search_%s", v) >=
        (int)sizeof o->set_buf[0])
        return bad(command, "--space value too long", v);
    o->sets[o->n_sets] = o->set_buf[o->n_sets];
    o->n_sets++;
    return 0;
}

/* Option --name (argument a) with its value v. */
static int set_option(cli_options *o, const char *command, const char *name, const char *a,
                      const char *v)
{
    if (strcmp(name, "set") == 0) {
        if (o->n_sets >= CLI_MAX_SETS)
            return bad(command, "too many --set options", v);
        o->sets[o->n_sets++] = v;
    } else if (strcmp(name, "seed") == 0 || strcmp(name, "units") == 0) {
        return set_run_key(o, command, name, v);
    } else if (strcmp(name, "threads") == 0) {
        long t;
        if (parse_long_arg(v, &t) != 0 || t < 1 || t > 1024)
            return bad(command, "--threads needs a whole number from 1 to 1024", v);
        o->threads = (int)t;
    } else if (strcmp(name, "out") == 0) {
        o->out = v; /* checked before any work, once the inputs are known */
    } else if (strcmp(name, "space") == 0) {
        return set_space(o, command, v);
    } else if (strcmp(name, "vary") == 0) {
        if (o->n_vary >= CLI_MAX_VARY)
            return bad(command, "at most two --vary axes", v);
        o->vary[o->n_vary++] = v;
    } else if (strcmp(name, "unit") == 0) {
        if (parse_long_arg(v, &o->unit) != 0 || o->unit < 0 || o->unit >= units_most()) {
            char msg[96];
            snprintf(msg, sizeof msg, "--unit needs a unit index from 0 to %ld", units_most() - 1);
            return bad(command, msg, v);
        }
    } else if (strcmp(name, "only") == 0) {
        o->only = v;
    } else if (strcmp(name, "sensor") == 0) {
        o->sensor = v;
    } else if (strcmp(name, "until") == 0) {
        o->until = v;
    } else if (strcmp(name, "shard") == 0) {
        return set_shard(o, command, v);
    } else if (strcmp(name, "config") == 0) {
        o->config = v;
    } else if (strcmp(name, "isa") == 0) {
        o->isa = v;
    } else if (strcmp(name, "format") == 0) {
        o->format = v;
    } else if (strcmp(name, "duplicates") == 0) {
        o->duplicates = v;
    } else if (strcmp(name, "onboard") == 0) {
        o->onboard = v; /* lab_onboard_parse checks it */
    } else {
        return bad(command, "unknown option", a);
    }
    return 0;
}

/* A positional argument: CONFIG, else one of the data files, else refused. */
static int set_positional(cli_options *o, const char *command, const char *allowed,
                          const char *a)
{
    int files = allowed_files(allowed);
    if (!o->config && takes_config(allowed))
        o->config = a;
    else if (o->n_positional < files && o->n_positional < 4)
        o->positional[o->n_positional++] = a;
    else {
        const char *what = files == 0 ? "no file arguments" : files == 1 ? "one data file"
                                                                         : "two files";
        if (allowed_has(allowed, "config") && !o->config) {
            fprintf(stderr, "sunmc %s: unexpected argument '%s': %s takes %s and needs --config "
                            "CONFIG (the sensor's config%s%s%s) (see sunmc %s --help)\n",
                    command, a, command, what, o->n_positional ? ": was '" : "",
                    o->n_positional ? o->positional[0] : "",
                    o->n_positional ? "' meant as --config?" : "", command);
            return EXIT_BAD_INPUT;
        }
        fprintf(stderr, "sunmc %s: unexpected argument '%s': %s takes %s%s and options starting "
                        "with -- (see sunmc %s --help)\n",
                command, a, command, takes_config(allowed) ? "one CONFIG" : what,
                takes_config(allowed) && files ? (files == 1 ? ", one data file" : ", two files")
                                               : "",
                command);
        return EXIT_BAD_INPUT;
    }
    return 0;
}

/* Before any work: --out must be writable, and replacing it whole must
 * destroy neither a file sunmc did not write nor an input of the command;
 * then it is this command's until it ends (outlock.h: another live command
 * into it is refused).  Under mpirun rank 0 alone writes, so it alone locks. */
static int check_out(const cli_options *o, const char *command)
{
    char err[SUNMC_ERRLEN];
    const char *inputs[5] = {o->config};
    for (int k = 0; k < o->n_positional && k < 4; k++)
        inputs[k + 1] = o->positional[k];
    if (out_check(o->out, err, sizeof err) != SUNMC_OK ||
        out_check_inputs(o->out, inputs, 1 + o->n_positional, err, sizeof err) != SUNMC_OK ||
        (ranks_rank() == 0 && out_lock(o->out, err, sizeof err) != SUNMC_OK)) {
        fprintf(stderr, "sunmc %s: %s\n", command, err);
        return EXIT_BAD_INPUT;
    }
    return 0;
}

/* One option argument a = "--name" or "--name=value"; *i moves past a
 * value taken from the next argument. */
static int parse_option(int argc, char **argv, int *i, const char *command, const char *allowed,
                        cli_options *o)
{
    const char *a = argv[*i];
    char name[OPT_NAME_MAX];
    const char *eq = strchr(a, '=');
    size_t len = eq ? (size_t)(eq - a - 2) : strlen(a + 2);
    if (len >= sizeof name)
        return unknown_option(command, allowed, a, "");
    memcpy(name, a + 2, len);
    name[len] = '\0';
    if (!allowed_has(allowed, name))
        return unknown_option(command, allowed, a, name);
    int rc = given_once(o, command, allowed, name);
    if (rc)
        return rc;
    if (set_flag(o, name)) {
        if (eq)
            return bad(command, "this option takes no value", a);
        return 0;
    }
    const char *v = eq ? eq + 1 : NULL;
    if (!v) {
        if (*i + 1 >= argc)
            return bad(command, "option needs a value", a);
        v = argv[++*i];
        if (strncmp(v, "--", 2) == 0 && v[2] != '\0' && allowed_has(allowed, v + 2)) {
            char msg[96];
            snprintf(msg, sizeof msg, "--%s needs a value before the next option", name);
            return bad(command, msg, v);
        }
    }
    return set_option(o, command, name, a, v);
}

int cli_split_until(const char *arg, char *name, size_t len, double *halfwidth)
{
    const char *colon = strrchr(arg, ':');
    size_t n = colon ? (size_t)(colon - arg) : 0;
    double h = NAN;
    if (!colon || n >= len || num_parse_double(colon + 1, &h) != 0 || !(h > 0))
        return 0;
    memcpy(name, arg, n);
    name[n] = '\0';
    *halfwidth = h;
    return 1;
}

int cli_parse(int argc, char **argv, int first, const char *command, const char *allowed,
              cli_options *o)
{
    memset(o, 0, sizeof *o);
    o->end = -1;
    o->threads = -1;
    o->unit = -1;
    int options_done = 0;
    for (int i = first; i < argc; i++) {
        const char *a = argv[i];
        int rc;
        if (!options_done && strcmp(a, "--") == 0) {
            options_done = 1;
            continue;
        }
        if (options_done || a[0] != '-' || a[1] == '\0')
            rc = set_positional(o, command, allowed, a);
        else if (a[1] != '-')
            rc = unknown_option(command, allowed, a, a + 1);
        else
            rc = parse_option(argc, argv, &i, command, allowed, o);
        if (rc)
            return rc;
    }
    if (allowed_has(allowed, "CONFIG") && !o->config)
        return bad(command, "missing CONFIG file", NULL);
    int rc = one_value_per_key(o, command);
    if (rc)
        return rc;
    return o->out ? check_out(o, command) : 0;
}
