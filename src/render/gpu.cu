/* curray cuda backend: the kernel around cr_trace_pixel, the device query of
 * -i (listing E.1), device selection, and the session that keeps one device
 * set up for a whole run (gpu.h).
 *
 * The physics is the shared header code of src/core (DESIGN rule 1); this
 * file only moves data. Compiling it also checks that the core headers build
 * as CUDA C++ for the device (DESIGN rule 2).
 *
 * Floating point: nvcc contracts a * b + c into fused multiply-adds by
 * default (--fmad=true; CURRAY_CUDA_NO_FMA=ON turns that off), while gcc on
 * x86-64 without -march flags has no FMA instruction to use, and with -std=c11
 * does not contract anyway. Device sin/cos/atan2/... also differ from glibc's
 * in the last bits. Pixels therefore agree with the CPU backend except where a
 * ray passes within rounding error of an object's edge (tests/test_backends.c).
 */
#include "gpu.h"

#include <cuda_runtime.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/trace.h"
#include "gpu_config.h"

/* Pixels per tile row: a 32-thread warp covers an 8 x 4 tile of neighbouring
 * pixels, whose rays tend to take similar paths (fewer divergent branches
 * than a 32 x 1 strip). */
#define CR_GPU_TILE_W 8
/* A launch covers about this many waves of resident threads. */
#define CR_GPU_WAVES_PER_LAUNCH 4

/* Record a failed CUDA call as "file:line: cudaXxx failed: message (name)".
 * Returns -1. */
static int cr_gpu_fail(cr_err *err, const char *file, int line, const char *call, cudaError_t e)
{
    const char *base = strrchr(file, '/');
    size_t n = strcspn(call, "(");
    const char *hint = "";
    if (e == cudaErrorLaunchTimeout)
        hint = "; the display driver's watchdog stopped the kernel: render on a GPU without a "
               "display, or use a smaller frame";
    else if (e == cudaErrorNoKernelImageForDevice)
        hint = "; this build has no code for the device's compute capability (CURRAY_CUDA_ARCHS)";
    return cr_err_set(err, "%s:%d: %.*s failed: %s (%s)%s", base ? base + 1 : file, line, (int)n,
                      call, cudaGetErrorString(e), cudaGetErrorName(e), hint);
}

/* Evaluate a CUDA runtime call: 0 on success, else -1 with err set. */
#define CR_CUDA_TRY(call) cr_gpu_try_((call), err, __FILE__, __LINE__, #call)
/* In a function returning int with nothing to clean up: return -1 on error. */
#define CR_CUDA_CHECK(call)                                                                    \
    do {                                                                                       \
        if (CR_CUDA_TRY(call) != 0)                                                            \
            return -1;                                                                         \
    } while (0)
/* With resources to free: jump to the function's `fail` label on error. */
#define CR_CUDA_CHECK_GOTO(call)                                                               \
    do {                                                                                       \
        if (CR_CUDA_TRY(call) != 0)                                                            \
            goto fail;                                                                         \
    } while (0)

static int cr_gpu_try_(cudaError_t e, cr_err *err, const char *file, int line, const char *call)
{
    if (e == cudaSuccess)
        return 0;
    return cr_gpu_fail(err, file, line, call, e);
}

/* One thread per pixel; rows [row0, row_end) of the frame f, passed by value
 * (a __grid_constant__ argument lives in the constant bank and its address
 * can be taken without a copy to local memory; needs compute capability
 * 7.0). Blocks that start after *abort became non-zero return at once. The
 * flag lives in mapped pinned host memory, so each read crosses the bus: one
 * thread per block reads it, not every thread.
 * CR_GPU_MAX_THREADS / CR_GPU_MIN_BLOCKS (CMake's CURRAY_CUDA_LAUNCH_BOUNDS)
 * give the kernel __launch_bounds__. */
#if defined(CR_GPU_MAX_THREADS) && defined(CR_GPU_MIN_BLOCKS)
#define CR_GPU_LAUNCH_BOUNDS __launch_bounds__(CR_GPU_MAX_THREADS, CR_GPU_MIN_BLOCKS)
#elif defined(CR_GPU_MAX_THREADS)
#define CR_GPU_LAUNCH_BOUNDS __launch_bounds__(CR_GPU_MAX_THREADS)
#else
#define CR_GPU_LAUNCH_BOUNDS
#endif
__global__ void CR_GPU_LAUNCH_BOUNDS cr_gpu_trace_kernel(const __grid_constant__ cr_frame f,
                                                         cr_pixel *__restrict__ out, int row0,
                                                         int row_end, const volatile int *abort)
{
    __shared__ int stop;
    int i = (int)(blockIdx.x * blockDim.x + threadIdx.x);
    int j = row0 + (int)(blockIdx.y * blockDim.y + threadIdx.y);
    if (threadIdx.x == 0 && threadIdx.y == 0)
        stop = *abort;
    __syncthreads();
    if (stop)
        return;
    if (i < f.width && j < row_end)
        out[(size_t)j * f.width + i] = cr_trace_pixel(&f, i, j);
}

