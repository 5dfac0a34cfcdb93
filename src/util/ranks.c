/* ranks.c - MPI ranks when built with MPI and launched by mpirun; one rank
 * otherwise (see ranks.h). */
#include "ranks.h"
#include "status.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef SUNMC_MPI
#include <mpi.h>

static int par_on, par_me, par_n = 1;

/* Started by an MPI launcher? */
static int launched(void)
{
    const char *off = getenv("SUNMC_MPI");
    if (off && strcmp(off, "0") == 0)
        return 0;
    static const char *const vars[] = {"PMI_RANK", "PMI_SIZE", "PMIX_RANK",
                                       "OMPI_COMM_WORLD_SIZE"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
        if (getenv(vars[i]))
            return 1;
    return 0;
}

int ranks_init(int *argc, char ***argv, char *err, size_t errlen)
{
    if (!launched())
        return SUNMC_OK;
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return sunmc_fail(err, errlen, SUNMC_EIO, "MPI_Init_thread failed");
    if (provided < MPI_THREAD_FUNNELED) {
        MPI_Finalize();
        return sunmc_fail(err, errlen, SUNMC_EIO,
                          "the MPI library does not support MPI_THREAD_FUNNELED");
    }
    par_on = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &par_me);
    MPI_Comm_size(MPI_COMM_WORLD, &par_n);
    return SUNMC_OK;
}

void ranks_finalize(void)
{
    if (par_on)
        MPI_Finalize();
    par_on = 0;
}

int ranks_rank(void)
{
    return par_me;
}

int ranks_size(void)
{
    return par_n;
}

const char *ranks_library(void)
{
    static char v[MPI_MAX_LIBRARY_VERSION_STRING];
    int len = 0;
    if (!v[0] && MPI_Get_library_version(v, &len) == MPI_SUCCESS)
        v[strcspn(v, "\n")] = '\0';
    for (char *q = v; *q; q++)
        if (*q == '\t')
            *q = ' ';
    return v;
}

int ranks_send(const void *buf, size_t bytes, int peer, int tag)
{
    return MPI_Send(buf, (int)bytes, MPI_BYTE, peer, tag, MPI_COMM_WORLD) == MPI_SUCCESS
               ? SUNMC_OK
               : SUNMC_EIO;
}

int ranks_recv(void *buf, size_t bytes, int peer, int tag)
{
    return MPI_Recv(buf, (int)bytes, MPI_BYTE, peer, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE) ==
                   MPI_SUCCESS
               ? SUNMC_OK
               : SUNMC_EIO;
}

int ranks_bcast_long(long *v)
{
    if (!par_on)
        return SUNMC_OK;
    return MPI_Bcast(v, 1, MPI_LONG, 0, MPI_COMM_WORLD) == MPI_SUCCESS ? SUNMC_OK : SUNMC_EIO;
}

void ranks_abort(int code)
{
    if (par_on)
        MPI_Abort(MPI_COMM_WORLD, code);
    exit(code);
}

#else /* one rank */

int ranks_init(int *argc, char ***argv, char *err, size_t errlen)
{
    (void)argc;
    (void)argv;
    (void)err;
    (void)errlen;
    return SUNMC_OK;
}

void ranks_finalize(void)
{
}

int ranks_rank(void)
{
    return 0;
}

int ranks_size(void)
{
    return 1;
}

const char *ranks_library(void)
{
    return "no MPI";
}

int ranks_send(const void *buf, size_t bytes, int peer, int tag)
{
    (void)buf;
    (void)bytes;
    (void)peer;
    (void)tag;
    return SUNMC_EIO;
}

int ranks_recv(void *buf, size_t bytes, int peer, int tag)
{
    return ranks_send(buf, bytes, peer, tag);
}

int ranks_bcast_long(long *v)
{
    (void)v;
    return SUNMC_OK;
}

void ranks_abort(int code)
{
    exit(code);
}

#endif
