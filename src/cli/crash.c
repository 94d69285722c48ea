/* curray cli: the crash handler (crash.h). */
#define _XOPEN_SOURCE 700 /* sigaltstack, SA_ONSTACK, SIGSTKSZ */
#include "crash.h"

#include <errno.h>
#include <execinfo.h>
#include <fcntl.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../base/fsutil.h"

static const int cr_crash_signals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
#define CR_CRASH_NSIG ((int)(sizeof cr_crash_signals / sizeof cr_crash_signals[0]))

/* The report prepared by cr_crash_install (see crash.h: the one static). */
static struct {
    int installed;
    char prefix[4096];  /* "<log folder>/crash-" */
    char version[64];
    char *settings;     /* malloc'ed copy */
    size_t settings_len;
    long utc_offset;    /* local time minus UTC, s, at install */
    long pid;
    void *altstack;
    struct sigaction old[CR_CRASH_NSIG];
    atomic_flag busy;   /* set by the first crashing thread */
} cr_crash;

/* ---- async-signal-safe text ------------------------------------------------ */

static void cr_crash_put(int fd, const char *s)
{
    size_t n = strlen(s);
    while (n > 0) {
        ssize_t w = write(fd, s, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return;
        s += w;
        n -= (size_t)w;
    }
}

/* Decimal digits of v, at least `width` (zero-padded), into buf (>= 24). */
static char *cr_crash_ulong(char *buf, unsigned long v, int width)
{
    char tmp[24];
    int n = 0, k = 0;
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v && n < 23);
    while (n < width && n < 23)
        tmp[n++] = '0';
    while (n > 0)
        buf[k++] = tmp[--n];
    buf[k] = '\0';
    return buf;
}

static char *cr_crash_hex(char *buf, unsigned long v)
{
    static const char digits[] = "0123456789abcdef";
    char tmp[20];
    int n = 0, k = 2;
    do {
        tmp[n++] = digits[v & 15];
        v >>= 4;
    } while (v);
    buf[0] = '0';
    buf[1] = 'x';
    while (n > 0)
        buf[k++] = tmp[--n];
    buf[k] = '\0';
    return buf;
}

/* Append s to buf (size n). */
static void cr_crash_cat(char *buf, size_t n, const char *s)
{
    size_t len = strlen(buf), m = strlen(s);
    if (len + m >= n)
        m = n - len - 1;
    memcpy(buf + len, s, m);
    buf[len + m] = '\0';
}

/* "YYYYmmdd-HHMMSS" of the Unix time t (days to civil date: H. Hinnant's
 * algorithm, proleptic Gregorian). */
static void cr_crash_stamp(char *out, long t)
{
    long days = t >= 0 ? t / 86400 : -((-t + 86399) / 86400), s = t - days * 86400;
    long z = days + 719468, era = (z >= 0 ? z : z - 146096) / 146097;
    long doe = z - era * 146097;
    long yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    long y = yoe + era * 400, doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    long mp = (5 * doy + 2) / 153, d = doy - (153 * mp + 2) / 5 + 1;
    long m = mp < 10 ? mp + 3 : mp - 9;
    char num[24];
    out[0] = '\0';
    cr_crash_cat(out, 16, cr_crash_ulong(num, (unsigned long)(y + (m <= 2)), 4));
    cr_crash_cat(out, 16, cr_crash_ulong(num, (unsigned long)m, 2));
    cr_crash_cat(out, 16, cr_crash_ulong(num, (unsigned long)d, 2));
    cr_crash_cat(out, 16, "-");
    cr_crash_cat(out, 16, cr_crash_ulong(num, (unsigned long)(s / 3600), 2));
    cr_crash_cat(out, 16, cr_crash_ulong(num, (unsigned long)(s / 60 % 60), 2));
    cr_crash_cat(out, 16, cr_crash_ulong(num, (unsigned long)(s % 60), 2));
}

static const char *cr_crash_signame(int sig)
{
    switch (sig) {
    case SIGSEGV: return "SIGSEGV (invalid memory access)";
    case SIGBUS: return "SIGBUS (bus error)";
    case SIGFPE: return "SIGFPE (arithmetic exception)";
    case SIGILL: return "SIGILL (illegal instruction)";
    case SIGABRT: return "SIGABRT (aborted)";
    default: return "an unexpected signal";
    }
}