/* A kernel argument is limited to 4 KiB on every CUDA version and device. */
static_assert(sizeof(cr_frame) <= 4000, "cr_frame is too large to pass by value");


/* ---- devices ------------------------------------------------------------ */

static const int cr_gpu_sass[] = CR_GPU_SASS_ARCHS;
static const int cr_gpu_ptx[] = CR_GPU_PTX_ARCHS;

/* Smallest compute capability (10 major + minor) this build can run on. */
static int cr_gpu_min_cc(void)
{
    int k, m = 0;
    for (k = 0; cr_gpu_sass[k]; k++)
        if (m == 0 || cr_gpu_sass[k] < m)
            m = cr_gpu_sass[k];
    for (k = 0; cr_gpu_ptx[k]; k++)
        if (m == 0 || cr_gpu_ptx[k] < m)
            m = cr_gpu_ptx[k];
    return m;
}

/* 1 when the build carries SASS of the device's family (same major, minor
 * not above the device's) or PTX not newer than the device. */
static int cr_gpu_has_code(int cc)
{
    int k;
    for (k = 0; cr_gpu_sass[k]; k++)
        if (cr_gpu_sass[k] / 10 == cc / 10 && cr_gpu_sass[k] <= cc)
            return 1;
    for (k = 0; cr_gpu_ptx[k]; k++)
        if (cr_gpu_ptx[k] <= cc)
            return 1;
    return 0;
}

/* Why cudaGetDeviceCount failed, in words. Returns -1. */
static int cr_gpu_no_device(cudaError_t e, cr_err *err)
{
    int drv = 0, rt = 0;
    cudaGetLastError();
    cudaDriverGetVersion(&drv);
    cudaRuntimeGetVersion(&rt);
    if (e == cudaErrorNoDevice)
        return cr_err_set(err, "no CUDA device found");
    if (e == cudaErrorInsufficientDriver && drv == 0)
        return cr_err_set(err, "no CUDA driver found (libcuda.so.1 is not installed or cannot "
                               "be loaded)");
    if (e == cudaErrorInsufficientDriver)
        return cr_err_set(err,
                          "the CUDA driver (version %d.%d) is older than this build's CUDA "
                          "runtime (%d.%d)",
                          drv / 1000, drv % 1000 / 10, rt / 1000, rt % 1000 / 10);
    return cr_err_set(err, "no usable CUDA device: cudaGetDeviceCount failed: %s (%s)",
                      cudaGetErrorString(e), cudaGetErrorName(e));
}

/* Can this build run on device d (which exists)? 1, or 0 with the reason. */
static int cr_gpu_check_device(int d, cr_err *err)
{
    int major = 0, minor = 0, mode = 0, cc, need = cr_gpu_min_cc();
    if (CR_CUDA_TRY(cudaDeviceGetAttribute(&major, cudaDevAttrComputeCapabilityMajor, d)) ||
        CR_CUDA_TRY(cudaDeviceGetAttribute(&minor, cudaDevAttrComputeCapabilityMinor, d)) ||
        CR_CUDA_TRY(cudaDeviceGetAttribute(&mode, cudaDevAttrComputeMode, d)))
        return 0;
    cc = 10 * major + minor;
    if (!cr_gpu_has_code(cc)) {
        cr_err_set(err,
                   "device #%d has compute capability %d.%d; this build runs on %d.%d and up "
                   "(it carries %s)",
                   d, major, minor, need / 10, need % 10, CR_GPU_ARCHS_TEXT);
        return 0;
    }
    if (mode == cudaComputeModeProhibited) {
        cr_err_set(err, "device #%d is in the compute mode \"prohibited\"", d);
        return 0;
    }
    return 1;
}

extern "C" int cr_gpu_built(void)
{
    return 1;
}

extern "C" int cr_gpu_count(cr_err *err)
{
    int n = 0, d, usable = 0;
    cr_err first;
    cudaError_t e = cudaGetDeviceCount(&n);
    if (e != cudaSuccess) {
        cr_gpu_no_device(e, err);
        return 0;
    }
    if (n == 0) {
        cr_err_set(err, "no CUDA device found");
        return 0;
    }
    first.msg[0] = '\0';
    for (d = 0; d < n; d++) {
        cr_err why;
        if (cr_gpu_check_device(d, &why))
            usable++;
        else if (!first.msg[0])
            first = why;
    }
    if (usable == 0)
        cr_err_set(err, "%d CUDA device%s found, none usable: %s", n, n == 1 ? "" : "s",
                   first.msg);
    return usable;
}

