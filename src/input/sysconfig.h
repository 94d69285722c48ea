/* curray io: the system configuration (appendix E.2).
 *
 * Built-in defaults apply to every key the file leaves out; the command line
 * overrides the file (-v -q -a). Keys: gpus.<n>.enabled, cpu.threads,
 * every key of settings.def (raytracer.integrator, raytracer.tolerance, ...),
 * video.fps, video.keep_frames, log.verbose, log.quiet, log.keep_log,
 * auto_accept.
 */
#ifndef CR_IO_SYSCONFIG_H
#define CR_IO_SYSCONFIG_H

#include <stddef.h>

#include "../base/error.h"
#include "../base/limits.h" /* CR_MAX_GPUS, CR_SYSCONFIG_MAX_THREADS */
#include "names.h"          /* cr_integrator_name, ... */
#include "settings.h"

typedef struct cr_sysconfig {
    /* gpus: gpu_enabled[i] for device i; devices not listed are disabled,
     * except that with no gpus section at all device 0 is enabled */
    int gpu_enabled[CR_MAX_GPUS];
    int cpu_threads;        /* 0 = number of online cores */
    cr_trace_settings raytracer; /* the raytracer section: one field per line of
                                    settings.def, defaults cr_trace_defaults() */
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
