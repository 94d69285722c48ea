/* curray cli: Ctrl-C and SIGTERM during a render (interrupt.h). */
#include "interrupt.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../base/fsutil.h"

/* The installed cr_interrupt, for the signal handler (the one static, see
 * interrupt.h); NULL when none. */
static _Atomic(cr_interrupt *) cr_interrupt_active;

static void cr_interrupt_handler(int sig)
{
    cr_interrupt *in = atomic_load(&cr_interrupt_active);
    int saved = errno;
    (void)sig;
    if (in) {
        int n = atomic_fetch_add(&in->count, 1) + 1;
        if (n == 1) {
            static const char msg[] = "\ncurray: stopping after the frames being written; press "
                                      "Ctrl-C again to stop at once\n";
            (void)!write(2, msg, sizeof msg - 1);
        } else if (n == 2) {
            sem_post(&in->wake);
        }
    }
    errno = saved;
}

/* After cr_interrupt_remove of a run that is stopping: a further signal
 * ends the process at once with the status of an interrupted run (nothing
 * is being written by then but info.txt's last fsync). */
static void cr_interrupt_late_handler(int sig)
{
    (void)sig;
    _exit(130);
}

static double cr_interrupt_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Remove our temporaries in the output folder: ".<name>.tmp.<pid>.*". Marks
 * the slots whose file they were. Caller holds in->lock. */
static void cr_interrupt_sweep(cr_interrupt *in)
{
    char tag[48], path[4096];
    DIR *d = opendir(in->dir);
    struct dirent *e;
    int k;
    if (!d)
        return;
    snprintf(tag, sizeof tag, ".tmp.%ld.", (long)getpid());
    while ((e = readdir(d)) != NULL) {
        const char *t = strstr(e->d_name, tag);
        if (e->d_name[0] != '.' || !t)
            continue;
        if (cr_path_join(path, sizeof path, in->dir, e->d_name) != 0 || unlink(path) != 0)
            continue;
        for (k = 0; k < CR_INTERRUPT_SLOTS; k++) {
            size_t n = strlen(in->slot[k].writing);
            if (n && (size_t)(t - e->d_name) == n + 1 &&
                memcmp(e->d_name + 1, in->slot[k].writing, n) == 0)
                in->slot[k].removed = 1;
        }
    }
    closedir(d);
}

/* The second signal: stop at once, leaving no temporary and no file of an
 * unfinished frame (interrupt.h). Does not return. */
static void cr_interrupt_hard_stop(cr_interrupt *in)
{
    double deadline = cr_interrupt_now() + 5.0;
    char path[4096];
    int k, f, pending;
    struct timespec nap = {0, 5 * 1000 * 1000};

    pthread_mutex_lock(&in->lock);
    in->closed = 1;
    for (;;) {
        cr_interrupt_sweep(in);
        pending = 0;
        for (k = 0; k < CR_INTERRUPT_SLOTS; k++)
            pending += in->slot[k].writing[0] && !in->slot[k].removed;
        if (!pending || cr_interrupt_now() > deadline)
            break;
        pthread_mutex_unlock(&in->lock);
        nanosleep(&nap, NULL);
        pthread_mutex_lock(&in->lock);
    }
    for (k = 0; k < CR_INTERRUPT_SLOTS; k++)
        for (f = 0; in->slot[k].frame >= 0 && f < in->slot[k].n_kept; f++)
            if (cr_path_join(path, sizeof path, in->dir, in->slot[k].kept[f]) == 0)
                unlink(path);
    /* the lock stays held: no writer may start or finish a file now */
    cr_log_error(in->log, "curray: interrupted again: stopped at once; the frames finished "
                          "before are kept, the unfinished ones left no file");
    _exit(130); /* the log file is flushed line by line */
}

static void *cr_interrupt_stopper(void *arg)
{
    cr_interrupt *in = arg;
    for (;;) {
        while (sem_wait(&in->wake) != 0 && errno == EINTR)
            ;
        if (atomic_load(&in->quit))
            return NULL;
        if (atomic_load(&in->count) >= 2)
            cr_interrupt_hard_stop(in);
    }
}

