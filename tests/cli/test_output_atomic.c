/* test_output_atomic.c - output directories, all or nothing (output.h): --out is
 * checked before any work; a command's files replace the directory whole
 * (no stale file of an earlier command survives); a write error or a
 * SIGTERM/SIGINT while writing leaves the target as it was and no temporary
 * file; Table 1 is printed even when writing fails. */
#include "test_util.h"

#include "output.h"
#include "status.h"

#include <dirent.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[64];

static int setup(void **state)
{
    snprintf(dir, sizeof dir, "/tmp/sunmc_output_XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static void path_of(char *buf, size_t len, const char *name)
{
    snprintf(buf, len, "%s/%s", dir, name);
}

static int exists(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0;
}

/* Entries of d whose name starts with '.' (temporaries, probes), besides
 * "." and ".." and the marker. */
/* Hidden entries left in d, not counting the checkpoints of interrupted
 * runs (.NAME.resume, kept on purpose for run --resume). */
static int hidden_entries(const char *d)
{
    DIR *h = opendir(d);
    assert_non_null(h);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(h)) != NULL) {
        size_t len = strlen(e->d_name);
        int checkpoint = len > 7 && strcmp(e->d_name + len - 7, ".resume") == 0;
        /* a run killed before its signal handlers are set (a SIGTERM that
         * lands early on a loaded machine) leaves its lock file, which
         * locks nothing once the process is gone (docs/trust.md) */
        int lock = len > 5 && strcmp(e->d_name + len - 5, ".lock") == 0;
        if (e->d_name[0] == '.' && strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0 &&
            strcmp(e->d_name, OUT_MARKER) != 0 && !checkpoint && !lock)
            n++;
    }
    closedir(h);
    return n;
}

static int entries(const char *d)
{
    DIR *h = opendir(d);
    if (!h)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(h)) != NULL)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(h);
    return n;
}

static void expect_check_error(const char *out, const char *needle)
{
    char err[SUNMC_ERRLEN] = "";
    assert_int_equal(out_check(out, err, sizeof err), SUNMC_EINPUT);
    if (!strstr(err, needle))
        fail_msg("out_check(\"%s\"): '%s' lacks '%s'", out, err, needle);
    assert_int_equal(hidden_entries(dir), 0);
}

static void test_check_refuses(void **state)
{
    char p[256], q[256];
    expect_check_error("", "needs a directory name");
    expect_check_error("/", "not /, . or ..");
    expect_check_error(".", "not /, . or ..");
    path_of(p, sizeof p, "..");
    expect_check_error(p, "not /, . or ..");
    path_of(p, sizeof p, "file");
    assert_int_equal(test_write_file(p, "x\n"), 0);
    expect_check_error(p, "exists and is not a directory");
    path_of(q, sizeof q, "file/sub");
    expect_check_error(q, "is a file, not a directory");
    path_of(q, sizeof q, "file/sub/deeper");
    expect_check_error(q, "is a file, not a directory");
    /* a directory sunmc did not write is never replaced */
    path_of(p, sizeof p, "home");
    assert_int_equal(mkdir(p, 0777), 0);
    path_of(q, sizeof q, "home/notes.txt");
    assert_int_equal(test_write_file(q, "mine\n"), 0);
    path_of(p, sizeof p, "home/");
    expect_check_error(p, "no .sunmc marker");
    path_of(p, sizeof p, "link");
    path_of(q, sizeof q, "home");
    assert_int_equal(symlink(q, p), 0);
    expect_check_error(p, "symbolic link");
    expect_check_error("/proc/sunmc_no_such_dir", "cannot create anything in /proc");
    if (geteuid() != 0) { /* root writes anywhere */
        path_of(p, sizeof p, "ro");
        assert_int_equal(mkdir(p, 0555), 0);
        path_of(q, sizeof q, "ro/out");
        expect_check_error(q, "cannot create anything");
    }
}

static void test_check_accepts(void **state)
{
    char p[256], err[SUNMC_ERRLEN];
    int before = entries(dir);
    path_of(p, sizeof p, "new/nested/out");
    assert_int_equal(out_check(p, err, sizeof err), SUNMC_OK);
    path_of(p, sizeof p, "empty");
    assert_int_equal(mkdir(p, 0777), 0);
    assert_int_equal(out_check(p, err, sizeof err), SUNMC_OK);
    assert_int_equal(entries(dir), before + 1); /* created nothing */
    assert_int_equal(hidden_entries(dir), 0);
}

