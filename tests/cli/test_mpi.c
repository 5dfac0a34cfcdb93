/* test_mpi.c - `mpirun -np R sunmc run` splits the units across R ranks
 * and writes the files of a single process byte for byte: 2 ranks of one
 * thread against --threads 2, 3 ranks with a last round short, and a
 * --until stop inside a round.  Runs when the binary under test is an MPI
 * build (make MPI=1, make test-mpi) and mpirun is installed; passes with a
 * note otherwise. */
#include "test_util.h"

static char dir[128];

#define RUN "run configs/ess_type_a.ini --quiet --set campaign.alpha_step_deg=0.4 " \
            "--set validation.alpha_step_deg=0.7 --set campaign.beta_deg=-15,15 "    \
            "--set run.block_units=32"
/* Ranks started by MPICH's or Open MPI's launcher, on this machine; the
 * sanitizers' leak checker would report the MPI library's own. */
#define MPIRUN "ASAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 " \
               "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -np"

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "mpi");
}

/* An MPI build with a launcher at hand? */
static int mpi_present(void)
{
    char out[1024];
    if (test_sunmc_in(dir, "--version", out, sizeof out) != 0 || !strstr(out, "built with MPI"))
        return 0;
    return test_run("command -v mpirun", out, sizeof out) == 0;
}

static void same_files(const char *a, const char *b)
{
    const char *files[] = {"summary.tsv", "units.tsv", "config.ini", "manifest.ini", "units.bin"};
    char cmd[1024], out[256];
    for (int i = 0; i < 5; i++) {
        snprintf(cmd, sizeof cmd, "cmp %s/%s/%s %s/%s/%s", dir, a, files[i], dir, b, files[i]);
        if (test_run(cmd, out, sizeof out) != 0)
            fail_msg("%s differs between %s and %s", files[i], a, b);
    }
}

/* `mpirun -np ranks sunmc RUN extra` against `sunmc RUN extra --threads 2`. */
static void ranks_equal_threads(int ranks, const char *extra, const char *name)
{
    char args[2048], out[16384], cmd[4096];
    snprintf(args, sizeof args, RUN " %s --threads 2 --out $D/%s_t2", extra, name);
    assert_int_equal(test_sunmc_in(dir, args, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "D=%s; " MPIRUN " %d %s " RUN " %s --threads 1 --out $D/%s_mpi", dir,
             ranks, test_sunmc(), extra, name);
    int st = test_run(cmd, out, sizeof out);
    if (st != 0)
        fail_msg("mpirun: exit %d\n%.3000s", st, out);
    char t2[64], mpi[64];
    snprintf(t2, sizeof t2, "%s_t2", name);
    snprintf(mpi, sizeof mpi, "%s_mpi", name);
    same_files(t2, mpi);
}

static void two_ranks_equal_two_threads(void **state)
{
    if (!mpi_present()) {
        printf("test_mpi: not an MPI build or no mpirun: skipped (make test-mpi)\n");
        return;
    }
    ranks_equal_threads(2, "--units 300", "np2");
}

static void three_ranks_short_last_round(void **state)
{
    if (!mpi_present())
        return;
    ranks_equal_threads(3, "--units 250", "np3"); /* 8 blocks: the last round has 2 */
}

/* --until stops at a block inside a round: the other ranks' blocks of the
 * round are received and dropped, every rank ends. */
static void until_stops_every_rank(void **state)
{
    if (!mpi_present())
        return;
    ranks_equal_threads(2, "--units 600 --until rms_after_mean:0.00025", "until");
}

/* --format hdf5 under mpirun: rank 0 writes results.h5 from the tables,
 * the same bytes as a threads-only run (issue 28.5). */
static void ranks_write_hdf5(void **state)
{
    if (!mpi_present())
        return;
    ranks_equal_threads(2, "--units 100 --format hdf5", "h5");
    char cmd[1024], out[256];
    snprintf(cmd, sizeof cmd, "cmp %s/h5_t2/results.h5 %s/h5_mpi/results.h5", dir, dir);
    if (test_run(cmd, out, sizeof out) != 0)
        fail_msg("results.h5 differs between 2 ranks and 2 threads: %s", out);
}

/* A resume under mpirun: a run whose files hit the file-size limit keeps
 * the blocks its checkpoint could hold; 2 ranks resume it from there. */
static void ranks_resume_a_checkpoint(void **state)
{
    if (!mpi_present())
        return;
    char out[16384], cmd[4096];
    snprintf(cmd, sizeof cmd, "D=%s; %s " RUN " --units 300 --threads 2 --out $D/res_t2", dir,
             test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "D=%s; (trap '' XFSZ; ulimit -f 40; %s " RUN " --units 300 "
             "--out $D/res_mpi) 2>&1; test -d $D/.res_mpi.resume", dir, test_sunmc());
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    if (!strstr(out, "this writes them without running them again"))
        fail_msg("no checkpoint note in: %.3000s", out);
    snprintf(cmd, sizeof cmd, "D=%s; " MPIRUN " 2 %s " RUN " --units 300 --threads 1 "
             "--out $D/res_mpi --resume", dir, test_sunmc());
    int st = test_run(cmd, out, sizeof out);
    if (st != 0)
        fail_msg("mpirun --resume: exit %d\n%.3000s", st, out);
    same_files("res_t2", "res_mpi");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(two_ranks_equal_two_threads),
        cmocka_unit_test(three_ranks_short_last_round),
        cmocka_unit_test(until_stops_every_rank),
        cmocka_unit_test(ranks_resume_a_checkpoint),
        cmocka_unit_test(ranks_write_hdf5),
    };
    return cmocka_run_group_tests_name("mpi", tests, setup, NULL);
}
