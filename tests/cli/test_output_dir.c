/* test_output_dir.c - issue 22, rule 1: an output directory is sunmc's or it
 * is refused.  --out is replaced whole only when empty or holding nothing
 * but what sunmc wrote there (the files its marker lists) and no input of
 * the command; otherwise exit 2 before any work, naming the files.  What a
 * killed run left beside the target is cleaned up by the next run. */
#include "test_util.h"

#include "output.h"

#include <dirent.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "outdir");
}

#define E "configs/ess_type_a.ini"
#define D "configs/dss.ini"
#define TINY "--set campaign.alpha_step_deg=2 --set validation.alpha_step_deg=5 " \
             "--set campaign.beta_deg=-15,15 --quiet"

/* `sunmc ARGS` with $D the suite's directory: exit status, output in out. */
static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int exists(const char *rel)
{
    char p[1600];
    struct stat st;
    snprintf(p, sizeof p, "%s/%s", dir, rel);
    return stat(p, &st) == 0;
}

static void must_have(const char *out, const char *needle)
{
    if (!strstr(out, needle))
        fail_msg("output lacks '%s': %s", needle, out);
}

/* The reproducer: calibrate --out lab with lab/my.ini and
 * lab/campaign.csv as its inputs and the user's NOTES.txt there exited 0
 * and deleted all of them. */
