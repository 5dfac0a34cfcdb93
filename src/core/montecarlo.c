/* montecarlo.c - the parallel loop over units, whole or in blocks. */
#include "montecarlo.h"
#include "modelform.h"
#include "ranks.h"
#include "status.h"
#include "unit_store.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

/* Units handed to a thread at a time: small enough to balance two cores. */
#define MC_CHUNK 4

/* Shared state of one parallel region. */
typedef struct {
    const sunmc_config *c;
    const sensor_family *fam;
    const sunmc_config *mf; /* the model-form pass's config (modelform.h); NULL: none */
    unit_store *store;  /* NULL: each unit runs whole (unit_run) */
    int status;
    long done, total;
    mc_progress_fn progress;
    void *ctx;
    char *err;
    size_t errlen;
} mc_shared;

static void mc_fail(mc_shared *s, int st, const char *msg, long u)
{
#pragma omp critical(mc_error)
    if (s->status == SUNMC_OK)
        s->status = u < 0 ? sunmc_fail(s->err, s->errlen, st, "%s", msg)
                          : sunmc_fail(s->err, s->errlen, st, "unit %ld: simulation failed", u);
}

/* Unit u from the store: its readings read into its slot unless the slot
 * holds them already, then the rest of the unit (unit_store.h). */
static int run_stored(mc_shared *s, void *ws, long u, unit_result *r)
{
    int held;
    void *rd = unit_store_slot(s->store, u, &held);
    int rs = unit_read_finish(s->c, u, ws, rd, held, r);
    if (!held && rs == SUNMC_OK)
        unit_store_fill(s->store, u);
    return rs;
}

/* A thread's workspaces: the family's for c and the model-form pass's. */
typedef struct {
    void *ws;
    modelform_pass mf;
} mc_thread;

/* Unit u into r, then its model-form pass when it is due. */
static int run_one(mc_shared *s, mc_thread *t, long u, unit_result *r)
{
    int rs = s->store ? run_stored(s, t->ws, u, r) : s->fam->unit_run(s->c, u, t->ws, r);
    return rs == SUNMC_OK ? modelform_pass_run(&t->mf, s->c, u, r) : rs;
}

/* Units [first, end) into results[u - first], shared by the calling team
 * (an orphaned `omp for`; its end is a barrier). */
static void run_units(mc_shared *s, mc_thread *t, long first, long end, unit_result *results)
{
#pragma omp for schedule(dynamic, MC_CHUNK)
    for (long u = first; u < end; u++) {
        int st;
#pragma omp atomic read
        st = s->status;
        if (!t->ws || st != SUNMC_OK)
            continue;
        int rs = run_one(s, t, u, &results[u - first]);
        if (rs != SUNMC_OK)
            mc_fail(s, rs, "", u);
        long d;
#pragma omp atomic capture
        d = ++s->done;
        if (s->progress && omp_get_thread_num() == 0)
            s->progress(d, s->total, s->ctx);
    }
}

static void thread_free(mc_shared *s, mc_thread *t)
{
    if (t->ws)
        s->fam->workspace_free(t->ws);
    modelform_pass_free(&t->mf);
    t->ws = NULL;
}

/* Each thread's workspaces (t->ws NULL after a failure, recorded in s). */
static void thread_alloc(mc_shared *s, mc_thread *t)
{
    char terr[SUNMC_ERRLEN] = "";
    t->ws = s->fam->workspace_alloc(s->c, terr, sizeof terr);
    int st = modelform_pass_init(&t->mf, t->ws ? s->mf : NULL, terr, sizeof terr);
    if (!t->ws || st != SUNMC_OK) {
        mc_fail(s, SUNMC_ENOMEM, terr[0] ? terr : "out of memory for a workspace", -1);
        thread_free(s, t);
    }
}

int mc_run(const sunmc_config *c, long first, long end, int threads,
           unit_result *results, mc_progress_fn progress, void *ctx, char *err, size_t errlen)
{
    return mc_run_store(c, NULL, first, end, threads, results, progress, ctx, err, errlen);
}

int mc_run_store(const sunmc_config *c, unit_store *store, long first, long end, int threads,
                 unit_result *results, mc_progress_fn progress, void *ctx, char *err,
                 size_t errlen)
{
    const sensor_family *fam = c->family;
    sunmc_config mfc;
    const sunmc_config *mf;
    int rc = modelform_setup(c, &mfc, &mf, err, errlen);
    if (rc != SUNMC_OK)
        return rc;
    unit_store *st = unit_store_bind(store, c, first, end) ? store : NULL;
    mc_shared s = {c, fam, mf, st, SUNMC_OK, 0, end - first, progress, ctx, err, errlen};
    if (threads > 0)
        omp_set_num_threads(threads);
#pragma omp parallel
    {
        mc_thread t;
        thread_alloc(&s, &t);
        run_units(&s, &t, first, end, results);
        thread_free(&s, &t);
    }
    return s.status;
}

/* Tags of the messages of a distributed stream. */
enum { MC_TAG_STATUS = 1, MC_TAG_DATA = 2 };

/* A stream in rounds: round j is blocks jR .. jR+R-1, block jR+r run by
 * rank r (R = 1 without MPI: a round is a block).  Rank 0 hands every block
 * to the sink in unit order and tells the ranks whether to go on. */
