/* test_config_limits.c - every config limit on both sides of its boundary.
 *
 * Driven by the key table, so a new key is covered without a new test: for
 * every number key of every family, its min and max pass (and are stored)
 * and min - eps, max + eps are refused with SUNMC_EINPUT and a message that
 * names the key and its allowed range; for list keys each element's range,
 * for band keys each bound's; every enum choice passes and a near miss does
 * not; the product label's length on both sides.  Then the cross-key checks,
 * each just inside and just outside: the number of fine rows, the coarse
 * code's coverage of the field of view, the coarse cell against the fine
 * period, and each of the four grids (min below max, inside the field of
 * view, at most 100000 steps).  Finally the command line: a value out of
 * range exits 2 naming the key and writes nothing.
 *
 * All through the public API: config_build with "section.key=value"
 * overrides, config_format_value to read a value back. */
#include "test_util.h"

#include "config.h"
#include "registry.h"
#include "status.h"

#include <sys/stat.h>

#define MAX_SETS 16
#define VALUE_LEN 1200

/* ---- the key tables, as (key, families it applies to) ---- */

#define MAX_FAMILIES 8
static int n_families;
static const char *families[MAX_FAMILIES];

typedef struct {
    const config_key *k;
    int applies[MAX_FAMILIES];
} key_row;

/* Every key of every registered family (a shared key once), and which
 * families it applies to. */
static size_t list_keys(key_row *rows, size_t max)
{
    static const config_key *keys[CONFIG_KEYS_MAX];
    static const sensor_family *owners[CONFIG_KEYS_MAX];
    size_t n = config_list_keys(NULL, keys, owners, CONFIG_KEYS_MAX), out = 0;
    n_families = sensor_family_count() < MAX_FAMILIES ? sensor_family_count() : MAX_FAMILIES;
    for (int f = 0; f < n_families; f++)
        families[f] = sensor_family_at(f)->name;
    for (size_t i = 0; i < n && out < max; i++, out++) {
        rows[out].k = keys[i];
        for (int f = 0; f < n_families; f++)
            rows[out].applies[f] = config_key_applies(keys[i], sensor_family_at(f));
    }
    return out;
}

static int family_index(const char *name)
{
    for (int f = 0; f < n_families; f++)
        if (strcmp(families[f], name) == 0)
            return f;
    fail_msg("no family '%s'", name);
    return -1;
}

/* ---- building with overrides ---- */

typedef struct {
    const char *v[MAX_SETS];
    int n;
} set_list;

/* Build family fam's config with `extra` and then `set` (may be NULL). On
 * success, the formatted value of key k (if k) goes to value. */
static int build(const char *fam, const set_list *extra, const char *set, const config_key *k,
                 char *value, char *err)
{
    char famset[64];
    snprintf(famset, sizeof famset, "sensor.family=%s", fam);
    const char *sets[MAX_SETS + 2];
    int n = 0;
    sets[n++] = famset;
    for (int i = 0; extra && i < extra->n; i++)
        sets[n++] = extra->v[i];
    if (set)
        sets[n++] = set;
    config_state st;
    err[0] = '\0';
    int s = config_build(&st, NULL, sets, n, err, SUNMC_ERRLEN);
    if (s == SUNMC_OK) {
        if (k && value)
            config_format_value(k, &st.cfg, value, VALUE_LEN);
        config_state_free(&st);
    }
    return s;
}

/* ---- companions: other keys a boundary value needs to pass the
 * cross-key checks (a 0.05 deg coarse cell needs 12 Gray rows to cover the
 * field, a 5 deg one a 10 deg fine period, ...). ---- */

#define ROWS12 "design.coarse_rows_x_mm=-6.6,-6,-5.4,-4.8,-4.2,-3.6,-3,-2.4,-1.8,-1.2,-0.6,0"
#define ROWS8 "design.coarse_rows_x_mm=-4.8,-4.2,-3.6,-3,-2.4,-1.8,-1.2,-0.6"
#define NARROW_ALPHA                                                                              \
    "campaign.alpha_min_deg=-1", "campaign.alpha_max_deg=1", "validation.alpha_min_deg=-1",       \
        "validation.alpha_max_deg=1"
#define NARROW_B                                                                                  \
    "campaign.b_min_deg=-1", "campaign.b_max_deg=1", "campaign.b_step_deg=0.5",                   \
        "validation.b_min_deg=-1",                                                                \
        "validation.b_max_deg=1"

#define PSD_NARROW                                                                                \
    "campaign.alpha_max_deg=1", "campaign.alpha_step_deg=0.5", "campaign.beta_deg=-1,0,1",        \
        "validation.alpha_max_deg=1", "validation.alpha_step_deg=0.5",                            \
        "validation.beta_deg=-0.5,0.5"

typedef struct {
    const char *key; /* section.name */
    int side;        /* 0 min, 1 max */
    set_list extra;
    const char *family; /* only for this family; NULL: any (a family's own entry first) */
} companion;

