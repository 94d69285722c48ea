/* curray cuda backend: the host-side interface. Compiles in every build;
 * without CUDA (gpu_stub.c) it reports that this build has no GPU support.
 *
 * Devices are numbered as the CUDA runtime numbers them (CUDA_VISIBLE_DEVICES
 * applies), the same numbers -i prints and the sysconfig's `gpus:` uses (E.2).
 * A device "can be used" when this binary carries code it can run: SASS for
 * its architecture family or PTX it can compile (see cr_gpu_usable). */
#ifndef CR_CUDA_GPU_H
#define CR_CUDA_GPU_H

#include <stdio.h>

#include "../core/defs.h"

#ifdef __cplusplus
extern "C" {
#endif

#include "../base/error.h"

/* The type of backend.h's cr_progress_fn (spelt again here, since this
 * header is also C++ for nvcc, and backend.h's C11 atomics are not): called
 * from the calling thread with the number of finished rows. */
typedef void (*cr_gpu_progress_fn)(void *ctx, int rows_done, int rows_total);

/* Polled from the calling thread between kernel launches: non-zero stops the
 * render. (A function rather than the CPU backend's C11 atomic_int *, since
 * this header is also C++ for nvcc, where C's _Atomic does not exist.) */
typedef int (*cr_gpu_cancel_fn)(void *ctx);

/* One CUDA device as the selection sees it (cr_gpu_devices). */
typedef struct cr_gpu_device {
    int usable;    /* 1: this build can run on it */
    char why[256]; /* usable == 0: why not ("compute capability 5.2; ...") */
} cr_gpu_device;

/* Fill table[0..max) with the devices the CUDA runtime reports, numbered as
 * -i numbers them. Returns the number of devices found (usable or not; only
 * the first max are described), or 0 with the reason in err (no CUDA in this
 * build, no driver, no device). */
int cr_gpu_devices(cr_gpu_device *table, int max, cr_err *err);

/* The GPU selection, a pure function: device d is chosen when d < n_devices,
 * d < n_enabled, enabled[d] != 0 and table[d].usable. chosen[] receives the
 * chosen device numbers in increasing order (at most max_chosen of them); the
 * count is returned. Device numbers are the runtime's, so an unusable device
 * 0 does not hide a usable device 1. err gets one line: with a count of 0, why
 * nothing was chosen (none found, none enabled, the enabled ones unusable and
 * why, usable ones that are not enabled); with a count > 0, the enabled
 * devices that were skipped as unusable, or "" when none was. */
int cr_gpu_select(const cr_gpu_device *table, int n_devices, const int *enabled, int n_enabled,
                  int *chosen, int max_chosen, cr_err *err);

/* The devices --backend auto|cuda trace on: cr_gpu_devices (at most
 * CR_MAX_GPUS of them), then cr_gpu_select with the configuration's enabled
 * flags. Returns the count chosen, err as cr_gpu_select leaves it; or 0 with
 * why in err (no CUDA in this build, no driver, no device, none usable or
 * enabled). The command line and the Python package choose with it. */
int cr_gpu_choose(const int *enabled, int n_enabled, int *chosen, int max_chosen, cr_err *err);

/* The GPU of one MPI rank, a pure function (no MPI, no CUDA): the ranks on
 * a node are numbered 0..local_size-1 (their local rank), and local rank k
 * takes chosen[k % n_chosen], chosen[] being what cr_gpu_select chose on
 * that node. So every rank traces on a GPU: with fewer GPUs than ranks on a
 * node, ranks share a GPU (its time is divided); with more, the GPUs past
 * the first local_size stay idle (one GPU per rank: start as many ranks per
 * node as it has GPUs). No rank falls back to the CPU while its node has a
 * usable GPU, so every pixel comes from the same kernel and an MPI run's
 * files equal a one-process GPU run's. Returns the device number, or -1 when
 * n_chosen < 1 or local_rank < 0. note (may be NULL) gets "" or one line
 * saying that GPUs are shared or left idle. */
int cr_gpu_for_local_rank(const int *chosen, int n_chosen, int local_rank, int local_size,
                          cr_err *note);

/* 1 when this binary was built with the CUDA backend. */
int cr_gpu_built(void);

/* Number of CUDA devices curray can use (0 when the build has no CUDA, the
 * driver is missing or no device exists; err then says which). Unusable
 * devices are not counted, but keep their numbers: with devices 0 (too old)
 * and 1 (usable) the count is 1 and the usable device is #1. */
int cr_gpu_count(cr_err *err);

/* 1 when device `device` exists and this build can run on it, else 0 with
 * the reason in err (an unknown number, a compute capability without code in
 * this build, a prohibited compute mode, no driver, a build without CUDA). */
int cr_gpu_usable(int device, cr_err *err);

/* Print the device list of listing E.1 (-i) to out. */
void cr_gpu_print_info(FILE *out);

/* Trace every pixel of the prepared frame f on device `device` into
 * out[j * width + i], exactly as cr_cpu_render does on the host: the frame,
 * spheres and sky texture are copied to the device, the kernel runs
 * cr_trace_pixel per pixel, the pixels come back (a session of one frame;
 * for many frames, keep a cr_gpu_session instead). Selects `device` for the
 * calling thread (cudaSetDevice). Returns 0, or -1 with a message naming the
 * failing CUDA call, file and line; device memory is freed on every path. */
int cr_gpu_render(int device, const cr_frame *f, cr_pixel *out, cr_err *err);

/* cr_gpu_render with progress and cancellation: the frame is traced in
 * chunks of rows (one kernel launch each, a few waves of the device, which
 * also keeps every launch short for a display watchdog); after each chunk
 * progress (may be NULL) is called, and when cancelled(ctx) (cancelled may
 * be NULL) returns non-zero the call stops and returns -1 with
 * "interrupted". */
int cr_gpu_render_ex(int device, const cr_frame *f, cr_pixel *out, cr_gpu_progress_fn progress,
                     cr_gpu_cancel_fn cancelled, void *ctx, cr_err *err);

/* ---- a session: one device for a whole run ------------------------------ */

/* A device set up once for many frames, not once per frame: its stream, launch
 * configuration, pixel buffer, spheres and sky texture stay for the session,
 * and a frame is traced asynchronously while the host writes the previous
 * one. Two frames may be in flight; their results land in two pinned host
 * buffers (allocated at the first launch that uses each). Device memory and
 * pinned memory are freed by cr_gpu_session_free only. A session belongs to
 * one host thread at a time; every call selects its device for that thread
 * (cudaSetDevice). */
typedef struct cr_gpu_session cr_gpu_session;

/* Check that `device` can be used, select it, query the launch
 * configuration and allocate the device's pixel buffer for frames of up to
 * max_pixels pixels (width * height). Returns the session, or NULL with err
 * set (nothing left allocated). */
cr_gpu_session *cr_gpu_session_create(int device, size_t max_pixels, cr_err *err);

/* Start tracing the prepared frame f, asynchronously. Copies what the device
 * lacks: the sky texture when f->sky.rgb, its width or height differ from
 * the last one uploaded (a texture must not change under the same pointer
 * and size during the session; replacing it waits for the frames in flight),
 * and the spheres (copied from f->spheres before the call returns, so the
 * caller may reuse that array at once). The frame itself is a kernel
 * argument. The kernel is queued in chunks of rows (a few waves of the
 * device each), then the copy of the pixels into the frame's pinned buffer.
 * At most two frames may be in flight (launched and not yet waited for).
 * Returns 0, or -1 with err set. */
int cr_gpu_session_launch(cr_gpu_session *s, const cr_frame *f, cr_err *err);

/* cr_gpu_session_launch for rows [row0, row0 + rows) of f only (an MPI run
 * of one frame spreads blocks of rows): cr_gpu_session_wait then returns
 * those rows' rows * width pixels, row-major, and its progress counts rows
 * of the block. The pixels are those of the whole frame's launch. Returns
 * 0, or -1 with err set (also for a range outside the frame). */
int cr_gpu_session_launch_rows(cr_gpu_session *s, const cr_frame *f, int row0, int rows,
                               cr_err *err);

/* Wait for the oldest frame in flight. After each chunk of rows progress
 * (may be NULL) is called with the rows finished, then cancelled(ctx) (may
 * be NULL) is asked: non-zero stops every frame in flight (their remaining
 * blocks return at once), leaves the session idle and usable, and returns
 * NULL with "interrupted". *seconds (may be NULL) receives the frame's time
 * on the device's stream, from the end of the work queued before it to the
 * end of its pixel copy. Returns the frame's width * height pixels in pinned
 * host memory, row-major as cr_gpu_render writes them, valid until the
 * second cr_gpu_session_launch after the one that started this frame (so
 * the next frame may be launched while the caller reads this one); or NULL
 * with err set (a CUDA error; the session may then be unusable). */
const cr_pixel *cr_gpu_session_wait(cr_gpu_session *s, cr_gpu_progress_fn progress,
                                    cr_gpu_cancel_fn cancelled, void *ctx, double *seconds,
                                    cr_err *err);

/* The last frame that cr_gpu_session_wait returned, split: *trace_s from the
 * start of its work to the end of its last kernel (the tracing itself),
 * *copy_s the copy of its pixels to the host after that; the two add up to
 * wait's *seconds. Both 0 before the first frame. */
void cr_gpu_session_times(const cr_gpu_session *s, double *trace_s, double *copy_s);
/* Stop the frames in flight (as a cancel does), then free the session's
 * device and pinned memory, stream and events. NULL is ignored. */
void cr_gpu_session_free(cr_gpu_session *s);

#ifdef __cplusplus
}
#endif

#endif
