/* test_cli_signals.c - issue 22, rule 7: signals and pipes lose nothing.
 * SIGPIPE is ignored, so `sunmc ... --out DIR | head` still writes DIR;
 * after SIGINT the message says what was kept and the exact command that
 * resumes, and that command finishes the run byte for byte; a checkpoint
 * killed before its first commit (no progress file) is one of 0 units. */
#include "test_util.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "signals");
}

#define D "configs/dss.ini"
#define RUN "run configs/ess_type_a.ini --set campaign.alpha_step_deg=0.4 " \
            "--set validation.alpha_step_deg=0.7 --set campaign.beta_deg=-15,15 "    \
            "--units 600 --set run.block_units=32"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int exists(const char *rel)
{
    char p[1024];
    struct stat st;
    snprintf(p, sizeof p, "%s/%.400s", dir, rel);
    return stat(p, &st) == 0;
}

/* `sunmc ARGS | true` (the reader gone before the table is printed): the
 * exit status of sunmc. */
static int piped_to_true(const char *args)
{
    char cmd[4096], out[4096], rcfile[600];
    snprintf(rcfile, sizeof rcfile, "%s/rc", dir);
    snprintf(cmd, sizeof cmd, "D=%s; { %s %s; echo $? > %s; } | true", dir, test_sunmc(), args,
             rcfile);
    test_run(cmd, out, sizeof out);
    FILE *f = fopen(rcfile, "r");
    int rc = -1;
    if (!f || fscanf(f, "%d", &rc) != 1)
        fail_msg("no exit status: %s", out);
    fclose(f);
    return rc;
}

/* The reproducer: `sweep ... --out sw | head -3` exited 141 and sw
 * was never written; budget and run likewise. */
static void test_sigpipe_keeps_out(void **state)
{
    assert_int_equal(piped_to_true("sweep " D " --units 5 --vary tolerance.dh_px=0.1:2:0.1 "
                                   "--out $D/sw"),
                     0);
    assert_true(exists("sw/sweep.tsv"));
    assert_int_equal(piped_to_true("budget " D " --units 10 --out $D/bu"), 0);
    assert_true(exists("bu/budget.tsv"));
    assert_int_equal(piped_to_true("run " D " --units 20 --out $D/ru"), 0);
    assert_true(exists("ru/units.bin"));
    assert_false(exists(".ru.resume")); /* no checkpoint left */
    /* without --out the printed table was the result: a failure */
    assert_int_equal(piped_to_true("curve " D " --unit 1 --quiet"), 1);
}

static long committed(const char *name)
{
    char path[700];
    snprintf(path, sizeof path, "%s/.%s.resume/progress", dir, name);
    FILE *f = fopen(path, "r");
    long k = -1;
    if (f) {
        if (fscanf(f, "units_done %ld", &k) != 1)
            k = -1;
        fclose(f);
    }
    return k;
}

/* SIGINT part-way: the message names what was kept and the command that
 * resumes; that command, run as printed, gives the uninterrupted files. */
static void test_sigint_says_how_to_resume(void **state)
{
    char out[16384], cmd[4096], log[600];
    assert_int_equal(sunmc(RUN " --quiet --out $D/whole", out, sizeof out), 0);
    snprintf(log, sizeof log, "%s/int.log", dir);
    char bin[1024];
    snprintf(bin, sizeof bin, "%s%s%s", test_sunmc()[0] == '/' ? "" : getenv("PWD"),
             test_sunmc()[0] == '/' ? "" : "/", test_sunmc());
    snprintf(cmd, sizeof cmd, "cd %s && exec %s " RUN " --out int 2> %s", dir, bin, log);
    /* configs/ relative to the repository: link it into the directory */
    char ln[1200];
    snprintf(ln, sizeof ln, "ln -sfn %s/configs %s/configs", getenv("PWD"), dir);
    assert_int_equal(system(ln), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    for (int i = 0; i < 20000 && committed("int") < 64; i++)
        usleep(2000);
    kill(pid, SIGINT);
    waitpid(pid, NULL, 0);
    long k = committed("int");
    if (k < 64 || k >= 600)
        fail_msg("not caught part-way (%ld units)", k);
    FILE *f = fopen(log, "r");
    assert_non_null(f);
    size_t n = fread(out, 1, sizeof out - 1, f);
    out[n] = '\0';
    fclose(f);
    if (!strstr(out, "interrupted: int is as it was") || !strstr(out, "kept:") ||
        !strstr(out, ".int.resume"))
        fail_msg("%s", out);
    char *line = strstr(out, "\n  sunmc run ");
    assert_non_null(line);
    line += 3;
    line[strcspn(line, "\n")] = '\0';
    assert_non_null(strstr(line, "--resume"));
    snprintf(cmd, sizeof cmd, "cd %s && sunmc() { %s \"$@\"; } && %s --quiet", dir, bin, line);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    const char *files[] = {"summary.tsv", "units.tsv", "units.bin"};
    for (int i = 0; i < 3; i++) {
        snprintf(cmd, sizeof cmd, "cmp %s/whole/%s %s/int/%s", dir, files[i], dir, files[i]);
        if (test_run(cmd, out, sizeof out) != 0)
            fail_msg("%s differs after the printed resume command", files[i]);
    }
}

/* The reproducer: kill -9 before the first checkpoint commit made
 * --resume fail for ever ("not a checkpoint's progress file"), and the
 * cluster scripts always pass --resume. */
static void test_checkpoint_without_progress(void **state)
{
    char out[16384], cmd[2048];
    snprintf(cmd, sizeof cmd,
             "mkdir -p %s/.np.resume && printf 'format = 1\\n' > %s/.np.resume/manifest.ini && "
             ": > %s/.np.resume/units.bin",
             dir, dir, dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(sunmc("run " D " --units 4 --quiet --out $D/np --resume", out, sizeof out), 0);
    assert_true(exists("np/units.bin"));
    assert_false(exists(".np.resume"));
    /* an empty checkpoint directory likewise */
    snprintf(cmd, sizeof cmd, "mkdir -p %s/.np2.resume", dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(sunmc("run " D " --units 4 --quiet --out $D/np2 --resume", out, sizeof out),
                     0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sigpipe_keeps_out),
        cmocka_unit_test(test_sigint_says_how_to_resume),
        cmocka_unit_test(test_checkpoint_without_progress),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