static const companion companions[] = {
    {"design.theta0_deg", 0, {{"design.coarse_resolution_deg=0.05", ROWS12}, 2}},
    {"design.coarse_resolution_deg", 0, {{ROWS12}, 1}},
    {"design.coarse_resolution_deg", 1, {{"design.theta0_deg=10"}, 1}},
    {"design.fov_deg", 0, {{NARROW_ALPHA, "report.bands_deg=0:1"}, 5}},
    {"design.fov_deg", 1, {{ROWS8}, 1}},
    {"campaign.alpha_step_deg", 0,
     {{"campaign.alpha_min_deg=-50", "campaign.alpha_max_deg=50"}, 2}},
    {"validation.alpha_step_deg", 0,
     {{"validation.alpha_min_deg=-50", "validation.alpha_max_deg=50"}, 2}},
    {"design.dss_fov_deg", 0, {{NARROW_B, "report.bands_deg=0:1"}, 6}},
    {"design.h_mm", 0, {{"design.glass_thickness_mm=0.1"}, 1}},
    {"campaign.alpha_step_deg", 1, {{"campaign.beta_deg=-20,-10,0,10,20"}, 1}},
    {"campaign.b_step_deg", 1, {{"calibration.fit_glass_index=off", "campaign.mount=aligned"}, 2}},
    {"design.glass_thickness_mm", 1, {{"design.h_mm=6"}, 1}},
    /* a slit of no width cannot have a width tolerance: the draws would
     * make it negative */
    {"design.slit_width_um", 0, {{"tolerance.slit_width_um=0"}, 1}},
    {"design.glass_thickness_mm", 0, {{"tolerance.glass_thickness_um=0"}, 1}},
    {"design.glass_index", 0, {{"tolerance.glass_index=0"}, 1}},
    /* the reproducer: a 90 deg validation step leaves band 30:60
     * empty (refused, test_bands_hold_points); one band over the grid */
    {"validation.alpha_step_deg", 1, {{"report.bands_deg=0:62"}, 1}},
    {"validation.b_step_deg", 1, {{"report.bands_deg=0:70"}, 1}},
    /* 0.01 deg steps over +-60 deg would need 47 GB a thread: over +-5 deg */
    {"campaign.b_step_deg", 0, {{"campaign.b_min_deg=-5", "campaign.b_max_deg=5"}, 2}},
    {"validation.b_step_deg", 0,
     {{"validation.b_min_deg=-5", "validation.b_max_deg=5", "report.bands_deg=0:10"}, 3}},
    /* the largest tolerances need a design that stays physical under them */
    {"tolerance.slit_width_um", 1, {{"design.slit_width_um=100"}, 1}},
    {"tolerance.dh_px", 1, {{"design.h_mm=50", "design.pixel_um=10"}, 2}},
    {"tolerance.glass_thickness_um", 1, {{"design.glass_thickness_mm=1"}, 1}},
    /* the four-channel sensor (psd) */
    {"design.aperture_um", 0, {{"tolerance.aperture_um=0"}, 1}, "psd"},
    {"design.psd_fov_deg", 0, {{PSD_NARROW, "report.bands_deg=0:1"}, 7}, "psd"},
    {"validation.alpha_max_deg", 0, {{"validation.alpha_step_deg=0.25", "validation.alpha_offset_deg=0", "report.bands_deg=0:28"}, 3}, "psd"},
    {"campaign.alpha_max_deg", 0, {{"campaign.alpha_step_deg=0.25"}, 1}, "psd"},
    {"validation.beta_deg", 1, {{"design.psd_fov_deg=80"}, 1}, "psd"},
    {"validation.beta_deg", 0, {{"design.psd_fov_deg=80"}, 1}, "psd"},
    {"campaign.beta_deg", 1, {{"design.psd_fov_deg=80"}, 1}, "psd"},
    {"campaign.beta_deg", 0, {{"design.psd_fov_deg=80"}, 1}, "psd"},
    {"campaign.alpha_step_deg", 1, {{"campaign.beta_deg=-20,-15,-10,-5,0,5,10,15,20"}, 1}, "psd"},
    {"validation.alpha_step_deg", 1, {{"report.bands_deg=0:28"}, 1}, "psd"},
    {"validation.alpha_step_deg", 0, {{"validation.alpha_max_deg=20"}, 1}, "psd"},
    {"campaign.alpha_step_deg", 0, {{"campaign.alpha_max_deg=20"}, 1}, "psd"},
    {"tolerance.aperture_um", 1, {{"design.aperture_um=2100"}, 1}, "psd"},
    {"tolerance.dh_um", 1, {{"design.h_mm=6"}, 1}, "psd"},
    {"design.glass_thickness_mm", 1, {{"design.h_mm=11"}, 1}, "psd"},
    /* a family without a thermal model validates at the lab's temperature only */
    {"environment.calibration_temp_c", 0, {{"environment.operating_temp_c=-100"}, 1}, "psd"},
    {"environment.calibration_temp_c", 1, {{"environment.operating_temp_c=150"}, 1}, "psd"},
    {"environment.operating_temp_c", 0, {{"environment.calibration_temp_c=-100"}, 1}, "psd"},
    {"environment.operating_temp_c", 1, {{"environment.calibration_temp_c=150"}, 1}, "psd"},
};

