#!/usr/bin/env python3
"""bench/timecmd.py: run one command and report its wall and CPU time.

Usage: timecmd.py OUTFILE -- COMMAND [ARGS...]

Runs COMMAND with its stdout and stderr going to OUTFILE.log, waits for it,
and writes one line to OUTFILE:
    wall_s user_s sys_s maxrss_kb exit_status
wall_s is time.perf_counter() around the process (start to exit); user_s and
sys_s come from wait4()'s rusage, which Linux reports to the microsecond (GNU
time prints only centiseconds, too coarse for a 70 ms frame). The exit status
of timecmd.py is the command's (128 + signal when it was killed).
Standard library only: it is used by bench/kerrz.sh and bench/mino.sh.
"""
import os
import sys
import time


def main():
    if len(sys.argv) < 4 or sys.argv[2] != "--":
        sys.stderr.write("usage: timecmd.py OUTFILE -- COMMAND [ARGS...]\n")
        return 2
    out, cmd = sys.argv[1], sys.argv[3:]
    with open(out + ".log", "wb") as log:
        t0 = time.perf_counter()
        if hasattr(os, "posix_spawnp"):
            # posix_spawn (vfork-like): the child runs no Python, so its CPU
            # time is the command's own (a fork of this interpreter adds about
            # 1.5 ms of copy-on-write page faults to the child's rusage)
            fa = [(os.POSIX_SPAWN_DUP2, log.fileno(), 1), (os.POSIX_SPAWN_DUP2, log.fileno(), 2),
                  (os.POSIX_SPAWN_OPEN, 0, os.devnull, os.O_RDONLY, 0)]
            try:
                pid = os.posix_spawnp(cmd[0], cmd, os.environ, file_actions=fa)
            except OSError as e:
                sys.stderr.write("timecmd.py: cannot run %s: %s\n" % (cmd[0], e))
                return 127
        else:
            try:
                pid = os.fork()
            except OSError as e:
                sys.stderr.write("timecmd.py: fork: %s\n" % e)
                return 127
            if pid == 0:
                try:
                    os.dup2(log.fileno(), 1)
                    os.dup2(log.fileno(), 2)
                    devnull = os.open(os.devnull, os.O_RDONLY)
                    os.dup2(devnull, 0)
                    os.execvp(cmd[0], cmd)
                except OSError as e:
                    os.write(2, ("timecmd.py: cannot run %s: %s\n" % (cmd[0], e)).encode())
                os._exit(127)
        _, status, ru = os.wait4(pid, 0)
        t1 = time.perf_counter()
    if os.WIFEXITED(status):
        rc = os.WEXITSTATUS(status)
    else:
        rc = 128 + os.WTERMSIG(status)
    with open(out, "w") as f:
        f.write("%.6f %.6f %.6f %d %d\n" % (t1 - t0, ru.ru_utime, ru.ru_stime, ru.ru_maxrss, rc))
    return rc


if __name__ == "__main__":
    sys.exit(main())
