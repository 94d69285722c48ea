/* curray cli: the crash handler (E.2: a crash leaves its own log file).
 *
 * On SIGSEGV, SIGBUS, SIGFPE, SIGILL or SIGABRT the handler writes
 * <log folder>/crash-YYYYmmdd-HHMMSS-<pid>.log (local time of the crash) with
 * the signal, a backtrace of the thread that received it and the run's
 * settings, prints one line naming that file on stderr, then restores the
 * signal's default action and raises it again, so the process still dies by
 * the same signal (exit status 128 + signal in a shell, a core dump where
 * enabled). When the file cannot be created the report goes to stderr.
 *
 * The handler makes only async-signal-safe calls (open, write, close,
 * clock_gettime, sigaction, raise, backtrace_symbols_fd; backtrace itself is
 * run once at install so that its library is loaded then, not in the
 * handler). Everything else (the file name prefix, the settings text, the
 * time zone offset) is prepared by cr_crash_install.
 *
 * State: a signal handler can reach nothing but statics, so the prepared
 * report lives in one static struct in crash.c, written only by
 * cr_crash_install/cr_crash_uninstall on the main thread before and after the
 * render, read only by the handler. */
#ifndef CR_CLI_CRASH_H
#define CR_CLI_CRASH_H

#include "../base/error.h"

/* Install the handler for the five signals. log_dir: the folder for the
 * crash file (it should exist; "" or NULL: the current folder). version:
 * curray's version. settings: the run's settings as text, copied. Also gives
 * the calling thread an alternate signal stack, so that a stack overflow
 * there is reported too. Returns 0, or -1 with err set (nothing installed). */
int cr_crash_install(const char *log_dir, const char *version, const char *settings,
                     cr_err *err);

/* Restore the default actions and free what cr_crash_install prepared. */
void cr_crash_uninstall(void);

#endif