static const set_list *companion_of(const char *key, int side, const char *family)
{
    const set_list *any = NULL;
    for (size_t i = 0; i < sizeof companions / sizeof companions[0]; i++)
        if (strcmp(companions[i].key, key) == 0 && companions[i].side == side) {
            if (companions[i].family && strcmp(companions[i].family, family) == 0)
                return &companions[i].extra;
            if (!companions[i].family && !any)
                any = &companions[i].extra;
        }
    return any;
}

/* Keys whose own range is wider than a cross-key check lets through: the
 * grids' ends must lie inside the field of view (at most 80 deg).  At its
 * own limit such a key is refused by the cross-key check, not by its range;
 * just past the limit, by its range.  (Listed so that a new key of this
 * kind is a decision, not an accident.) */
static const char *const fov_bounded[] = {
    "campaign.alpha_min_deg", "campaign.alpha_max_deg", "validation.alpha_min_deg",
    "validation.alpha_max_deg", "campaign.b_min_deg", "campaign.b_max_deg",
    "validation.b_min_deg", "validation.b_max_deg",
};

static int is_fov_bounded(const char *key)
{
    for (size_t i = 0; i < sizeof fov_bounded / sizeof fov_bounded[0]; i++)
        if (strcmp(fov_bounded[i], key) == 0)
            return 1;
    return 0;
}

/* ---- formatting boundary values ---- */

static int is_integer(const config_key *k) { return k->type == KEY_INT || k->type == KEY_LONG; }

static void fmt_number(const config_key *k, double v, char *buf, size_t len)
{
    if (is_integer(k))
        snprintf(buf, len, "%.0f", v);
    else
        snprintf(buf, len, "%.17g", v);
}

static double step_past(const config_key *k, double limit, int side)
{
    double eps = is_integer(k) ? 1.0 : 1e-9 * fmax(1.0, fabs(limit));
    return side ? limit + eps : limit - eps;
}

/* The key's current text with element `which` of a list replaced by v, or
 * band 0 made lo:hi; scalars are just v. */
static void key_text(const config_key *k, const char *current, const char *v_text, int bound,
                     char *out, size_t len)
{
    if (k->type == KEY_LIST) {
        const char *rest = strchr(current, ',');
        snprintf(out, len, "%s%s", v_text, rest ? rest : "");
    } else if (k->type == KEY_BANDS) {
        /* one band; the other bound inside the range */
        char other[64];
        snprintf(other, sizeof other, "%.17g", bound ? k->min : k->max);
        if (bound)
            snprintf(out, len, "%s:%s", other, v_text);
        else
            snprintf(out, len, "%s:%s", v_text, other);
    } else {
        snprintf(out, len, "%s", v_text);
    }
}

/* First number of a formatted value. */
static double first_number(const config_key *k, const char *text, int bound)
{
    if (k->type == KEY_BANDS && bound) {
        const char *colon = strchr(text, ':');
        return colon ? strtod(colon + 1, NULL) : NAN;
    }
    return strtod(text, NULL);
}

static void check_number_key(const key_row *r, int f)
{
    const config_key *k = r->k;
    char dotted[128], current[VALUE_LEN], err[SUNMC_ERRLEN], got[VALUE_LEN];
    snprintf(dotted, sizeof dotted, "%s.%s", k->section, k->name);
    assert_int_equal(build(families[f], NULL, NULL, k, current, err), SUNMC_OK);
    for (int side = 0; side < 2; side++) {
        /* the psd's alpha_max_deg is a half range (0.5 to 80): only its
         * top can leave the field of view */
        int bounded = is_fov_bounded(dotted) && !(strcmp(families[f], "psd") == 0 && side == 0);
        double limit = side ? k->max : k->min;
        char num[64], text[VALUE_LEN], set[VALUE_LEN + 128];
        const set_list *extra = companion_of(dotted, side, families[f]);
        /* at the limit: passes and is stored */
        fmt_number(k, limit, num, sizeof num);
        key_text(k, current, num, side, text, sizeof text);
        snprintf(set, sizeof set, "%s=%s", dotted, text);
        int s = build(families[f], extra, set, k, got, err);
        if (bounded) {
            if (s == SUNMC_OK || strstr(err, "out of range"))
                fail_msg("%s (%s) at its limit %s: expected the field-of-view check, got '%s'",
                         dotted, families[f], num, s == SUNMC_OK ? "accepted" : err);
        } else {
            if (s != SUNMC_OK)
                fail_msg("%s (%s) = %s refused at its limit: %s", dotted, families[f], text, err);
            double stored = first_number(k, got, side);
            if (!(fabs(stored - limit) <= 1e-9 * fmax(1.0, fabs(limit))))
                fail_msg("%s (%s) = %s stored as %s", dotted, families[f], text, got);
        }
        /* just past the limit: refused, naming the key and its range */
        double past = step_past(k, limit, side);
        fmt_number(k, past, num, sizeof num);
        key_text(k, current, num, side, text, sizeof text);
        snprintf(set, sizeof set, "%s=%s", dotted, text);
        s = build(families[f], extra, set, k, got, err);
        if (s != SUNMC_EINPUT || !strstr(err, dotted) || !strstr(err, "out of range"))
            fail_msg("%s (%s) = %s: expected SUNMC_EINPUT naming the key, got %d '%s'", dotted,
                     families[f], text, s, err);
        char range[64];
        snprintf(range, sizeof range, "allowed %.10g to %.10g", k->min, k->max);
        if (!strstr(err, range))
            fail_msg("%s: message '%s' does not give the range '%s'", dotted, err, range);
    }
}

