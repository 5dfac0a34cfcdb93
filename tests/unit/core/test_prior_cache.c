/* test_prior_cache.c - the store of priors' pilots (prior_cache.h): a pilot
 * is found only under exactly the bytes it was kept under, with its priors
 * and status; a failed pilot's message comes back with it; a status that
 * is not a pilot's outcome is not kept; the store forgets its oldest pilot
 * beyond PRIOR_CACHE_SIZE. */
#include "test_util.h"

#include "prior_cache.h"
#include "status.h"

static calib_prior prior_of(double v)
{
    calib_prior p;
    calib_prior_reset(&p, 3);
    p.units = 48;
    for (int j = 0; j < 3; j++)
        p.mean[j] = v + j, p.sum2[j] = 2 * v + j;
    return p;
}

static int clear(void **state)
{
    prior_cache_clear();
    return 0;
}

static void test_found_only_under_its_bytes(void **state)
{
    double a[4] = {1, 2, 3, 4}, b[4] = {1, 2, 3, 4};
    int layout = 7;
    prior_key_part key[] = {{&layout, sizeof layout}, {a, sizeof a}};
    calib_prior p = prior_of(0.5), q;
    int st = -1;
    char err[SUNMC_ERRLEN] = "untouched";
    assert_int_equal(prior_cache_find(key, 2, &q, &st, err, sizeof err), 0);
    assert_int_equal(st, -1);
    prior_cache_keep(key, 2, &p, SUNMC_OK, NULL);
    prior_key_part same[] = {{&layout, sizeof layout}, {b, sizeof b}};
    assert_int_equal(prior_cache_find(same, 2, &q, &st, err, sizeof err), 1);
    assert_int_equal(st, SUNMC_OK);
    assert_memory_equal(&q, &p, sizeof p);
    assert_string_equal(err, "untouched");
    /* the last bit of the last value, a shorter key, another layout */
    b[3] = nextafter(4.0, 5.0);
    assert_int_equal(prior_cache_find(same, 2, &q, &st, err, sizeof err), 0);
    b[3] = 4.0;
    prior_key_part shorter[] = {{&layout, sizeof layout}, {b, 3 * sizeof *b}};
    assert_int_equal(prior_cache_find(shorter, 2, &q, &st, err, sizeof err), 0);
    int other = 8;
    prior_key_part relaid[] = {{&other, sizeof other}, {b, sizeof b}};
    assert_int_equal(prior_cache_find(relaid, 2, &q, &st, err, sizeof err), 0);
}

static void test_failed_pilot_kept_with_message(void **state)
{
    int k = 3;
    prior_key_part key[] = {{&k, sizeof k}};
    calib_prior p = prior_of(1), q;
    prior_cache_keep(key, 1, &p, SUNMC_EINPUT, "prior: 1 of 48 pilot units converged");
    int st = SUNMC_OK;
    char err[SUNMC_ERRLEN] = "";
    assert_int_equal(prior_cache_find(key, 1, &q, &st, err, sizeof err), 1);
    assert_int_equal(st, SUNMC_EINPUT);
    assert_string_equal(err, "prior: 1 of 48 pilot units converged");
    /* out of memory is no outcome of the pilot: not kept */
    int m = 4;
    prior_key_part key2[] = {{&m, sizeof m}};
    prior_cache_keep(key2, 1, &p, SUNMC_ENOMEM, "out of memory");
    assert_int_equal(prior_cache_find(key2, 1, &q, &st, err, sizeof err), 0);
}

static void test_oldest_forgotten(void **state)
{
    int ids[PRIOR_CACHE_SIZE + 1];
    calib_prior q;
    int st;
    for (int i = 0; i <= PRIOR_CACHE_SIZE; i++) {
        ids[i] = 100 + i;
        prior_key_part key[] = {{&ids[i], sizeof ids[i]}};
        calib_prior p = prior_of(i);
        prior_cache_keep(key, 1, &p, SUNMC_OK, NULL);
    }
    prior_key_part first[] = {{&ids[0], sizeof ids[0]}};
    assert_int_equal(prior_cache_find(first, 1, &q, &st, NULL, 0), 0);
    for (int i = 1; i <= PRIOR_CACHE_SIZE; i++) {
        prior_key_part key[] = {{&ids[i], sizeof ids[i]}};
        assert_int_equal(prior_cache_find(key, 1, &q, &st, NULL, 0), 1);
        assert_true(q.mean[0] == i);
    }
    /* keeping a pilot the store has leaves it once */
    prior_key_part last[] = {{&ids[PRIOR_CACHE_SIZE], sizeof(int)}};
    calib_prior p = prior_of(-1);
    prior_cache_keep(last, 1, &p, SUNMC_OK, NULL);
    assert_int_equal(prior_cache_find(last, 1, &q, &st, NULL, 0), 1);
    assert_true(q.mean[0] == PRIOR_CACHE_SIZE);
    prior_key_part second[] = {{&ids[1], sizeof ids[1]}};
    assert_int_equal(prior_cache_find(second, 1, &q, &st, NULL, 0), 1);
}

/* A pilot that counts its makings; fails while *ctx's fail is set. */
typedef struct {
    int made, fail;
} maker;

static int make_pilot(void *ctx, calib_prior *p, char *err, size_t errlen)
{
    maker *m = ctx;
    m->made++;
    if (m->fail)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the pilot");
    *p = prior_of(2);
    return SUNMC_OK;
}

/* prior_cache_pilot makes a pilot once and finds it after; a failed
 * making is returned with its message and not kept. */
static void test_pilot_made_once(void **state)
{
    int id = 9;
    prior_key_part key[] = {{&id, sizeof id}};
    maker m = {0, 1};
    calib_prior p, want = prior_of(2);
    char err[SUNMC_ERRLEN] = "";
    assert_int_equal(prior_cache_pilot(key, 1, &p, make_pilot, &m, err, sizeof err),
                     SUNMC_ENOMEM);
    assert_string_equal(err, "out of memory for the pilot");
    m.fail = 0;
    for (int k = 0; k < 3; k++) {
        memset(&p, 0, sizeof p);
        assert_int_equal(prior_cache_pilot(key, 1, &p, make_pilot, &m, err, sizeof err),
                         SUNMC_OK);
        assert_memory_equal(&p, &want, sizeof p);
    }
    assert_int_equal(m.made, 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_found_only_under_its_bytes, clear),
        cmocka_unit_test_setup(test_failed_pilot_kept_with_message, clear),
        cmocka_unit_test_setup(test_oldest_forgotten, clear),
        cmocka_unit_test_setup(test_pilot_made_once, clear),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
