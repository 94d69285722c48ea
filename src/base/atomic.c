/* curray io: files that readers only ever see whole (atomic.h).
 *
 * Atomic output: the data goes to a temporary file ".<name>.tmp.<pid>.<n>" in
 * the destination's own folder (so that rename() never crosses file systems),
 * which is flushed, fsync'ed, closed and renamed over the destination only
 * when every step succeeded. A reader therefore sees either the old file or
 * the complete new one, never a truncated one.
 *
 * Appending: one write(2) per record on an O_APPEND descriptor, and on any
 * failure ftruncate() back to the last whole record. */
#include "atomic.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

int cr_atomic_open(cr_atomic *a, const char *path, cr_err *err)
{
    const char *slash;
    int dirlen, fd = -1;

    memset(a, 0, sizeof *a);
    if (!path || !*path)
        return cr_err_set(err, "cannot write a file with an empty name");
    if (strlen(path) >= sizeof a->path)
        return cr_err_set(err, "cannot write '%s': path too long", path);
    memcpy(a->path, path, strlen(path) + 1);

    slash = strrchr(path, '/');
    dirlen = slash ? (int)(slash - path + 1) : 0; /* keeps the '/' */
    if (slash && slash[1] == '\0')
        return cr_err_set(err, "cannot write '%s': the name is a folder", path);

    /* open(O_CREAT | O_EXCL) gives the same exclusivity as mkstemp, and
     * unlike mkstemp's 0600 it lets the umask decide the final mode. The name
     * holds the pid and the address of *a, which differ between concurrent
     * writers; a clash with a stale temporary just takes the next attempt. */
    for (int attempt = 0; attempt < 100; attempt++) {
        int len = snprintf(a->tmp, sizeof a->tmp, "%.*s.%s.tmp.%ld.%lx.%d", dirlen, path,
                           path + dirlen, (long)getpid(), (unsigned long)(uintptr_t)a, attempt);
        if (len < 0 || (size_t)len >= sizeof a->tmp)
            return cr_err_set(err, "cannot write '%s': path too long", path);
        fd = open(a->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST)
            break;
    }
    if (fd < 0) {
        int e = errno;
        a->tmp[0] = '\0';
        return cr_err_set(err, "cannot write '%s': cannot create a file in its folder: %s", path,
                          strerror(e));
    }
    a->fp = fdopen(fd, "wb");
    if (!a->fp) {
        int e = errno;
        close(fd);
        unlink(a->tmp);
        a->tmp[0] = '\0';
        return cr_err_set(err, "cannot write '%s': %s", path, strerror(e));
    }
    return 0;
}

int cr_stream_check(FILE *fp, const char *name, cr_err *err)
{
    if (fflush(fp) != 0)
        return cr_err_set(err, "writing %s: %s", name, strerror(errno));
    if (ferror(fp))
        return cr_err_set(err, "writing %s: an earlier write failed", name);
    return 0;
}

int cr_atomic_commit(cr_atomic *a, cr_err *err)
{
    int e;

    if (!a->fp)
        return cr_err_set(err, "writing %s: the file is not open", a->path);
    if (cr_stream_check(a->fp, a->path, err) != 0)
        goto fail;
    if (fsync(fileno(a->fp)) != 0 && errno != EINVAL && errno != EROFS) {
        /* EINVAL/EROFS: the file cannot be synced (a special file); nothing
         * was lost. */
        cr_err_set(err, "writing %s: %s", a->path, strerror(errno));
        goto fail;
    }
    e = fclose(a->fp);
    a->fp = NULL;
    if (e != 0) {
        cr_err_set(err, "writing %s: %s", a->path, strerror(errno));
        goto fail;
    }
    if (rename(a->tmp, a->path) != 0) {
        cr_err_set(err, "writing %s: cannot rename '%s' to it: %s", a->path, a->tmp,
                   strerror(errno));
        goto fail;
    }
    a->tmp[0] = '\0';
    return 0;

fail:
    cr_atomic_abort(a);
    return -1;
}

void cr_atomic_abort(cr_atomic *a)
{
    if (a->fp) {
        fclose(a->fp);
        a->fp = NULL;
    }
    if (a->tmp[0]) {
        unlink(a->tmp);
        a->tmp[0] = '\0';
    }
}

void cr_appender_init(cr_appender *a)
{
    memset(a, 0, sizeof *a);
    a->fd = -1;
}

int cr_appender_create(cr_appender *a, const char *path, const void *data, size_t n,
                       cr_err *err)
{
    cr_atomic at;
    int fd, flags;

    cr_appender_init(a);
    if (cr_atomic_open(&at, path, err) != 0)
        return -1;
    memcpy(a->path, at.path, sizeof a->path);
    /* A second descriptor of the temporary keeps the file once it has been
     * renamed: no window in which another file could take the name. */
    fd = dup(fileno(at.fp));
    if (fd < 0) {
        int e = errno;
        cr_atomic_abort(&at);
        return cr_err_set(err, "writing %s: %s", path, strerror(e));
    }
    /* a short write sets the stream's error flag, which the commit reports */
    if (n > 0)
        fwrite(data, 1, n, at.fp);
    if (cr_atomic_commit(&at, err) != 0) {
        close(fd);
        return -1;
    }
    flags = fcntl(fd, F_GETFL);
    if (flags < 0 || fcntl(fd, F_SETFL, flags | O_APPEND) != 0 ||
        fcntl(fd, F_SETFD, FD_CLOEXEC) != 0) {
        int e = errno;
        close(fd);
        return cr_err_set(err, "writing %s: %s", path, strerror(e));
    }
    a->fd = fd;
    a->size = (long long)n;
    a->bytes_written = n;
    return 0;
}

int cr_appender_add(cr_appender *a, const void *rec, size_t n, cr_err *err)
{
    const char *p = rec;
    size_t left = n;
    int e;

    if (a->fd < 0)
        return cr_err_set(err, "writing %s: the file is not open", a->path);
    while (left > 0) {
        ssize_t w = write(a->fd, p, left);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            e = w < 0 ? errno : EIO;
            goto fail;
        }
        a->bytes_written += (unsigned long long)w;
        p += w;
        left -= (size_t)w;
    }
    a->size += (long long)n;
    return 0;

fail:
    /* Cut off whatever part of the record did get written. */
    if (left < n && ftruncate(a->fd, (off_t)a->size) != 0) {
        int e2 = errno;
        return cr_err_set(err, "writing %s: %s (and cutting off the partial record: %s)",
                          a->path, strerror(e), strerror(e2));
    }
    return cr_err_set(err, "writing %s: %s", a->path, strerror(e));
}

int cr_appender_close(cr_appender *a, cr_err *err)
{
    int rc = 0;

    if (a->fd < 0)
        return 0;
    if (fsync(a->fd) != 0 && errno != EINVAL && errno != EROFS)
        rc = cr_err_set(err, "writing %s: %s", a->path, strerror(errno));
    if (close(a->fd) != 0 && rc == 0)
        rc = cr_err_set(err, "writing %s: %s", a->path, strerror(errno));
    a->fd = -1;
    return rc;
}
