/* curray cli: one run per output folder.
 *
 * A run holds an exclusive flock(2) on "<folder>/.curray.lock" from the
 * moment it knows the folder exists until it ends; a second curray (or
 * curray_mpi) asking for the same folder is refused with a message that
 * names the folder and the process holding it. The kernel drops the lock
 * when its process dies (even by SIGKILL), so a lock file that a dead run
 * left behind never blocks: only a live holder refuses.
 *
 * The file holds "pid <pid>\n" of its holder, for the message only; the
 * lock itself is the flock. The holder removes the file when it releases
 * the lock; a run that takes the lock checks that the file it locked is
 * still the one at the path (not removed meanwhile), else it takes again. */
#ifndef CR_CLI_LOCK_H
#define CR_CLI_LOCK_H

#include "../base/error.h"

#define CR_LOCK_NAME ".curray.lock"

/* A zeroed cr_dirlock holds nothing. */
typedef struct cr_dirlock {
    int held; /* 1 while fd holds the lock */
    int fd;
    char path[4096];
} cr_dirlock;

/* Take the lock of folder dir for this process. Returns 0 when held (also
 * when it was held already), 1 when it cannot be taken for a reason other
 * than another run (no such folder, not writable, a file system without
 * flock): nothing is held then, and the run's own writes report the
 * folder's problem; -1 with err set when another live process holds it. */
int cr_dirlock_take(cr_dirlock *l, const char *dir, cr_err *err);

/* Remove the lock file and drop the lock (nothing when none is held). */
void cr_dirlock_release(cr_dirlock *l);

#endif
