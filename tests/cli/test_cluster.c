/* test_cluster.c - the cluster recipes run unchanged on this machine with
 * the scheduler's variables faked: scripts/slurm-array.sh as array tasks
 * (SLURM_ARRAY_TASK_ID) and a merge, and through its `submit` with a
 * stand-in sbatch (tests/fake-sbatch.sh), give the files of a single run;
 * scripts/mpi-batch.sh (SLURM_NTASKS=2) does on an MPI build. */
#include "test_util.h"

static char dir[128];

#define CFG "configs/ess_type_a.ini"
#define OPTS "--units 120 --set campaign.alpha_step_deg=0.4 --set validation.alpha_step_deg=0.7 " \
             "--set campaign.beta_deg=-15,15 --set run.block_units=16"

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "cluster");
}

/* `cmd` with D = dir and SUNMC = the binary under test; its exit status. */
static int sh(const char *cmd, char *out, size_t len)
{
    char full[4096];
    snprintf(full, sizeof full, "D=%s; export SUNMC=%s; %s", dir, test_sunmc(), cmd);
    return test_run(full, out, len);
}

static void same_results(const char *a, const char *b)
{
    const char *files[] = {"summary.tsv", "units.tsv", "units.bin"};
    char cmd[1024], out[256];
    for (int i = 0; i < 3; i++) {
        snprintf(cmd, sizeof cmd, "cmp %s/%s/%s %s/%s/%s", dir, a, files[i], dir, b, files[i]);
        if (test_run(cmd, out, sizeof out) != 0)
            fail_msg("%s differs between %s and %s", files[i], a, b);
    }
}

static void single_run(void)
{
    static int done;
    char out[8192];
    if (!done++)
        assert_int_equal(sh("$SUNMC run " CFG " --quiet " OPTS " --out $D/single", out, sizeof out), 0);
}

static void slurm_array_tasks_and_merge(void **state)
{
    single_run();
    char out[16384];
    int st = sh("for k in 0 1 2; do SLURM_ARRAY_TASK_ID=$k SLURM_CPUS_PER_TASK=2 "
                "scripts/slurm-array.sh shard " CFG " $D/arr 3 " OPTS " || exit 1; done && "
                "scripts/slurm-array.sh merge " CFG " $D/arr 3",
                out, sizeof out);
    if (st != 0)
        fail_msg("exit %d\n%.3000s", st, out);
    assert_non_null(strstr(out, "merged units 0:120 from 3 shards"));
    same_results("single", "arr");
    /* a shard outside an array task is refused */
    assert_int_not_equal(sh("scripts/slurm-array.sh shard " CFG " $D/x 3", out, sizeof out), 0);
    assert_non_null(strstr(out, "SLURM_ARRAY_TASK_ID"));
}

static void slurm_array_submit_with_stand_in_sbatch(void **state)
{
    single_run();
    static char out[65536]; /* four shards' tables, then the merge's */
    int st = sh("SBATCH='bash tests/fake-sbatch.sh' scripts/slurm-array.sh submit " CFG
                " $D/sub 4 " OPTS, out, sizeof out);
    if (st != 0)
        fail_msg("exit %d\n%.3000s", st, out);
    assert_non_null(strstr(out, "shards: job array"));
    same_results("single", "sub");
}

static void mpi_batch_script(void **state)
{
    char out[16384];
    if (sh("$SUNMC --version | grep -q 'built with MPI' && command -v mpiexec", out,
           sizeof out) != 0) {
        printf("test_cluster: not an MPI build: mpi-batch.sh not run (make test-mpi)\n");
        return;
    }
    single_run();
    int st = sh("ASAN_OPTIONS=detect_leaks=0 SLURM_NTASKS=2 SLURM_CPUS_PER_TASK=1 "
                "scripts/mpi-batch.sh " CFG " $D/mpi " OPTS, out, sizeof out);
    if (st != 0)
        fail_msg("exit %d\n%.3000s", st, out);
    same_results("single", "mpi");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(slurm_array_tasks_and_merge),
        cmocka_unit_test(slurm_array_submit_with_stand_in_sbatch),
        cmocka_unit_test(mpi_batch_script),
    };
    return cmocka_run_group_tests_name("cluster", tests, setup, NULL);
}
