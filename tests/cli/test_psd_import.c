/* test_psd_import.c - scripts/psd-import.py and scripts/psd-score.py end to
 * end on synthetic files of the three public formats (.mat written here with
 * scipy, the kenscl CSV and the 14og YAML by hand): a well-formed set gives
 * the right CSV rows, and every input the importer cannot stand behind
 * (non-finite, complex, empty, mis-shaped, off the grid, out of range, an
 * --out that is an input or a folder, a full disk) is refused with
 * "psd-import.py: FILE: message", exit 2, nothing written, the input
 * untouched, never a traceback (issue 36). */
#include "test_util.h"

#include "csv.h"

#include <string.h>
#include <sys/stat.h>

static char dir[512];

/* $D/mk.py PATH EXPR ...: writes each PATH as a .mat whose data_a is EXPR,
 * evaluated with np, g (the 810 x 4 grid of the file's beta: channel k of
 * reading r at alpha index j is 100 beta + 10 j + k + r / 100, so every
 * value says where it came from), put(R, C, V) (g with g[R, C] = V),
 * cell(X, ...) (a cell array) and data_d the grid's counts; an EXPR that is a dict is saved as it is. */
static const char mk_py[] =
    "import os, re, sys, numpy as np, scipy.io\n"
    "for path, expr in zip(sys.argv[1::2], sys.argv[2::2]):\n"
    "    m = re.search(r'beta_(-?[0-9]+(\\.[0-9]+)?)\\.mat$', path)\n"
    "    beta = float(m.group(1)) if m else 0.0\n"
    "    g = np.array([[100 * beta + 10 * j + k + r / 100 for k in range(4)]\n"
    "                  for j in range(81) for r in range(10)])\n"
    "    d = np.array([[(10 * j + k + r) % 4096 for k in range(4)]\n"
    "                  for j in range(81) for r in range(10)], dtype=np.uint16)\n"
    "    d[0, 0], d[1, 0] = 0, 4095\n"
    "    def put(r, c, v):\n"
    "        a = g.astype(np.result_type(g, v))\n"
    "        a[r, c] = v\n"
    "        return a\n"
    "    def cell(*items):\n"
    "        a = np.empty((1, len(items)), dtype=object)\n"
    "        for i, x in enumerate(items):\n"
    "            a[0, i] = x\n"
    "        return a\n"
    "    v = eval(expr)\n"
    "    os.makedirs(os.path.dirname(path) or '.', exist_ok=True)\n"
    "    scipy.io.savemat(path, v if isinstance(v, dict) else {'data_a': v, 'data_d': d})\n";

static int setup(void **state)
{
    if (test_private_dir(dir, sizeof dir, "psd_import") != 0)
        return -1;
    char p[600];
    snprintf(p, sizeof p, "%s/mk.py", dir);
    return test_write_file(p, mk_py);
}

/* Run a shell command with $D the suite's folder. */
static int sh(const char *args, char *out, size_t len)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "D=%s; %s", dir, args);
    return test_run(cmd, out, len);
}

static int importer(const char *args, char *out, size_t len)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "scripts/psd-import.py %s", args);
    return sh(cmd, out, len);
}

/* Write .mat files: "PATH EXPR ..." arguments of mk.py, paths under $D. */
static void mat(const char *args)
{
    char out[8192], cmd[4096];
    snprintf(cmd, sizeof cmd, "cd $D && /usr/bin/python3 mk.py %s", args);
    if (sh(cmd, out, sizeof out) != 0)
        fail_msg("writing .mat files needs python3-scipy (scripts/install-deps.sh): %s", out);
}

static void write_in(const char *name, const char *text)
{
    char p[1024];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "mkdir -p \"$(dirname %s)\"", p);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(test_write_file(p, text), 0);
}

/* The whole of $D/name (static buffer), "" when absent. */
static const char *slurp(const char *name)
{
    static char buf[65536];
    char p[1024];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    buf[0] = '\0';
    FILE *f = fopen(p, "rb");
    if (f) {
        size_t n = fread(buf, 1, sizeof buf - 1, f);
        buf[n] = '\0';
        fclose(f);
    }
    return buf;
}

