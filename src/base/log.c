/* curray io: console + log file (log.h).
 *
 * Console: info and detail lines on stdout, errors on stderr, each as given
 * plus a newline. Log file: the same lines, each prefixed with the local time
 * and a level tag ("2024-05-01 12:00:00.123 [info] ..."), flushed line by
 * line so that a crash keeps everything logged before it. */
#include "log.h"

#include <ctype.h>
#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "fsutil.h"

enum cr_log_level { CR_LOG_INFO, CR_LOG_DETAIL, CR_LOG_ERROR };

/* The log's lock (see cr_log.lock); a NULL log or one never opened has none
 * and is used from one thread only. */
static void cr_log_lock(cr_log *lg)
{
    if (lg && lg->lock_ready)
        pthread_mutex_lock(&lg->lock);
}

static void cr_log_unlock(cr_log *lg)
{
    if (lg && lg->lock_ready)
        pthread_mutex_unlock(&lg->lock);
}

static const char *const cr_log_tags[] = {"info", "detail", "error"};

/* The most bytes of file lines cr_log_hold keeps. */
#define CR_LOG_HOLD_MAX (1u << 20)

static void cr_log_init(cr_log *lg, int verbose, int quiet)
{
    memset(lg, 0, sizeof *lg);
    lg->lock_ready = pthread_mutex_init(&lg->lock, NULL) == 0;
    lg->verbose = verbose;
    lg->quiet = quiet;
}

void cr_log_hold(cr_log *lg, int verbose, int quiet)
{
    cr_log_init(lg, verbose, quiet);
    lg->held_fp = open_memstream(&lg->held, &lg->held_len); /* NULL: nothing is kept */
}

/* End holding: close the memory stream, free its text. */
static void cr_log_drop_held(cr_log *lg)
{
    if (lg->held_fp)
        fclose(lg->held_fp);
    free(lg->held);
    lg->held_fp = NULL;
    lg->held = NULL;
    lg->held_len = 0;
}

int cr_log_open(cr_log *lg, const char *log_dir, int keep_log, int verbose, int quiet,
                cr_err *err)
{
    cr_log_init(lg, verbose, quiet);
    if (!log_dir || !*log_dir)
        return 0; /* console only, by choice */
    return cr_log_attach(lg, log_dir, keep_log, err);
}

/* Create the file of cr_log_attach; caller holds the lock. */
static int cr_log_create(cr_log *lg, const char *log_dir, int keep_log, cr_err *err)
{
    char name[128];

    if (keep_log) {
        time_t now = time(NULL);
        struct tm tm;
        char stamp[32] = "unknown";
        if (localtime_r(&now, &tm))
            strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
        snprintf(name, sizeof name, "curray-%s-%ld.log", stamp, (long)getpid());
    } else {
        snprintf(name, sizeof name, "curray.log");
    }
    if (cr_path_join(lg->path, sizeof lg->path, log_dir, name) != 0)
        return cr_err_set(err, "cannot create the log file: folder name too long: '%s'",
                          log_dir);
    if (cr_mkdir_p(log_dir, err) != 0) {
        char why[CR_ERR_MSG];
        snprintf(why, sizeof why, "%s", err ? err->msg : "");
        return cr_err_set(err, "cannot create the log file %s: %s", lg->path, why);
    }
    lg->file = fopen(lg->path, "w");
    if (!lg->file)
        return cr_err_set(err, "cannot create the log file %s: %s", lg->path, strerror(errno));
    return 0;
}

int cr_log_attach(cr_log *lg, const char *log_dir, int keep_log, cr_err *err)
{
    int rc;
    cr_log_lock(lg);
    rc = cr_log_create(lg, log_dir, keep_log, err);
    if (lg->held_fp) {
        fclose(lg->held_fp); /* makes held / held_len final */
        lg->held_fp = NULL;
    }
    if (rc == 0 && lg->held && lg->held_len > 0) {
        fwrite(lg->held, 1, lg->held_len, lg->file);
        if (lg->held_dropped)
            fprintf(lg->file, "(%ld log lines were dropped here: more than %u bytes came before "
                              "the log file could be made)\n",
                    lg->held_dropped, CR_LOG_HOLD_MAX);
        fflush(lg->file);
    }
    cr_log_drop_held(lg);
    cr_log_unlock(lg);
    return rc;
}

