/* curray render: one interface over the backends that trace frames.
 *
 * A backend traces work items, each the rows [row0, row0 + rows) of one
 * prepared frame, on the CPU's worker threads (cpu.h) or on one CUDA device
 * (gpu.h). Its life: open, then any number of launch/wait pairs, then close.
 * Up to CR_BACKEND_IN_FLIGHT items may be launched before the oldest is
 * waited for, so that the next item is traced while the caller writes the
 * last one (the CUDA backend traces asynchronously; the CPU backend traces
 * an item inside its wait, in the calling thread's time). Every pixel is
 * cr_trace_pixel's, so the backends give the same pixels (to the tolerance
 * of tests/test_backends.c for the GPU, bit for bit between CPU runs).
 *
 * One progress type (cr_progress_fn) and one cancel flag (a C11 atomic_int
 * that the caller sets and the backend only reads) serve every backend. A
 * backend belongs to one thread at a time. Without nvcc the CUDA backend
 * opens with "this build of curray has no CUDA support ...". */
#ifndef CR_RENDER_BACKEND_H
#define CR_RENDER_BACKEND_H

#include <stdatomic.h>
#include <stddef.h>

#include "../base/error.h"
#include "../core/defs.h"

/* Called from the waiting thread while an item is traced, with the number
 * of the item's rows finished: the CPU backend about every 0.25 s and once
 * at the end, the CUDA backend after each chunk of rows. */
typedef void (*cr_progress_fn)(void *ctx, int rows_done, int rows_total);

/* --backend: CUDA when a usable GPU is enabled (auto), the CPU, or CUDA. */
typedef enum cr_backend_choice {
    CR_BACKEND_AUTO = 0,
    CR_BACKEND_CPU,
    CR_BACKEND_CUDA
} cr_backend_choice;

/* Items launched and not yet waited for, at most. */
#define CR_BACKEND_IN_FLIGHT 2

/* The operations of a backend; impl is its own state. A test may supply
 * its own table (tests/test_run.c: a fake backend). */
typedef struct cr_backend_ops {
    int (*launch)(void *impl, const cr_frame *f, int row0, int rows, cr_err *err);
    const cr_pixel *(*wait)(void *impl, cr_progress_fn progress, void *ctx, atomic_int *cancel,
                            double *seconds, cr_err *err);
    /* the last item waited for, split into tracing and copying (CUDA); 0
     * when the backend has no such split */
    int (*times)(const void *impl, double *trace_s, double *copy_s);
    void (*close)(void *impl);
} cr_backend_ops;

typedef struct cr_backend {
    const cr_backend_ops *ops;
    void *impl;
    int device; /* the CUDA device traced on, or -1 for the CPU */
} cr_backend;

/* Open the CPU backend (device < 0) with `threads` worker threads (as
 * cr_cpu_render takes them: <= 0 for every online core) or CUDA device
 * `device`, for items of at most width * height pixels. Returns 0, or -1
 * with err set (nothing left open). */
int cr_backend_open(cr_backend *b, int device, int threads, int width, int height, cr_err *err);

/* Queue rows [row0, row0 + rows) of the prepared frame f. The frame and its
 * spheres are copied before the call returns (the caller may reuse them at
 * once); the sky texture f->sky.rgb must stay unchanged until the item is
 * waited for. Returns 0, or -1 with err set (also for rows outside f, or a
 * third item in flight). */
int cr_backend_launch(cr_backend *b, const cr_frame *f, int row0, int rows, cr_err *err);

/* Wait for the oldest item in flight: progress (may be NULL) is called with
 * ctx while it is traced; once *cancel (may be NULL) is non-zero the items
 * in flight are dropped and NULL comes back with "interrupted". *seconds
 * (may be NULL) receives the item's tracing time (CUDA: on the device's
 * stream, its pixel copy included). Returns the item's rows * width
 * pixels, row-major, valid until the next wait or close; or NULL with err
 * set, every item in flight dropped. */
const cr_pixel *cr_backend_wait(cr_backend *b, cr_progress_fn progress, void *ctx,
                                atomic_int *cancel, double *seconds, cr_err *err);

/* cr_backend_ops.times of the last item waited for. */
int cr_backend_times(const cr_backend *b, double *trace_s, double *copy_s);

/* Drop the items in flight and free everything open made. A backend that
 * was never opened (memset to 0) or is closed already is ignored. */
void cr_backend_close(cr_backend *b);

/* The command line's and the Python package's backend choice: with
 * CR_BACKEND_CPU, 0 (why = ""); otherwise the GPUs enabled[0..n_enabled)
 * that are usable (cr_gpu_choose), at most max of them into devices[]: their
 * count when there is one (why: the enabled ones skipped, or ""); else with
 * CR_BACKEND_AUTO 0 (the CPU, why says why not a GPU) and with
 * CR_BACKEND_CUDA -1 (why says why no GPU can be used). */
int cr_backend_choose(cr_backend_choice want, const int *enabled, int n_enabled, int *devices,
                      int max, cr_err *why);

/* The CPU threads a run uses: the command line's count when > 0, else the
 * configuration's when > 0, else every online core; at most
 * CR_SYSCONFIG_MAX_THREADS (the cores of a machine with more). */
int cr_backend_cpu_threads(long cli_threads, int cfg_threads);

#endif