extern "C" int cr_gpu_devices(cr_gpu_device *table, int max, cr_err *err)
{
    int n = 0, d;
    cudaError_t e = cudaGetDeviceCount(&n);
    if (e != cudaSuccess) {
        cr_gpu_no_device(e, err);
        return 0;
    }
    if (n <= 0) {
        cr_err_set(err, "no CUDA device found");
        return 0;
    }
    for (d = 0; d < n && d < max; d++) {
        cr_err why;
        why.msg[0] = '\0';
        table[d].usable = cr_gpu_check_device(d, &why);
        snprintf(table[d].why, sizeof table[d].why, "%s", table[d].usable ? "" : why.msg);
    }
    return n;
}

extern "C" int cr_gpu_usable(int device, cr_err *err)
{
    int n = 0;
    cudaError_t e = cudaGetDeviceCount(&n);
    if (e != cudaSuccess) {
        cr_gpu_no_device(e, err);
        return 0;
    }
    if (device < 0 || device >= n) {
        cr_err_set(err, "there is no CUDA device #%d (found %d: #0 to #%d)", device, n, n - 1);
        return 0;
    }
    return cr_gpu_check_device(device, err);
}

/* ---- -i ----------------------------------------------------------------- */

static void cr_gpu_line(FILE *out, const char *label, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static void cr_gpu_line(FILE *out, const char *label, const char *fmt, ...)
{
    va_list ap;
    fprintf(out, "%-34s", label);
    va_start(ap, fmt);
    vfprintf(out, fmt, ap);
    va_end(ap);
    fputc('\n', out);
}

static double cr_gpu_mib(size_t bytes)
{
    return (double)bytes / (1024.0 * 1024.0);
}

/* Attribute `a` of device d, or -1 where the driver does not report it. */
static int cr_gpu_attr(cudaDeviceAttr a, int d)
{
    int v = -1;
    if (cudaDeviceGetAttribute(&v, a, d) != cudaSuccess) {
        cudaGetLastError();
        return -1;
    }
    return v;
}

/* Print the kernel's resources on device d (-i): registers and local memory
 * per thread, and how many threads of the session's block size fit on one
 * multiprocessor. */
static void cr_gpu_print_kernel(FILE *out, int d)
{
    cudaFuncAttributes a;
    int min_grid = 0, block = 0, per_sm = 0, max_threads = 0;
    if (cudaSetDevice(d) != cudaSuccess || cudaFuncGetAttributes(&a, cr_gpu_trace_kernel) ||
        cudaOccupancyMaxPotentialBlockSize(&min_grid, &block, cr_gpu_trace_kernel, 0, 0) ||
        cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, cr_gpu_trace_kernel, block, 0)) {
        cudaGetLastError();
        return;
    }
    max_threads = cr_gpu_attr(cudaDevAttrMaxThreadsPerMultiProcessor, d);
    cr_gpu_line(out, "Kernel registers per thread:", "%d%s", a.numRegs, CR_GPU_REGCAP_TEXT);
    cr_gpu_line(out, "Kernel local memory per thread:", "%zu bytes", a.localSizeBytes);
    cr_gpu_line(out, "Kernel occupancy:", "%d blocks of %d threads per multiprocessor (%.0f %%)",
                per_sm, block,
                max_threads > 0 ? 100.0 * per_sm * block / max_threads : 0.0);
    fputc('\n', out);
}

