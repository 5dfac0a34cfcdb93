/* ranks.h - the ranks of an MPI run, or a single rank.
 *
 * Built with MPI (make MPI=1: SUNMC_MPI defined, linked by mpicc) and
 * started by an MPI launcher (mpirun/mpiexec, srun: it sets PMI_RANK,
 * PMI_SIZE, PMIX_RANK or OMPI_COMM_WORLD_SIZE in the environment),
 * ranks_init initialises MPI with MPI_THREAD_FUNNELED (only the master
 * thread of each rank's OpenMP team calls MPI).  Otherwise, or without
 * MPI, there is one rank and every call below is a no-op, so the same
 * binary runs alone as usual (and MPI is never initialised where it is not
 * wanted, e.g. under the sanitizers' leak checker).  SUNMC_MPI=0 in the
 * environment keeps MPI off even under a launcher.
 *
 * Messages are bytes: the ranks must share the byte order and the struct
 * layout (one build of sunmc on one kind of machine), as on a cluster.
 */
#ifndef SUNMC_RANKS_H
#define SUNMC_RANKS_H

#include <stddef.h>

/* SUNMC_OK, or SUNMC_EIO when MPI could not be initialised (message in err). */
int ranks_init(int *argc, char ***argv, char *err, size_t errlen);
void ranks_finalize(void);

int ranks_rank(void);
int ranks_size(void);

/* "MPICH 4.0.2" (the library's version string, first line) or "no MPI". */
const char *ranks_library(void);

/* Blocking point-to-point transfer of bytes to / from rank `peer`. */
int ranks_send(const void *buf, size_t bytes, int peer, int tag);
int ranks_recv(void *buf, size_t bytes, int peer, int tag);

/* Rank 0's value of *v to every rank. */
int ranks_bcast_long(long *v);

/* End every rank (a rank that cannot go on). */
void ranks_abort(int code);

#endif
