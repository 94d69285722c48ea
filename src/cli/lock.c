/* curray cli: one run per output folder (lock.h). */
#include "lock.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../base/fsutil.h"

/* The holder's pid as written in the lock file, or 0 when unknown. */
static long cr_dirlock_holder(int fd)
{
    char buf[64];
    long pid = 0;
    ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
    if (n <= 0)
        return 0;
    buf[n] = '\0';
    if (sscanf(buf, "pid %ld", &pid) != 1 || pid <= 0)
        return 0;
    return pid;
}

int cr_dirlock_take(cr_dirlock *l, const char *dir, cr_err *err)
{
    char text[32];
    int tries;
    if (l->held)
        return 0;
    if (cr_path_join(l->path, sizeof l->path, dir, CR_LOCK_NAME) != 0)
        return 1;
    for (tries = 0; tries < 100; tries++) {
        struct stat a, b;
        int fd = open(l->path, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
        if (fd < 0)
            return 1;
        if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
            int e = errno;
            long pid = e == EWOULDBLOCK ? cr_dirlock_holder(fd) : 0;
            close(fd);
            if (e != EWOULDBLOCK)
                return 1; /* no flock here (some network file systems) */
            if (pid > 0)
                return cr_err_set(err,
                                  "output folder %s is in use by another curray (process %ld): "
                                  "two runs cannot write into one folder; wait until it ends, "
                                  "or choose another folder with -o",
                                  dir, pid);
            return cr_err_set(err,
                              "output folder %s is in use by another process (it holds %s): "
                              "two runs cannot write into one folder; wait until it ends, or "
                              "choose another folder with -o",
                              dir, l->path);
        }
        /* the holder before us may have removed the file it locked */
        if (fstat(fd, &a) != 0 || stat(l->path, &b) != 0 || a.st_dev != b.st_dev ||
            a.st_ino != b.st_ino) {
            close(fd);
            continue;
        }
        snprintf(text, sizeof text, "pid %ld\n", (long)getpid());
        if (ftruncate(fd, 0) != 0 || pwrite(fd, text, strlen(text), 0) < 0) {
            /* a full disk: the lock holds, only the message lacks the pid */
        }
        l->fd = fd;
        l->held = 1;
        return 0;
    }
    return 1;
}

void cr_dirlock_release(cr_dirlock *l)
{
    if (!l->held)
        return;
    unlink(l->path);
    close(l->fd);
    l->held = 0;
}
