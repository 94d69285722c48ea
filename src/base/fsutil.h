/* curray io: folders and paths. Files written atomically: atomic.h (included
 * here for the callers that used to find them in this header). */
#ifndef CR_IO_FSUTIL_H
#define CR_IO_FSUTIL_H

#include <stdio.h>

#include "atomic.h"
#include "error.h"

/* Create dir and its parents (like mkdir -p); fine if it exists as a folder.
 * Errors name the folder asked for and the part that failed, e.g.
 * "cannot create folder 'out/a': 'out' exists and is not a folder". */
int cr_mkdir_p(const char *dir, cr_err *err);

/* Join dir and name into out (size n) with one '/' between them; an empty or
 * NULL dir, or an absolute name, gives name alone. Returns -1 (and out = "")
 * if it does not fit. */
int cr_path_join(char *out, size_t n, const char *dir, const char *name);

#endif
