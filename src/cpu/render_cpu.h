/* curray cpu backend: all pixels of one frame over N threads. */
#ifndef CR_CPU_RENDER_CPU_H
#define CR_CPU_RENDER_CPU_H

#include <signal.h>

#include "../core/defs.h"
#include "../io/error.h"

/* Called from the calling thread about every 0.25 s while a frame renders,
 * and once at the end, with the number of finished rows. */
typedef void (*cr_progress_fn)(void *ctx, int rows_done, int rows_total);

/* Trace every pixel of the prepared frame f into out[j * width + i] with
 * `threads` worker threads (<= 0: number of online cores). Rows are handed
 * out dynamically. When *cancel becomes non-zero (may be NULL) the workers
 * stop after their current row and the call returns -1 with "interrupted".
 * progress may be NULL. */
int cr_cpu_render(const cr_frame *f, int threads, cr_pixel *out, cr_progress_fn progress,
                  void *ctx, volatile sig_atomic_t *cancel, cr_err *err);

/* Number of online cores (>= 1). */
int cr_cpu_cores(void);

#endif
