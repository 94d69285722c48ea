/* curray io: files and folders: create output folders, write atomically. */
#ifndef CR_IO_FSUTIL_H
#define CR_IO_FSUTIL_H

#include <stdio.h>

#include "error.h"

/* Create dir and its parents (like mkdir -p); fine if it exists as a folder.
 * Errors name the folder asked for and the part that failed, e.g.
 * "cannot create folder 'out/a': 'out' exists and is not a folder". */
int cr_mkdir_p(const char *dir, cr_err *err);

/* Atomic text/binary output: cr_atomic_open creates a temporary file
 * ".<name>.tmp.<pid>.<n>" next to path; cr_atomic_commit flushes, fsyncs,
 * closes and renames it over path, reporting any write error (a full disk)
 * and removing the temporary on failure; cr_atomic_abort closes and removes
 * it. The final file gets mode 0666 minus the umask. */
typedef struct cr_atomic {
    FILE *fp;
    char path[4096];
    char tmp[4096];
} cr_atomic;

int cr_atomic_open(cr_atomic *a, const char *path, cr_err *err);
int cr_atomic_commit(cr_atomic *a, cr_err *err);
void cr_atomic_abort(cr_atomic *a);

/* Flush fp and check its error flag; on failure the message reads
 * "writing <name>: <cause>" (e.g. "No space left on device"). Used by
 * cr_atomic_commit; callers writing to any stream can use it too. */
int cr_stream_check(FILE *fp, const char *name, cr_err *err);

/* Join dir and name into out (size n) with one '/' between them; an empty or
 * NULL dir, or an absolute name, gives name alone. Returns -1 (and out = "")
 * if it does not fit. */
int cr_path_join(char *out, size_t n, const char *dir, const char *name);

#endif