static void check_enum_key(const key_row *r, int f)
{
    const config_key *k = r->k;
    char dotted[128], err[SUNMC_ERRLEN], got[VALUE_LEN], set[256];
    snprintf(dotted, sizeof dotted, "%s.%s", k->section, k->name);
    char family_choices[256];
    const char *choices = k->choices;
    if (k->type == KEY_FAMILY) {
        config_family_choices(family_choices, sizeof family_choices);
        choices = family_choices;
    }
    const char *p = choices;
    int n = 0;
    while (p && *p) {
        const char *bar = strchr(p, '|');
        size_t len = bar ? (size_t)(bar - p) : strlen(p);
        char choice[64];
        snprintf(choice, sizeof choice, "%.*s", (int)len, p);
        int fam = k->type == KEY_FAMILY ? family_index(choice) : f; /* it chooses the family */
        snprintf(set, sizeof set, "%s=%s", dotted, choice);
        if (build(families[fam], NULL, set, k, got, err) != SUNMC_OK)
            fail_msg("%s = %s refused: %s", dotted, choice, err);
        assert_string_equal(got, choice);
        /* a near miss: one letter more, or upper case */
        snprintf(set, sizeof set, "%s=%sx", dotted, choice);
        assert_int_equal(build(families[f], NULL, set, k, got, err), SUNMC_EINPUT);
        assert_non_null(strstr(err, dotted));
        assert_non_null(strstr(err, choices));
        snprintf(set, sizeof set, "%s=%c%s", dotted, choice[0] - 32, choice + 1);
        assert_int_equal(build(families[f], NULL, set, k, got, err), SUNMC_EINPUT);
        n++;
        p = bar ? bar + 1 : NULL;
    }
    assert_true(n >= 2);
}

static void check_string_key(const key_row *r, int f)
{
    const config_key *k = r->k;
    char dotted[128], err[SUNMC_ERRLEN], got[VALUE_LEN], set[256], text[CONFIG_STR_MAX + 2];
    snprintf(dotted, sizeof dotted, "%s.%s", k->section, k->name);
    memset(text, 'x', sizeof text);
    text[CONFIG_STR_MAX - 1] = '\0'; /* the longest allowed */
    snprintf(set, sizeof set, "%s=%s", dotted, text);
    if (build(families[f], NULL, set, k, got, err) != SUNMC_OK)
        fail_msg("%s of %d characters refused: %s", dotted, CONFIG_STR_MAX - 1, err);
    assert_string_equal(got, text);
    text[CONFIG_STR_MAX - 1] = 'x';
    text[CONFIG_STR_MAX] = '\0';
    snprintf(set, sizeof set, "%s=%s", dotted, text);
    assert_int_equal(build(families[f], NULL, set, k, got, err), SUNMC_EINPUT);
    assert_non_null(strstr(err, dotted));
    snprintf(set, sizeof set, "%s=", dotted);
    assert_int_equal(build(families[f], NULL, set, k, got, err), SUNMC_EINPUT);
    assert_non_null(strstr(err, dotted));
    snprintf(set, sizeof set, "%s=a\tb", dotted);
    assert_int_equal(build(families[f], NULL, set, k, got, err), SUNMC_EINPUT);
}

/* Every key of the table, for every family it applies to. */
static void test_every_key_both_sides(void **state)
{
    static key_row rows[1024];
    size_t n = list_keys(rows, 1024);
    int numbers = 0, enums = 0, strings = 0;
    for (size_t i = 0; i < n; i++)
        for (int f = 0; f < n_families; f++) {
            if (!rows[i].applies[f])
                continue;
            switch (rows[i].k->type) {
            case KEY_DOUBLE:
            case KEY_INT:
            case KEY_LONG:
            case KEY_LIST:
            case KEY_BANDS:
                check_number_key(&rows[i], f);
                numbers++;
                break;
            case KEY_ENUM:
            case KEY_FAMILY:
                check_enum_key(&rows[i], f);
                enums++;
                break;
            case KEY_STRING:
                /* report.spec_bands names bands of report.bands_deg, and
                 * calibration.onboard a form (double, float, table:STEP):
                 * free text is refused; their limits are in test_verdict
                 * and test_onboard */
                if (strcmp(rows[i].k->name, "spec_bands") != 0 &&
                    strcmp(rows[i].k->name, "onboard") != 0)
                    check_string_key(&rows[i], f);
                strings++;
                break;
            default:
                fail_msg("%s.%s: a key type this test does not know", rows[i].k->section,
                         rows[i].k->name);
            }
        }
    assert_true(numbers > 80 && enums > 20 && strings >= 2);
}