/* No *.tmp file anywhere under $D. */
static void no_temp_left(void)
{
    char out[4096];
    assert_int_equal(sh("find $D -name '*.tmp' | head -3", out, sizeof out), 0);
    if (out[0])
        fail_msg("temporary files left: %s", out);
}

/* `psd-import.py ARGS --out $D/OUT` (OUT "no.csv" unless ARGS has --out):
 * exit 2, one line "psd-import.py: " naming `file` and saying `what`, no
 * traceback nor unexpected error, $D/no.csv not made (removed first, so a
 * failure does not spill into the next case), no temporary file. */
static void refused(const char *args, const char *file, const char *what)
{
    char out[16384], full[2048];
    snprintf(full, sizeof full, "rm -f $D/no.csv; scripts/psd-import.py %s%s", args,
             strstr(args, "--out") ? "" : " --out $D/no.csv");
    int rc = sh(full, out, sizeof out);
    if (rc != 2 || strncmp(out, "psd-import.py: ", 15) != 0 || !strstr(out, file) ||
        !strstr(out, what) || strstr(out, "Traceback") || strstr(out, "unexpected"))
        fail_msg("%s: exit %d, want 2 naming '%s' and '%s':\n%s", full, rc, file,
                 what, out);
    if (strchr(out, '\n') != out + strlen(out) - 1)
        fail_msg("%s: more than one line:\n%s", full, out);
    assert_string_equal(slurp("no.csv"), "");
    no_temp_left();
}

/* The CSV rows of $D/name. */
static csv_table *load(const char *name)
{
    char p[1024], err[SUNMC_ERRLEN];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    csv_table *t = NULL;
    if (csv_read(p, &t, err, sizeof err) != SUNMC_OK)
        fail_msg("%s", err);
    return t;
}

static double cell(const csv_table *t, size_t row, size_t col)
{
    return strtod(t->field[row * (size_t)t->n_cols + col], NULL);
}

/* ---- aeroztark: the right rows ---- */

/* Two beta files, -2 and 89.5 (the largest beta below 90, one past in
 * aeroztark_beta_range): 2 x 810 rows, alphas -40..40 deg in 1 deg steps
 * of 10 readings each, channels in the file's order, sorted by name. */
