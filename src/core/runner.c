/* runner.c - a run's units streamed into its statistics and files. */
#include "runner.h"
#include "status.h"

#include <string.h>

int run_sink_init(run_sink *r, const sunmc_config *c, const sensor_family *fam, FILE *units_tsv,
                  char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    r->c = c;
    r->fam = fam;
    r->units_tsv = units_tsv;
    r->acc = report_acc_new(c, fam);
    if (!r->acc)
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for the statistics");
    if (units_tsv)
        report_write_units_header(units_tsv, c, fam);
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
        report_write_unit_rows(r->units_tsv, r->c, r->fam, results, n);
    for (long u = 0; u < n; u++)
        for (int k = 0; k < UNIT_PHASES; k++)
            r->phase_s[k] += results[u].phase_s[k];
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
}

int run_stream(run_sink *r, long first, long end, int threads, mc_progress_fn progress,
               void *progress_ctx, long *done, char *err, size_t errlen)
{
    mc_plan p = {first, end, r->c->block_units, threads, run_sink_block, r, progress,
                 progress_ctx};
    return mc_stream(r->c, r->fam, &p, done, err, errlen);
}
