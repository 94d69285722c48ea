/* curray cuda backend: the kernel around cr_trace_pixel, the device query of
 * -i (listing E.1) and device selection.
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

/* One thread per pixel; rows [row0, row_end) of the frame. */
__global__ void cr_gpu_trace_kernel(const cr_frame *__restrict__ f, cr_pixel *__restrict__ out,
                                    int row0, int row_end)
{
    int i = (int)(blockIdx.x * blockDim.x + threadIdx.x);
    int j = row0 + (int)(blockIdx.y * blockDim.y + threadIdx.y);
    if (i < f->width && j < row_end)
        out[(size_t)j * f->width + i] = cr_trace_pixel(f, i, j);
}

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

extern "C" int cr_gpu_render(int device, const cr_frame *f, cr_pixel *out, cr_err *err)
{
    return cr_gpu_render_ex(device, f, out, NULL, NULL, NULL, err);
}

extern "C" int cr_gpu_render_ex(int device, const cr_frame *f, cr_pixel *out,
                                cr_gpu_progress_fn progress, cr_gpu_cancel_fn cancelled,
                                void *ctx, cr_err *err)
{
    cr_frame df;
    cr_frame *d_frame = NULL;
    cr_sphere *d_spheres = NULL;
    uint8_t *d_sky = NULL;
    cr_pixel *d_out = NULL;
    size_t n_pix, sky_bytes = 0;
    int min_grid = 0, block = 0, per_sm = 0, sms = 0, rows_per_launch, row0;
    long long wave;
    dim3 threads, blocks;
    int rc = -1;

    if (!f || !out || f->width <= 0 || f->height <= 0)
        return cr_err_set(err, "cr_gpu_render: empty frame");
    if (f->n_spheres < 0 || (f->n_spheres > 0 && !f->spheres))
        return cr_err_set(err, "cr_gpu_render: frame without its sphere array");
    if (f->sky.rgb && (f->sky.width <= 0 || f->sky.height <= 0))
        return cr_err_set(err, "cr_gpu_render: sky texture without a size");
    if (!cr_gpu_usable(device, err))
        return -1;
    n_pix = (size_t)f->width * (size_t)f->height;

    CR_CUDA_CHECK(cudaSetDevice(device));

    /* Launch configuration: the block size of best occupancy, shaped as
     * tiles CR_GPU_TILE_W pixels wide. */
    CR_CUDA_CHECK(cudaOccupancyMaxPotentialBlockSize(&min_grid, &block, cr_gpu_trace_kernel, 0, 0));
    block -= block % 32;
    if (block < 32)
        block = 32;
    CR_CUDA_CHECK(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, cr_gpu_trace_kernel,
                                                                block, 0));
    CR_CUDA_CHECK(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device));
    threads = dim3(CR_GPU_TILE_W, (unsigned)(block / CR_GPU_TILE_W), 1);
    wave = (long long)(per_sm > 0 ? per_sm : 1) * (sms > 0 ? sms : 1) * block;
    /* rows per launch: a few waves of pixels, whole tiles, at most the frame
     * and within the grid's y limit */
    rows_per_launch = (int)((CR_GPU_WAVES_PER_LAUNCH * wave + f->width - 1) / f->width);
    rows_per_launch += (int)threads.y - 1;
    rows_per_launch -= rows_per_launch % (int)threads.y;
    if (rows_per_launch < (int)threads.y)
        rows_per_launch = (int)threads.y;
    if (rows_per_launch > 65535 * (int)threads.y)
        rows_per_launch = 65535 * (int)threads.y;
    if (rows_per_launch > f->height)
        rows_per_launch = f->height;

    /* the frame with device pointers, its spheres and sky, once per call */
    df = *f;
    CR_CUDA_CHECK_GOTO(cudaMalloc((void **)&d_frame, sizeof df));
    if (f->n_spheres > 0) {
        CR_CUDA_CHECK_GOTO(cudaMalloc((void **)&d_spheres, sizeof(cr_sphere) * f->n_spheres));
        CR_CUDA_CHECK_GOTO(cudaMemcpy(d_spheres, f->spheres, sizeof(cr_sphere) * f->n_spheres,
                                      cudaMemcpyHostToDevice));
    }
    df.spheres = d_spheres;
    if (f->sky.rgb) {
        sky_bytes = (size_t)3 * (size_t)f->sky.width * (size_t)f->sky.height;
        CR_CUDA_CHECK_GOTO(cudaMalloc((void **)&d_sky, sky_bytes));
        CR_CUDA_CHECK_GOTO(cudaMemcpy(d_sky, f->sky.rgb, sky_bytes, cudaMemcpyHostToDevice));
    }
    df.sky.rgb = d_sky;
    CR_CUDA_CHECK_GOTO(cudaMemcpy(d_frame, &df, sizeof df, cudaMemcpyHostToDevice));
    CR_CUDA_CHECK_GOTO(cudaMalloc((void **)&d_out, sizeof(cr_pixel) * n_pix));

    for (row0 = 0; row0 < f->height; row0 += rows_per_launch) {
        int row_end = row0 + rows_per_launch < f->height ? row0 + rows_per_launch : f->height;
        blocks = dim3((unsigned)((f->width + CR_GPU_TILE_W - 1) / CR_GPU_TILE_W),
                      (unsigned)((row_end - row0 + (int)threads.y - 1) / (int)threads.y), 1);
        cr_gpu_trace_kernel<<<blocks, threads>>>(d_frame, d_out, row0, row_end);
        CR_CUDA_CHECK_GOTO(cudaGetLastError());
        CR_CUDA_CHECK_GOTO(cudaDeviceSynchronize());
        if (progress)
            progress(ctx, row_end, f->height);
        if (cancelled && cancelled(ctx)) {
            cr_err_set(err, "interrupted");
            goto fail;
        }
    }
    CR_CUDA_CHECK_GOTO(cudaMemcpy(out, d_out, sizeof(cr_pixel) * n_pix, cudaMemcpyDeviceToHost));
    rc = 0;

fail:
    /* after a failed kernel the context may be unusable; freeing then fails
     * too, and the first error is the one reported */
    cudaFree(d_out);
    cudaFree(d_sky);
    cudaFree(d_spheres);
    cudaFree(d_frame);
    cudaGetLastError();
    return rc;
}
