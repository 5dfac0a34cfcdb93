/* test_compensate_strict.c - issue 36 rule 6: compensate reads params.ini
 * strictly: a fractional polynomial order, a coefficient beyond the order
 * (present in the file or added) and an unknown parameter key are refused
 * at FILE:LINE, exit 2, nothing written (they used to be read as order 2,
 * dropped or ignored, exit 0). */
#include "test_util.h"

static char dir[512];

static int sunmc(const char *args, char *out, size_t len)
{
    return test_sunmc_in(dir, args, out, len);
}

static int setup(void **state)
{
    (void)state;
    if (test_private_dir(dir, sizeof dir, "strict") != 0)
        return -1;
    static const char *const steps[] = {
        "simulate configs/psd.ini --unit 3 --quiet --out $D/sp",
        "calibrate --config configs/psd.ini $D/sp/campaign.csv --quiet --out $D/cp",
        "simulate configs/psd_14og.ini --unit 2 --quiet --out $D/sq",
        "calibrate --config configs/psd_14og.ini $D/sq/campaign.csv --quiet --out $D/cq"};
    char out[16384];
    for (size_t i = 0; i < sizeof steps / sizeof *steps; i++)
        if (sunmc(steps[i], out, sizeof out) != 0) {
            fprintf(stderr, "%s: %s\n", steps[i], out);
            return -1;
        }
    return 0;
}

/* params.ini of cal edited by the shell command edit (reading $D/IN,
 * writing $D/OUT.ini): compensate refuses it with `says`, writes nothing. */
static void refused(const char *cal, const char *edit, const char *says)
{
    char args[2048], out[8192];
    snprintf(args, sizeof args, "true; IN=$D/%s/params.ini; OUT=$D/edited.ini; %s && %s "
             "compensate $OUT $D/sp/validation.csv",
             cal, edit, test_sunmc());
    int rc = sunmc(args, out, sizeof out);
    if (rc != 2 || !strstr(out, says) || strstr(out, "compensated_alpha_deg"))
        fail_msg("%s: exit %d, want 2 and '%s': %s", edit, rc, says, out);
}

static void order_must_be_whole(void **state)
{
    (void)state;
    refused("cq", "sed 's/^order = 3/order = 2.5/' $IN > $OUT",
            "edited.ini:31: key polynomial.order: '2.5' is not a whole number");
    /* the edge: a whole number written as one is read */
    char args[1024], out[8192];
    snprintf(args, sizeof args, "true; sed 's/^order = 3/order = 3.0/' $D/cq/params.ini > "
             "$D/whole.ini && %s compensate $D/whole.ini $D/sq/validation.csv > /dev/null",
             test_sunmc());
    assert_int_equal(sunmc(args, out, sizeof out), 0);
}

static void coefficients_beyond_order(void **state)
{
    (void)state;
    refused("cq", "sed 's/^order = 3/order = 2/' $IN > $OUT",
            "unknown key polynomial.tana_x3y0: not a term of order 2 (full): a coefficient "
            "beyond the order");
    refused("cq", "(cat $IN; echo 'tana_x4y0 = 1') > $OUT",
            "unknown key polynomial.tana_x4y0: not a term of order 3");
}

static void unknown_parameter_key(void **state)
{
    (void)state;
    refused("cp", "awk '{ print } /^dark4_raw/ { print \"foo_um = 1\" }' $IN > $OUT",
            "edited.ini:44: unknown key parameters.foo_um");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(order_must_be_whole),
        cmocka_unit_test(coefficients_beyond_order),
        cmocka_unit_test(unknown_parameter_key),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
