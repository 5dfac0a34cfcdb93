/* test_hdf5.c - issue 28 item 5: `sunmc run --format hdf5 --out DIR` writes
 * DIR/results.h5 beside the TSV files: byte-identical at 1 and 2 threads; the
 * documented loader (docs/examples/load_h5.py, h5py) reads columns equal to
 * units.tsv's and summary.tsv's printed values and the config as attributes;
 * bad --format values, the refused combinations and a missing HDF5 library
 * exit 2 writing nothing;
 * h5out's own error paths (missing table, ragged row) and its typing rules
 * (int64, float64, "-" as nan, text). */
#include "test_util.h"

#include "h5out.h"
#include "status.h"

#include <math.h>
#include <unistd.h>

static char dir[512];

static int setup(void **state)
{
    return test_private_dir(dir, sizeof dir, "h5");
}

#define E "configs/ess_type_a.ini"
#define TINY "--set campaign.alpha_step_deg=2 --set validation.alpha_step_deg=5 " \
             "--set campaign.beta_deg=-15,15 --quiet"

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

/* The check of the docs' loader against the TSV files of run directory d. */
static const char check_py[] =
    "import csv, math, sys\n"
    "sys.path.insert(0, 'docs/examples')\n"
    "from load_h5 import load\n"
    "d = sys.argv[1]\n"
    "units, summary, attrs = load(d + '/results.h5')\n"
    "def rows(p):\n"
    "    with open(p, newline='') as f:\n"
    "        return list(csv.reader(f, delimiter='\\t'))\n"
    "def same(table, cols):\n"
    "    head, body = table[0], table[1:]\n"
    "    assert sorted(head) == sorted(cols), (head, sorted(cols))\n"
    "    for j, name in enumerate(head):\n"
    "        col = cols[name]\n"
    "        assert len(col) == len(body), name\n"
    "        for i, r in enumerate(body):\n"
    "            t, v = r[j], col[i]\n"
    "            if col.dtype.kind == 'U': ok = t == v\n"
    "            elif t in ('-', 'nan'): ok = math.isnan(v)\n"
    "            elif col.dtype.kind == 'i': ok = int(t) == v\n"
    "            else: ok = float(t) == v or (math.isinf(v) and float(t) == v)\n"
    "            assert ok, (name, i, t, v)\n"
    "    return len(head)\n"
    "n = same(rows(d + '/units.tsv'), units)\n"
    "m = same(rows(d + '/summary.tsv'), summary)\n"
    "assert attrs['config'] == open(d + '/config.ini').read()\n"
    "assert attrs['family'] == 'ess' and attrs['seed'] == 1 and attrs['first'] == 0\n"
    "assert attrs['end'] == 50 and attrs['units'] == 50, attrs\n"
    "assert units['dH_um'].dtype == 'float64' and units['unit'].dtype == 'int64'\n"
    "assert list(units['unit']) == list(range(50))\n"
    "print('checked', n, m)\n";