/* Remove an unfinished \r progress line from the terminal. */
static void cr_log_end_progress(cr_log *lg)
{
    if (lg && lg->progress_len > 0) {
        printf("\r%*s\r", lg->progress_len, "");
        fflush(stdout);
        lg->progress_len = 0;
    }
}

void cr_log_close(cr_log *lg)
{
    if (!lg)
        return;
    cr_log_lock(lg);
    if (lg->progress_len > 0) { /* keep the last progress line visible */
        fputc('\n', stdout);
        fflush(stdout);
        lg->progress_len = 0;
    }
    cr_log_drop_held(lg);
    cr_log_unlock(lg);
    if (lg->file) {
        fclose(lg->file);
        lg->file = NULL;
    }
    if (lg->lock_ready) {
        pthread_mutex_destroy(&lg->lock);
        lg->lock_ready = 0;
    }
}

/* vasprintf-like: text in stack_buf when it fits, else malloc'ed (the
 * caller frees the result if it differs from stack_buf). NULL: no memory. */
static char *cr_log_format(char *stack_buf, size_t n, const char *fmt, va_list ap)
{
    va_list ap2;
    int len;
    char *big;

    va_copy(ap2, ap);
    len = vsnprintf(stack_buf, n, fmt, ap);
    if (len < 0) {
        va_end(ap2);
        snprintf(stack_buf, n, "(unprintable log message)");
        return stack_buf;
    }
    if ((size_t)len < n) {
        va_end(ap2);
        return stack_buf;
    }
    big = malloc((size_t)len + 1);
    if (big)
        vsnprintf(big, (size_t)len + 1, fmt, ap2);
    va_end(ap2);
    return big ? big : stack_buf; /* truncated rather than lost */
}

/* msg[0..len) as one or more lines, each with a timestamp and level tag. */
static void cr_log_to_file(FILE *f, enum cr_log_level level, const char *msg, size_t len)
{
    struct timespec ts;
    struct tm tm;
    char stamp[40] = "unknown time";
    const char *p = msg, *end = msg + len;

    clock_gettime(CLOCK_REALTIME, &ts);
    if (localtime_r(&ts.tv_sec, &tm))
        strftime(stamp, sizeof stamp, "%Y-%m-%d %H:%M:%S", &tm);
    for (;;) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *e = nl ? nl : end;
        fprintf(f, "%s.%03ld [%s] %.*s\n", stamp, (long)(ts.tv_nsec / 1000000),
                cr_log_tags[level], (int)(e - p), p);
        if (!nl)
            break;
        p = nl + 1;
    }
    fflush(f);
}

static void cr_log_line(cr_log *lg, enum cr_log_level level, const char *fmt, va_list ap)
{
    char stack_buf[1024];
    char *msg = cr_log_format(stack_buf, sizeof stack_buf, fmt, ap);
    size_t len;
    int console = level == CR_LOG_ERROR || !lg || !lg->quiet;

    if (!msg)
        return;
    len = strlen(msg);
    if (len > 0 && msg[len - 1] == '\n')
        len--; /* the newline is ours to add */
    cr_log_lock(lg);
    if (console) {
        FILE *out = level == CR_LOG_ERROR ? stderr : stdout;
        cr_log_end_progress(lg);
        fwrite(msg, 1, len, out);
        fputc('\n', out);
        fflush(out);
    }
    if (lg && lg->file) {
        cr_log_to_file(lg->file, level, msg, len);
    } else if (lg && lg->held_fp) {
        if (lg->held_len + len < CR_LOG_HOLD_MAX)
            cr_log_to_file(lg->held_fp, level, msg, len); /* its fflush updates held_len */
        else
            lg->held_dropped++;
    }
    cr_log_unlock(lg);
    if (msg != stack_buf)
        free(msg);
}