static void cr_gpu_print_device(FILE *out, int d)
{
    cudaDeviceProp p;
    cr_err why;
    cudaError_t e;
    int usable, clock_khz, mem_khz, timeout, overlap;

    fprintf(out, "Device #%d\n\n", d);
    e = cudaGetDeviceProperties(&p, d);
    if (e != cudaSuccess) {
        cudaGetLastError();
        fprintf(out, "Cannot query this device: %s (%s)\n\n", cudaGetErrorString(e),
                cudaGetErrorName(e));
        return;
    }
    usable = cr_gpu_check_device(d, &why);
    clock_khz = cr_gpu_attr(cudaDevAttrClockRate, d);
    mem_khz = cr_gpu_attr(cudaDevAttrMemoryClockRate, d);
    timeout = cr_gpu_attr(cudaDevAttrKernelExecTimeout, d);
    overlap = cr_gpu_attr(cudaDevAttrGpuOverlap, d);

    if (usable)
        cr_gpu_line(out, "Can be used:", "Yes");
    else
        cr_gpu_line(out, "Can be used:", "No (%s)", why.msg);
    fputc('\n', out);
    cr_gpu_line(out, "Name:", "%s", p.name);
    cr_gpu_line(out, "Compute capability:", "%d.%d", p.major, p.minor);
    cr_gpu_line(out, "PCI bus/device/domain:", "%d/%d/%d", p.pciBusID, p.pciDeviceID,
                p.pciDomainID);
    cr_gpu_line(out, "Clock rate:", "%d kHz", clock_khz);
    cr_gpu_line(out, "Memory clock rate:", "%d kHz", mem_khz);
    cr_gpu_line(out, "Memory bus width:", "%d bit", p.memoryBusWidth);
    cr_gpu_line(out, "Device copy overlap:", "%s", overlap > 0 ? "enabled" : "disabled");
    cr_gpu_line(out, "Kernel execution timeout:", "%s",
                timeout > 0 ? "enabled (display watchdog; long frames may be stopped)"
                            : "disabled");
    cr_gpu_line(out, "Total global memory:", "%zu (%.0f MiB)", p.totalGlobalMem,
                cr_gpu_mib(p.totalGlobalMem));
    cr_gpu_line(out, "Total const. memory:", "%zu", p.totalConstMem);
    cr_gpu_line(out, "Max. memory pitch:", "%zu", p.memPitch);
    cr_gpu_line(out, "Texture alignment:", "%zu", p.textureAlignment);
    cr_gpu_line(out, "L2 cache size:", "%d", p.l2CacheSize);
    fputc('\n', out);
    cr_gpu_line(out, "Multiprocessor count:", "%d", p.multiProcessorCount);
    cr_gpu_line(out, "Max. threads per multiprocessor:", "%d", p.maxThreadsPerMultiProcessor);
    cr_gpu_line(out, "Max. blocks per multiprocessor:", "%d", p.maxBlocksPerMultiProcessor);
    cr_gpu_line(out, "Shared memory per multiprocessor:", "%zu", p.sharedMemPerMultiprocessor);
    cr_gpu_line(out, "Shared memory per block:", "%zu", p.sharedMemPerBlock);
    cr_gpu_line(out, "Registers per multiprocessor:", "%d", p.regsPerMultiprocessor);
    cr_gpu_line(out, "Registers per block:", "%d", p.regsPerBlock);
    cr_gpu_line(out, "Threads per warp:", "%d", p.warpSize);
    cr_gpu_line(out, "Max. threads per block:", "%d", p.maxThreadsPerBlock);
    cr_gpu_line(out, "Max. block dimensions:", "(%d,%d,%d)", p.maxThreadsDim[0],
                p.maxThreadsDim[1], p.maxThreadsDim[2]);
    cr_gpu_line(out, "Max. grid dimensions:", "(%d,%d,%d)", p.maxGridSize[0], p.maxGridSize[1],
                p.maxGridSize[2]);
    fputc('\n', out);
    if (usable)
        cr_gpu_print_kernel(out, d);
}

extern "C" void cr_gpu_print_info(FILE *out)
{
    int drv = 0, rt = 0, n = 0, d, need = cr_gpu_min_cc();
    cudaError_t e;

    fprintf(out, "CUDA GPU information:\n\n");
    cudaDriverGetVersion(&drv);
    cudaRuntimeGetVersion(&rt);
    if (drv > 0)
        cr_gpu_line(out, "Driver version:", "%d (CUDA %d.%d)", drv, drv / 1000,
                    drv % 1000 / 10);
    else
        cr_gpu_line(out, "Driver version:", "none (no CUDA driver found)");
    cr_gpu_line(out, "Runtime version:", "%d (CUDA %d.%d, linked statically)", rt, rt / 1000,
                rt % 1000 / 10);
    cr_gpu_line(out, "Required compute capability:", "%d.%d", need / 10, need % 10);
    cr_gpu_line(out, "Code in this build:", "%s", CR_GPU_ARCHS_TEXT);
    cr_gpu_line(out, "Multiply-add contraction:", "%s",
                CR_GPU_FMAD ? "FMA (nvcc --fmad=true)" : "off (--fmad=false)");
    fputc('\n', out);

    e = cudaGetDeviceCount(&n);
    if (e != cudaSuccess || n == 0) {
        cr_err why;
        if (e != cudaSuccess)
            cr_gpu_no_device(e, &why);
        else
            cr_err_set(&why, "no CUDA device found");
        fprintf(out, "No CUDA GPU can be used on this machine: %s. curray renders on the "
                     "CPU.\n",
                why.msg);
        return;
    }
    cr_gpu_line(out, "Devices found:", "%d", n);
    fputc('\n', out);
    for (d = 0; d < n; d++)
        cr_gpu_print_device(out, d);
}

/* ---- rendering ---------------------------------------------------------- */

/* Frames in flight at once in a session: one traced while the host writes
 * the other. */
#define CR_GPU_SLOTS 2

/* One frame in flight: its pinned result, its staged spheres and the events
 * that mark its progress on the stream. */
typedef struct cr_gpu_slot {
    cr_pixel *px;          /* pinned, max_pixels; NULL until first used */
    cr_sphere *spheres;    /* pinned staging of the frame's spheres */
    int sphere_cap;        /* spheres[] capacity */
    cudaEvent_t start;     /* before the frame's work (timing) */
    cudaEvent_t traced;    /* after its last kernel, before the pixel copy (timing) */
    cudaEvent_t end;       /* after its pixel copy (timing, blocking sync) */
    cudaEvent_t *chunk;    /* after each chunk of rows (blocking sync) */
    int *chunk_row_end;    /* rows finished when chunk[c] has completed */
    int chunk_cap;         /* events created in chunk[] */
    int n_chunks;          /* chunks of the frame in flight */
    int height;            /* rows launched (the pixels hold these rows only) */
} cr_gpu_slot;

