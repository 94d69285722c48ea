/* curray output: loadable output modules (module.h). */
#include "module.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#if defined(__APPLE__)
#include <mach-o/dyld.h>
#include <stdint.h>
#endif

#include "../base/fsutil.h"

/* Loaded modules (a handful of files at most), under cr_module_lock. */
#define CR_MODULE_MAX 8
static struct {
    const char *file;
    const void *table;
} cr_modules[CR_MODULE_MAX];
static pthread_mutex_t cr_module_lock = PTHREAD_MUTEX_INITIALIZER;

/* The folder of the running program into dir[n] (no trailing '/'): from
 * /proc/self/exe (Linux), _NSGetExecutablePath (macOS). Returns 0, or -1
 * when the system does not tell. */
static int cr_program_dir(char *dir, size_t n)
{
    char *slash;
#if defined(__APPLE__)
    uint32_t size = (uint32_t)n;
    if (_NSGetExecutablePath(dir, &size) != 0)
        return -1;
#else
    ssize_t len = readlink("/proc/self/exe", dir, n - 1);
    if (len <= 0 || (size_t)len >= n - 1)
        return -1;
    dir[len] = '\0';
#endif
    slash = strrchr(dir, '/');
    if (!slash)
        return -1;
    *slash = '\0';
    if (!dir[0])
        snprintf(dir, n, "/");
    return 0;
}

/* The places file is looked for (module.h), into dirs[3][4096]; returns how
 * many. */
static int cr_module_dirs(char dirs[][4096])
{
    const char *env = getenv("CURRAY_MODULE_DIR");
    char prog[4096];
    if (env && env[0]) {
        snprintf(dirs[0], 4096, "%s", env);
        return 1;
    }
    if (cr_program_dir(prog, sizeof prog) != 0)
        return 0;
    if (cr_path_join(dirs[0], 4096, prog, CURRAY_MODULE_RELDIR) != 0)
        return 0;
    snprintf(dirs[1], 4096, "%s", prog);
    return 2;
}

/* Open file from the first of the places that holds it; its table, or NULL
 * with err set. */
static const void *cr_module_open(const char *file, const char *entry, const char *what,
                                  const char *needs, cr_err *err)
{
    char dirs[3][4096], path[4096], looked[3 * 4096 + 16] = "";
    int n = cr_module_dirs(dirs), i;
    for (i = 0; i < n; i++) {
        void *h;
        const cr_module_header *(*get)(void);
        const cr_module_header *t;
        if (cr_path_join(path, sizeof path, dirs[i], file) != 0)
            continue;
        if (access(path, F_OK) != 0) {
            size_t len = strlen(looked);
            snprintf(looked + len, sizeof looked - len, "%s%s", len ? ", " : "", dirs[i]);
            continue;
        }
        h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
        if (!h) {
            const char *why = dlerror();
            cr_err_set(err, "cannot load curray's %s %s: %s (it needs %s)", what, path,
                       why ? why : "unknown reason", needs);
            return NULL;
        }
        /* dlsym gives an object pointer; POSIX guarantees the conversion */
        *(void **)&get = dlsym(h, entry);
        t = get ? get() : NULL;
        if (!t) {
            cr_err_set(err, "cannot load curray's %s %s: it has no function %s", what, path,
                       entry);
            dlclose(h);
            return NULL;
        }
        if (strcmp(t->version, CURRAY_VERSION) != 0 || t->layout != CR_MODULE_LAYOUT) {
            cr_err_set(err,
                       "cannot load curray's %s %s: it was built for curray %s (layout %lu), "
                       "this is curray %s (layout %lu); install the module of this build",
                       what, path, t->version, t->layout, CURRAY_VERSION,
                       (unsigned long)CR_MODULE_LAYOUT);
            dlclose(h);
            return NULL;
        }
        return t;
    }
    if (n == 0)
        cr_err_set(err, "cannot load curray's %s %s: the folder of the running program is "
                        "unknown; set CURRAY_MODULE_DIR to the folder that holds it", what, file);
    else
        cr_err_set(err, "cannot load curray's %s: %s is not in %s (set CURRAY_MODULE_DIR to "
                        "the folder that holds it, or install curray again)", what, file, looked);
    return NULL;
}

const void *cr_module_load(const char *file, const char *entry, const char *what,
                           const char *needs, cr_err *err)
{
    const void *t = NULL;
    int i;
    pthread_mutex_lock(&cr_module_lock);
    for (i = 0; i < CR_MODULE_MAX && cr_modules[i].file; i++)
        if (!strcmp(cr_modules[i].file, file)) {
            t = cr_modules[i].table;
            break;
        }
    if (!t && i < CR_MODULE_MAX) {
        t = cr_module_open(file, entry, what, needs, err);
        if (t) {
            cr_modules[i].file = file;
            cr_modules[i].table = t;
        }
    } else if (!t) {
        cr_err_set(err, "cannot load curray's %s %s: too many modules", what, file);
    }
    pthread_mutex_unlock(&cr_module_lock);
    return t;
}
