/* curray cpu backend: all pixels of one frame over N threads. */
#ifndef CR_CPU_RENDER_CPU_H
#define CR_CPU_RENDER_CPU_H

#include <stdatomic.h>

#include "../core/defs.h"
#include "../base/error.h"
#include "../base/limits.h" /* CR_SYSCONFIG_MAX_THREADS: curray's one thread limit */
#include "backend.h"         /* cr_progress_fn: called about every 0.25 s and at the end */

/* Trace every pixel of the prepared frame f into out[j * width + i] with
 * `threads` worker threads: 1 to CR_SYSCONFIG_MAX_THREADS (more is an error,
 * never a silent clamp), or <= 0 for the number of online cores (then at most
 * CR_SYSCONFIG_MAX_THREADS). Rows are handed out dynamically.
 *
 * cancel (may be NULL) is read, never written, with relaxed C11 atomic loads
 * before every pixel: once it is non-zero the workers stop after the pixel
 * they are tracing (one pixel takes at most max_steps integrator steps, a few
 * tens of milliseconds), the call returns -1 with "interrupted", and `out` is
 * incomplete. progress may be NULL. */
int cr_cpu_render(const cr_frame *f, int threads, cr_pixel *out, cr_progress_fn progress,
                  void *ctx, atomic_int *cancel, cr_err *err);

/* The same for the rows [row0, row0 + rows) of f only (MPI: a row block of
 * one frame), into out[(j - row0) * width + i]; progress counts those rows.
 * The pixels are those cr_cpu_render gives, bit for bit. */
int cr_cpu_render_rows(const cr_frame *f, int row0, int rows, int threads, cr_pixel *out,
                       cr_progress_fn progress, void *ctx, atomic_int *cancel, cr_err *err);

/* Number of online cores (>= 1). */
int cr_cpu_cores(void);

/* Whether `bytes` of host memory can be had: 0 when they fit in the
 * physical memory, or in the address-space or data-size limit (ulimit -v,
 * -d) when lower, or when none of these can be known; else -1 with "needs
 * about X GiB of memory, more than the Y GiB of <which limit>" (the caller
 * says what needs it). For refusing a run before anything large is
 * allocated, rather than being killed by the out-of-memory killer. */
int cr_cpu_memory_check(double bytes, cr_err *err);

#endif
