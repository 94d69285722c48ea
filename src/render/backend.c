/* curray render: the backend interface (backend.h) over the CPU threads
 * (cpu.h) and a CUDA session (gpu.h). */
#include "backend.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../base/limits.h"
#include "cpu.h"
#include "gpu.h"

static double cr_backend_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cr_backend_check_rows(const cr_frame *f, int row0, int rows, cr_err *err)
{
    if (row0 < 0 || rows < 1 || row0 + rows > f->height)
        return cr_err_set(err, "rows %d to %d of a frame of %d rows", row0, row0 + rows - 1,
                          f->height);
    return 0;
}

/* ---- the CPU: an item is traced inside its wait ------------------------- */

typedef struct cr_cpu_item {
    cr_frame f;          /* f.spheres points to spheres */
    cr_sphere *spheres;  /* a copy of the launched frame's spheres */
    int cap_spheres;
    int row0, rows;
} cr_cpu_item;

typedef struct cr_cpu_backend {
    int threads;
    size_t max_pixels;
    cr_pixel *px; /* the last item waited for */
    cr_cpu_item item[CR_BACKEND_IN_FLIGHT];
    int first, n; /* the items in flight: item[first], item[first + 1] (mod 2) */
} cr_cpu_backend;

static int cr_cpu_launch(void *impl, const cr_frame *f, int row0, int rows, cr_err *err)
{
    cr_cpu_backend *c = impl;
    cr_cpu_item *it;
    if (c->n == CR_BACKEND_IN_FLIGHT)
        return cr_err_set(err, "cr_backend_launch: %d items in flight already",
                          CR_BACKEND_IN_FLIGHT);
    if (cr_backend_check_rows(f, row0, rows, err))
        return -1;
    if ((size_t)rows * (size_t)f->width > c->max_pixels)
        return cr_err_set(err, "cr_backend_launch: %d rows of %d pixels, more than the %zu "
                               "pixels the backend was opened for",
                          rows, f->width, c->max_pixels);
    it = &c->item[(c->first + c->n) % CR_BACKEND_IN_FLIGHT];
    if (f->n_spheres > it->cap_spheres) {
        cr_sphere *p = realloc(it->spheres, sizeof *p * (size_t)f->n_spheres);
        if (!p)
            return cr_err_set(err, "out of memory for %d spheres", f->n_spheres);
        it->spheres = p;
        it->cap_spheres = f->n_spheres;
    }
    if (f->n_spheres > 0)
        memcpy(it->spheres, f->spheres, sizeof *it->spheres * (size_t)f->n_spheres);
    it->f = *f;
    it->f.spheres = it->spheres;
    it->row0 = row0;
    it->rows = rows;
    c->n++;
    return 0;
}

static const cr_pixel *cr_cpu_wait(void *impl, cr_progress_fn progress, void *ctx,
                                   atomic_int *cancel, double *seconds, cr_err *err)
{
    cr_cpu_backend *c = impl;
    cr_cpu_item *it = &c->item[c->first];
    double t0;
    int rc;
    if (c->n == 0) {
        cr_err_set(err, "cr_backend_wait: no item in flight");
        return NULL;
    }
    t0 = cr_backend_now();
    rc = cr_cpu_render_rows(&it->f, it->row0, it->rows, c->threads, c->px, progress, ctx, cancel,
                            err);
    if (seconds)
        *seconds = cr_backend_now() - t0;
    c->first = (c->first + 1) % CR_BACKEND_IN_FLIGHT;
    c->n--;
    if (rc) {
        c->n = 0; /* a failed or cancelled wait drops every item */
        return NULL;
    }
    return c->px;
}

static int cr_cpu_times(const void *impl, double *trace_s, double *copy_s)
{
    (void)impl;
    *trace_s = *copy_s = 0.0;
    return 0;
}

static void cr_cpu_close(void *impl)
{
    cr_cpu_backend *c = impl;
    int k;
    for (k = 0; k < CR_BACKEND_IN_FLIGHT; k++)
        free(c->item[k].spheres);
    free(c->px);
    free(c);
}

static const cr_backend_ops cr_cpu_ops = {cr_cpu_launch, cr_cpu_wait, cr_cpu_times,
                                          cr_cpu_close};