typedef struct {
    const mc_plan *p;
    long bsize;
    int ranks, me;
    unit_result *buf;   /* this rank's block */
    unit_result *rbuf;  /* rank 0: a block received */
    long handed;
    int stop;
    long go_on;
} mc_round;

static long block_start(const mc_round *rd, long round, int rank)
{
    return rd->p->first + (round * rd->ranks + rank) * rd->bsize;
}

static long block_len(const mc_round *rd, long b0)
{
    return rd->p->end - b0 < rd->bsize ? rd->p->end - b0 : rd->bsize;
}

/* Rank 0's master thread: the round's blocks to the sink in order, its own
 * from buf and the others' as they arrive (all of them are received, even
 * after a stop, so that no rank is left waiting). */
static void round_collect(mc_shared *s, mc_round *rd, long round)
{
    for (int r = 0; r < rd->ranks; r++) {
        long b0 = block_start(rd, round, r);
        if (b0 >= rd->p->end)
            break;
        long n = block_len(rd, b0);
        const unit_result *blk = rd->buf;
        if (r > 0) {
            int rs = SUNMC_OK;
            if (ranks_recv(&rs, sizeof rs, r, MC_TAG_STATUS) != SUNMC_OK ||
                ranks_recv(rd->rbuf, (size_t)n * sizeof *rd->rbuf, r, MC_TAG_DATA) != SUNMC_OK)
                rs = SUNMC_EIO;
            if (rs != SUNMC_OK && s->status == SUNMC_OK)
                s->status = sunmc_fail(s->err, s->errlen, rs, "rank %d: units %ld:%ld failed", r,
                                       b0, b0 + n);
            blk = rd->rbuf;
        }
        if (s->status != SUNMC_OK || rd->stop)
            continue;
        int st = rd->p->sink(blk, n, rd->p->sink_ctx, &rd->stop, s->err, s->errlen);
        if (st != SUNMC_OK)
            s->status = st;
        rd->handed += n;
        if (rd->ranks > 1 && rd->p->progress)
            rd->p->progress(rd->handed, s->total, rd->p->progress_ctx);
    }
    rd->go_on = s->status == SUNMC_OK && !rd->stop && block_start(rd, round + 1, 0) < rd->p->end;
}

/* Another rank's master thread: its block and status to rank 0. */
static void round_send(mc_shared *s, mc_round *rd, long round)
{
    long b0 = block_start(rd, round, rd->me);
    if (b0 >= rd->p->end)
        return;
    int st = s->status;
    if (ranks_send(&st, sizeof st, 0, MC_TAG_STATUS) != SUNMC_OK ||
        ranks_send(rd->buf, (size_t)block_len(rd, b0) * sizeof *rd->buf, 0, MC_TAG_DATA) != SUNMC_OK)
        ranks_abort(1);
}

static void stream_rounds(mc_shared *s, mc_round *rd)
{
    mc_thread t;
    thread_alloc(s, &t);
    for (long round = 0;; round++) {
        long b0 = block_start(rd, round, rd->me);
        if (b0 < rd->p->end)
            run_units(s, &t, b0, b0 + block_len(rd, b0), rd->buf);
        /* The block is complete (barrier); the master thread passes it on
         * while the others wait, so every thread sees the same go_on. */
#pragma omp master
        {
            if (rd->me == 0)
                round_collect(s, rd, round);
            else
                round_send(s, rd, round);
            if (rd->ranks > 1 && ranks_bcast_long(&rd->go_on) != SUNMC_OK)
                ranks_abort(1);
        }
#pragma omp barrier
        if (!rd->go_on)
            break;
    }
    thread_free(s, &t);
}

int mc_stream(const sunmc_config *c, const mc_plan *p, long *done,
              char *err, size_t errlen)
{
    const sensor_family *fam = c->family;
    mc_round rd = {p, p->block_units > 0 ? p->block_units : 1, 1, 0, NULL, NULL, 0, 0, 0};
    if (p->distribute) {
        rd.ranks = ranks_size();
        rd.me = ranks_rank();
    }
    long span = p->end - p->first;
    size_t len = (size_t)(span < rd.bsize ? (span > 0 ? span : 1) : rd.bsize);
    rd.buf = calloc(len, sizeof *rd.buf);
    rd.rbuf = rd.ranks > 1 ? calloc(len, sizeof *rd.rbuf) : NULL;
    if (!rd.buf || (rd.ranks > 1 && !rd.rbuf)) {
        free(rd.buf);
        free(rd.rbuf);
        return sunmc_fail(err, errlen, SUNMC_ENOMEM, "out of memory for a block of %ld units",
                          rd.bsize);
    }
    sunmc_config mfc;
    const sunmc_config *mf;
    int rc = modelform_setup(c, &mfc, &mf, err, errlen);
    if (rc != SUNMC_OK) {
        free(rd.buf);
        free(rd.rbuf);
        return rc;
    }
    /* Several ranks: progress per block received (rank 0 runs a part). */
    mc_shared s = {c, fam, mf, NULL, SUNMC_OK, 0, span, rd.ranks > 1 ? NULL : p->progress,
                   p->progress_ctx, err, errlen};
    if (p->threads > 0)
        omp_set_num_threads(p->threads);
#pragma omp parallel
    stream_rounds(&s, &rd);
    free(rd.buf);
    free(rd.rbuf);
    if (done)
        *done = rd.handed;
    return s.status;
}
