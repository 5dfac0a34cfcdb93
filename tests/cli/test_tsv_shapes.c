/* test_tsv_shapes.c - every TSV sunmc writes has as many fields in each row
 * as names in its header, the names unique, in every mode (issue 43): each
 * family, with and without operating temperatures, random and designed
 * sampling, `run` and `curve`.  A header that loses the temperature
 * columns while its rows keep them shifts every column a reader takes by
 * name. */
#include "test_util.h"

#include <dirent.h>

static int split(char *line, char **f, int max)
{
    int n = 0;
    line[strcspn(line, "\n")] = '\0';
    for (char *p = line; n < max;) {
        f[n++] = p;
        char *t = strchr(p, '\t');
        if (!t)
            break;
        *t = '\0';
        p = t + 1;
    }
    return n;
}

/* One file: the header's names unique, every row as wide; its row count. */
static long check_file(const char *path, const char *must_have, int unique)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    static char line[1 << 16], head[1 << 16];
    static char *names[4096], *row[4096];
    int nh = 0;
    long rows = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#' || line[0] == '\n')
            continue;
        if (!nh) {
            memcpy(head, line, sizeof head);
            nh = split(head, names, 4096);
            for (int i = 0; i < nh && unique; i++)
                for (int j = 0; j < i; j++)
                    if (strcmp(names[i], names[j]) == 0)
                        fail_msg("%s: column '%s' named twice (%d and %d)", path, names[i], j + 1,
                                 i + 1);
            continue;
        }
        int n = split(line, row, 4096);
        if (n != nh)
            fail_msg("%s: data row %ld has %d fields, the header %d", path, rows + 1, n, nh);
        rows++;
    }
    fclose(f);
    assert_true(nh > 1);
    if (must_have) {
        int found = 0;
        for (int i = 0; i < nh; i++)
            found |= strstr(names[i], must_have) != NULL;
        if (!found)
            fail_msg("%s: no column holds '%s'", path, must_have);
    }
    return rows;
}

/* Run sunmc ARGS --out DIR/name, then check every .tsv of it; want: a
 * column name piece units.tsv must hold (NULL: none). */
static void check_mode_u(const char *name, const char *args, const char *want, long units,
                         int unique)
{
    char cmd[4096], out[1 << 15], dir[512];
    snprintf(dir, sizeof dir, "%s", test_tmp(name));
    snprintf(cmd, sizeof cmd, "%s %s --quiet --out %s", test_sunmc(), args, dir);
    int rc = test_run(cmd, out, sizeof out);
    if (rc != 0)
        fail_msg("%s: exit %d\n%s", cmd, rc, out);
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    int files = 0;
    while ((e = readdir(d))) {
        size_t l = strlen(e->d_name);
        if (l < 5 || strcmp(e->d_name + l - 4, ".tsv") != 0)
            continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        int is_units = strcmp(e->d_name, "units.tsv") == 0;
        long rows = check_file(path, is_units ? want : NULL, unique);
        if (is_units)
            assert_int_equal(rows, units);
        files++;
    }
    closedir(d);
    assert_true(files > 0);
}

static void check_mode(const char *name, const char *args, const char *want, long units)
{
    check_mode_u(name, args, want, units, 1);
}

static void ess_modes(void **state)
{
    check_mode("e1", "run configs/ess_type_a.ini --units 6", "rms_after_sys_", 6);
    check_mode("e2",
               "run configs/ess_type_a.ini --units 6 "
               "--set environment.operating_temp_c=-20,20,60",
               "_worst", 6);
    /* two temperatures, the smallest list that makes a worst column */
    check_mode("e3",
               "run configs/ess_type_a.ini --units 6 --set run.sampling=lhs "
               "--set run.sampling_block=2 --set environment.operating_temp_c=0,40",
               "_at_40C", 6);
}

static void dss_modes(void **state)
{
    check_mode("d1", "run configs/dss.ini --units 4 --set run.sampling=lhs --set run.sampling_block=2",
               "rms_after_sys_", 4);
    check_mode("d2",
               "run configs/dss.ini --units 4 --set run.sampling=sobol --set run.sampling_block=4 "
               "--set environment.operating_temp_c=-10,50",
               "_worst", 4);
    check_mode("d3", "curve configs/dss.ini --unit 2", NULL, 0);
}

/* The PSD's units.tsv once named its fitted parameters as its deviations
 * (dx_um ... twice); fit_* now, so its names are unique too. */
static void psd_modes(void **state)
{
    check_mode_u("p1", "run configs/psd.ini --units 5", "rms_after_sys_", 5, 1);
    check_mode_u("p2",
                 "run configs/psd.ini --units 8 --set run.sampling=sobol --set run.sampling_block=4 "
                 "--set environment.operating_temp_c=0,40",
                 "_at_0C", 8, 1);
    check_mode("p3", "curve configs/psd.ini --unit 1", NULL, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ess_modes),
        cmocka_unit_test(dss_modes),
        cmocka_unit_test(psd_modes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
