#include "cpu.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "../base/memcheck.h"
#include "../core/trace.h"
#include "cpu_packet.h"

typedef struct cr_cpu_job {
    const cr_frame *f;
    cr_pixel *out;         /* row row0 of the frame */
    int row0, rows;        /* the rows [row0, row0 + rows) */
    int *left;             /* pixels of each row not yet done (its worker's) */
    cr_cpu_trace_fn trace; /* the path (cr_cpu_simd_path) */
    atomic_int next_row;
    atomic_int rows_done;
    atomic_int *cancel;   /* NULL: cannot be cancelled */
    pthread_mutex_t lock; /* with `finished`: wakes the caller when the last row is done */
    pthread_cond_t finished;
} cr_cpu_job;

/* One worker's place in the rows: it takes a row at a time and hands out
 * its pixels in order; a row is done when all its pixels are back. */
typedef struct cr_cpu_worker_feed {
    cr_cpu_job *job;
    int row; /* the row being handed out (job-relative), -1 before the first */
    int col; /* its next pixel */
} cr_cpu_worker_feed;

static int cr_cpu_cancelled(const cr_cpu_job *job)
{
    return job->cancel && atomic_load_explicit(job->cancel, memory_order_relaxed) != 0;
}

static void cr_cpu_wake(cr_cpu_job *job)
{
    pthread_mutex_lock(&job->lock);
    pthread_cond_signal(&job->finished);
    pthread_mutex_unlock(&job->lock);
}

/* checked per pixel, so that a long row near the hole stops within a pixel */
static int cr_cpu_next(void *ctx, int *i, int *j)
{
    cr_cpu_worker_feed *w = ctx;
    cr_cpu_job *job = w->job;
    if (cr_cpu_cancelled(job))
        return 0;
    if (w->row < 0 || w->col >= job->f->width) {
        int r = atomic_fetch_add(&job->next_row, 1);
        if (r >= job->rows)
            return 0;
        w->row = r;
        w->col = 0;
        job->left[r] = job->f->width;
    }
    *i = w->col++;
    *j = job->row0 + w->row;
    return 1;
}

static void cr_cpu_done(void *ctx, int i, int j, const cr_pixel *px)
{
    cr_cpu_worker_feed *w = ctx;
    cr_cpu_job *job = w->job;
    int r = j - job->row0;
    job->out[(size_t)r * job->f->width + i] = *px;
    if (--job->left[r] == 0 && atomic_fetch_add(&job->rows_done, 1) + 1 == job->rows)
        cr_cpu_wake(job); /* the last row is done */
}

/* The scalar path: cr_trace_pixel, pixel by pixel (the reference). */
static void cr_cpu_trace_scalar(const cr_frame *f, const cr_pixel_feed *feed)
{
    int i, j;
    while (feed->next(feed->ctx, &i, &j)) {
        cr_pixel px = cr_trace_pixel(f, i, j);
        feed->done(feed->ctx, i, j, &px);
    }
}

static void *cr_cpu_worker(void *arg)
{
    cr_cpu_job *job = arg;
    cr_cpu_worker_feed w;
    cr_pixel_feed feed;
    w.job = job;
    w.row = -1;
    w.col = 0;
    feed.next = cr_cpu_next;
    feed.done = cr_cpu_done;
    feed.ctx = &w;
    job->trace(job->f, &feed);
    if (cr_cpu_cancelled(job))
        cr_cpu_wake(job);
    return NULL;
}

/* ---- the choice of path ------------------------------------------------- */

static const char *const cr_cpu_simd_names[CR_CPU_SIMD_COUNT_] = {"scalar", "AVX2, 4 lanes",
                                                                  "AVX-512, 8 lanes"};

int cr_cpu_simd_pick(int mode, int has_avx2, int has_avx512f)
{
    if (mode == CR_SIMD_OFF || !cr_cpu_simd_built())
        return CR_CPU_SIMD_SCALAR;
    if (has_avx512f && has_avx2)
        return CR_CPU_SIMD_AVX512;
    return has_avx2 ? CR_CPU_SIMD_AVX2 : CR_CPU_SIMD_SCALAR;
}

int cr_cpu_simd_built(void)
{
#ifdef CR_HAVE_PACKETS
    return 1;
#else
    return 0;
#endif
}

const char *cr_cpu_simd_name(int path)
{
    return path >= 0 && path < CR_CPU_SIMD_COUNT_ ? cr_cpu_simd_names[path] : "?";
}

/* The CPU's features, less those CURRAY_TEST_CPU_FEATURES (for tests)
 * takes away: "none" (a CPU without AVX2), "avx2" (AVX2 but no AVX-512). */
static void cr_cpu_features(int *avx2, int *avx512f)
{
    const char *t = getenv("CURRAY_TEST_CPU_FEATURES");
    *avx2 = *avx512f = 0;
#if defined(CR_HAVE_PACKETS) && defined(__GNUC__)
    __builtin_cpu_init();
    *avx2 = __builtin_cpu_supports("avx2") != 0;
    *avx512f = __builtin_cpu_supports("avx512f") != 0;
#endif
    if (t && strcmp(t, "none") == 0)
        *avx2 = *avx512f = 0;
    else if (t && strcmp(t, "avx2") == 0)
        *avx512f = 0;
}

/* cpu.simd for the renders of this process (cr_cpu_simd_configure). */
static atomic_int cr_cpu_simd_mode = CR_SIMD_AUTO;

int cr_cpu_simd_configure(int mode)
{
    atomic_store(&cr_cpu_simd_mode, mode);
    return cr_cpu_simd_path(mode);
}

int cr_cpu_simd_path(int mode)
{
    int avx2, avx512f;
    cr_cpu_features(&avx2, &avx512f);
    return cr_cpu_simd_pick(mode, avx2, avx512f);
}

static cr_cpu_trace_fn cr_cpu_trace_of(int path)
{
#ifdef CR_HAVE_PACKETS
    if (path == CR_CPU_SIMD_AVX512)
        return cr_packet_trace_x8;
    if (path == CR_CPU_SIMD_AVX2)
        return cr_packet_trace_x4;
#endif
    (void)path;
    return cr_cpu_trace_scalar;
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
    return cr_cpu_render_rows_path(f, row0, rows, threads,
                                   cr_cpu_simd_path(atomic_load(&cr_cpu_simd_mode)), out,
                                   progress, ctx, cancel, err);
}

int cr_cpu_render_rows_path(const cr_frame *f, int row0, int rows, int threads, int path,
                            cr_pixel *out, cr_progress_fn progress, void *ctx,
                            atomic_int *cancel, cr_err *err)
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
    job.left = malloc(sizeof *job.left * (size_t)rows);
    if (!tid || !job.left) {
        free(tid);
        free(job.left);
        return cr_err_set(err, "out of memory for %d worker threads", threads);
    }
    job.trace = cr_cpu_trace_of(path);
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
                free(job.left);
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
    free(job.left);
    pthread_cond_destroy(&job.finished);
    pthread_mutex_destroy(&job.lock);
    if (atomic_load(&job.rows_done) < rows)
        rc = cr_err_set(err, "interrupted");
    else if (progress)
        progress(ctx, rows, rows);
    return rc;
}