/* ---- the handler ----------------------------------------------------------- */

static void cr_crash_handler(int sig, siginfo_t *si, void *uctx)
{
    char path[sizeof cr_crash.prefix + 64], stamp[16], num[24];
    void *frames[64];
    struct timespec ts;
    struct sigaction dfl;
    int fd, n;
    (void)uctx;

    if (atomic_flag_test_and_set(&cr_crash.busy)) {
        /* another thread is writing the report and will end the process */
        for (;;)
            pause();
    }
    clock_gettime(CLOCK_REALTIME, &ts);
    cr_crash_stamp(stamp, (long)ts.tv_sec + cr_crash.utc_offset);
    path[0] = '\0';
    cr_crash_cat(path, sizeof path, cr_crash.prefix);
    cr_crash_cat(path, sizeof path, stamp);
    cr_crash_cat(path, sizeof path, "-");
    cr_crash_cat(path, sizeof path, cr_crash_ulong(num, (unsigned long)cr_crash.pid, 1));
    cr_crash_cat(path, sizeof path, ".log");
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);

    cr_crash_put(fd >= 0 ? fd : 2, "curray ");
    cr_crash_put(fd >= 0 ? fd : 2, cr_crash.version);
    cr_crash_put(fd >= 0 ? fd : 2, " crashed: signal ");
    cr_crash_put(fd >= 0 ? fd : 2, cr_crash_ulong(num, (unsigned long)sig, 1));
    cr_crash_put(fd >= 0 ? fd : 2, ", ");
    cr_crash_put(fd >= 0 ? fd : 2, cr_crash_signame(sig));
    cr_crash_put(fd >= 0 ? fd : 2, "\n");
    if (si && si->si_code <= 0) {
        /* SI_USER, SI_TKILL, SI_QUEUE: sent by a process, not a fault */
        cr_crash_put(fd >= 0 ? fd : 2, "sent by process ");
        cr_crash_put(fd >= 0 ? fd : 2, cr_crash_ulong(num, (unsigned long)si->si_pid, 1));
        cr_crash_put(fd >= 0 ? fd : 2, "\n");
    } else if (si && sig != SIGABRT) {
        cr_crash_put(fd >= 0 ? fd : 2, "fault address ");
        cr_crash_put(fd >= 0 ? fd : 2, cr_crash_hex(num, (unsigned long)si->si_addr));
        cr_crash_put(fd >= 0 ? fd : 2, ", si_code ");
        cr_crash_put(fd >= 0 ? fd : 2, cr_crash_ulong(num, (unsigned long)si->si_code, 1));
        cr_crash_put(fd >= 0 ? fd : 2, "\n");
    }
    cr_crash_put(fd >= 0 ? fd : 2, "process ");
    cr_crash_put(fd >= 0 ? fd : 2, cr_crash_ulong(num, (unsigned long)cr_crash.pid, 1));
    cr_crash_put(fd >= 0 ? fd : 2, ", local time ");
    cr_crash_put(fd >= 0 ? fd : 2, stamp);
    cr_crash_put(fd >= 0 ? fd : 2, "\n\nBacktrace of the thread that received the signal "
                                   "(innermost first):\n");
    n = backtrace(frames, (int)(sizeof frames / sizeof frames[0]));
    backtrace_symbols_fd(frames, n, fd >= 0 ? fd : 2);
    cr_crash_put(fd >= 0 ? fd : 2, "\nRun settings:\n");
    if (cr_crash.settings)
        cr_crash_put(fd >= 0 ? fd : 2, cr_crash.settings);
    if (fd >= 0) {
        close(fd);
        cr_crash_put(2, "\ncurray: crashed with ");
        cr_crash_put(2, cr_crash_signame(sig));
        cr_crash_put(2, "; crash report in ");
        cr_crash_put(2, path);
        cr_crash_put(2, "\n");
    }

    /* die by the same signal: default action, raised again; it is blocked
     * while this handler runs and is delivered when the handler returns (a
     * fault would also recur on return) */
    memset(&dfl, 0, sizeof dfl);
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    sigaction(sig, &dfl, NULL);
    raise(sig);
}

