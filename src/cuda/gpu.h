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

#include "../io/error.h"

/* Same contract as cr_progress_fn of the CPU backend: called from the
 * calling thread with the number of finished rows. */
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
 * cr_trace_pixel per pixel, the pixels come back. Selects `device` for the
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

#ifdef __cplusplus
}
#endif

#endif
