/* test_cli_lock.c - issue 36, rule 8: a live command owns its --out.
 * Two runs into one --out at once took each other's checkpoint ("discarded
 * the checkpoint of an interrupted run" while it ran) and only one result
 * survived; `run --until ... --resume` run twice failed the second time; a
 * run onto a full disk left .NAME.resume without a word.  CLI tests of
 * build/sunmc (SUNMC). */
#include "test_util.h"

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "lock");
}

#define P "configs/psd.ini"
/* A run slow enough to be caught part-way (blocks of 32 units, 1 thread). */
#define SLOW "run " P " --quiet --threads 1 --set run.block_units=32 --units 2000"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int exists(const char *name)
{
    char path[1024];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &st) == 0;
}

/* Entries of dir whose names start with prefix. */
static int entries_starting(const char *prefix)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    while (d && (e = readdir(d)))
        n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
    if (d)
        closedir(d);
    return n;
}

/* Units the checkpoint of output directory name has committed (-1: none). */
static long committed(const char *name)
{
    char path[1024];
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

/* Hold the lock of output directory name as a live command would (its
 * PID text in the file); the fd (close it to release). */
static int hold_lock(const char *name, const char *pid)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/.%s.lock", dir, name);
    int fd = open(path, O_RDWR | O_CREAT, 0644);
    assert_true(fd >= 0);
    assert_int_equal(flock(fd, LOCK_EX | LOCK_NB), 0);
    assert_int_equal(write(fd, pid, strlen(pid)), (int)strlen(pid));
    return fd;
}

/* Every command writing an --out DIR is refused at once (exit 2, the
 * holder's PID named) while another holds DIR, and touches nothing. */
static void held_lock_refuses_every_writer(void **state)
{
    static const char *const cmds[] = {
        "run " P " --units 2",
        "sweep " P " --units 2 --vary run.seed=1,2",
        "budget " P " --units 2",
        "sensitivity " P " --units 8",
        "design " P " --units 2",
        "allocate " P " --units 2",
        "simulate " P " --unit 1",
        "curve " P " --unit 1",
        "calibrate --config " P " $D/data.csv",
        "merge $D/busy $D/shard",
    };
    int fd = hold_lock("busy", "4242\n");
    char args[1024], out[16384];
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++) {
        if (strncmp(cmds[i], "merge", 5) == 0)
            snprintf(args, sizeof args, "%s --quiet", cmds[i]);
        else
            snprintf(args, sizeof args, "%s --quiet --out $D/busy", cmds[i]);
        int rc = sunmc(args, out, sizeof out);
        if (rc != 2 || !strstr(out, "--out ") ||
            !strstr(out, "another sunmc (PID 4242) is writing it"))
            fail_msg("sunmc %s: exit %d: %s", args, rc, out);
        assert_false(exists("busy"));
        assert_int_equal(entries_starting(".busy.resume"), 0);
        assert_int_equal(entries_starting(".busy.tmp"), 0);
    }
    assert_true(test_file_has(test_tmp("lock/.busy.lock"), "4242"));
    close(fd);
    /* released: the lock file a dead holder left locks nothing; the run
     * takes it and removes it at its end */
    assert_int_equal(sunmc("run " P " --units 2 --quiet --out $D/busy", out, sizeof out), 0);
    assert_true(exists("busy/summary.tsv"));
    assert_false(exists(".busy.lock"));
}

/* The race made deterministic: a second run into the live run's --out is
 * refused naming the live PID, the live run's checkpoint untouched; after
 * the live run is killed (-9), --resume continues it. */
static void second_run_refused_then_resume_after_kill_9(void **state)
{
    char cmd[2048], out[16384];
    snprintf(cmd, sizeof cmd, "exec %s " SLOW " --out %s/live", test_sunmc(), dir);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    long k = -1;
    for (int i = 0; i < 20000 && (k = committed("live")) < 32; i++)
        usleep(2000);
    assert_true(k >= 32 && k < 2000);
    char want[96];
    snprintf(want, sizeof want, "another sunmc (PID %ld) is writing it", (long)pid);
    assert_int_equal(sunmc(SLOW " --seed 7 --out $D/live", out, sizeof out), 2);
    if (!strstr(out, want))
        fail_msg("'%s' lacks '%s'", out, want);
    assert_null(strstr(out, "discarded the checkpoint"));
    assert_true(committed("live") >= k); /* not reset by the second run */
    kill(pid, SIGKILL);
    int ws;
    waitpid(pid, &ws, 0);
    assert_true(WIFSIGNALED(ws));
    assert_true(exists(".live.lock")); /* left, but no longer locked */
    assert_int_equal(sunmc("run " P " --quiet --set run.block_units=32 --units 2000 --out $D/live "
                           "--resume",
                           out, sizeof out),
                     0);
    assert_true(exists("live/summary.tsv"));
    assert_false(exists(".live.lock"));
    assert_int_equal(committed("live"), -1);
}