/* Write a set of files into out: name[k] holds text[k]. */
static int write_set(const char *out, const char *const *names, int n, char *err)
{
    out_set os;
    FILE *f[4];
    int st = out_begin(&os, out, err, SUNMC_ERRLEN);
    if (st == SUNMC_OK)
        st = out_open_all(&os, names, f, n, err, SUNMC_ERRLEN);
    if (st != SUNMC_OK) {
        out_abort(&os);
        return st;
    }
    for (int k = 0; k < n; k++)
        fprintf(f[k], "%s\n", names[k]);
    return out_commit(&os, err, SUNMC_ERRLEN);
}

static void test_commit_replaces_whole(void **state)
{
    char out[256], p[300], err[SUNMC_ERRLEN];
    path_of(out, sizeof out, "a/b/run");
    static const char *const ess[] = {"field.tsv", "params.ini"};
    static const char *const dss[] = {"params.ini", "residuals.tsv", "bands.tsv"};
    assert_int_equal(write_set(out, ess, 2, err), SUNMC_OK);
    assert_int_equal(entries(out), 3); /* two files and the marker */
    snprintf(p, sizeof p, "%s/%s", out, OUT_MARKER);
    assert_true(exists(p));
    assert_int_equal(write_set(out, dss, 3, err), SUNMC_OK);
    assert_int_equal(entries(out), 4);
    snprintf(p, sizeof p, "%s/field.tsv", out);
    assert_false(exists(p)); /* the earlier command's file is gone */
    snprintf(p, sizeof p, "%s/residuals.tsv", out);
    assert_true(exists(p));
    path_of(p, sizeof p, "a/b");
    assert_int_equal(hidden_entries(p), 0);
    assert_int_equal(entries(p), 1);
    /* permissions as a plain mkdir would give, not mkdtemp's 0700 */
    struct stat st;
    assert_int_equal(stat(out, &st), 0);
    mode_t mask = umask(0);
    umask(mask);
    assert_int_equal(st.st_mode & 0777, 0777 & ~mask);
}

static void test_abort_keeps_old(void **state)
{
    char out[256], p[300], err[SUNMC_ERRLEN];
    path_of(out, sizeof out, "keep");
    static const char *const one[] = {"summary.tsv"};
    assert_int_equal(write_set(out, one, 1, err), SUNMC_OK);
    out_set os;
    FILE *f;
    assert_int_equal(out_begin(&os, out, err, sizeof err), SUNMC_OK);
    assert_int_equal(out_open(&os, "units.tsv", &f, err, sizeof err), SUNMC_OK);
    fputs("half", f);
    out_abort(&os);
    snprintf(p, sizeof p, "%s/summary.tsv", out);
    assert_true(exists(p));
    assert_int_equal(entries(out), 2);
    assert_int_equal(hidden_entries(dir), 0);
    /* bad names are refused */
    assert_int_equal(out_begin(&os, out, err, sizeof err), SUNMC_OK);
    assert_int_not_equal(out_open(&os, "a/b", &f, err, sizeof err), SUNMC_OK);
    assert_int_not_equal(out_open(&os, OUT_MARKER, &f, err, sizeof err), SUNMC_OK);
    out_abort(&os);
    assert_int_equal(hidden_entries(dir), 0);
}

/* A file size limit makes the writes fail as a full disk would: the commit
 * must report it and move nothing. */
static void test_write_error_at_commit(void **state)
{
    char out[256];
    path_of(out, sizeof out, "full");
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        signal(SIGXFSZ, SIG_IGN);
        struct rlimit rl = {1000, 1000};
        setrlimit(RLIMIT_FSIZE, &rl);
        char err[SUNMC_ERRLEN] = "";
        out_set os;
        FILE *f;
        if (out_begin(&os, out, err, sizeof err) != SUNMC_OK ||
            out_open(&os, "units.tsv", &f, err, sizeof err) != SUNMC_OK)
            _exit(10);
        for (int i = 0; i < 1000; i++)
            fprintf(f, "%d\t0.123456789\n", i);
        int st = out_commit(&os, err, sizeof err);
        _exit(st == SUNMC_EIO && strstr(err, "units.tsv: write error") ? 0 : 11);
    }
    int ws;
    assert_int_equal(waitpid(pid, &ws, 0), pid);
    assert_true(WIFEXITED(ws));
    assert_int_equal(WEXITSTATUS(ws), 0);
    assert_false(exists(out));
    assert_int_equal(hidden_entries(dir), 0);
}

/* A child writes into out (which may hold an earlier result), tells us it
 * is in the middle of writing, and waits: the signal must end it and leave
 * out as it was, with no temporary file anywhere. */
