/* test_compensate_edges.c - params.ini limits at their exact edges in
 * `compensate` (issue 29), both sides: a glass index of exactly 1 (nominal,
 * or nominal + fitted deviation = 1.5 - 0.5) and 3, a glass thickness of 0
 * are accepted, a hair beyond is refused with the key and the range named.
 * An index of 1 bends no ray, so its compensation must equal the one with
 * no glass at all (thickness 0): an independent value for the accepted edge. */
#include "test_util.h"

static char dir[128];

static int setup(void **state)
{
    char cmd[2048], out[16384];
    if (test_private_dir(dir, sizeof dir, "comp_edges"))
        return -1;
    snprintf(cmd, sizeof cmd,
             "D=%s; %s simulate configs/dss.ini --unit 1 --quiet --out $D/sim >/dev/null && "
             "%s calibrate --config configs/dss.ini $D/sim/campaign.csv --out $D/cal",
             dir, test_sunmc(), test_sunmc());
    return test_run(cmd, out, sizeof out);
}

/* params.ini with "key = value" edits (sed expressions, ';'-separated
 * keys), compensated into DIR/name.csv; exit status, messages in out. */
static int compensate(const char *name, const char *edits, char *out, size_t len)
{
    char cmd[4096], sed[1024] = "";
    for (const char *p = edits; *p;) {
        size_t k = strcspn(p, ";");
        const char *eq = memchr(p, '=', k);
        assert_non_null(eq);
        size_t used = strlen(sed);
        snprintf(sed + used, sizeof sed - used, " -e 's/^%.*s *= .*/%.*s = %.*s/'",
                 (int)(eq - p), p, (int)(eq - p), p, (int)(k - (size_t)(eq - p) - 1), eq + 1);
        p += k + (p[k] == ';');
    }
    snprintf(cmd, sizeof cmd,
             "D=%s; %s%s $D/cal/params.ini > $D/%s.ini && { %s compensate $D/%s.ini "
             "$D/sim/validation.csv > $D/%s.csv; }",
             dir, sed[0] ? "sed" : "cat", sed, name, test_sunmc(), name, name);
    return test_run(cmd, out, len);
}

static void accepted(const char *name, const char *edits)
{
    char out[16384];
    int st = compensate(name, edits, out, sizeof out);
    if (st != 0)
        fail_msg("%s: exit %d\n%s", edits, st, out);
}

static void refused(const char *edits, const char *needle)
{
    char out[16384];
    int st = compensate("refused", edits, out, sizeof out);
    if (st != 2 || !strstr(out, needle))
        fail_msg("%s: exit %d (want 2), message lacks '%s':\n%s", edits, st, needle, out);
}

/* Largest difference (deg) of the compensated columns of two outputs; the
 * rows compared in *rows. */
static double max_difference(const char *a, const char *b, long *rows)
{
    char cmd[2048], out[256];
    snprintf(cmd, sizeof cmd,
             "D=%s; paste -d, $D/%s.csv $D/%s.csv | awk -F, 'NR > 1 {if ($7 == \"\" || $15 == "
             "\"\") {print \"missing\"; exit} d = $7 - $15; e = $8 - $16; d = d < 0 ? -d : d; "
             "e = e < 0 ? -e : e; m = d > m ? d : m; m = e > m ? e : m; n++} END {print m + 0, "
             "n + 0}'",
             dir, a, b);
    assert_int_equal(test_run(cmd, out, sizeof out), 0);
    double m;
    if (sscanf(out, "%lf %ld", &m, rows) != 2)
        fail_msg("compare %s %s: %s", a, b, out);
    return m;
}

static void glass_index_one_bends_nothing(void **state)
{
    accepted("n1", "glass_index=1;fit_glass_index=0");
    accepted("t0", "glass_thickness_mm=0;fit_glass_thickness_um=0");
    accepted("n1sum", "glass_index=1.5;fit_glass_index=-0.5");
    long rows = 0;
    assert_true(max_difference("n1", "t0", &rows) < 1e-9);
    assert_true(rows > 100);
    assert_true(max_difference("n1sum", "t0", &rows) < 1e-9);
    /* the glass as fitted does bend the rays: the comparison can fail */
    accepted("asis", "");
    assert_true(max_difference("asis", "t0", &rows) > 1e-3);
}

static void limits_on_both_sides(void **state)
{
    accepted("n3", "glass_index=3");
    refused("glass_index=3.0000001",
            "design.glass_index = 3.0000001 is out of range: allowed 1 to 3");
    refused("glass_index=0.9999999",
            "design.glass_index = 0.9999999 is out of range: allowed 1 to 3");
    refused("glass_thickness_mm=-0.0001",
            "design.glass_thickness_mm = -0.0001 is out of range: allowed 0 to 5 mm");
    /* nominal 1 and a negative fitted deviation: an index below 1 */
    refused("glass_index=1;fit_glass_index=-0.001",
            "key parameters.fit_glass_index must be >= 1 - design.glass_index");
    refused("glass_index=1.5;fit_glass_index=-0.5000001",
            "parameters.fit_glass_index = -0.5000001 is out of range");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(glass_index_one_bends_nothing),
        cmocka_unit_test(limits_on_both_sides),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