/* ---- install --------------------------------------------------------------- */

/* Days from 1970-01-01 to the civil date y-m-d (H. Hinnant). */
static long cr_crash_days(long y, long m, long d)
{
    long era, yoe, doy, doe;
    y -= m <= 2;
    era = (y >= 0 ? y : y - 399) / 400;
    yoe = y - era * 400;
    doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
    doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + doe - 719468;
}

/* Local time minus UTC now, in seconds. */
static long cr_crash_utc_offset(void)
{
    time_t now = time(NULL);
    struct tm lt, ut;
    if (!localtime_r(&now, &lt) || !gmtime_r(&now, &ut))
        return 0;
    return (cr_crash_days(lt.tm_year + 1900L, lt.tm_mon + 1L, lt.tm_mday) -
            cr_crash_days(ut.tm_year + 1900L, ut.tm_mon + 1L, ut.tm_mday)) * 86400L +
           (lt.tm_hour - ut.tm_hour) * 3600L + (lt.tm_min - ut.tm_min) * 60L +
           (lt.tm_sec - ut.tm_sec);
}

int cr_crash_install(const char *log_dir, const char *version, const char *settings,
                     cr_err *err)
{
    struct sigaction sa;
    stack_t ss;
    void *probe[2];
    int k;

    if (cr_crash.installed)
        cr_crash_uninstall();
    memset(&cr_crash, 0, sizeof cr_crash);
    atomic_flag_clear(&cr_crash.busy);
    if (cr_path_join(cr_crash.prefix, sizeof cr_crash.prefix, log_dir, "crash-") != 0)
        return cr_err_set(err, "crash handler: folder name too long: '%s'", log_dir);
    snprintf(cr_crash.version, sizeof cr_crash.version, "%s", version ? version : "");
    cr_crash.settings_len = settings ? strlen(settings) : 0;
    cr_crash.settings = malloc(cr_crash.settings_len + 2);
    if (!cr_crash.settings)
        return cr_err_set(err, "crash handler: out of memory");
    memcpy(cr_crash.settings, settings ? settings : "", cr_crash.settings_len);
    if (cr_crash.settings_len == 0 || cr_crash.settings[cr_crash.settings_len - 1] != '\n')
        cr_crash.settings[cr_crash.settings_len++] = '\n';
    cr_crash.settings[cr_crash.settings_len] = '\0';
    cr_crash.pid = (long)getpid();
    cr_crash.utc_offset = cr_crash_utc_offset();
    backtrace(probe, 2); /* loads libgcc's unwinder now, not in the handler */

    /* an alternate stack for this thread, so that a stack overflow can be reported */
    cr_crash.altstack = malloc((size_t)SIGSTKSZ * 4);
    if (cr_crash.altstack) {
        ss.ss_sp = cr_crash.altstack;
        ss.ss_size = (size_t)SIGSTKSZ * 4;
        ss.ss_flags = 0;
        if (sigaltstack(&ss, NULL) != 0) {
            free(cr_crash.altstack);
            cr_crash.altstack = NULL;
        }
    }

    memset(&sa, 0, sizeof sa);
    sa.sa_sigaction = cr_crash_handler;
    sa.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigemptyset(&sa.sa_mask);
    for (k = 0; k < CR_CRASH_NSIG; k++)
        sigaddset(&sa.sa_mask, cr_crash_signals[k]); /* one crash report at a time */
    for (k = 0; k < CR_CRASH_NSIG; k++)
        sigaction(cr_crash_signals[k], &sa, &cr_crash.old[k]);
    cr_crash.installed = 1;
    return 0;
}

void cr_crash_uninstall(void)
{
    stack_t ss;
    int k;
    if (!cr_crash.installed)
        return;
    for (k = 0; k < CR_CRASH_NSIG; k++)
        sigaction(cr_crash_signals[k], &cr_crash.old[k], NULL);
    if (cr_crash.altstack) {
        memset(&ss, 0, sizeof ss);
        ss.ss_flags = SS_DISABLE;
        sigaltstack(&ss, NULL);
        free(cr_crash.altstack);
    }
    free(cr_crash.settings);
    memset(&cr_crash, 0, sizeof cr_crash);
}