struct cr_gpu_session {
    int device;
    size_t max_pixels;
    cudaStream_t stream;
    int stream_made;
    int block, per_sm, sms; /* launch configuration, queried once */
    cr_pixel *d_out;        /* max_pixels; frames in flight take turns (stream order) */
    cr_sphere *d_spheres;
    int d_sphere_cap;
    uint8_t *d_sky;         /* the uploaded sky texture */
    size_t d_sky_cap;       /* bytes allocated at d_sky */
    const uint8_t *sky_host; /* which texture d_sky holds: host pointer, width, height */
    int sky_w, sky_h;
    cr_track_point *d_track; /* the uploaded worldline table (cr_frame.track) */
    long d_track_cap;        /* samples allocated at d_track */
    const cr_track_point *track_host; /* which table d_track holds: host pointer, count */
    long track_n;
    int *abort_host;        /* pinned, mapped: non-zero makes queued blocks return */
    int *abort_dev;         /* the same int as the device sees it */
    cr_gpu_slot slot[CR_GPU_SLOTS];
    long long launched, waited; /* frames; slot of frame n is n % CR_GPU_SLOTS */
    double trace_s, copy_s;     /* the last waited frame's split (cr_gpu_session_times) */
};

/* Rows per kernel launch for frames `width` pixels wide: a few waves of
 * pixels, whole tiles, at most `height` and within the grid's y limit. */
static int cr_gpu_rows_per_launch(const cr_gpu_session *s, int width, int height)
{
    int tile_h = s->block / CR_GPU_TILE_W, rows;
    long long wave = (long long)(s->per_sm > 0 ? s->per_sm : 1) * (s->sms > 0 ? s->sms : 1) *
                     s->block;
    rows = (int)((CR_GPU_WAVES_PER_LAUNCH * wave + width - 1) / width);
    rows += tile_h - 1;
    rows -= rows % tile_h;
    if (rows < tile_h)
        rows = tile_h;
    if (rows > 65535 * tile_h)
        rows = 65535 * tile_h;
    if (rows > height)
        rows = height;
    return rows;
}

/* Stop every frame in flight: queued blocks see the abort flag and return;
 * then the flag is cleared for the next launch. Returns 0, or -1 with err
 * set when the stream reports an error. */
static int cr_gpu_session_abort(cr_gpu_session *s, cr_err *err)
{
    int rc = 0;
    if (s->launched == s->waited)
        return 0;
    *(volatile int *)s->abort_host = 1;
    rc = CR_CUDA_TRY(cudaStreamSynchronize(s->stream));
    *(volatile int *)s->abort_host = 0;
    s->waited = s->launched;
    return rc;
}

extern "C" void cr_gpu_session_free(cr_gpu_session *s)
{
    cr_err ignored;
    int k, c;
    if (!s)
        return;
    /* after a failed kernel the context may be unusable; these calls then
     * fail too, and the first error is the one already reported */
    cudaSetDevice(s->device);
    if (s->abort_host)
        cr_gpu_session_abort(s, &ignored);
    for (k = 0; k < CR_GPU_SLOTS; k++) {
        cr_gpu_slot *sl = &s->slot[k];
        cudaFreeHost(sl->px);
        cudaFreeHost(sl->spheres);
        if (sl->start)
            cudaEventDestroy(sl->start);
        if (sl->traced)
            cudaEventDestroy(sl->traced);
        if (sl->end)
            cudaEventDestroy(sl->end);
        for (c = 0; c < sl->chunk_cap; c++)
            cudaEventDestroy(sl->chunk[c]);
        free(sl->chunk);
        free(sl->chunk_row_end);
    }
    cudaFree(s->d_out);
    cudaFree(s->d_spheres);
    cudaFree(s->d_sky);
    cudaFree(s->d_track);
    cudaFreeHost(s->abort_host);
    if (s->stream_made)
        cudaStreamDestroy(s->stream);
    cudaGetLastError();
    free(s);
}

