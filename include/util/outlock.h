/* outlock.h - one live command per output directory.
 *
 * Two commands writing one --out DIR at once would take each other's
 * checkpoint (.DIR.resume) and temporary files, and only one result would
 * survive.  So a command holds, from its argument check to its exit, an
 * exclusive flock(2) on PARENT/.NAME.lock (NAME the last part of DIR), which
 * holds the holder's PID.  A second command is refused at once, before it
 * touches anything, naming that PID.  The kernel drops the lock when the
 * holder ends, however (kill -9 included), so a lock file left by a killed
 * command locks nothing; the holder removes it at its end (out_unlock, and
 * output.h's signal handler).  Missing parents of DIR are made to hold the
 * lock file and removed again at out_unlock when still empty.
 *
 * One lock per process.  Modules never print: a status and err.
 */
#ifndef SUNMC_OUTLOCK_H
#define SUNMC_OUTLOCK_H

#include <stddef.h>

/* Suffix of the lock file beside DIR: PARENT/.NAME.lock. */
#define OUT_LOCK_SUFFIX ".lock"

/* Take the lock of output directory dir: SUNMC_OK (also when this process
 * holds it already), SUNMC_EINPUT "--out DIR: another sunmc (PID N) is
 * writing it ..." when another process holds it, SUNMC_EIO when the lock
 * file cannot be made. */
int out_lock(const char *dir, char *err, size_t errlen);

/* Remove the lock file and release the lock (at the end of the command). */
void out_unlock(void);

/* In a signal handler ending the process: remove the lock file (the kernel
 * releases the lock).  Async-signal-safe. */
void out_lock_drop_on_signal(void);

#endif