static void signal_while_writing(int sig, const char *name, int with_old)
{
    char out[256], p[300], err[SUNMC_ERRLEN];
    path_of(out, sizeof out, name);
    static const char *const old[] = {"summary.tsv", "units.tsv"};
    if (with_old)
        assert_int_equal(write_set(out, old, 2, err), SUNMC_OK);
    int fd[2];
    assert_int_equal(pipe(fd), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        out_set os;
        FILE *f[3];
        static const char *const names[] = {"summary.tsv", "config.ini", "params.ini"};
        if (out_begin(&os, out, err, sizeof err) != SUNMC_OK ||
            out_open_all(&os, names, f, 3, err, sizeof err) != SUNMC_OK)
            _exit(10);
        for (int i = 0; i < 100000; i++)
            fprintf(f[0], "%d\n", i);
        fflush(f[0]);
        if (write(fd[1], "w", 1) != 1)
            _exit(11);
        for (;;)
            pause();
    }
    close(fd[1]);
    char c;
    assert_int_equal(read(fd[0], &c, 1), 1);
    close(fd[0]);
    assert_int_equal(kill(pid, sig), 0);
    int ws;
    assert_int_equal(waitpid(pid, &ws, 0), pid);
    assert_true(WIFSIGNALED(ws));
    assert_int_equal(WTERMSIG(ws), sig);
    assert_int_equal(hidden_entries(dir), 0);
    if (!with_old) {
        assert_false(exists(out));
        return;
    }
    assert_int_equal(entries(out), 3);
    snprintf(p, sizeof p, "%s/config.ini", out);
    assert_false(exists(p));
}

static void test_sigterm_while_writing(void **state)
{
    signal_while_writing(SIGTERM, "term_new", 0);
    signal_while_writing(SIGTERM, "term_old", 1);
    signal_while_writing(SIGINT, "int_old", 1);
}

static int handled;
static void my_handler(int sig) { handled = sig; }

/* The handlers a program had are back after a commit and after an abort. */
static void test_handlers_restored(void **state)
{
    char out[256], err[SUNMC_ERRLEN];
    struct sigaction sa, now;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = my_handler;
    sigemptyset(&sa.sa_mask);
    assert_int_equal(sigaction(SIGTERM, &sa, NULL), 0);
    path_of(out, sizeof out, "handlers");
    static const char *const one[] = {"a.tsv"};
    assert_int_equal(write_set(out, one, 1, err), SUNMC_OK);
    assert_int_equal(sigaction(SIGTERM, NULL, &now), 0);
    assert_ptr_equal(now.sa_handler, my_handler);
    out_set os;
    assert_int_equal(out_begin(&os, out, err, sizeof err), SUNMC_OK);
    assert_int_equal(sigaction(SIGTERM, NULL, &now), 0);
    assert_ptr_not_equal(now.sa_handler, my_handler);
    out_abort(&os);
    assert_int_equal(sigaction(SIGTERM, NULL, &now), 0);
    assert_ptr_equal(now.sa_handler, my_handler);
    raise(SIGTERM);
    assert_int_equal(handled, SIGTERM);
    signal(SIGTERM, SIG_DFL);
}

/* ---- the command line ---- */

static double now_s(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (double)tv.tv_sec + 1e-6 * (double)tv.tv_usec;
}

static int sunmc(const char *args, char *out, size_t len)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s %s", test_sunmc(), args);
    return test_run(cmd, out, len);
}

/* A run that would take minutes is refused at once for a bad --out. */
static void test_cli_bad_out_at_once(void **state)
{
    char out[4096], args[512], p[256];
    path_of(p, sizeof p, "file");
    assert_int_equal(test_write_file(p, "x\n"), 0);
    const char *bad[] = {"/etc/passwd", "''", p, "/proc/sunmc_no_such_dir"};
    for (int i = 0; i < 4; i++) {
        snprintf(args, sizeof args, "run configs/ess_type_a.ini --units 1000000 --quiet --out %s",
                 bad[i]);
        double t0 = now_s();
        assert_int_equal(sunmc(args, out, sizeof out), 2);
        double dt = now_s() - t0;
        if (dt > 1.0)
            fail_msg("--out %s refused after %.2f s", bad[i], dt);
        assert_non_null(strstr(out, "--out"));
    }
    const char *cmds[] = {"sweep configs/dss.ini --vary tolerance.dh_px=0,1",
                          "budget configs/dss.ini", "curve configs/dss.ini --unit 1",
                          "simulate configs/dss.ini --unit 1",
                          "calibrate --sensor dss --config configs/dss.ini x.csv"};
    for (int i = 0; i < 5; i++) {
        snprintf(args, sizeof args, "%s --out /etc/passwd", cmds[i]);
        assert_int_equal(sunmc(args, out, sizeof out), 2);
        assert_non_null(strstr(out, "--out /etc/passwd: exists and is not a directory"));
    }
}