/* cmp of every file of a and b (directories of $D); 1 when all the same. */
static int same_files(const char *a, const char *b)
{
    static const char *const files[] = {"summary.tsv", "units.tsv", "config.ini",
                                        "manifest.ini", "units.bin", ".sunmc"};
    char cmd[4096], out[256];
    for (int i = 0; i < 6; i++) {
        snprintf(cmd, sizeof cmd, "cmp %s/%s/%s %s/%s/%s", dir, a, files[i], dir, b, files[i]);
        if (test_run(cmd, out, sizeof out) != 0)
            return 0;
    }
    return 1;
}

#define UNTIL "run " P " --units 2000 --quiet --until rms_after_mean:1.5"

/* The cluster scripts always pass --resume: a requeued --until task whose
 * run finished reprints its result, files unchanged byte for byte; another
 * target (tighter or looser) is still refused. */
static void until_resume_repeats(void **state)
{
    char first[16384], again[16384], out[16384], cmd[2048];
    assert_int_equal(sunmc(UNTIL " --out $D/u2 --resume", first, sizeof first), 0);
    assert_non_null(strstr(first, ": met after 512 units"));
    snprintf(cmd, sizeof cmd, "cp -a %s/u2 %s/u2_copy", dir, dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(sunmc(UNTIL " --out $D/u2 --resume", again, sizeof again), 0);
    assert_string_equal(again, first); /* the same Table 1 and --until line */
    assert_true(same_files("u2", "u2_copy"));
    assert_int_equal(entries_starting(".u2."), 0);
    /* without --quiet it says why nothing ran */
    assert_int_equal(sunmc("run " P " --units 2000 --until rms_after_mean:1.5 --out $D/u2 "
                           "--resume",
                           out, sizeof out),
                     0);
    assert_non_null(strstr(out, "holds this run, finished (units 0:512); nothing to run"));
    static const char *const other[] = {"rms_after_mean:1.2", "rms_after_mean:3"};
    for (int i = 0; i < 2; i++) {
        snprintf(cmd, sizeof cmd, "run " P " --units 2000 --quiet --until %s --out $D/u2 --resume",
                 other[i]);
        assert_int_equal(sunmc(cmd, out, sizeof out), 2);
        assert_non_null(strstr(out, "holds a finished run, not this one"));
        assert_true(same_files("u2", "u2_copy"));
    }
    /* a target not met after all the units: a repeat is a no-op too */
    const char *unmet = "run " P " --units 64 --quiet --until rms_after_mean:0.0001 "
                        "--set run.block_units=32 --out $D/u3 --resume";
    assert_int_equal(sunmc(unmet, first, sizeof first), 0);
    assert_non_null(strstr(first, "NOT met"));
    assert_int_equal(sunmc(unmet, again, sizeof again), 0);
    assert_string_equal(again, first);
}

/* A full disk (a file-size limit) fails the checkpoint, then the final
 * write: the message names the checkpoint kept and the command that
 * finishes the job, which does; with no unit checkpointed nothing is left. */
static void full_disk_says_what_was_kept(void **state)
{
    char cmd[2048], out[16384], bin[512];
    char real[PATH_MAX];
    assert_non_null(realpath(test_sunmc(), real));
    snprintf(bin, sizeof bin, "%.500s", real); /* the commands run in dir */
    snprintf(cmd, sizeof cmd,
             "(cd %s && trap '' XFSZ; ulimit -f 60; %s run %s/" P " --units 600 --quiet "
             "--set run.block_units=32 --out full2 >/dev/null)",
             dir, bin, getenv("PWD"));
    assert_int_equal(test_run(cmd, out, sizeof out), 1);
    if (!strstr(out, "checkpointing stopped (the run went on)"))
        fail_msg("%s: %s", cmd, out);
    assert_non_null(strstr(out, "results not saved"));
    assert_non_null(strstr(out, " units checkpointed in .full2.resume"));
    char *line = strstr(out, "\n  sunmc run ");
    assert_non_null(line);
    char resume[1024];
    snprintf(resume, sizeof resume, "%s", line + 3);
    resume[strcspn(resume, "\n")] = '\0';
    assert_non_null(strstr(resume, "--out full2 --resume"));
    assert_false(exists("full2"));
    assert_true(committed("full2") > 0);
    /* room again: the printed command finishes the job */
    snprintf(cmd, sizeof cmd, "cd %s && %s%s", dir, bin, resume + strlen("sunmc"));
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_true(exists("full2/summary.tsv"));
    assert_int_equal(committed("full2"), -1);
    assert_false(exists(".full2.lock"));
    /* the checkpoint's first block fails too: nothing is left, and it says so */
    snprintf(cmd, sizeof cmd,
             "(cd %s && trap '' XFSZ; ulimit -f 4; %s run %s/" P " --units 200 --quiet "
             "--out full >/dev/null)",
             dir, bin, getenv("PWD"));
    assert_int_equal(test_run(cmd, out, sizeof out), 1);
    assert_non_null(strstr(out, "nothing kept"));
    assert_int_equal(entries_starting(".full."), 0);
    assert_false(exists("full"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(held_lock_refuses_every_writer),
        cmocka_unit_test(second_run_refused_then_resume_after_kill_9),
        cmocka_unit_test(until_resume_repeats),
        cmocka_unit_test(full_disk_says_what_was_kept),
    };
    return cmocka_run_group_tests_name("cli_lock", tests, setup, NULL);
}