static void test_calibrate_keeps_inputs_and_notes(void **state)
{
    char out[16384], cmd[2048];
    assert_int_equal(sunmc("simulate " D " --unit 5 --quiet --out $D/lab", out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "cp " D " %s/lab/my.ini && echo notes > %s/lab/NOTES.txt", dir, dir);
    assert_int_equal(system(cmd), 0);
    int rc = sunmc("calibrate --config $D/lab/my.ini $D/lab/campaign.csv --out $D/lab", out,
                   sizeof out);
    assert_int_equal(rc, 2);
    must_have(out, "--out");
    must_have(out, "my.ini");
    must_have(out, "NOTES.txt");
    const char *kept[] = {"lab/campaign.csv", "lab/my.ini", "lab/NOTES.txt", "lab/truth.csv",
                          "lab/validation.csv"};
    for (int i = 0; i < 5; i++)
        if (!exists(kept[i]))
            fail_msg("%s was deleted", kept[i]);
    /* nothing but the command's input: still refused, the input named */
    snprintf(cmd, sizeof cmd, "rm %s/lab/my.ini %s/lab/NOTES.txt", dir, dir);
    assert_int_equal(system(cmd), 0);
    rc = sunmc("calibrate --config " D " $D/lab/campaign.csv --out $D/lab", out, sizeof out);
    assert_int_equal(rc, 2);
    must_have(out, "holds an input of this command");
    must_have(out, "campaign.csv");
    assert_true(exists("lab/campaign.csv"));
    /* through a symbolic link or a relative path: resolved by real path */
    snprintf(cmd, sizeof cmd, "ln -s lab %s/lablink", dir);
    assert_int_equal(system(cmd), 0);
    rc = sunmc("calibrate --config " D " $D/lablink/campaign.csv --out $D/lab", out, sizeof out);
    assert_int_equal(rc, 2);
    must_have(out, "holds an input");
    /* the config inside the output directory is an input too */
    snprintf(cmd, sizeof cmd, "mkdir %s/r && cp " E " %s/r/my.ini", dir, dir);
    assert_int_equal(system(cmd), 0);
    rc = sunmc("run $D/r/my.ini --units 2 " TINY " --out $D/r", out, sizeof out);
    assert_int_equal(rc, 2);
    must_have(out, "my.ini");
    assert_true(exists("r/my.ini"));
    /* elsewhere it works, and a second run replaces the first whole */
    assert_int_equal(sunmc("calibrate --config " D " $D/lab/campaign.csv --quiet --out $D/cal",
                           out, sizeof out), 0);
    assert_int_equal(sunmc("calibrate --config " D " $D/lab/campaign.csv --quiet --out $D/cal",
                           out, sizeof out), 0);
}

/* The reproducer: `make plots RUN=runs/budget` then a new run into
 * runs/budget deleted the plots without a word. */
static void test_user_files_in_a_run_directory(void **state)
{
    char out[16384], cmd[1024];
    assert_int_equal(sunmc("run " E " --units 2 " TINY " --out $D/budget", out, sizeof out), 0);
    assert_true(test_file_has(test_tmp("outdir/budget/.sunmc"), "file\tunits.tsv\n"));
    snprintf(cmd, sizeof cmd, "echo png > %s/budget/rms.png", dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(sunmc("run " E " --units 3 " TINY " --out $D/budget", out, sizeof out), 2);
    must_have(out, "rms.png");
    must_have(out, "sunmc did not write");
    assert_true(exists("budget/rms.png"));
    assert_true(test_file_has(test_tmp("outdir/budget/config.ini"), "units = 2"));
    /* another command's files are sunmc's: replaced whole */
    snprintf(cmd, sizeof cmd, "rm %s/budget/rms.png", dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(sunmc("curve " E " --unit 1 --quiet --out $D/budget", out, sizeof out), 0);
    assert_false(exists("budget/units.tsv"));
}

/* merge into one of its own shards destroyed the shard. */
static void test_merge_into_a_shard(void **state)
{
    char out[16384];
    assert_int_equal(sunmc("run " E " --units 4 --shard 0/2 " TINY " --out $D/s0", out, sizeof out),
                     0);
    assert_int_equal(sunmc("run " E " --units 4 --shard 1/2 " TINY " --out $D/s1", out, sizeof out),
                     0);
    assert_int_equal(sunmc("merge $D/s0 $D/s0 $D/s1", out, sizeof out), 2);
    must_have(out, "holds an input of this command");
    assert_true(exists("s0/units.bin"));
    assert_int_equal(sunmc("merge $D/m $D/s0 $D/s1", out, sizeof out), 0);
}

/* A pid no process has: a child that has ended. */
static long dead_pid(void)
{
    pid_t p = fork();
    if (p == 0)
        _exit(0);
    waitpid(p, NULL, 0);
    return (long)p;
}

static void host_tag(char *buf, size_t len, long pid)
{
    char host[65] = "";
    if (gethostname(host, sizeof host - 1) != 0 || !host[0])
        strcpy(host, "host");
    host[strcspn(host, ".-/")] = '\0';
    snprintf(buf, len, "%.32s-%ld", host, pid);
}

/* .NAME.tmp.* and .NAME.old.* of a killed run are cleaned up by the next
 * run into NAME; an old directory is put back when NAME is missing (a kill
 * between two renames); a live run's directories are left alone. */
static void test_litter_cleaned_next_run(void **state)
{
    char tag[96], live[96], p[1024], err[SUNMC_ERRLEN];
    host_tag(tag, sizeof tag, dead_pid());
    host_tag(live, sizeof live, (long)getpid());
    snprintf(p, sizeof p, "%s/.t.tmp.%s.AAAAAA", dir, tag);
    assert_int_equal(mkdir(p, 0777), 0);
    snprintf(p, sizeof p, "%s/.t.tmp.%s.AAAAAA/units.tsv", dir, tag);
    assert_int_equal(test_write_file(p, "big\n"), 0);
    snprintf(p, sizeof p, "%s/.t.tmp.OLDFMT", dir); /* an older sunmc's, tagless */
    assert_int_equal(mkdir(p, 0777), 0);
    snprintf(p, sizeof p, "%s/.t.tmp.%s.BBBBBB", dir, live);
    assert_int_equal(mkdir(p, 0777), 0);
    /* the target is missing, its old contents aside: put back */
    snprintf(p, sizeof p, "%s/.t.old.%s.CCCCCC", dir, tag);
    assert_int_equal(mkdir(p, 0777), 0);
    snprintf(p, sizeof p, "%s/.t.old.%s.CCCCCC/summary.tsv", dir, tag);
    assert_int_equal(test_write_file(p, "old\n"), 0);
    snprintf(p, sizeof p, "%s/t", dir);
    out_set os;
    assert_int_equal(out_begin(&os, p, err, sizeof err), SUNMC_OK);
    out_abort(&os);
    assert_true(exists("t/summary.tsv")); /* the old directory is back */
    snprintf(p, sizeof p, ".t.tmp.%s.AAAAAA", tag);
    assert_false(exists(p));
    assert_false(exists(".t.tmp.OLDFMT"));
    snprintf(p, sizeof p, ".t.old.%s.CCCCCC", tag);
    assert_false(exists(p));
    snprintf(p, sizeof p, ".t.tmp.%s.BBBBBB", live);
    assert_true(exists(p)); /* this process is alive: not touched */
    snprintf(p, sizeof p, "%s/.t.tmp.%s.BBBBBB", dir, live);
    rmdir(p);
}

/* A commit into an existing sunmc directory leaves nothing beside it and
 * the target exists at every moment (one exchange, no window). */
static void test_commit_leaves_no_litter(void **state)
{
    char out[16384];
    for (int i = 0; i < 2; i++)
        assert_int_equal(sunmc("curve " E " --unit 1 --quiet --out $D/c", out, sizeof out), 0);
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strncmp(e->d_name, ".c.", 3) == 0)
            fail_msg("litter %s left", e->d_name);
    closedir(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_calibrate_keeps_inputs_and_notes),
        cmocka_unit_test(test_user_files_in_a_run_directory),
        cmocka_unit_test(test_merge_into_a_shard),
        cmocka_unit_test(test_litter_cleaned_next_run),
        cmocka_unit_test(test_commit_leaves_no_litter),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