#define SMALL_RUN "run configs/ess_type_a.ini --quiet --units 40 --set campaign.alpha_step_deg=0.4"

/* A stale file of an earlier command in the output directory is gone. */
static void test_cli_no_stale_files(void **state)
{
    char out[8192], args[512], p[300], o[256];
    path_of(o, sizeof o, "run");
    snprintf(args, sizeof args, "simulate configs/ess_type_a.ini --unit 1 --out %s", o);
    assert_int_equal(sunmc(args, out, sizeof out), 0);
    snprintf(args, sizeof args, SMALL_RUN " --out %s", o);
    assert_int_equal(sunmc(args, out, sizeof out), 0);
    snprintf(p, sizeof p, "%s/campaign.csv", o);
    assert_false(exists(p));
    assert_int_equal(entries(o), 6); /* summary, units, config, manifest, units.bin, marker */
    assert_int_equal(hidden_entries(dir), 0);
}

/* Writing fails (file size limit): Table 1 is printed all the same, the
 * exit status says so, and nothing is written. */
static void test_cli_write_fails_table_kept(void **state)
{
    char out[8192], cmd[1024], o[256];
    path_of(o, sizeof o, "limited");
    snprintf(cmd, sizeof cmd, "trap '' XFSZ; ulimit -f 2; %s " SMALL_RUN " --out %s",
             test_sunmc(), o);
    assert_int_equal(test_run(cmd, out, sizeof out), 1);
    assert_non_null(strstr(out, "times improvement"));
    assert_non_null(strstr(out, "write error"));
    assert_non_null(strstr(out, "results not saved"));
    assert_false(exists(o));
    assert_int_equal(hidden_entries(dir), 0);
}

/* A real SIGTERM to the command: whenever it lands, the target is absent
 * or complete, and no temporary directory is left.  The run is timed first
 * and the signals land around its end, where the files are written (the
 * write phase itself is covered deterministically by
 * test_sigterm_while_writing). */
#define WIDE_RUN                                                                                  \
    "run configs/ess_type_a.ini --quiet --units 2000 --set campaign.alpha_step_deg=2 "            \
    "--set campaign.beta_deg=0 --set validation.alpha_step_deg=5"

static void test_cli_sigterm(void **state)
{
    char out[8192], cmd[1024], o[256];
    snprintf(o, sizeof o, "%s/timed", dir);
    snprintf(cmd, sizeof cmd, "%s " WIDE_RUN " --out %s", test_sunmc(), o);
    double t0 = now_s();
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    double t_run = now_s() - t0;
    const double at[] = {0.5, 0.85, 0.92, 0.97, 1.0, 1.03};
    for (int i = 0; i < 6; i++) {
        snprintf(o, sizeof o, "%s/sig%d", dir, i);
        snprintf(cmd, sizeof cmd,
                 "%s " WIDE_RUN " --out %s & sleep %.3f; kill -TERM $! 2>/dev/null; wait $!",
                 test_sunmc(), o, at[i] * t_run);
        int st = test_run(cmd, out, sizeof out);
        assert_int_equal(hidden_entries(dir), 0);
        if (!exists(o)) {
            assert_int_equal(st, 128 + SIGTERM);
            continue;
        }
        assert_int_equal(entries(o), 6);
        snprintf(cmd, sizeof cmd, "test $(wc -l < %s/units.tsv) -eq 2001 && "
                 "test $(wc -l < %s/summary.tsv) -ge 2 && grep -q '^\\[run\\]' %s/config.ini",
                 o, o, o);
        assert_int_equal(system(cmd), 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_check_refuses, setup, teardown),
        cmocka_unit_test_setup_teardown(test_check_accepts, setup, teardown),
        cmocka_unit_test_setup_teardown(test_commit_replaces_whole, setup, teardown),
        cmocka_unit_test_setup_teardown(test_abort_keeps_old, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_error_at_commit, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sigterm_while_writing, setup, teardown),
        cmocka_unit_test_setup_teardown(test_handlers_restored, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cli_bad_out_at_once, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cli_no_stale_files, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cli_write_fails_table_kept, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cli_sigterm, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
