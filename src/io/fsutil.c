/* curray io: folders and atomic files (fsutil.h).
 *
 * Atomic output: the data goes to a temporary file ".<name>.tmp.<pid>.<n>" in
 * the destination's own folder (so that rename() never crosses file systems),
 * which is flushed, fsync'ed, closed and renamed over the destination only
 * when every step succeeded. A reader therefore sees either the old file or
 * the complete new one, never a truncated one. */
#include "fsutil.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

int cr_mkdir_p(const char *dir, cr_err *err)
{
    char buf[4096];
    size_t len;
    struct stat st;

    if (!dir || !*dir)
        return cr_err_set(err, "cannot create folder: empty folder name");
    len = strlen(dir);
    if (len >= sizeof buf)
        return cr_err_set(err, "cannot create folder '%s': name too long", dir);
    memcpy(buf, dir, len + 1);

    /* Create each prefix that ends before a '/', then the whole path. */
    for (size_t i = 1; i <= len; i++) {
        if (buf[i] != '/' && buf[i] != '\0')
            continue;
        if (buf[i - 1] == '/')
            continue; /* "a//b": the prefix "a/" was already made */
        char saved = buf[i];
        buf[i] = '\0';
        if (mkdir(buf, 0777) != 0) {
            int e = errno;
            /* Whatever mkdir says (EEXIST, or EACCES/EROFS for a folder that
             * exists in a place we cannot write), an existing folder is fine. */
            if (stat(buf, &st) != 0)
                return cr_err_set(err, "cannot create folder '%s': cannot create '%s': %s", dir,
                                  buf, strerror(e));
            if (!S_ISDIR(st.st_mode) && i == len)
                return cr_err_set(err, "cannot create folder '%s': it exists and is not a folder",
                                  dir);
            if (!S_ISDIR(st.st_mode))
                return cr_err_set(err, "cannot create folder '%s': '%s' exists and is not a folder",
                                  dir, buf);
        }
        buf[i] = saved;
    }
    return 0;
}

int cr_path_join(char *out, size_t n, const char *dir, const char *name)
{
    int len;
    if (!out || n == 0)
        return -1;
    if (!dir || !*dir || name[0] == '/') {
        len = snprintf(out, n, "%s", name);
    } else {
        size_t dl = strlen(dir);
        const char *sep = dir[dl - 1] == '/' ? "" : "/";
        len = snprintf(out, n, "%s%s%s", dir, sep, name);
    }
    if (len < 0 || (size_t)len >= n) {
        out[0] = '\0';
        return -1;
    }
    return 0;
}

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