/* Family f has a key section.name of its own (calibration.model: the ESS's
 * paper|extended, the DSS's physical|polynomial). */
static int family_has_name(const key_row *rows, size_t n, int f, const config_key *k)
{
    for (size_t i = 0; i < n; i++)
        if (rows[i].applies[f] && strcmp(rows[i].k->section, k->section) == 0 &&
            strcmp(rows[i].k->name, k->name) == 0)
            return 1;
    return 0;
}

/* A key of the other family is refused, naming it and the family. */
static void test_other_family_keys(void **state)
{
    static key_row rows[1024];
    size_t n = list_keys(rows, 1024);
    char err[SUNMC_ERRLEN], set[VALUE_LEN + 256], got[VALUE_LEN], cur[VALUE_LEN];
    int checked = 0;
    for (size_t i = 0; i < n; i++)
        for (int f = 0; f < n_families; f++) {
            if (rows[i].applies[f] || family_has_name(rows, n, f, rows[i].k))
                continue;
            const config_key *k = rows[i].k;
            int owner = 0;
            while (!rows[i].applies[owner])
                owner++;
            assert_int_equal(build(families[owner], NULL, NULL, k, cur, err), SUNMC_OK);
            snprintf(set, sizeof set, "%s.%s=%s", k->section, k->name, cur);
            assert_int_equal(build(families[f], NULL, set, NULL, got, err), SUNMC_EINPUT);
            char want[160];
            snprintf(want, sizeof want, "%s.%s applies to ", k->section, k->name);
            if (!strstr(err, want) || !strstr(strstr(err, want), families[owner]))
                fail_msg("'%s' does not say '%s'", err, want);
            checked++;
        }
    assert_true(checked > 40);
}

/* ---- cross-key checks, each on both sides ---- */

static void expect_ok(const char *fam, const set_list *s)
{
    char err[SUNMC_ERRLEN];
    if (build(fam, s, NULL, NULL, NULL, err) != SUNMC_OK)
        fail_msg("refused: %s", err);
}

static void expect_refused(const char *fam, const set_list *s, const char *needle)
{
    char err[SUNMC_ERRLEN];
    int st = build(fam, s, NULL, NULL, NULL, err);
    if (st != SUNMC_EINPUT || !strstr(err, needle))
        fail_msg("expected SUNMC_EINPUT naming '%s', got %d '%s'", needle, st, err);
}

static void test_fine_row_count(void **state)
{
    set_list s3 = {{"design.fine_rows_x_mm=0.6,1.2,1.8"}, 1};
    set_list s4 = {{"design.fine_rows_x_mm=0.6,1.2,1.8,2.4"}, 1};
    set_list s5 = {{"design.fine_rows_x_mm=0.6,1.2,1.8,2.4,3.0"}, 1};
    expect_refused("ess", &s3, "design.fine_rows_x_mm must list exactly 4 rows, has 3");
    expect_ok("ess", &s4);
    expect_refused("ess", &s5, "design.fine_rows_x_mm must list exactly 4 rows, has 5");
}

/* n Gray rows of r deg cover r 2^n deg, which must hold the field of view
 * plus a cell at each end: 2 fov + 2 r <= r 2^n. */
static void test_coarse_coverage(void **state)
{
    /* 7 rows of 1 deg: fov up to 63 deg */
    set_list in7 = {{"design.fov_deg=63"}, 1};
    set_list out7 = {{"design.fov_deg=63.000001"}, 1};
    expect_ok("ess", &in7);
    expect_refused("ess", &out7, "coarse rows of 1 deg cover 128 deg");
    /* 6 rows: up to 31 deg (with the grids inside) */
    set_list in6 = {{"design.coarse_rows_x_mm=-3.6,-3,-2.4,-1.8,-1.2,-0.6", "design.fov_deg=31",
                     "campaign.alpha_min_deg=-31", "campaign.alpha_max_deg=31",
                     "validation.alpha_min_deg=-31", "validation.alpha_max_deg=31"},
                    6};
    set_list out6 = in6;
    out6.v[1] = "design.fov_deg=31.000001";
    expect_ok("ess", &in6);
    expect_refused("ess", &out6, "6 coarse rows");
    /* 0.5 deg cells, 8 rows: 128 deg again */
    set_list in_r = {{"design.coarse_resolution_deg=0.5", ROWS8, "design.fov_deg=63.5"}, 3};
    set_list out_r = in_r;
    out_r.v[2] = "design.fov_deg=63.500001";
    expect_ok("ess", &in_r);
    expect_refused("ess", &out_r, "coarse rows");
}

