/* curray io: console + log file.
 *
 * Everything shown on the console also goes to the log file log/curray.log
 * (overwritten each run), or log/curray-YYYYmmdd-HHMMSS-<pid>.log when
 * keep_log is set. quiet silences the console (the log still gets
 * everything); verbose adds detail lines to both. Errors go to stderr, even
 * when quiet. A NULL cr_log * logs to the console only. The functions may be
 * called from several threads (one lock serializes them). */
#ifndef CR_IO_LOG_H
#define CR_IO_LOG_H

#include <pthread.h>
#include <stdio.h>

#include "error.h"

typedef struct cr_log {
    FILE *file;      /* NULL: no log file */
    char path[4096]; /* where the log file is */
    int verbose, quiet;
    /* progress state, private to log.c; all-zero is a valid start */
    int progress_len;          /* width of the \r line now on a terminal, 0: none */
    unsigned progress_key[8];  /* non-terminal: hash of the text before the % figure, */
    int progress_decile[8];    /* with 1 + the last decile printed for it (0: free) */
    int progress_next;         /* slot to reuse next */
    double progress_time;      /* monotonic s of the last line printed without a % */
    /* one lock per log for its console and file lines: lines from several
     * threads never interleave; set up by cr_log_open, ended by cr_log_close */
    pthread_mutex_t lock;
    int lock_ready;
} cr_log;

/* Open the log under log_dir (created if missing; NULL or "": no log file,
 * console only). On failure the log still works on the console and the
 * error says why the file could not be made. */
int cr_log_open(cr_log *lg, const char *log_dir, int keep_log, int verbose, int quiet,
                cr_err *err);
void cr_log_close(cr_log *lg);

#if defined(__GNUC__)
#define CR_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define CR_PRINTF(a, b)
#endif

void cr_log_info(cr_log *lg, const char *fmt, ...) CR_PRINTF(2, 3);    /* normal */
void cr_log_detail(cr_log *lg, const char *fmt, ...) CR_PRINTF(2, 3);  /* only verbose */
void cr_log_error(cr_log *lg, const char *fmt, ...) CR_PRINTF(2, 3);   /* stderr + log */
/* Progress line on the console only (\r-updated on a terminal, not logged),
 * silent when quiet. When stdout is not a terminal (CI logs) a line is
 * printed only when the last "<number>%" in it moves into another multiple
 * of 10 than was last printed for the same text before the number (so
 * "frame 1/3: 42%" and "frame 2/3: 7%" are followed separately, and a
 * repeated text starting over is printed again); a line without a
 * percentage at most every 5 s. */
void cr_log_progress(cr_log *lg, const char *fmt, ...) CR_PRINTF(2, 3);

#endif
