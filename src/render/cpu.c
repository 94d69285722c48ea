#include "cpu.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "../base/memcheck.h"
#include "../core/trace.h"

typedef struct cr_cpu_job {
    const cr_frame *f;
    cr_pixel *out;         /* row row0 of the frame */
    int row0, rows;        /* the rows [row0, row0 + rows) */
    atomic_int next_row;
    atomic_int rows_done;
    atomic_int *cancel;   /* NULL: cannot be cancelled */
    pthread_mutex_t lock; /* with `finished`: wakes the caller when the last row is done */
    pthread_cond_t finished;
} cr_cpu_job;

static int cr_cpu_cancelled(const cr_cpu_job *job)
{
    return job->cancel && atomic_load_explicit(job->cancel, memory_order_relaxed) != 0;
}

static void *cr_cpu_worker(void *arg)
{
    cr_cpu_job *job = arg;
    const cr_frame *f = job->f;
    for (;;) {
        int j = atomic_fetch_add(&job->next_row, 1), i;
        if (j >= job->rows)
            break;
        /* per pixel, so that a long row near the hole stops within a pixel */
        for (i = 0; i < f->width; i++) {
            if (cr_cpu_cancelled(job))
                goto wake;
            job->out[(size_t)j * f->width + i] = cr_trace_pixel(f, i, job->row0 + j);
        }
        if (atomic_fetch_add(&job->rows_done, 1) + 1 == job->rows)
            goto wake;
    }
    return NULL;
wake: /* the last row is done, or the render is cancelled */
    pthread_mutex_lock(&job->lock);
    pthread_cond_signal(&job->finished);
    pthread_mutex_unlock(&job->lock);
    return NULL;
}

int cr_cpu_cores(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

int cr_cpu_memory_check(double bytes, cr_err *err)
{
    return cr_mem_check(bytes, err);
}

int cr_cpu_render(const cr_frame *f, int threads, cr_pixel *out, cr_progress_fn progress,
                  void *ctx, atomic_int *cancel, cr_err *err)
{
    return cr_cpu_render_rows(f, 0, f->height, threads, out, progress, ctx, cancel, err);
}

int cr_cpu_render_rows(const cr_frame *f, int row0, int rows, int threads, cr_pixel *out,
                       cr_progress_fn progress, void *ctx, atomic_int *cancel, cr_err *err)
{
    pthread_t *tid;
    cr_cpu_job job;
    int t, started = 0, rc = 0;

    if (threads > CR_SYSCONFIG_MAX_THREADS)
        return cr_err_set(err, "%d CPU threads asked for; curray runs at most %d", threads,
                          CR_SYSCONFIG_MAX_THREADS);
    if (threads <= 0) {
        threads = cr_cpu_cores();
        if (threads > CR_SYSCONFIG_MAX_THREADS)
            threads = CR_SYSCONFIG_MAX_THREADS;
    }
    if (row0 < 0 || rows < 1 || row0 + rows > f->height)
        return cr_err_set(err, "rows %d to %d of a frame of %d rows", row0, row0 + rows - 1,
                          f->height);
    if (threads > rows)
        threads = rows;
    tid = malloc(sizeof *tid * (size_t)threads);
    if (!tid)
        return cr_err_set(err, "out of memory for %d worker threads", threads);
    job.f = f;
    job.out = out;
    job.row0 = row0;
    job.rows = rows;
    job.cancel = cancel;
    atomic_init(&job.next_row, 0);
    atomic_init(&job.rows_done, 0);
    pthread_mutex_init(&job.lock, NULL);
    pthread_cond_init(&job.finished, NULL);

    for (t = 0; t < threads; t++) {
        int e = pthread_create(&tid[t], NULL, cr_cpu_worker, &job);
        if (e != 0) {
            if (started == 0) {
                pthread_cond_destroy(&job.finished);
                pthread_mutex_destroy(&job.lock);
                free(tid);
                return cr_err_set(err, "cannot start a worker thread: %s", strerror(e));
            }
            break; /* render with the threads we have */
        }
        started++;
    }
    /* wake every 0.25 s for progress, or at once when done or cancelled */
    pthread_mutex_lock(&job.lock);
    while (atomic_load(&job.rows_done) < rows && !cr_cpu_cancelled(&job)) {
        struct timespec ts;
        if (progress) {
            pthread_mutex_unlock(&job.lock);
            progress(ctx, atomic_load(&job.rows_done), rows);
            pthread_mutex_lock(&job.lock);
        }
        clock_gettime(CLOCK_REALTIME, &ts);
        ts.tv_nsec += 250 * 1000 * 1000;
        if (ts.tv_nsec >= 1000000000L) {
            ts.tv_sec++;
            ts.tv_nsec -= 1000000000L;
        }
        if (atomic_load(&job.rows_done) < rows && !cr_cpu_cancelled(&job))
            pthread_cond_timedwait(&job.finished, &job.lock, &ts);
    }
    pthread_mutex_unlock(&job.lock);
    for (t = 0; t < started; t++)
        pthread_join(tid[t], NULL);
    free(tid);
    pthread_cond_destroy(&job.finished);
    pthread_mutex_destroy(&job.lock);
    if (atomic_load(&job.rows_done) < rows)
        rc = cr_err_set(err, "interrupted");
    else if (progress)
        progress(ctx, rows, rows);
    return rc;
}