/* The coarse cell must be at most half the fine period to pick it. */
static void test_coarse_cell_vs_period(void **state)
{
    set_list at = {{"design.coarse_resolution_deg=1", "design.theta0_deg=2"}, 2};
    set_list small_period = {{"design.coarse_resolution_deg=1", "design.theta0_deg=1.999999"}, 2};
    set_list big_cell = {{"design.coarse_resolution_deg=1.000001", "design.theta0_deg=2"}, 2};
    expect_ok("ess", &at);
    expect_refused("ess", &small_period, "coarse_resolution_deg");
    expect_refused("ess", &big_cell, "must be at most half of design.theta0_deg");
}

/* One grid: min below max, ends inside the field of view (1e-9 deg of
 * slack), at most 100000 steps. */
static void check_grid(const char *fam, const char *prefix, const char *min_key,
                       const char *max_key, const char *step_key, const char *fov_key,
                       double fov, int with_steps)
{
    char a[128], b[128], c[128], d[128], name[64];
    snprintf(name, sizeof name, "%s", prefix);
    /* min = max refused; min a hair below max passes (a campaign grid also
     * needs points for the fit: there 0.04 deg below in 0.01 deg steps) */
    int campaign = strncmp(prefix, "campaign", 8) == 0;
    snprintf(a, sizeof a, "%s=10", min_key);
    snprintf(b, sizeof b, "%s=10", max_key);
    snprintf(c, sizeof c, "%s=%s", step_key, campaign ? "0.01" : "1");
    set_list eq = {{a, b, c}, 3};
    char want[160];
    snprintf(want, sizeof want, "%s: min must be below max", name);
    expect_refused(fam, &eq, want);
    snprintf(a, sizeof a, "%s=%s", min_key, campaign ? "9.96" : "9.999999");
    set_list below = {{a, b, c}, 3};
    /* a validation grid that narrow holds one point, at its start, and one
     * band around it (every band must hold a validation point) */
    char off[128];
    snprintf(off, sizeof off, "%s_offset_deg=0", prefix);
    if (!campaign) {
        below.v[below.n++] = off;
        below.v[below.n++] = "report.bands_deg=0:60";
    }
    expect_ok(fam, &below);
    /* ends at the field of view pass, just beyond are refused */
    snprintf(d, sizeof d, "%s=%.17g", fov_key, fov);
    snprintf(a, sizeof a, "%s=%.17g", min_key, -fov);
    snprintf(b, sizeof b, "%s=%.17g", max_key, fov);
    set_list at = {{d, a, b}, 3};
    expect_ok(fam, &at);
    snprintf(b, sizeof b, "%s=%.17g", max_key, fov + 1e-8);
    set_list past_hi = {{d, a, b}, 3};
    snprintf(want, sizeof want, "%s: range", name);
    expect_refused(fam, &past_hi, want);
    expect_refused(fam, &past_hi, "leaves the field of view");
    snprintf(a, sizeof a, "%s=%.17g", min_key, -fov - 1e-8);
    snprintf(b, sizeof b, "%s=%.17g", max_key, fov);
    set_list past_lo = {{d, a, b}, 3};
    expect_refused(fam, &past_lo, want);
    /* 100000 steps pass, a hair more are refused: 100 deg in 0.001 deg
     * steps (reachable only where the smallest step allows it: the DSS's
     * 0.01 deg steps over at most 160 deg never come near). */
    if (!with_steps)
        return;
    snprintf(a, sizeof a, "%s=-50", min_key);
    snprintf(b, sizeof b, "%s=50", max_key);
    snprintf(c, sizeof c, "%s=0.001", step_key);
    set_list steps = {{a, b, c}, 3};
    expect_ok(fam, &steps);
    snprintf(b, sizeof b, "%s=50.000001", max_key);
    set_list more = {{a, b, c}, 3};
    snprintf(want, sizeof want, "%s: more than 100000 steps", name);
    expect_refused(fam, &more, want);
}

static void test_grids(void **state)
{
    check_grid("ess", "campaign.alpha", "campaign.alpha_min_deg", "campaign.alpha_max_deg",
               "campaign.alpha_step_deg", "design.fov_deg", 62, 1);
    check_grid("ess", "validation.alpha", "validation.alpha_min_deg", "validation.alpha_max_deg",
               "validation.alpha_step_deg", "design.fov_deg", 62, 1);
    check_grid("dss", "campaign.b", "campaign.b_min_deg", "campaign.b_max_deg",
               "campaign.b_step_deg", "design.dss_fov_deg", 60, 0);
    check_grid("dss", "validation.b", "validation.b_min_deg", "validation.b_max_deg",
               "validation.b_step_deg", "design.dss_fov_deg", 60, 0);
    /* the grid follows the field of view it is checked against */
    set_list narrow = {{"design.fov_deg=45", "campaign.alpha_min_deg=-45",
                        "campaign.alpha_max_deg=45.0001"}, 3};
    expect_refused("ess", &narrow, "campaign.alpha: range -45..45.0001 deg leaves the field of "
                                   "view +-45 deg");
}

