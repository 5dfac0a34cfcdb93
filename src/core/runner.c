/* runner.c - a run's units streamed into its statistics and files. */
#include "runner.h"
#include "status.h"

#include <stdlib.h>
#include <string.h>

int run_sink_init(run_sink *r, const sunmc_config *c, FILE *units_tsv,
                  FILE *units_bin, char *err, size_t errlen)
{
    const sensor_family *fam = c->family;
    memset(r, 0, sizeof *r);
    r->c = c;
    r->fam = fam;
    r->units_tsv = units_tsv;
    r->units_bin = units_bin;
    unitfile_layout_of(c, &r->layout);
    unitsum_init(&r->sum, UNITSUM_LEAF_UNITS);
    r->acc = report_acc_new(c);
    if (!r->acc)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the statistics");
    if (units_tsv)
        report_write_units_header(units_tsv, c);
    if (units_bin && unitfile_write_header(units_bin, &r->layout, err, errlen) != SUNMC_OK) {
        run_sink_free(r);
        return SUNMC_EIO;
    }
    return SUNMC_OK;
}

int run_sink_block(const unit_result *results, long n, void *ctx, int *stop, char *err,
                   size_t errlen)
{
    run_sink *r = ctx;
    if (report_acc_add(r->acc, results, n) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the statistics of %ld units",
                          report_acc_units(r->acc) + n);
    if (r->units_tsv)
        report_write_unit_rows(r->units_tsv, r->c, results, n);
    /* A write error (full disk) leaves the stream in error: the output's
     * commit refuses it, and the run goes on to print its result. */
    if (r->units_bin && !ferror(r->units_bin))
        unitfile_write(r->units_bin, &r->layout, results, n, NULL, 0);
    if (r->units_bin && unitsum_add_results(&r->sum, &r->layout, results, n) != SUNMC_OK)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the checksums");
    for (long u = 0; u < n; u++)
        for (int k = 0; k < UNIT_PHASES; k++)
            r->phase_s[k] += results[u].phase_s[k];
    /* A checkpoint that cannot be written stops checkpointing, not the run. */
    if (r->ckpt && r->ckpt_status == SUNMC_OK)
        r->ckpt_status = checkpoint_append(r->ckpt, results, n, r->ckpt_err, sizeof r->ckpt_err);
    if (r->until) {
        run_until *t = r->until;
        t->reached = report_acc_halfwidth(r->acc, t->stat, t->band);
        t->met = t->reached <= t->halfwidth;
        *stop = t->met;
    }
    return SUNMC_OK;
}

void run_sink_free(run_sink *r)
{
    report_acc_free(r->acc);
    r->acc = NULL;
    unitsum_free(&r->sum);
}

void run_sink_sums(run_sink *r, run_manifest *m)
{
    unitsum_finish(&r->sum, m->sum, &m->nsum, &m->sum_units);
}

int run_stream(run_sink *r, long first, long end, int threads, mc_progress_fn progress,
               void *progress_ctx, long *done, char *err, size_t errlen)
{
    mc_plan p = {.first = first, .end = end, .block_units = r->c->block_units,
                 .threads = threads, .sink = run_sink_block, .sink_ctx = r,
                 .progress = progress, .progress_ctx = progress_ctx,
                 .distribute = r->distribute};
    return mc_stream(r->c, &p, done, err, errlen);
}

/* Check that the records r[n] read at position `at` are units at, at+1, ... */
static int check_units(const unit_result *r, long n, long at, const char *path, char *err,
                       size_t errlen)
{
    for (long i = 0; i < n; i++)
        if (r[i].unit != at + i)
            return sunmc_fail(err, errlen, SUNMC_EINPUT,
                              "%s: record %ld holds unit %ld where unit %ld was expected", path,
                              at + i, r[i].unit, at + i);
    return SUNMC_OK;
}

int run_replay(run_sink *r, const char *path, long first, long end, long *done, char *err,
               size_t errlen)
{
    long bsize = r->c->block_units > 0 ? r->c->block_units : 1, handed = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: cannot be read", path);
    unit_result *buf = calloc((size_t)bsize, sizeof *buf);
    int st = buf ? unitfile_read_header(f, path, &r->layout, err, errlen)
                 : sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory");
    int stop = 0;
    for (long at = first; st == SUNMC_OK && at < end && !stop; at += bsize) {
        long want = end - at < bsize ? end - at : bsize, got = 0;
        st = unitfile_read(f, path, &r->layout, buf, want, &got, err, errlen);
        if (st == SUNMC_OK && got < want)
            st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: ends after unit %ld; units %ld:%ld "
                            "are missing", path, at + got - 1, at + got, end);
        if (st == SUNMC_OK)
            st = check_units(buf, got, at, path, err, errlen);
        if (st == SUNMC_OK && (st = run_sink_block(buf, got, r, &stop, err, errlen)) == SUNMC_OK)
            handed += got;
    }
    long extra = 0;
    if (st == SUNMC_OK && !stop && unitfile_read(f, path, &r->layout, buf, 1, &extra, err,
                                                 errlen) == SUNMC_OK && extra > 0)
        st = sunmc_fail(err, errlen, SUNMC_EINPUT, "%s: holds units beyond %ld (unit %ld)", path,
                        end - 1, buf[0].unit);
    free(buf);
    fclose(f);
    if (done)
        *done = handed;
    return st;
}
