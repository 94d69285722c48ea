/* curray io: the system configuration (appendix E.2).
 *
 * Built-in defaults apply to every key the file leaves out; the command line
 * overrides the file (-v -q -a). Keys: gpus.<n>.enabled, cpu.threads,
 * raytracer.integrator, raytracer.tolerance, raytracer.horizon_epsilon,
 * raytracer.step_multiplier, raytracer.max_steps, raytracer.max_turns,
 * raytracer.samples, video.fps, video.keep_frames,
 * log.verbose, log.quiet, log.keep_log, auto_accept.
 */
#ifndef CR_IO_SYSCONFIG_H
#define CR_IO_SYSCONFIG_H

#include <stddef.h>

#include "../base/error.h"
#include "../base/limits.h" /* CR_MAX_GPUS, CR_SYSCONFIG_MAX_THREADS */
#include "names.h"          /* cr_integrator_name, ... */

typedef struct cr_sysconfig {
    /* gpus: gpu_enabled[i] for device i; devices not listed are disabled,
     * except that with no gpus section at all device 0 is enabled */
    int gpu_enabled[CR_MAX_GPUS];
    int cpu_threads;        /* 0 = number of online cores */
    int integrator;         /* cr_integrator, default CR_DEFAULT_INTEGRATOR (mino) */
    double tolerance;       /* > 0, default CR_DEFAULT_TOLERANCE; mino only */
    double horizon_epsilon; /* > 0, default 0.5e-2 */
    double step_multiplier; /* > 0, default 1/32; rk4 only */
    long max_steps;         /* > 0 */
    double max_turns;       /* > 0 */
    int samples;            /* 1..CR_MAX_SAMPLES (trace.h), default 1:
                               samples x samples rays per pixel */
    int verbose, quiet, keep_log, auto_accept;
    int video_fps;          /* video.fps: frames per second of -t v videos,
                               1..CR_VIDEO_MAX_FPS (limits.h), default 30 */
    int video_keep_frames;  /* video.keep_frames: keep the PNG frames a video
                               was made from (default true) */
} cr_sysconfig;

/* Built-in defaults. */
void cr_sysconfig_defaults(cr_sysconfig *c);

/* Read a configuration file over the defaults. On failure returns -1 with a
 * message naming the file, line, column and key. *c is set to the built-in
 * defaults overlaid with the file's keys (an empty file gives the defaults);
 * on failure *c is left unchanged. */
int cr_sysconfig_load(const char *path, cr_sysconfig *c, cr_err *err);
int cr_sysconfig_load_string(const char *text, size_t len, const char *name, cr_sysconfig *c,
                             cr_err *err);

#endif