extern "C" cr_gpu_session *cr_gpu_session_create(int device, size_t max_pixels, cr_err *err)
{
    cr_gpu_session *s;
    int min_grid = 0, k;
    if (max_pixels == 0) {
        cr_err_set(err, "cr_gpu_session_create: no pixels");
        return NULL;
    }
    if (!cr_gpu_usable(device, err))
        return NULL;
    s = (cr_gpu_session *)calloc(1, sizeof *s);
    if (!s) {
        cr_err_set(err, "out of memory");
        return NULL;
    }
    s->device = device;
    s->max_pixels = max_pixels;
    CR_CUDA_CHECK_GOTO(cudaSetDevice(device));
    /* Launch configuration: the block size of best occupancy, shaped as
     * tiles CR_GPU_TILE_W pixels wide. */
    CR_CUDA_CHECK_GOTO(
        cudaOccupancyMaxPotentialBlockSize(&min_grid, &s->block, cr_gpu_trace_kernel, 0, 0));
    s->block -= s->block % 32;
    if (s->block < 32)
        s->block = 32;
    CR_CUDA_CHECK_GOTO(cudaOccupancyMaxActiveBlocksPerMultiprocessor(
        &s->per_sm, cr_gpu_trace_kernel, s->block, 0));
    CR_CUDA_CHECK_GOTO(cudaDeviceGetAttribute(&s->sms, cudaDevAttrMultiProcessorCount, device));
    CR_CUDA_CHECK_GOTO(cudaStreamCreateWithFlags(&s->stream, cudaStreamNonBlocking));
    s->stream_made = 1;
    CR_CUDA_CHECK_GOTO(cudaMalloc((void **)&s->d_out, sizeof(cr_pixel) * max_pixels));
    CR_CUDA_CHECK_GOTO(cudaHostAlloc((void **)&s->abort_host, sizeof(int), cudaHostAllocMapped));
    *s->abort_host = 0;
    CR_CUDA_CHECK_GOTO(cudaHostGetDevicePointer((void **)&s->abort_dev, s->abort_host, 0));
    for (k = 0; k < CR_GPU_SLOTS; k++) {
        CR_CUDA_CHECK_GOTO(cudaEventCreateWithFlags(&s->slot[k].start, cudaEventDefault));
        CR_CUDA_CHECK_GOTO(cudaEventCreateWithFlags(&s->slot[k].traced, cudaEventDefault));
        CR_CUDA_CHECK_GOTO(cudaEventCreateWithFlags(&s->slot[k].end, cudaEventBlockingSync));
    }
    return s;
fail:
    cr_gpu_session_free(s);
    return NULL;
}

/* Make the device hold f's sky texture (see cr_gpu_session_launch). */
static int cr_gpu_session_sky(cr_gpu_session *s, const cr_frame *f, cr_err *err)
{
    size_t bytes;
    if (!f->sky.rgb || (f->sky.rgb == s->sky_host && f->sky.width == s->sky_w &&
                        f->sky.height == s->sky_h))
        return 0;
    bytes = cr_sky_bytes(&f->sky); /* ours and the other exterior's */
    /* frames in flight may still read the texture held now */
    CR_CUDA_CHECK(cudaStreamSynchronize(s->stream));
    s->sky_host = NULL;
    if (bytes > s->d_sky_cap) {
        CR_CUDA_CHECK(cudaFree(s->d_sky));
        s->d_sky = NULL;
        s->d_sky_cap = 0;
        CR_CUDA_CHECK(cudaMalloc((void **)&s->d_sky, bytes));
        s->d_sky_cap = bytes;
    }
    /* on the session's stream, so the kernels that follow see all of it (a
     * plain cudaMemcpy from pageable memory may return before its DMA ends,
     * and the stream does not wait for the legacy default stream) */
    CR_CUDA_CHECK(
        cudaMemcpyAsync(s->d_sky, f->sky.rgb, bytes, cudaMemcpyHostToDevice, s->stream));
    s->sky_host = f->sky.rgb;
    s->sky_w = f->sky.width;
    s->sky_h = f->sky.height;
    return 0;
}

/* Make the device hold f's worldline table (particle spheres), as the sky
 * texture: uploaded when the host table or its length changes (a scene's
 * table is the same for all its frames). */
static int cr_gpu_session_track(cr_gpu_session *s, const cr_frame *f, cr_err *err)
{
    size_t bytes;
    if (!f->track || f->n_track <= 0 || (f->track == s->track_host && f->n_track == s->track_n))
        return 0;
    bytes = sizeof(cr_track_point) * (size_t)f->n_track;
    /* frames in flight may still read the table held now */
    CR_CUDA_CHECK(cudaStreamSynchronize(s->stream));
    s->track_host = NULL;
    if (f->n_track > s->d_track_cap) {
        CR_CUDA_CHECK(cudaFree(s->d_track));
        s->d_track = NULL;
        s->d_track_cap = 0;
        CR_CUDA_CHECK(cudaMalloc((void **)&s->d_track, bytes));
        s->d_track_cap = f->n_track;
    }
    CR_CUDA_CHECK(
        cudaMemcpyAsync(s->d_track, f->track, bytes, cudaMemcpyHostToDevice, s->stream));
    s->track_host = f->track;
    s->track_n = f->n_track;
    return 0;
}

/* Give slot sl room for n spheres (pinned) and n_chunks chunk events, and
 * the device room for n spheres. */
