/* curray io: folders and paths (fsutil.h). */
#include "fsutil.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

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