static void aeroztark_rows(void **state)
{
    char out[4096];
    mat("az/beta_-2.mat g az/beta_89.5.mat g");
    assert_int_equal(sh("umask 022; scripts/psd-import.py aeroztark $D/az --out $D/az.csv", out,
                        sizeof out),
                     0);
    csv_table *t = load("az.csv");
    assert_int_equal((int)t->n_rows, 1620);
    /* row 15: alpha index 1 (-39 deg), reading 5 of beta -2 */
    assert_near(cell(t, 15, 0), -39, 0);
    assert_near(cell(t, 15, 1), -2, 0);
    assert_near(cell(t, 15, 2), -200 + 10 + 0 + 0.05, 1e-9);
    assert_near(cell(t, 15, 5), -200 + 10 + 3 + 0.05, 1e-9);
    assert_near(cell(t, 0, 0), -40, 0);
    assert_near(cell(t, 809, 0), 40, 0);
    assert_near(cell(t, 810, 0), -40, 0);
    assert_near(cell(t, 810, 1), 89.5, 0);
    assert_near(cell(t, 1619, 4), 8950 + 800 + 2 + 0.09, 1e-6);
    csv_free(t);
    assert_non_null(strstr(slurp("az.csv"), "# source: beta_-2.mat\n"));
    assert_non_null(strstr(slurp("az.csv"), "# source: beta_89.5.mat\n"));
    char p[1024];
    struct stat st;
    snprintf(p, sizeof p, "%s/az.csv", dir);
    assert_int_equal(stat(p, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0644); /* as any file the user writes */
    no_temp_left();
}

/* --digital reads data_d, 12-bit counts 0 and 4095 included. */
static void aeroztark_digital_rows(void **state)
{
    char out[4096];
    mat("dg/beta_3.mat g");
    assert_int_equal(importer("aeroztark $D/dg/beta_3.mat --digital --out $D/dg.csv", out,
                              sizeof out),
                     0);
    csv_table *t = load("dg.csv");
    assert_int_equal((int)t->n_rows, 810);
    assert_near(cell(t, 0, 2), 0, 0);
    assert_near(cell(t, 1, 2), 4095, 0);
    assert_near(cell(t, 23, 5), (10 * 2 + 3 + 3) % 4096, 0);
    csv_free(t);
}

/* ---- aeroztark: refusals ---- */

static void aeroztark_non_finite(void **state)
{
    mat("nf/beta_1.mat 'put(5,2,np.nan)' pi/beta_1.mat 'put(0,0,np.inf)' "
        "mi/beta_1.mat 'put(809,3,-np.inf)'");
    refused("aeroztark $D/nf", "beta_1.mat", "data_a row 6 channel 3 is nan");
    refused("aeroztark $D/pi/beta_1.mat", "beta_1.mat", "row 1 channel 1 is inf");
    refused("aeroztark $D/mi", "beta_1.mat", "row 810 channel 4 is -inf");
}

static void aeroztark_complex_empty_cell(void **state)
{
    mat("cx/beta_1.mat g+1j "
        "e0/beta_1.mat 'np.zeros((0,4))' "
        "ce/beta_1.mat \"{'data_a':cell(g,'x')}\" "
        "nv/beta_1.mat \"{'other':g}\"");
    refused("aeroztark $D/cx", "cx/beta_1.mat", "complex numbers");
    refused("aeroztark $D/e0", "e0/beta_1.mat", "data_a is empty (0 x 4)");
    refused("aeroztark $D/ce", "ce/beta_1.mat", "a cell array");
    refused("aeroztark $D/nv", "nv/beta_1.mat", "no variable data_a");
}

/* 81 x 10 rows of 4 channels, no fewer, no more: a beta_5.mat of 400 rows
 * among 810-row files is named with what it has. */
static void aeroztark_grid(void **state)
{
    mat("gr/beta_1.mat g gr/beta_5.mat 'g[:400]' g8/beta_1.mat 'g[:800]' "
        "g9/beta_1.mat 'g[:809]' g1/beta_1.mat 'np.vstack([g,g[:1]])' "
        "g3/beta_1.mat 'g[:,:3]' gt/beta_1.mat g.T");
    refused("aeroztark $D/gr", "beta_5.mat", "data_a is 400 x 4, want 810 x 4");
    refused("aeroztark $D/g8", "beta_1.mat", "is 800 x 4");
    refused("aeroztark $D/g9", "beta_1.mat", "is 809 x 4");
    refused("aeroztark $D/g1", "beta_1.mat", "is 811 x 4");
    refused("aeroztark $D/g3", "beta_1.mat", "is 810 x 3");
    refused("aeroztark $D/gt", "beta_1.mat", "is 4 x 810");
}

static void aeroztark_digital_range(void **state)
{
    mat("d6/beta_1.mat \"{'data_d':np.full((810,4),4096,dtype=np.uint16)}\" "
        "dh/beta_1.mat \"{'data_d':np.full((810,4),1.5)}\"");
    refused("aeroztark $D/d6 --digital", "beta_1.mat", "is 4096, not a 12-bit count");
    refused("aeroztark $D/dh --digital", "beta_1.mat", "is 1.5, not a 12-bit count");
    refused("kenscl $D/d6 --digital", "--digital", "only aeroztark");
}

/* File names: beta a number within (-90, 90), one file per beta. */
static void aeroztark_names(void **state)
{
    mat("n1/beta_1.2.3.mat g n2/beta_..mat g n3/beta_1.mat g n3/beta_1.0.mat g "
        "n4/beta_90.mat g n5/beta_-90.mat g n6/beta_x.mat g");
    refused("aeroztark $D/n1", "beta_1.2.3.mat", "must be beta_<deg>.mat");
    refused("aeroztark $D/n1/beta_1.2.3.mat", "beta_1.2.3.mat", "must be beta_<deg>.mat");
    refused("aeroztark $D/n2", "beta_..mat", "must be beta_<deg>.mat");
    refused("aeroztark $D/n3", "beta_1.mat", "beta 1 deg is also beta_1.0.mat");
    refused("aeroztark $D/n4", "beta_90.mat", "beta 90 deg is outside (-90, 90)");
    refused("aeroztark $D/n5", "beta_-90.mat", "beta -90 deg is outside");
    refused("aeroztark $D/n6", "beta_x.mat", "must be beta_<deg>.mat");
    write_in("nm/beta_1.mat", "not a mat file");
    refused("aeroztark $D/nm", "beta_1.mat", "not a MATLAB v5 file");
    refused("aeroztark $D/nothing", "nothing", "no such file");
    write_in("em/readme.txt", "x");
    refused("aeroztark $D/em", "em", "no file matches");
}

/* ---- kenscl ---- */

static const char ken_head[] = "# Sensor: ADPD2140, Rotationstage: ELL18M\n"
                               "Datetime,Stage Angle,xL,xR,yL,yR,X,Y\n";

static void ken_file(const char *name, const char *rows)
{
    char text[4096];
    snprintf(text, sizeof text, "%s%s", ken_head, rows);
    write_in(name, text);
}

/* i1..i4 = yL, yR, xL, xR; the stage angle is alpha in _X, beta in _Y,
 * up to 89.99 deg either way; a folder's files in sorted order. */
static void kenscl_rows(void **state)
{
    char out[4096];
    ken_file("ken/a_X.txt", "01.12.2021 18:29:29,-59.992,650.634,648.529,392.150,718.597,-46.5,0\n"
                            "01.12.2021 18:29:30,89.99,653.198,650.604,393.188,720.397,-46.5,0\n");
    ken_file("ken/b_Y.txt", "x,12.5,1,2,3,4,0,0\nx,-89.99,1,2,3,4,0,0\n");
    write_in("ken/notes.txt", "ignored: neither _X nor _Y");
    assert_int_equal(importer("kenscl $D/ken --out $D/ken.csv", out, sizeof out), 0);
    const char *csv = slurp("ken.csv");
    const char *want = "alpha_deg,beta_deg,i1,i2,i3,i4\n"
                       "# source: a_X.txt\n"
                       "-59.992,0,392.15,718.597,650.634,648.529\n"
                       "89.99,0,393.188,720.397,653.198,650.604\n"
                       "# source: b_Y.txt\n"
                       "0,12.5,3,4,1,2\n"
                       "0,-89.99,3,4,1,2\n";
    const char *body = strstr(csv, "alpha_deg");
    assert_non_null(body);
    assert_string_equal(body, want);
}

/* The hostile tester's `kenscl ken/keep_X.txt --out ken/keep_X.txt`, and
 * the same file reached through the folder, a symbolic and a hard link. */
static void kenscl_out_is_input(void **state)
{
    ken_file("keep/keep_X.txt", "x,1,1,2,3,4,0,0\n");
    char before[4096];
    snprintf(before, sizeof before, "%s", slurp("keep/keep_X.txt"));
    char out[1024];
    assert_int_equal(sh("ln -s keep_X.txt $D/keep/sym.csv && ln $D/keep/keep_X.txt $D/hard.csv",
                        out, sizeof out),
                     0);
    refused("kenscl $D/keep/keep_X.txt --out $D/keep/keep_X.txt", "keep_X.txt", "is the input");
    refused("kenscl $D/keep --out $D/keep/keep_X.txt", "keep_X.txt", "is the input");
    refused("kenscl $D/keep --out $D/keep/../keep/keep_X.txt", "keep_X.txt", "is the input");
    refused("kenscl $D/keep --out $D/keep/sym.csv", "sym.csv", "is the input");
    refused("kenscl $D/keep/keep_X.txt --out $D/hard.csv", "hard.csv", "is the input");
    assert_string_equal(slurp("keep/keep_X.txt"), before);
}

static void kenscl_cells(void **state)
{
    const char *bad[][3] = {
        {"nan", "x,1,nan,2,3,4,0,0\n", "xL is not a number: 'nan'"},
        {"inf", "x,1,1,inf,3,4,0,0\n", "xR is not a number: 'inf'"},
        {"minf", "x,1,1,2,-inf,4,0,0\n", "yL is not a number: '-inf'"},
        {"huge", "x,1,1,2,3,1e999,0,0\n", "yR is out of range: '1e999'"},
        {"under", "x,1,1_0,2,3,4,0,0\n", "xL is not a number: '1_0'"},
        {"three", "x,1,1\n", "3 cells, the header has 8"},
        {"nine", "x,1,1,2,3,4,0,0,9\n", "9 cells, the header has 8"},
        {"s90", "x,90,1,2,3,4,0,0\n", "Stage Angle 90 deg is outside (-90, 90)"},
        {"sm90", "x,-90,1,2,3,4,0,0\n", "Stage Angle -90 deg is outside"},
        {"empty", "", "no data rows"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char name[64], args[256], file[80];
        snprintf(name, sizeof name, "kc/%s_X.txt", bad[i][0]);
        ken_file(name, bad[i][1]);
        snprintf(args, sizeof args, "kenscl $D/%s", name);
        /* the line is named (the rows start on line 3) */
        snprintf(file, sizeof file, "%s_X.txt%s", bad[i][0], bad[i][1][0] ? ":3" : "");
        refused(args, file, bad[i][2]);
        char rm[600];
        snprintf(rm, sizeof rm, "rm %s/%s", dir, name);
        assert_int_equal(system(rm), 0);
    }
    write_in("kc/bad.txt", "Datetime,Stage Angle,xL\n");
    refused("kenscl $D/kc/bad.txt", "bad.txt", "_X.txt or _Y.txt");
    write_in("kc/bad_X.txt", "Datetime,Stage Angle,xL\n1,2,3\n");
    refused("kenscl $D/kc/bad_X.txt", "bad_X.txt:1", "header lacks");
}

/* ---- 14og ---- */

/* elevation 30, azimuth 90: the sun along +Y, alpha 0, beta 30; the
 * channels' ratios give back x and y; elevation 0 and 89.9, azimuth -360
 * and 360, x and y +-1 are taken. */
static void og14_rows(void **state)
{
    char out[4096];
    write_in("og/m.yaml", "- elevation: 30.0\n  azimuth: 90.0\n  x: 0.1\n  y: -0.2\n"
                          "- elevation: 0.0\n  azimuth: -360\n  x: 1\n  y: -1\n"
                          "- elevation: 89.9\n  azimuth: 360\n  x: -1.0\n  y: 1.0\n"
                          "- elevation: 45\n  azimuth: 0\n  x: 1.5e-1\n  y: 0\n");
    assert_int_equal(importer("14og $D/og/m.yaml --out $D/og.csv", out, sizeof out), 0);
    csv_table *t = load("og.csv");
    assert_int_equal((int)t->n_rows, 4);
    assert_near(cell(t, 0, 0), 0, 1e-9);
    assert_near(cell(t, 0, 1), 30, 1e-9);
    double v[4], sum = 0;
    for (int k = 0; k < 4; k++)
        sum += v[k] = cell(t, 0, 2 + (size_t)k);
    assert_near((v[1] + v[2] - v[0] - v[3]) / sum, 0.1, 1e-9);
    assert_near((v[1] + v[3] - v[0] - v[2]) / sum, -0.2, 1e-9);
    assert_near(cell(t, 1, 0), 0, 1e-9);
    assert_near(cell(t, 2, 0), 89.9, 1e-7); /* azimuth 360: the sun along +X */
    assert_near(cell(t, 3, 0), 45, 1e-9);
    assert_near(cell(t, 3, 3) + cell(t, 3, 4) - cell(t, 3, 2) - cell(t, 3, 5), 0.15, 1e-9);
    csv_free(t);
}

static void og14_refusals(void **state)
{
    const char *bad[][3] = {
        {"nan", "- elevation: .nan\n  azimuth: 0\n  x: 0\n  y: 0\n", "elevation is out of range"},
        {"inf", "- elevation: 1\n  azimuth: -.inf\n  x: 0\n  y: 0\n", "azimuth is out of range"},
        {"e400", "- elevation: 1e400\n  azimuth: 0\n  x: 0\n  y: 0\n",
         "elevation is out of range: '1e400'"},
        {"f400", "- elevation: 1.0e+400\n  azimuth: 0\n  x: 0\n  y: 0\n",
         "elevation is out of range"},
        {"e90", "- elevation: 90\n  azimuth: 0\n  x: 0\n  y: 0\n", "elevation 90 is outside [0, 90)"},
        {"e95", "- elevation: 95\n  azimuth: 0\n  x: 0\n  y: 0\n", "elevation 95 is outside"},
        {"e180", "- elevation: 180\n  azimuth: 0\n  x: 0\n  y: 0\n", "elevation 180 is outside"},
        {"eneg", "- elevation: -0.5\n  azimuth: 0\n  x: 0\n  y: 0\n", "elevation -0.5 is outside"},
        {"az", "- elevation: 5\n  azimuth: 361\n  x: 0\n  y: 0\n", "azimuth 361 is outside"},
        {"x", "- elevation: 5\n  azimuth: 0\n  x: 1.01\n  y: 0\n", "x 1.01 is outside [-1, 1]"},
        {"y", "- elevation: 5\n  azimuth: 0\n  x: 0\n  y: -1.5\n", "y -1.5 is outside"},
        {"bool", "- elevation: true\n  azimuth: 0\n  x: 0\n  y: 0\n", "is not a number: True"},
        {"text", "- elevation: high\n  azimuth: 0\n  x: 0\n  y: 0\n", "is not a number: 'high'"},
        {"lacks", "- elevation: 3\n  x: 1\n", "point 1 lacks elevation, azimuth"},
        {"scalar", "- 3\n", "point 1 lacks"},
        {"syntax", "- elevation: [1,\n  azimuth: 0\n", "not YAML"},
        {"map", "elevation: 3\n", "not a list of points"},
        {"empty", "", "not a list of points"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char name[64], args[256];
        snprintf(name, sizeof name, "oy/%s.yaml", bad[i][0]);
        write_in(name, bad[i][1]);
        snprintf(args, sizeof args, "14og $D/%s", name);
        refused(args, name, bad[i][2]);
    }
    refused("14og $D/oy/missing.yaml", "missing.yaml", "no such file");
    refused("14og $D/oy", "oy", "is a folder");
}

/* ---- where the CSV goes ---- */

static void out_refusals(void **state)
{
    char out[4096];
    ken_file("o/k_X.txt", "x,1,1,2,3,4,0,0\n");
    refused("kenscl $D/o/k_X.txt --out $D/nofolder/k.csv", "nofolder", "no such folder");
    assert_int_equal(sh("mkdir -p $D/outdir", out, sizeof out), 0);
    refused("kenscl $D/o/k_X.txt --out $D/outdir", "outdir", "is a folder");
    refused("kenscl $D/o --out $D/o", "o", "is a folder");
    assert_int_equal(importer("kenscl $D/o/k_X.txt", out, sizeof out), 2); /* no --out */
    assert_non_null(strstr(out, "usage: psd-import.py"));
}

/* A write that fails (a full disk: here the file-size limit of 0 bytes,
 * the same failing write): exit 2 naming the CSV, no temporary file, an
 * earlier CSV of that name untouched; a good import then replaces it. */
static void out_write_fails(void **state)
{
    char out[4096];
    ken_file("w/k_X.txt", "x,1,1,2,3,4,0,0\n");
    write_in("w.csv", "earlier\n");
    int rc = sh("ulimit -f 0; scripts/psd-import.py kenscl $D/w/k_X.txt --out $D/w.csv", out,
                sizeof out);
    if (rc != 2 || !strstr(out, "psd-import.py: ") || !strstr(out, "w.csv: cannot write") ||
        strstr(out, "Traceback"))
        fail_msg("exit %d: %s", rc, out);
    assert_string_equal(slurp("w.csv"), "earlier\n");
    no_temp_left();
    assert_int_equal(importer("kenscl $D/w/k_X.txt --out $D/w.csv", out, sizeof out), 0);
    assert_non_null(strstr(slurp("w.csv"), "1,0,3,4,1,2\n"));
}

/* A refused import leaves an earlier CSV of that name as it was. */
static void refusal_keeps_earlier_csv(void **state)
{
    char out[4096];
    ken_file("r/k_X.txt", "x,1,1,nan,3,4,0,0\n");
    write_in("r.csv", "earlier\n");
    assert_int_equal(importer("kenscl $D/r/k_X.txt --out $D/r.csv", out, sizeof out), 2);
    assert_string_equal(slurp("r.csv"), "earlier\n");
}

/* --help prints the rules it keeps. */
static void help_text(void **state)
{
    char out[16384];
    assert_int_equal(importer("--help", out, sizeof out), 0);
    assert_non_null(strstr(out, "810 x 4"));
    assert_non_null(strstr(out, "Elevation within [0, 90)"));
    assert_non_null(strstr(out, "Refused, with \"psd-import.py: FILE[:LINE]: message\""));
}

/* ---- psd-score.py ---- */

static const char score_head[] = "alpha_deg,beta_deg,i1,compensated_alpha_deg,"
                                 "compensated_beta_deg,truth_alpha_deg,truth_beta_deg\n";

static int score(const char *name, const char *rows, char *out, size_t len)
{
    char text[4096], cmd[256];
    snprintf(text, sizeof text, "%s%s", score_head, rows);
    write_in(name, text);
    snprintf(cmd, sizeof cmd, "scripts/psd-score.py $D/%s", name);
    return sh(cmd, out, len);
}

/* 1" off in beta on one row, a nan row counted as failed. */
static void score_rows(void **state)
{
    char out[4096];
    assert_int_equal(score("s/ok.csv", "1,2,0,1,2.000277777777778,1,2\n1,2,0,nan,nan,1,2\n", out,
                           sizeof out),
                     0);
    assert_non_null(strstr(out, "1 readings, 1 failed; RMS total 1.0 arcsec, alpha 0.0, beta 1.0"));
}

static void score_refusals(void **state)
{
    const char *bad[][3] = {
        {"s/inf.csv", "1,2,0,inf,2,1,2\n", ":2: compensated_alpha_deg is not a finite"},
        {"s/short.csv", "1,2,0\n", ":2: 3 cells, the header has 7"},
        {"s/text.csv", "1,2,0,1,x,1,2\n", ":2: compensated_beta_deg is not a finite"},
        {"s/none.csv", "1,2,0,nan,nan,1,2\n", "no row could be scored (1 failed)"},
    };
    char out[4096];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        int rc = score(bad[i][0], bad[i][1], out, sizeof out);
        const char *what = bad[i][2];
        if (rc != 2 || strncmp(out, "psd-score.py: ", 14) != 0 || !strstr(out, bad[i][0]) ||
            !strstr(out, what) || strstr(out, "Traceback") || strstr(out, "unexpected"))
            fail_msg("psd-score.py %s: exit %d, want 2 saying '%s':\n%s", bad[i][0], rc, what, out);
    }
    assert_int_equal(sh("scripts/psd-score.py $D/s/missing.csv", out, sizeof out), 2);
    assert_non_null(strstr(out, "psd-score.py: "));
    assert_non_null(strstr(out, "missing.csv: cannot read"));
    write_in("s/nocol.csv", "alpha_deg,beta_deg\n1,2\n");
    assert_int_equal(sh("scripts/psd-score.py $D/s/nocol.csv", out, sizeof out), 2);
    assert_non_null(strstr(out, "nocol.csv:1: no column compensated_alpha_deg"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(aeroztark_rows),
        cmocka_unit_test(aeroztark_digital_rows),
        cmocka_unit_test(aeroztark_non_finite),
        cmocka_unit_test(aeroztark_complex_empty_cell),
        cmocka_unit_test(aeroztark_grid),
        cmocka_unit_test(aeroztark_digital_range),
        cmocka_unit_test(aeroztark_names),
        cmocka_unit_test(kenscl_rows),
        cmocka_unit_test(kenscl_out_is_input),
        cmocka_unit_test(kenscl_cells),
        cmocka_unit_test(og14_rows),
        cmocka_unit_test(og14_refusals),
        cmocka_unit_test(out_refusals),
        cmocka_unit_test(out_write_fails),
        cmocka_unit_test(refusal_keeps_earlier_csv),
        cmocka_unit_test(help_text),
        cmocka_unit_test(score_rows),
        cmocka_unit_test(score_refusals),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
