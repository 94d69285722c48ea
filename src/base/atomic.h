/* curray io: files that readers only ever see whole.
 *
 * Two ways to write one:
 * - cr_atomic: write a whole file under a temporary name, then rename it over
 *   the destination (c_<k>.png, r_<k>.png, d_<k>.csv, and the first version
 *   of info.txt). A reader sees the old file or the complete new one.
 * - cr_appender: a file that grows by records (info.txt after its first
 *   frame). It is created like a cr_atomic file, then each record is
 *   appended with one write(2); a record that cannot be written completely
 *   (a full disk) is cut off again, so the file always ends with a whole
 *   record. The cost of a record does not depend on the size of the file. */
#ifndef CR_IO_ATOMIC_H
#define CR_IO_ATOMIC_H

#include <stddef.h>
#include <stdio.h>

#include "error.h"

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

/* A file that grows by whole records; see the top of this file.
 *
 * Durability: the first version is fsynced before it is renamed into place
 * (cr_atomic); appended records are not fsynced one by one (that is a disk
 * flush per record), only by cr_appender_close. A crash of the program, a
 * kill or Ctrl-C loses nothing that was appended; after a crash of the
 * machine the last records may be missing. */
typedef struct cr_appender {
    int fd;                           /* -1 when not open */
    long long size;                   /* bytes of whole records in the file */
    unsigned long long bytes_written; /* bytes handed to write(2) so far,
                                         the first version included */
    char path[4096];
} cr_appender;

/* Before anything else: a closed appender (fd -1), so that close is safe. */
void cr_appender_init(cr_appender *a);

/* Write path atomically with data[0..n) as its content (cr_atomic), then
 * keep it open for cr_appender_add. */
int cr_appender_create(cr_appender *a, const char *path, const void *data, size_t n,
                       cr_err *err);

/* Append rec[0..n) at the end of the file with one write(2) (more only if
 * the system writes less than asked). On failure the file is truncated back
 * to its previous size and the message names the file and the cause. */
int cr_appender_add(cr_appender *a, const void *rec, size_t n, cr_err *err);

/* fsync and close (nothing when not open). Returns -1 with err set if the
 * fsync or close fails; the appender is closed either way. */
int cr_appender_close(cr_appender *a, cr_err *err);

#endif