/* The campaign must give the fit more data than parameters: the ESS's 8
 * need 9 points (alphas x betas); the DSS's physical model 2 n residuals
 * above its 8 free parameters (7 with the glass index held), the
 * polynomial of order k n readings above its (k + 1)(k + 2)/2 terms.  The
 * b grid gives n = (readings per axis)^2. */
static void test_campaign_size(void **state)
{
    const char *ess_at[] = {"campaign.beta_deg=0", "campaign.alpha_min_deg=-4",
                            "campaign.alpha_max_deg=4", "campaign.alpha_step_deg=1"};
    set_list e9 = {{ess_at[0], ess_at[1], ess_at[2], ess_at[3]}, 4};
    set_list e8 = e9;
    e8.v[2] = "campaign.alpha_max_deg=3";
    expect_ok("ess", &e9);
    expect_refused("ess", &e8, "campaign: 8 alpha x 1 beta_deg = 8 points, fewer than the 9");
    set_list e10 = {{"campaign.beta_deg=0,5", "campaign.alpha_min_deg=-2",
                     "campaign.alpha_max_deg=2", "campaign.alpha_step_deg=1"}, 4};
    set_list e8b = e10;
    e8b.v[2] = "campaign.alpha_max_deg=1";
    expect_ok("ess", &e10);
    expect_refused("ess", &e8b, "4 alpha x 2 beta_deg = 8 points");
    const struct {
        const char *lo, *hi, *model, *index, *mount, *needle; /* needle NULL: accepted */
    } dss[] = {
        /* aligned: 8 parameters (7 with the index held) */
        {"-5", "0", "physical", "on", "aligned", "2 x 2 b grid = 4 readings, too few for the "
                                                 "physical model's 8 parameters"},
        {"-5", "5", "physical", "on", "aligned", NULL},
        {"-5", "0", "physical", "off", "aligned", NULL},
        {"0", "0.001", "physical", "off", "aligned", "1 x 1 b grid = 1 readings"},
        /* as mounted: the sun simulator's two angles too, 10 (9) */
        {"-5", "0", "physical", "off", "as_mounted", "2 x 2 b grid = 4 readings, too few for "
                                                     "the physical model's 9 parameters"},
        {"-5", "5", "physical", "on", "as_mounted", NULL},
        {"-10", "0", "polynomial", "on", "as_mounted", "3 x 3 b grid = 9 readings, too few for "
                                                       "the polynomial model's 10 parameters"},
        {"-10", "5", "polynomial", "on", "as_mounted", NULL},
    };
    for (size_t i = 0; i < sizeof dss / sizeof dss[0]; i++) {
        char lo[64], hi[64], model[64], index[64], mount[64];
        snprintf(lo, sizeof lo, "campaign.b_min_deg=%s", dss[i].lo);
        snprintf(hi, sizeof hi, "campaign.b_max_deg=%s", dss[i].hi);
        snprintf(model, sizeof model, "calibration.model=%s", dss[i].model);
        snprintf(index, sizeof index, "calibration.fit_glass_index=%s", dss[i].index);
        snprintf(mount, sizeof mount, "campaign.mount=%s", dss[i].mount);
        set_list s = {{lo, hi, "campaign.b_step_deg=5", model, index, "calibration.poly_order=3",
                       mount},
                      7};
        if (dss[i].needle)
            expect_refused("dss", &s, dss[i].needle);
        else
            expect_ok("dss", &s);
    }
    /* order 7: 36 terms; 6 x 6 refused, 7 x 7 accepted */
    set_list p36 = {{"calibration.model=polynomial", "calibration.poly_order=7",
                     "campaign.b_min_deg=-25", "campaign.b_max_deg=0", "campaign.b_step_deg=5"}, 5};
    set_list p49 = p36;
    p49.v[3] = "campaign.b_max_deg=5";
    expect_refused("dss", &p36, "36 readings, too few for the polynomial model's 36 parameters");
    expect_ok("dss", &p49);
}

/* The cover glass lies under the pinhole: thickness below the height. */
static void test_glass_under_pinhole(void **state)
{
    set_list at = {{"design.h_mm=1", "design.glass_thickness_mm=1"}, 2};
    set_list below = {{"design.h_mm=1", "design.glass_thickness_mm=0.999999",
                       "tolerance.dh_px=0", "tolerance.glass_thickness_um=0"}, 4};
    expect_refused("dss", &at, "design.glass_thickness_mm = 1 must be below design.h_mm = 1");
    expect_ok("dss", &below);
}