static void test_threads_identical_and_loader_matches_tsv(void **state)
{
    char out[16384], cmd[4096];
    assert_int_equal(sunmc("run " E " --units 50 " TINY " --threads 1 --format hdf5 --out $D/t1",
                           out, sizeof out), 0);
    assert_int_equal(sunmc("run " E " --units 50 " TINY " --threads 2 --format hdf5 --out $D/t2",
                           out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "cmp %s/t1/results.h5 %s/t2/results.h5", dir, dir);
    if (test_run(cmd, out, sizeof out) != 0)
        fail_msg("results.h5 differs between 1 and 2 threads: %s", out);
    assert_true(test_file_has(test_tmp("h5/t1/.sunmc"), "file\tresults.h5\n"));
    assert_true(test_write_file(test_tmp("check.py"), check_py) == 0);
    /* Debian's python3-h5py is for the system python (scripts/install-deps.sh). */
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 %s %s/t1", test_tmp("check.py"), dir);
    if (test_run(cmd, out, sizeof out) != 0 || !strstr(out, "checked"))
        fail_msg("h5py check failed (python3-h5py: scripts/install-deps.sh): %s", out);
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 docs/examples/load_h5.py %s/t1", dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    assert_non_null(strstr(out, "seed 1, units 0:50: 50 units"));
    /* A run resumed without a checkpoint ends with the same file. */
    assert_int_equal(sunmc("run " E " --units 50 " TINY " --format hdf5 --out $D/t1 --resume",
                           out, sizeof out), 0);
    snprintf(cmd, sizeof cmd, "cmp %s/t1/results.h5 %s/t2/results.h5", dir, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
}

static void test_tsv_default_unchanged(void **state)
{
    char out[16384], cmd[4096];
    assert_int_equal(sunmc("run " E " --units 4 " TINY " --out $D/d0", out, sizeof out), 0);
    assert_int_equal(sunmc("run " E " --units 4 " TINY " --format tsv --out $D/d1", out,
                           sizeof out), 0);
    snprintf(cmd, sizeof cmd, "cmp %s/d0/units.tsv %s/d1/units.tsv && cmp %s/d0/summary.tsv "
             "%s/d1/summary.tsv && test ! -e %s/d0/results.h5 && test ! -e %s/d1/results.h5",
             dir, dir, dir, dir, dir, dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
}

static void test_format_refusals(void **state)
{
    char out[16384];
    const char *const bad[] = {
        E " --units 4 " TINY " --format xyz",
        E " --units 4 " TINY " --format HDF5",
        E " --units 4 " TINY " --format hdf5 --shard 0/2",
    };
    test_refused("run", bad, sizeof bad / sizeof *bad, test_tmp("h5/refused"));
    assert_int_equal(sunmc("run " E " --units 4 " TINY " --format xyz --out $D/x", out,
                           sizeof out), 2);
    assert_non_null(strstr(out, "--format xyz: one of tsv, hdf5"));
    assert_int_equal(sunmc("run " E " --units 4 " TINY " --format hdf5 --shard 1/2 --out $D/x",
                           out, sizeof out), 2);
    assert_non_null(strstr(out, "merge`, which writes TSV only"));
    assert_int_equal(sunmc("run " E " --units 4 " TINY " --format hdf5", out, sizeof out), 2);
    assert_non_null(strstr(out, "it needs --out DIR"));
}

/* The HDF5 library is loaded, not linked (h5out_load): a machine without it
 * (or a library that is not HDF5) refuses --format hdf5 before any unit,
 * exit 2, nothing written, saying how to install it; tsv runs need none. */
static void test_library_missing_refused(void **state)
{
    char out[16384], cmd[4096];
    static const char *const libs[] = {"libsunmc-no-such-hdf5.so.1", "libm.so.6"};
    static const char *const says[] = {"needs the HDF5 library (libsunmc-no-such-hdf5.so.1)",
                                       "libm.so.6 is not an HDF5 library sunmc can use (no "};
    for (int k = 0; k < 2; k++) {
        snprintf(cmd, sizeof cmd, "SUNMC_HDF5_LIB=%s %s run " E " --units 4 " TINY
                 " --format hdf5 --out %s/nolib", libs[k], test_sunmc(), dir);
        assert_int_equal(test_run(cmd, out, sizeof out), 2);
        assert_non_null(strstr(out, says[k]));
        assert_true(k > 0 || strstr(out, "scripts/install-deps.sh"));
        snprintf(cmd, sizeof cmd, "test ! -e %s/nolib && test ! -e %s/.nolib.resume", dir, dir);
        assert_int_equal(test_run(cmd, out, sizeof out), 0);
    }
    snprintf(cmd, sizeof cmd, "SUNMC_HDF5_LIB=libsunmc-no-such-hdf5.so.1 %s run " E
             " --units 4 " TINY " --format tsv --out %s/tsvonly", test_sunmc(), dir);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    /* and the binary does not link it: no HDF5 among its libraries */
    snprintf(cmd, sizeof cmd, "ldd %s | grep -c hdf5", test_sunmc());
    test_run(cmd, out, sizeof out);
    assert_int_equal(atoi(out), 0);
}

static const h5out_meta meta = {"ess", "P", 7, 3, 0, 3};

/* h5out alone: the typing rules, read back with h5py. */
static void test_h5out_types(void **state)
{
    char err[SUNMC_ERRLEN], out[4096], cmd[2048];
    assert_int_equal(test_write_file(test_tmp("u.tsv"),
                                     "i\tf\tm\ts\n1\t1.5\t2\ta b\n-2\tnan\t-\tc\n3\t-inf\t4\t-\n"),
                     0);
    assert_int_equal(test_write_file(test_tmp("s.tsv"), "band\tn\n0:30\t3\n"), 0);
    assert_int_equal(test_write_file(test_tmp("c.ini"), "[run]\nseed = 7\n"), 0);
    int st = h5out_write(test_tmp("r.h5"), test_tmp("u.tsv"), test_tmp("s.tsv"),
                         test_tmp("c.ini"), &meta, err, sizeof err);
    assert_int_equal(st, SUNMC_OK);
    snprintf(cmd, sizeof cmd,
             "/usr/bin/python3 -c \"import h5py, math; f = h5py.File('%s'); u = f['units']; "
             "assert u['i'].dtype == 'int64' and list(u['i']) == [1, -2, 3]; "
             "assert u['f'].dtype == 'float64' and u['f'][0] == 1.5 and math.isnan(u['f'][1]) "
             "and u['f'][2] == -math.inf; "
             "assert u['m'].dtype == 'float64' and math.isnan(u['m'][1]) and u['m'][2] == 4; "
             "assert list(u['s']) == [b'a b', b'c', b'-']; "
             "assert list(f['summary']['n']) == [3] and f['summary']['band'][0] == b'0:30'; "
             "assert f.attrs['config'] == '[run]\\nseed = 7\\n' and f.attrs['seed'] == 7; "
             "assert u.attrs['columns'] == 'i\\tf\\tm\\ts'; print('ok')\"",
             test_tmp("r.h5"));
    if (test_run(cmd, out, sizeof out) != 0 || !strstr(out, "ok"))
        fail_msg("%s", out);
}

static void test_h5out_errors(void **state)
{
    char err[SUNMC_ERRLEN];
    int st = h5out_write(test_tmp("e.h5"), test_tmp("missing.tsv"), test_tmp("s.tsv"),
                         test_tmp("c.ini"), &meta, err, sizeof err);
    assert_int_equal(st, SUNMC_EIO);
    assert_non_null(strstr(err, "missing.tsv: cannot read"));
    assert_int_not_equal(access(test_tmp("e.h5"), F_OK), 0);
    assert_int_equal(test_write_file(test_tmp("rag.tsv"), "a\tb\n1\t2\n3\n"), 0);
    st = h5out_write(test_tmp("e.h5"), test_tmp("rag.tsv"), test_tmp("s.tsv"), test_tmp("c.ini"),
                     &meta, err, sizeof err);
    assert_int_equal(st, SUNMC_EINPUT);
    assert_non_null(strstr(err, "rag.tsv:3: 1 cells, the header has 2"));
    assert_int_not_equal(access(test_tmp("e.h5"), F_OK), 0);
    assert_int_equal(test_write_file(test_tmp("dup.tsv"), "a\ta\n1\t2\n"), 0);
    st = h5out_write(test_tmp("e.h5"), test_tmp("dup.tsv"), test_tmp("s.tsv"), test_tmp("c.ini"),
                     &meta, err, sizeof err);
    assert_int_equal(st, SUNMC_EINPUT);
    assert_non_null(strstr(err, "column a twice"));
    st = h5out_write(test_tmp("nodir/e.h5"), test_tmp("u.tsv"), test_tmp("s.tsv"),
                     test_tmp("c.ini"), &meta, err, sizeof err);
    assert_int_equal(st, SUNMC_EIO);
    assert_non_null(strstr(err, "cannot create"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_threads_identical_and_loader_matches_tsv),
        cmocka_unit_test(test_tsv_default_unchanged),
        cmocka_unit_test(test_format_refusals),
        cmocka_unit_test(test_library_missing_refused),
        cmocka_unit_test(test_h5out_types),
        cmocka_unit_test(test_h5out_errors),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