static int cr_gpu_session_room(cr_gpu_session *s, cr_gpu_slot *sl, int n, int n_chunks,
                               cr_err *err)
{
    if (n > sl->sphere_cap) {
        CR_CUDA_CHECK(cudaFreeHost(sl->spheres));
        sl->spheres = NULL;
        sl->sphere_cap = 0;
        CR_CUDA_CHECK(cudaMallocHost((void **)&sl->spheres, sizeof(cr_sphere) * n));
        sl->sphere_cap = n;
    }
    if (n > s->d_sphere_cap) {
        /* the frame in flight may still read the old array */
        CR_CUDA_CHECK(cudaStreamSynchronize(s->stream));
        CR_CUDA_CHECK(cudaFree(s->d_spheres));
        s->d_spheres = NULL;
        s->d_sphere_cap = 0;
        CR_CUDA_CHECK(cudaMalloc((void **)&s->d_spheres, sizeof(cr_sphere) * n));
        s->d_sphere_cap = n;
    }
    if (n_chunks > sl->chunk_cap) {
        cudaEvent_t *ev = (cudaEvent_t *)realloc(sl->chunk, sizeof *ev * n_chunks);
        int *rows;
        if (ev)
            sl->chunk = ev;
        rows = ev ? (int *)realloc(sl->chunk_row_end, sizeof *rows * n_chunks) : NULL;
        if (!rows)
            return cr_err_set(err, "out of memory");
        sl->chunk_row_end = rows;
        while (sl->chunk_cap < n_chunks) {
            CR_CUDA_CHECK(cudaEventCreateWithFlags(&sl->chunk[sl->chunk_cap],
                                                   cudaEventBlockingSync |
                                                       cudaEventDisableTiming));
            sl->chunk_cap++;
        }
    }
    return 0;
}

extern "C" int cr_gpu_session_launch(cr_gpu_session *s, const cr_frame *f, cr_err *err)
{
    if (!f || f->width <= 0 || f->height <= 0)
        return cr_err_set(err, "cr_gpu_render: empty frame");
    return cr_gpu_session_launch_rows(s, f, 0, f->height, err);
}

extern "C" int cr_gpu_session_launch_rows(cr_gpu_session *s, const cr_frame *f, int first,
                                          int n_rows, cr_err *err)
{
    cr_gpu_slot *sl;
    cr_frame df;
    dim3 threads, blocks;
    int rows, n_chunks, row0, c, last;
    if (!s)
        return cr_err_set(err, "cr_gpu_session_launch: no session");
    if (!f || f->width <= 0 || f->height <= 0)
        return cr_err_set(err, "cr_gpu_render: empty frame");
    if (first < 0 || n_rows < 1 || first > f->height - n_rows)
        return cr_err_set(err, "cr_gpu_session_launch_rows: rows %d to %d are not rows of a "
                               "%d-row frame",
                          first, first + n_rows - 1, f->height);
    last = first + n_rows;
    if ((size_t)f->width * (size_t)f->height > s->max_pixels)
        return cr_err_set(err, "cr_gpu_render: a %dx%d frame is larger than the session's %zu "
                               "pixels",
                          f->width, f->height, s->max_pixels);
    if (f->n_spheres < 0 || (f->n_spheres > 0 && !f->spheres))
        return cr_err_set(err, "cr_gpu_render: frame without its sphere array");
    if (f->sky.rgb && (f->sky.width <= 0 || f->sky.height <= 0))
        return cr_err_set(err, "cr_gpu_render: sky texture without a size");
    if (f->n_track < 0 || (f->n_track > 0 && !f->track))
        return cr_err_set(err, "cr_gpu_render: frame without its worldline table");
    if (s->launched - s->waited >= CR_GPU_SLOTS)
        return cr_err_set(err, "cr_gpu_session_launch: %d frames are in flight already",
                          CR_GPU_SLOTS);
    sl = &s->slot[s->launched % CR_GPU_SLOTS];
    rows = cr_gpu_rows_per_launch(s, f->width, n_rows);
    n_chunks = (n_rows + rows - 1) / rows;

    CR_CUDA_CHECK(cudaSetDevice(s->device));
    if (cr_gpu_session_sky(s, f, err) || cr_gpu_session_track(s, f, err) ||
        cr_gpu_session_room(s, sl, f->n_spheres, n_chunks, err))
        return -1;
    if (!sl->px)
        CR_CUDA_CHECK(cudaMallocHost((void **)&sl->px, sizeof(cr_pixel) * s->max_pixels));

    CR_CUDA_CHECK(cudaEventRecord(sl->start, s->stream));
    df = *f;
    if (f->n_spheres > 0) {
        memcpy(sl->spheres, f->spheres, sizeof(cr_sphere) * f->n_spheres);
        CR_CUDA_CHECK(cudaMemcpyAsync(s->d_spheres, sl->spheres,
                                      sizeof(cr_sphere) * f->n_spheres, cudaMemcpyHostToDevice,
                                      s->stream));
    }
    df.spheres = f->n_spheres > 0 ? s->d_spheres : NULL;
    df.sky.rgb = f->sky.rgb ? s->d_sky : NULL;
    df.track = f->track && f->n_track > 0 ? s->d_track : NULL;

    threads = dim3(CR_GPU_TILE_W, (unsigned)(s->block / CR_GPU_TILE_W), 1);
    for (row0 = first, c = 0; row0 < last; row0 += rows, c++) {
        int row_end = row0 + rows < last ? row0 + rows : last;
        blocks = dim3((unsigned)((f->width + CR_GPU_TILE_W - 1) / CR_GPU_TILE_W),
                      (unsigned)((row_end - row0 + (int)threads.y - 1) / (int)threads.y), 1);
        cr_gpu_trace_kernel<<<blocks, threads, 0, s->stream>>>(df, s->d_out, row0, row_end,
                                                               s->abort_dev);
        CR_CUDA_CHECK(cudaGetLastError());
        CR_CUDA_CHECK(cudaEventRecord(sl->chunk[c], s->stream));
        sl->chunk_row_end[c] = row_end - first;
    }
    CR_CUDA_CHECK(cudaEventRecord(sl->traced, s->stream));
    CR_CUDA_CHECK(cudaMemcpyAsync(sl->px, s->d_out + (size_t)first * (size_t)f->width,
                                  sizeof(cr_pixel) * (size_t)f->width * (size_t)n_rows,
                                  cudaMemcpyDeviceToHost, s->stream));
    CR_CUDA_CHECK(cudaEventRecord(sl->end, s->stream));
    sl->n_chunks = n_chunks;
    sl->height = n_rows;
    s->launched++;
    return 0;
}