static int cr_cpu_open(cr_backend *b, int threads, int width, int height, cr_err *err)
{
    size_t max_pixels = (size_t)width * (size_t)height;
    cr_cpu_backend *c = calloc(1, sizeof *c);
    if (threads > CR_SYSCONFIG_MAX_THREADS) {
        free(c);
        return cr_err_set(err, "%d CPU threads asked for; curray runs at most %d", threads,
                          CR_SYSCONFIG_MAX_THREADS);
    }
    if (!c || !(c->px = malloc(sizeof *c->px * (max_pixels > 0 ? max_pixels : 1)))) {
        free(c);
        return cr_err_set(err, "cannot allocate %.1f MiB for a %dx%d frame",
                          (double)(max_pixels * sizeof(cr_pixel)) / (1 << 20), width, height);
    }
    c->threads = threads;
    c->max_pixels = max_pixels;
    b->ops = &cr_cpu_ops;
    b->impl = c;
    b->device = -1;
    return 0;
}

/* ---- CUDA: a session (gpu.h) -------------------------------------------- */

/* What a wait hands the session's callbacks. */
typedef struct cr_cuda_waiting {
    cr_progress_fn progress;
    void *ctx;
    atomic_int *cancel;
} cr_cuda_waiting;

static void cr_cuda_progress(void *ctx, int rows_done, int rows_total)
{
    cr_cuda_waiting *w = ctx;
    if (w->progress)
        w->progress(w->ctx, rows_done, rows_total);
}

static int cr_cuda_cancelled(void *ctx)
{
    cr_cuda_waiting *w = ctx;
    return w->cancel && atomic_load_explicit(w->cancel, memory_order_relaxed) != 0;
}

static int cr_cuda_launch(void *impl, const cr_frame *f, int row0, int rows, cr_err *err)
{
    if (cr_backend_check_rows(f, row0, rows, err))
        return -1;
    if (row0 == 0 && rows == f->height)
        return cr_gpu_session_launch(impl, f, err);
    return cr_gpu_session_launch_rows(impl, f, row0, rows, err);
}

static const cr_pixel *cr_cuda_wait(void *impl, cr_progress_fn progress, void *ctx,
                                    atomic_int *cancel, double *seconds, cr_err *err)
{
    cr_cuda_waiting w;
    w.progress = progress;
    w.ctx = ctx;
    w.cancel = cancel;
    return cr_gpu_session_wait(impl, cr_cuda_progress, cancel ? cr_cuda_cancelled : NULL, &w,
                               seconds, err);
}

static int cr_cuda_times(const void *impl, double *trace_s, double *copy_s)
{
    cr_gpu_session_times(impl, trace_s, copy_s);
    return 1;
}

static void cr_cuda_close(void *impl)
{
    cr_gpu_session_free(impl);
}

static const cr_backend_ops cr_cuda_ops = {cr_cuda_launch, cr_cuda_wait, cr_cuda_times,
                                           cr_cuda_close};

/* ---- the interface ------------------------------------------------------ */

int cr_backend_open(cr_backend *b, int device, int threads, int width, int height, cr_err *err)
{
    cr_gpu_session *s;
    memset(b, 0, sizeof *b);
    b->device = -1;
    if (device < 0)
        return cr_cpu_open(b, threads, width, height, err);
    if (!(s = cr_gpu_session_create(device, (size_t)width * (size_t)height, err)))
        return -1;
    b->ops = &cr_cuda_ops;
    b->impl = s;
    b->device = device;
    return 0;
}

int cr_backend_launch(cr_backend *b, const cr_frame *f, int row0, int rows, cr_err *err)
{
    return b->ops->launch(b->impl, f, row0, rows, err);
}

const cr_pixel *cr_backend_wait(cr_backend *b, cr_progress_fn progress, void *ctx,
                                atomic_int *cancel, double *seconds, cr_err *err)
{
    return b->ops->wait(b->impl, progress, ctx, cancel, seconds, err);
}

int cr_backend_times(const cr_backend *b, double *trace_s, double *copy_s)
{
    return b->ops->times(b->impl, trace_s, copy_s);
}

void cr_backend_close(cr_backend *b)
{
    if (b->ops && b->impl)
        b->ops->close(b->impl);
    b->ops = NULL;
    b->impl = NULL;
}

int cr_backend_choose(cr_backend_choice want, const int *enabled, int n_enabled, int *devices,
                      int max, cr_err *why)
{
    int n;
    why->msg[0] = '\0';
    if (want == CR_BACKEND_CPU)
        return 0;
    n = cr_gpu_choose(enabled, n_enabled, devices, max, why);
    if (n > 0)
        return n;
    return want == CR_BACKEND_CUDA ? -1 : 0;
}

int cr_backend_cpu_threads(long cli_threads, int cfg_threads)
{
    int threads = cli_threads > 0 ? (int)cli_threads
                                  : (cfg_threads > 0 ? cfg_threads : cr_cpu_cores());
    return threads > CR_SYSCONFIG_MAX_THREADS ? CR_SYSCONFIG_MAX_THREADS : threads;
}
