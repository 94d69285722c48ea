/* curray base: will this much memory fit? (memcheck.h) */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* pthread_getattr_default_np */
#endif
#include "memcheck.h"

#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

int cr_mem_check(double bytes, cr_err *err)
{
    const double gib = 1024.0 * 1024.0 * 1024.0;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double have = pages > 0 && page > 0 ? (double)pages * (double)page : 0.0;
    const char *what = "the machine's memory";
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        (have <= 0.0 || (double)rl.rlim_cur < have)) {
        have = (double)rl.rlim_cur;
        what = "the address-space limit (ulimit -v)";
    }
    if (getrlimit(RLIMIT_DATA, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        (have <= 0.0 || (double)rl.rlim_cur < have)) {
        have = (double)rl.rlim_cur;
        what = "the data-size limit (ulimit -d)";
    }
    if (have > 0.0 && bytes > have)
        return cr_err_set(err, "needs about %.2f GiB of memory, more than the %.2f GiB of %s",
                          bytes / gib, have / gib, what);
    return 0;
}

double cr_mem_thread_stack(void)
{
    size_t size = 0;
#if defined(__GLIBC__)
    pthread_attr_t a;
    if (pthread_getattr_default_np(&a) == 0) {
        if (pthread_attr_getstacksize(&a, &size) != 0)
            size = 0;
        pthread_attr_destroy(&a);
    }
#endif
    return size > 0 ? (double)size : 8.0 * 1024.0 * 1024.0;
}
