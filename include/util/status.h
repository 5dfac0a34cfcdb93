/* status.h - return codes shared by every sunmc module.
 *
 * Modules never print and never exit (the one exception: under MPI, a rank
 * whose peer is lost aborts the job through ranks_abort, since no status can
 * reach rank 0 then): they return one of these codes and,
 * where a caller-provided buffer is given, write a one-line message naming
 * what was wrong (file, line and key for input errors).  Only main() turns a
 * status into output and an exit code.
 */
#ifndef SUNMC_STATUS_H
#define SUNMC_STATUS_H

#include <stddef.h>

enum sunmc_status {
    SUNMC_OK = 0,
    SUNMC_EINPUT = 2,   /* bad config, CSV or command line: exit status 2 */
    SUNMC_EIO = 3,      /* a file could not be read or written */
    SUNMC_ENOMEM = 4,   /* allocation failed */
    SUNMC_EFIT = 5,     /* a fit failed (recorded per unit in Monte Carlo) */
    SUNMC_EDOM = 6      /* a computation left its domain (e.g. angle beyond 90 deg) */
};

/* Length of every error-message buffer passed between modules. */
#define SUNMC_ERRLEN 512

/* printf into err (if non-NULL) and return status; for one-line error exits. */
int sunmc_fail(char *err, size_t errlen, int status, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