int cr_interrupt_install(cr_interrupt *in, const char *dir, cr_log *log, cr_err *err)
{
    struct sigaction sa;
    sigset_t all, old;
    int k, e;

    memset(in, 0, sizeof *in);
    atomic_init(&in->count, 0);
    atomic_init(&in->quit, 0);
    in->dir = dir;
    in->log = log;
    for (k = 0; k < CR_INTERRUPT_SLOTS; k++)
        in->slot[k].frame = -1;
    if (sem_init(&in->wake, 0, 0) != 0)
        return cr_err_set(err, "cannot set up Ctrl-C handling: %s", strerror(errno));
    pthread_mutex_init(&in->lock, NULL);
    /* the stopper runs with every signal blocked: the handler runs elsewhere */
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    e = pthread_create(&in->stopper, NULL, cr_interrupt_stopper, in);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (e != 0) {
        pthread_mutex_destroy(&in->lock);
        sem_destroy(&in->wake);
        return cr_err_set(err, "cannot set up Ctrl-C handling: %s", strerror(e));
    }
    in->stopper_running = 1;
    atomic_store(&cr_interrupt_active, in);
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = cr_interrupt_handler;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    return 0;
}

void cr_interrupt_remove(cr_interrupt *in)
{
    struct sigaction sa;
    if (!in->stopper_running)
        return;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = atomic_load(&in->count) > 0 ? cr_interrupt_late_handler : SIG_DFL;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    atomic_store(&cr_interrupt_active, NULL);
    atomic_store(&in->quit, 1);
    sem_post(&in->wake);
    pthread_join(in->stopper, NULL);
    in->stopper_running = 0;
    pthread_mutex_destroy(&in->lock);
    sem_destroy(&in->wake);
}

int cr_interrupt_requested(cr_interrupt *in)
{
    return atomic_load_explicit(&in->count, memory_order_relaxed) > 0;
}

void cr_interrupt_frame_begin(cr_interrupt *in, int slot, int k)
{
    pthread_mutex_lock(&in->lock);
    in->slot[slot].frame = k;
    in->slot[slot].n_kept = 0;
    pthread_mutex_unlock(&in->lock);
}

int cr_interrupt_file_begin(cr_interrupt *in, int slot, const char *name)
{
    int rc = 0;
    pthread_mutex_lock(&in->lock);
    if (in->closed) {
        rc = -1;
    } else {
        snprintf(in->slot[slot].writing, sizeof in->slot[slot].writing, "%s", name);
        in->slot[slot].removed = 0;
    }
    pthread_mutex_unlock(&in->lock);
    return rc;
}

void cr_interrupt_file_end(cr_interrupt *in, int slot, int kept, int frame_done)
{
    cr_interrupt_slot *s = &in->slot[slot];
    pthread_mutex_lock(&in->lock);
    if (kept && s->n_kept < CR_INTERRUPT_FILES)
        memcpy(s->kept[s->n_kept++], s->writing, sizeof s->writing);
    s->writing[0] = '\0';
    s->removed = 0;
    if (frame_done) {
        s->frame = -1;
        s->n_kept = 0;
    }
    pthread_mutex_unlock(&in->lock);
}

void cr_interrupt_frame_end(cr_interrupt *in, int slot)
{
    pthread_mutex_lock(&in->lock);
    in->slot[slot].frame = -1;
    in->slot[slot].n_kept = 0;
    in->slot[slot].writing[0] = '\0';
    pthread_mutex_unlock(&in->lock);
}

int cr_interrupt_video_failed(cr_interrupt *in, cr_log *log, const char *msg, long frames,
                              const char *dir)
{
    if (!cr_interrupt_requested(in)) {
        cr_log_error(log, "curray: %s", msg);
        return 1;
    }
    cr_log_error(log,
                 "curray: interrupted while making the videos; all %ld frames are finished "
                 "and kept in %s; the same command with --resume makes the videos",
                 frames, dir);
    return 130;
}