/* Bands: LO < HI, each bound in 0..90; LO = HI refused, a hair apart passes. */
static void test_band_order(void **state)
{
    set_list eq = {{"report.bands_deg=0:30, 30:30"}, 1};
    /* a hair apart passes the order check, but the band must hold a
     * validation point: 30:30.000001 holds none of the 0.13-deg grid, 30:30.1
     * holds |alpha| = 30.03 */
    set_list hair = {{"report.bands_deg=0:30, 30:30.000001"}, 1};
    set_list ok = {{"report.bands_deg=0:30, 30:30.1"}, 1};
    expect_refused("ess", &hair, "band 30:30.000001 holds no point of the validation grid");
    set_list rev = {{"report.bands_deg=40:30"}, 1};
    expect_refused("ess", &eq, "band 30:30 must have LO < HI");
    expect_ok("ess", &ok);
    expect_refused("dss", &rev, "report.bands_deg");
    char many[256] = "report.bands_deg=";
    for (int i = 0; i < CONFIG_BANDS_MAX; i++)
        snprintf(many + strlen(many), sizeof many - strlen(many), "%s%d:%d", i ? "," : "", i,
                 i + 1);
    set_list max_bands = {{many}, 1};
    expect_ok("ess", &max_bands);
    strcat(many, ",20:21");
    set_list too_many = {{many}, 1};
    expect_refused("ess", &too_many, "more than 8 bands");
}

/* Lists: up to CONFIG_LIST_MAX values; an empty list is refused. */
static void test_list_length(void **state)
{
    char list[1024] = "campaign.beta_deg=";
    for (int i = 0; i < CONFIG_LIST_MAX; i++)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%d", i ? "," : "", i);
    set_list max_list = {{list}, 1};
    expect_ok("ess", &max_list);
    strcat(list, ",40");
    set_list too_long = {{list}, 1};
    expect_refused("ess", &too_long, "more than 32 values");
    set_list empty = {{"campaign.beta_deg= "}, 1};
    expect_refused("ess", &empty, "campaign.beta_deg is an empty list");
}

/* ---- the command line ---- */

static int exists(const char *p)
{
    struct stat sb;
    return stat(p, &sb) == 0;
}

/* Out of range on the command line: exit 2, the key named, no output; at
 * the limit: exit 0. */
static void test_cli_limits(void **state)
{
    const struct {
        const char *config, *bad, *good, *needle;
    } cases[] = {
        {"configs/ess_type_a.ini", "design.H_mm=0.49999", "design.H_mm=0.5", "design.H_mm"},
        {"configs/ess_type_a.ini", "campaign.repeats=0", "campaign.repeats=1", "campaign.repeats"},
        {"configs/ess_type_a.ini", "run.seed=2147483648", "run.seed=2147483647", "run.seed"},
        {"configs/ess_type_a.ini", "campaign.beta_deg=0,89.000001", "campaign.beta_deg=0,89",
         "campaign.beta_deg"},
        {"configs/dss.ini", "report.bands_deg=0:90.000001", "report.bands_deg=0:90",
         "report.bands_deg"},
        {"configs/dss.ini", "design.detector_px=15", "design.detector_px=16", "design.detector_px"},
        {"configs/dss.ini", "tolerance.glass_index=0.5000001", "tolerance.glass_index=0.5",
         "tolerance.glass_index"},
        {"configs/ess_type_a.ini", "campaign.alpha_step_deg=90", "campaign.alpha_step_deg=40",
         "campaign: 2 alpha x 3 beta_deg = 6 points"},
        {"configs/dss.ini", "campaign.b_step_deg=90", "campaign.b_step_deg=60",
         "campaign: 2 x 2 b grid = 4 readings"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char cmd[1024], out[4096], outdir[512], name[32];
        snprintf(name, sizeof name, "out%zu", i);
        snprintf(outdir, sizeof outdir, "%s", test_tmp(name));
        snprintf(cmd, sizeof cmd, "%s run %s --units 1 --quiet --set %s --out %s", test_sunmc(),
                 cases[i].config, cases[i].bad, outdir);
        int rc = test_run(cmd, out, sizeof out);
        if (rc != 2 || !strstr(out, cases[i].needle))
            fail_msg("%s: exit %d, '%s'", cases[i].bad, rc, out);
        assert_false(exists(outdir));
        snprintf(cmd, sizeof cmd, "%s config %s --set %s", test_sunmc(), cases[i].config,
                 cases[i].good);
        rc = test_run(cmd, out, sizeof out);
        if (rc != 0)
            fail_msg("%s: exit %d, '%s'", cases[i].good, rc, out);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_key_both_sides),
        cmocka_unit_test(test_other_family_keys),
        cmocka_unit_test(test_fine_row_count),
        cmocka_unit_test(test_coarse_coverage),
        cmocka_unit_test(test_coarse_cell_vs_period),
        cmocka_unit_test(test_grids),
        cmocka_unit_test(test_campaign_size),
        cmocka_unit_test(test_glass_under_pinhole),
        cmocka_unit_test(test_band_order),
        cmocka_unit_test(test_list_length),
        cmocka_unit_test(test_cli_limits),
    };
    return cmocka_run_group_tests_name("limits_config", tests, NULL, NULL);
}
