/* test_resume.c - `run --out DIR` checkpoints its completed blocks; after
 * kill -9 or SIGTERM part-way, `run ... --resume` runs the missing blocks
 * only and ends with the files of an uninterrupted run, byte for byte; a
 * block cut short is dropped; a resume of another run (seed, config, unit
 * range, block size) is refused and leaves the checkpoint as it was. */
#include "test_util.h"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[128];

#define RUN_CONFIG "run configs/ess_type_a.ini --quiet --set campaign.alpha_step_deg=0.4 " \
                   "--set validation.alpha_step_deg=0.7 --set campaign.beta_deg=-15,15 "    \
                   "--set run.block_units=32"
#define RUN RUN_CONFIG " --units 1200"

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "resume");
}

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int same_files(const char *a, const char *b)
{
    const char *files[] = {"summary.tsv", "units.tsv", "config.ini", "manifest.ini", "units.bin"};
    char cmd[1024], out[256];
    for (int i = 0; i < 5; i++) {
        snprintf(cmd, sizeof cmd, "cmp %s/%s/%s %s/%s/%s", dir, a, files[i], dir, b, files[i]);
        if (test_run(cmd, out, sizeof out) != 0) {
            fprintf(stderr, "%s differs between %s and %s\n", files[i], a, b);
            return 0;
        }
    }
    return 1;
}

/* Units the checkpoint of output directory name has committed (-1: none). */
static long committed(const char *name)
{
    char path[512];
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

/* Start RUN --out $D/name, wait until at least `units` are committed, then
 * send sig.  Returns the units committed when the signal was sent. */
static long interrupt_at(const char *name, const char *extra, long units, int sig)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "exec %s " RUN " %s --out %s/%s", test_sunmc(), extra, dir, name);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    long k = -1;
    for (int i = 0; i < 20000 && (k = committed(name)) < units; i++)
        usleep(2000);
    kill(pid, sig);
    int st;
    waitpid(pid, &st, 0);
    if (k < units || k >= 1200)
        fail_msg("the run was not caught part-way (%ld units committed)", k);
    return k;
}

static void whole_run(void)
{
    static int done;
    char out[8192];
    if (!done++)
        assert_int_equal(sunmc(RUN " --out $D/whole", out, sizeof out), 0);
}

static void resumed_after_kill_9_equals_whole_run(void **state)
{
    whole_run();
    char out[16384];
    long k = interrupt_at("k9", "", 256, SIGKILL);
    struct stat sb;
    char path[512];
    snprintf(path, sizeof path, "%s/k9", dir);
    assert_int_not_equal(stat(path, &sb), 0); /* no output yet */
    assert_int_equal(sunmc(RUN " --out $D/k9 --resume", out, sizeof out), 0);
    assert_true(same_files("whole", "k9"));
    assert_int_equal(committed("k9"), -1); /* the checkpoint is gone */
    (void)k;
}

static void resumed_after_sigterm_equals_whole_run(void **state)
{
    whole_run();
    char out[16384];
    interrupt_at("term", "--threads 1", 128, SIGTERM);
    /* a block cut short: records past the committed count are dropped */
    char cmd[512];
    snprintf(cmd, sizeof cmd, "head -c 1000 /dev/urandom >> %s/.term.resume/units.bin", dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(sunmc(RUN " --threads 2 --out $D/term --resume", out, sizeof out), 0);
    assert_true(same_files("whole", "term"));
}

static void resume_of_another_run_is_refused(void **state)
{
    char out[16384];
    long k = interrupt_at("other", "", 32, SIGKILL);
    struct {
        const char *extra, *needle;
    } bad[] = {
        {"--seed 2", "seed 1 against 2"},
        {"--set design.H_mm=4.5", "config (config_fnv1a64)"},
        {"--units 2000", "is of units 0:1200, this run of 0:2000"},
        {"--set run.block_units=16", "ran blocks of 32 units, this run of 16"},
    };
    char args[1024];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(args, sizeof args, RUN_CONFIG " %s %s --out $D/other --resume", bad[i].extra,
                 strstr(bad[i].extra, "--units") ? "" : "--units 1200");
        assert_int_equal(sunmc(args, out, sizeof out), 2);
        if (!strstr(out, bad[i].needle))
            fail_msg("'%s' lacks '%s'", out, bad[i].needle);
        assert_int_equal(committed("other"), k);
    }
    assert_int_equal(sunmc("run configs/ess_type_a.ini --resume", out, sizeof out), 2);
    assert_non_null(strstr(out, "--resume needs the --out DIR"));
    /* without --resume the checkpoint is discarded, with a note */
    assert_int_equal(sunmc(RUN_CONFIG " --units 32 --out $D/other", out, sizeof out), 0);
    assert_non_null(strstr(out, "discarded the checkpoint"));
    assert_int_equal(committed("other"), -1);
}

/* --until with a resume stops where the uninterrupted run stops. */
static void resumed_until_equals_until(void **state)
{
    char out[16384];
    const char *until = "--until rms_after_mean:0.00014";
    char args[1024];
    snprintf(args, sizeof args, RUN " %s --out $D/u_whole", until);
    assert_int_equal(sunmc(args, out, sizeof out), 0);
    assert_non_null(strstr(out, ": met after "));
    interrupt_at("u_res", until, 128, SIGKILL);
    snprintf(args, sizeof args, RUN " %s --out $D/u_res --resume", until);
    assert_int_equal(sunmc(args, out, sizeof out), 0);
    assert_true(same_files("u_whole", "u_res"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(resumed_after_kill_9_equals_whole_run),
        cmocka_unit_test(resumed_after_sigterm_equals_whole_run),
        cmocka_unit_test(resume_of_another_run_is_refused),
        cmocka_unit_test(resumed_until_equals_until),
    };
    return cmocka_run_group_tests_name("resume", tests, setup, NULL);
}
