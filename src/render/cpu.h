/* curray cpu backend: all pixels of one frame over N threads. */
#ifndef CR_CPU_RENDER_CPU_H
#define CR_CPU_RENDER_CPU_H

#include <stdatomic.h>

#include "../core/defs.h"
#include "../base/error.h"
#include "../base/limits.h" /* CR_SYSCONFIG_MAX_THREADS: curray's one thread limit */
#include "backend.h"         /* cr_progress_fn: called about every 0.25 s and at the end */
#include "cpu_packet.h"      /* cr_pixel_feed */

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

/* The CPU paths: the scalar reference (cr_trace_pixel per pixel) and the
 * packet path (cpu_packet.h) in 4 AVX2 or 8 AVX-512 lanes, with the same
 * pixels. cpu.simd (cr_simd_mode, settings.def) says whether the packet
 * path may be used. */
enum { CR_CPU_SIMD_SCALAR = 0, CR_CPU_SIMD_AVX2, CR_CPU_SIMD_AVX512, CR_CPU_SIMD_COUNT_ };

/* A path's tracer (cpu_packet.h). */
typedef void (*cr_cpu_trace_fn)(const cr_frame *f, const cr_pixel_feed *feed);

/* The path for cpu.simd mode on a CPU with the given features: scalar with
 * CR_SIMD_OFF, without AVX2 or in a build without the packet path; else
 * AVX-512 where the CPU has AVX-512F, else AVX2. */
int cr_cpu_simd_pick(int mode, int has_avx2, int has_avx512f);

/* The path for mode on this CPU (__builtin_cpu_supports). For tests, the
 * environment variable CURRAY_TEST_CPU_FEATURES takes features away:
 * "none" (a CPU without AVX2) or "avx2" (no AVX-512). */
int cr_cpu_simd_path(int mode);

/* Whether this build has the packet path (x86-64, GCC or clang). */
int cr_cpu_simd_built(void);

/* The path's name for -v and info.txt: "scalar", "AVX2, 4 lanes",
 * "AVX-512, 8 lanes". */
const char *cr_cpu_simd_name(int path);

/* Set cpu.simd (cr_simd_mode) for every later cr_cpu_render and
 * cr_cpu_render_rows of this process (CR_SIMD_AUTO until then); returns
 * the path they will take (cr_cpu_simd_path). Call before rendering. */
int cr_cpu_simd_configure(int mode);

/* cr_cpu_render_rows on the given path (cr_cpu_simd_path); cr_cpu_render
 * and cr_cpu_render_rows take the path of cr_cpu_simd_configure's mode. */
int cr_cpu_render_rows_path(const cr_frame *f, int row0, int rows, int threads, int path,
                            cr_pixel *out, cr_progress_fn progress, void *ctx,
                            atomic_int *cancel, cr_err *err);

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
