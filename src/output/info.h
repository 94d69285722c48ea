/* curray io: info.txt, the readable summary of a run (README "Outputs"), and
 * the statistics of a frame that it and the console report.
 *
 * info.txt is a fixed header (version, start time, run settings, every scene
 * value, the system configuration) followed by one record per finished
 * frame, in the order the frames finished. Each record ends with the line
 * "Finished <n> of <N> frames" (plus " (run incomplete)" while n < N), so the
 * last line of the file always tells how far the run got.
 *
 * A run uses cr_info: the header is formatted once, the file appears with the
 * first finished frame (written atomically), and every further frame appends
 * its record (atomic.h: cr_appender). The cost of a frame's record does not
 * grow with the number of frames before it. */
#ifndef CR_IO_INFO_H
#define CR_IO_INFO_H

#include <stddef.h>

#include "../core/defs.h"
#include "../base/atomic.h"
#include "../base/error.h"
#include "../input/names.h" /* cr_outcome_name */
#include "../input/scene.h"
#include "../input/sysconfig.h"

/* What info.txt's Run section says of a run of one frame of an animated
 * scene: that frame is the animation's start (cr_anim_at of frame 0 of 1),
 * so the scene's "start -> end" values below were traced at their start,
 * and the values derived per frame (the Keplerian disc's r_isco, ...) are
 * that frame's. */
#define CR_INFO_ONE_FRAME_OF_ANIMATION                                                         \
    "the scene is animated, but 1 frame traces only its start (each [linear, start, end] "     \
    "at start; the values derived per frame below are that frame's); -f N > 1 traces start "   \
    "to end"

/* What info.txt and the console say after the count of rays that ended on
 * the step or turn limit (outcome "limit", painted in the scene's
 * limit_color). */
#define CR_INFO_LIMIT_ADVICE                                                                   \
    "ended on raytracer.max_steps or raytracer.max_turns and are painted in limit_color "      \
    "(yellow by default), not traced to the end; raise those limits (rays that orbit the "     \
    "photon sphere need more turns), or with integrator: rk4 use integrator: mino"

/* What info.txt and the console say after the count of rays that ended in
 * error (outcome "error": the integration met a value that is not a finite
 * number; painted in the scene's error_color). */
#define CR_INFO_ERROR_ADVICE                                                                   \
    "ended in error (the integration met a number that is not finite) and are painted in "   \
    "error_color (blue by default): their pixels show no object and their CSV values are "    \
    "not valid; lengths far from M (observer, image plane, objects) can cause it"

/* Statistics of one rendered frame, for info.txt and the console. */
typedef struct cr_frame_stats {
    double seconds;                       /* wall time of the tracing */
    long long rays;
    unsigned long long steps;             /* total RK4 steps */
    unsigned int max_steps_ray;
    double err_mean;                      /* mean over rays of their mean null error */
    double err_max;                       /* largest per-ray mean null error */
    long long counts[CR_OUT_COUNT_];      /* pixels per outcome */
    int frame;                            /* frame index k (set by the caller) */
    const char *files;                    /* lines "  frame file ..." that end the frame's record
                                             (cli/resume.h), or NULL; the caller's */
} cr_frame_stats;

void cr_frame_stats_compute(const cr_pixel *px, long long n, double seconds,
                            cr_frame_stats *st);

/* What info.txt describes besides the scene and configuration. */
typedef struct cr_run_info {
    const char *scene_path;
    const char *config_path; /* NULL: built-in defaults */
    const char *backend;     /* "cpu" or "cuda" ... */
    int width, height, frames;
    const char *output_types;
    const char *version;
    const char *hash;    /* run hash (16 hex digits; --resume checks it), or NULL */
    const char *stale;   /* frame files in the folder this run does not overwrite, or NULL */
    const char *started; /* a resumed run: the earlier run's start time, or NULL */
    /* the run's first and last frame (0 and frames - 1) as traced, for the
       values derived per frame (the Keplerian disc's ISCO, inner edge,
       efficiency and peak temperature); NULL: those lines are left out */
    const cr_frame *first, *last;
} cr_run_info;

/* info.txt of one run, open from cr_info_begin to cr_info_end. */
typedef struct cr_info {
    char *header;       /* the fixed text before the first record (owned) */
    size_t header_len;
    int frames;         /* frames of the run; 0 when not known */
    int n_done;         /* records written */
    char path[4096];
    cr_appender file;   /* closed until the first record */
} cr_info;

/* Format the header from run, scene and cfg (each may be NULL and is then
 * left out), with the current time as the start of the run. Nothing is
 * written yet: a run that finishes no frame leaves no info.txt. */
int cr_info_begin(cr_info *info, const char *dir, const cr_run_info *run,
                  const cr_scene *scene, const cr_sysconfig *cfg, cr_err *err);

/* Record one finished frame (st->frame its index). The first call writes
 * header and record atomically; later calls append the record. On failure
 * the file is as it was before the call (still a valid summary of the frames
 * recorded so far). */
int cr_info_add_frame(cr_info *info, const cr_frame_stats *st, cr_err *err);

/* fsync and close the file, free the header. Safe after a failed
 * cr_info_begin, when no frame was recorded, and on a zeroed cr_info that
 * was never begun; -1 only if the fsync or close fails. */
int cr_info_end(cr_info *info, cr_err *err);

/* A resumed run (--resume): write the header and then the records kept from
 * the earlier run, bodies[order[0..n-1]] (each a record without its
 * "Finished" line, as read back), atomically, and continue from there: the
 * next cr_info_add_frame appends with the count after them. n == 0 writes
 * nothing (the file is replaced with the first new record). */
int cr_info_resume(cr_info *info, char *const *bodies, const int *order, int n, cr_err *err);

/* The whole info.txt in one go, written atomically: the header, then
 * stats[0..n_done-1] in the given order (with several GPUs the frames need
 * not be contiguous). For a one-frame program or a test; a run of many
 * frames uses cr_info_begin / cr_info_add_frame, whose cost per frame does
 * not grow. */
int cr_info_write(const char *dir, const cr_run_info *run, const cr_scene *scene,
                  const cr_sysconfig *cfg, const cr_frame_stats *stats, int n_done,
                  cr_err *err);

#endif