extern "C" const cr_pixel *cr_gpu_session_wait(cr_gpu_session *s, cr_gpu_progress_fn progress,
                                               cr_gpu_cancel_fn cancelled, void *ctx,
                                               double *seconds, cr_err *err)
{
    cr_gpu_slot *sl;
    float ms = 0.0f, ms_trace = 0.0f;
    int c;
    if (!s || s->launched == s->waited) {
        cr_err_set(err, "cr_gpu_session_wait: no frame in flight");
        return NULL;
    }
    sl = &s->slot[s->waited % CR_GPU_SLOTS];
    if (CR_CUDA_TRY(cudaSetDevice(s->device)))
        return NULL;
    /* asked before each chunk and after the last */
    for (c = 0; c <= sl->n_chunks; c++) {
        if (cancelled && cancelled(ctx)) {
            cr_gpu_session_abort(s, err);
            cr_err_set(err, "interrupted");
            return NULL;
        }
        if (c == sl->n_chunks)
            break;
        if (CR_CUDA_TRY(cudaEventSynchronize(sl->chunk[c])))
            return NULL;
        if (progress)
            progress(ctx, sl->chunk_row_end[c], sl->height);
    }
    if (CR_CUDA_TRY(cudaEventSynchronize(sl->end)) ||
        CR_CUDA_TRY(cudaEventElapsedTime(&ms, sl->start, sl->end)) ||
        CR_CUDA_TRY(cudaEventElapsedTime(&ms_trace, sl->start, sl->traced)))
        return NULL;
    if (seconds)
        *seconds = 1e-3 * (double)ms;
    s->trace_s = 1e-3 * (double)ms_trace;
    s->copy_s = 1e-3 * (double)(ms - ms_trace);
    s->waited++;
    return sl->px;
}

extern "C" void cr_gpu_session_times(const cr_gpu_session *s, double *trace_s, double *copy_s)
{
    *trace_s = s && s->waited > 0 ? s->trace_s : 0.0;
    *copy_s = s && s->waited > 0 ? s->copy_s : 0.0;
}

extern "C" int cr_gpu_render(int device, const cr_frame *f, cr_pixel *out, cr_err *err)
{
    return cr_gpu_render_ex(device, f, out, NULL, NULL, NULL, err);
}

extern "C" int cr_gpu_render_ex(int device, const cr_frame *f, cr_pixel *out,
                                cr_gpu_progress_fn progress, cr_gpu_cancel_fn cancelled,
                                void *ctx, cr_err *err)
{
    cr_gpu_session *s;
    const cr_pixel *px = NULL;
    if (!f || !out || f->width <= 0 || f->height <= 0)
        return cr_err_set(err, "cr_gpu_render: empty frame");
    s = cr_gpu_session_create(device, (size_t)f->width * (size_t)f->height, err);
    if (!s)
        return -1;
    if (cr_gpu_session_launch(s, f, err) == 0)
        px = cr_gpu_session_wait(s, progress, cancelled, ctx, NULL, err);
    if (px)
        memcpy(out, px, sizeof(cr_pixel) * (size_t)f->width * (size_t)f->height);
    cr_gpu_session_free(s);
    return px ? 0 : -1;
}
