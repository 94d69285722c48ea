/* curray io: error reporting.
 *
 * Library functions return 0 on success and -1 on failure, filling a
 * caller-owned cr_err with a complete, user-readable message (file, line,
 * column and key where known). Only main() prints and decides to exit.
 */
#ifndef CR_IO_ERROR_H
#define CR_IO_ERROR_H

#include <stdarg.h>

#define CR_ERR_MSG 1024

typedef struct cr_err {
    char msg[CR_ERR_MSG];
} cr_err;

/* printf-style: set err->msg (err may be NULL). Always returns -1 so that
 * `return cr_err_set(err, ...)` reads naturally. */
int cr_err_set(cr_err *err, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#endif