void cr_log_info(cr_log *lg, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    cr_log_line(lg, CR_LOG_INFO, fmt, ap);
    va_end(ap);
}

void cr_log_detail(cr_log *lg, const char *fmt, ...)
{
    va_list ap;
    if (!lg || !lg->verbose)
        return;
    va_start(ap, fmt);
    cr_log_line(lg, CR_LOG_DETAIL, fmt, ap);
    va_end(ap);
}

void cr_log_error(cr_log *lg, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    cr_log_line(lg, CR_LOG_ERROR, fmt, ap);
    va_end(ap);
}

/* The value of the last "<number>%" in s (a "%.1f%%" progress figure), or -1
 * when there is none; *prefix_len: where that number starts. */
static double cr_log_percent(const char *s, size_t *prefix_len)
{
    double v = -1.0;
    for (const char *p = strchr(s, '%'); p; p = strchr(p + 1, '%')) {
        const char *e = p, *b;
        while (e > s && e[-1] == ' ')
            e--;
        b = e;
        while (b > s && (isdigit((unsigned char)b[-1]) || b[-1] == '.'))
            b--;
        if (b < e) {
            v = strtod(b, NULL);
            *prefix_len = (size_t)(b - s);
        }
    }
    return v;
}

/* FNV-1a of s[0..n). */
static unsigned cr_log_hash(const char *s, size_t n)
{
    unsigned h = 2166136261u;
    for (size_t i = 0; i < n; i++)
        h = (h ^ (unsigned char)s[i]) * 16777619u;
    return h;
}

static double cr_log_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Non-terminal: should this progress line be printed? (see log.h) */
static int cr_log_progress_due(cr_log *lg, const char *msg)
{
    size_t pre = 0;
    double pct = cr_log_percent(msg, &pre);
    int n = (int)(sizeof lg->progress_key / sizeof lg->progress_key[0]);

    if (pct < 0.0) {
        double now = cr_log_now();
        if (lg->progress_time != 0.0 && now - lg->progress_time < 5.0)
            return 0;
        lg->progress_time = now;
        return 1;
    }
    unsigned key = cr_log_hash(msg, pre);
    int decile = (int)(pct / 10.0) + 1; /* 0 % -> 1, 100 % -> 11 */
    for (int i = 0; i < n; i++) {
        if (lg->progress_decile[i] && lg->progress_key[i] == key) {
            if (lg->progress_decile[i] == decile)
                return 0;
            lg->progress_decile[i] = decile;
            return 1;
        }
    }
    int slot = lg->progress_next;
    lg->progress_next = (slot + 1) % n;
    lg->progress_key[slot] = key;
    lg->progress_decile[slot] = decile;
    return 1;
}

void cr_log_progress(cr_log *lg, const char *fmt, ...)
{
    char stack_buf[512];
    char *msg;
    va_list ap;
    size_t len;

    if (lg && lg->quiet)
        return;
    va_start(ap, fmt);
    msg = cr_log_format(stack_buf, sizeof stack_buf, fmt, ap);
    va_end(ap);
    if (!msg)
        return;
    len = strcspn(msg, "\n");
    msg[len] = '\0';

    cr_log_lock(lg);
    if (isatty(STDOUT_FILENO)) {
        /* Overwrite the previous progress line, padding over its tail. */
        int old = lg ? lg->progress_len : 0;
        printf("\r%s%*s", msg, old > (int)len ? old - (int)len : 0, "");
        if (old > (int)len)
            printf("\r%s", msg);
        fflush(stdout);
        if (lg)
            lg->progress_len = len > 0 ? (int)len : 1;
    } else if (!lg || cr_log_progress_due(lg, msg)) {
        printf("%s\n", msg);
        fflush(stdout);
    }
    cr_log_unlock(lg);
    if (msg != stack_buf)
        free(msg);
}
