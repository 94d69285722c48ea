/* curray io: console + log file.
 *
 * Everything shown on the console also goes to the log file curray.log in
 * the log folder (overwritten each run), or curray-YYYYmmdd-HHMMSS-<pid>.log
 * when keep_log is set; curray's log folder is <output folder>/log. quiet
 * silences the console (the log still gets everything); verbose adds detail
 * lines to both. Errors go to stderr, even when quiet. A NULL cr_log * logs
 * to the console only. The functions may be called from several threads
 * (one lock serializes them).
 *
 * A log can start before its folder may be created (cr_log_hold): lines are
 * then kept in memory and written at the top of the file once
 * cr_log_attach makes it, so that a run refused early leaves no folder
 * behind and a run that goes ahead still has its whole story in the file. */
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
    /* cr_log_hold: file lines kept until cr_log_attach, in a memory stream */
    FILE *held_fp;     /* NULL: not holding */
    char *held;        /* its text (open_memstream) */
    size_t held_len;
    long held_dropped; /* lines not kept (over the limit) */
} cr_log;

/* Open the log under log_dir (created if missing; NULL or "": no log file,
 * console only). On failure the log still works on the console and the
 * error says why the file could not be made. */
int cr_log_open(cr_log *lg, const char *log_dir, int keep_log, int verbose, int quiet,
                cr_err *err);
void cr_log_close(cr_log *lg);

/* Start a log on the console whose file lines are kept in memory (up to
 * 1 MiB; beyond that a note says lines were dropped) until cr_log_attach. */
void cr_log_hold(cr_log *lg, int verbose, int quiet);

/* Create the log file under log_dir (created if missing), write the held
 * lines to it and log to it from now on. On failure the held lines are
 * dropped, the log goes on on the console only, and err says why. */
int cr_log_attach(cr_log *lg, const char *log_dir, int keep_log, cr_err *err);

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
