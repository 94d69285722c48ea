/* curray base: limits shared by every layer (configuration, backends, CLI).
 * Plain constants; no dependencies.
 */
#ifndef CR_BASE_LIMITS_H
#define CR_BASE_LIMITS_H

/* Most CUDA devices curray addresses (gpus.<n> in the configuration). */
#define CR_MAX_GPUS 64
/* Largest number of CPU worker threads (cpu.threads, -j). */
#define CR_SYSCONFIG_MAX_THREADS 4096
/* Default and limits of video.fps (frames per second). */
#define CR_VIDEO_DEFAULT_FPS 30
#define CR_VIDEO_MAX_FPS 1000

#endif
