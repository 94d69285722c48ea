/* The CUDA backend's interface in a build without CUDA. */
#include "gpu.h"

#define CR_GPU_NO_CUDA "this build of curray has no CUDA support (built without nvcc, or " \
                       "without an NVIDIA driver under CURRAY_CUDA=AUTO, or with CURRAY_CUDA=OFF; " \
                       "-DCURRAY_CUDA=ON builds it)"

int cr_gpu_built(void)
{
    return 0;
}

int cr_gpu_count(cr_err *err)
{
    cr_err_set(err, CR_GPU_NO_CUDA);
    return 0;
}

int cr_gpu_devices(cr_gpu_device *table, int max, cr_err *err)
{
    (void)table;
    (void)max;
    cr_err_set(err, CR_GPU_NO_CUDA);
    return 0;
}

int cr_gpu_usable(int device, cr_err *err)
{
    (void)device;
    cr_err_set(err, CR_GPU_NO_CUDA);
    return 0;
}

void cr_gpu_print_info(FILE *out)
{
    fprintf(out, "CUDA GPU information:\n\nThis build of curray has no CUDA support "
                 "(built without nvcc, or without an NVIDIA driver under CURRAY_CUDA=AUTO, "
                 "or with CURRAY_CUDA=OFF; -DCURRAY_CUDA=ON builds it); it renders "
                 "on the CPU.\n");
}

int cr_gpu_render(int device, const cr_frame *f, cr_pixel *out, cr_err *err)
{
    return cr_gpu_render_ex(device, f, out, NULL, NULL, NULL, err);
}

int cr_gpu_render_ex(int device, const cr_frame *f, cr_pixel *out, cr_gpu_progress_fn progress,
                     cr_gpu_cancel_fn cancelled, void *ctx, cr_err *err)
{
    (void)device;
    (void)f;
    (void)out;
    (void)progress;
    (void)cancelled;
    (void)ctx;
    return cr_err_set(err, CR_GPU_NO_CUDA);
}

cr_gpu_session *cr_gpu_session_create(int device, size_t max_pixels, cr_err *err)
{
    (void)device;
    (void)max_pixels;
    cr_err_set(err, CR_GPU_NO_CUDA);
    return NULL;
}

int cr_gpu_session_launch(cr_gpu_session *s, const cr_frame *f, cr_err *err)
{
    (void)s;
    (void)f;
    return cr_err_set(err, CR_GPU_NO_CUDA);
}

int cr_gpu_session_launch_rows(cr_gpu_session *s, const cr_frame *f, int row0, int rows,
                               cr_err *err)
{
    (void)s;
    (void)f;
    (void)row0;
    (void)rows;
    return cr_err_set(err, CR_GPU_NO_CUDA);
}

const cr_pixel *cr_gpu_session_wait(cr_gpu_session *s, cr_gpu_progress_fn progress,
                                    cr_gpu_cancel_fn cancelled, void *ctx, double *seconds,
                                    cr_err *err)
{
    (void)s;
    (void)progress;
    (void)cancelled;
    (void)ctx;
    (void)seconds;
    cr_err_set(err, CR_GPU_NO_CUDA);
    return NULL;
}

void cr_gpu_session_times(const cr_gpu_session *s, double *trace_s, double *copy_s)
{
    (void)s;
    *trace_s = *copy_s = 0.0;
}

void cr_gpu_session_free(cr_gpu_session *s)
{
    (void)s;
}
