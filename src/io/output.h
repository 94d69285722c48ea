/* curray io: the per-frame output files (6.9, 6.11) and info.txt.
 * All files are written atomically (fsutil.h). */
#ifndef CR_IO_OUTPUT_H
#define CR_IO_OUTPUT_H

#include <stdio.h>

#include "../core/defs.h"
#include "error.h"
#include "scene.h"
#include "sysconfig.h"

/* Redshift colour of one pixel (6.9.1): R = 255 - 255 atan(z) 2/pi, G = 0,
 * B = 255 atan(z) 2/pi for z = omega_r/omega_s >= 0 (horizon z = 0: red);
 * green where the source lies inside the ergosphere (z = -1 on a disc or
 * sphere hit); black for the sky and for pixels without a source (error,
 * limit). */
cr_rgb cr_redshift_color(const cr_pixel *p);

/* c_<k>.png, r_<k>.png, d_<k>.csv in dir. */
int cr_output_color_png(const char *dir, int k, const cr_pixel *px, int w, int h, cr_err *err);
int cr_output_redshift_png(const char *dir, int k, const cr_pixel *px, int w, int h,
                           cr_err *err);
/* CSV columns (6.11), one row per pixel, header line first:
 * x,y,r,g,b,steps,redshift,err_mean,err_std,outcome
 * (x, y pixel coordinates from the top-left; redshift -1 where undefined;
 * outcome as the word horizon/disc/sphere/sky/error/limit). */
int cr_output_csv(const char *dir, int k, const cr_pixel *px, int w, int h, cr_err *err);
/* The same CSV text written to an open stream, then flushed and checked
 * (cr_stream_check); name is used in the error message. */
int cr_output_csv_stream(FILE *fp, const char *name, const cr_pixel *px, int w, int h,
                         cr_err *err);

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
} cr_run_info;

/* Write (or rewrite) info.txt: a readable summary of the run, the scene,
 * the settings, and each finished frame (stats[0..n_done-1], in frame order,
 * stats[i].frame its index; with several GPUs they need not be contiguous)
 * with its statistics. Rewritten after every frame so that an interrupted run keeps a
 * valid summary of what it finished. */
int cr_info_write(const char *dir, const cr_run_info *run, const cr_scene *scene,
                  const cr_sysconfig *cfg, const cr_frame_stats *stats, int n_done,
                  cr_err *err);

/* Names of outcomes as used in CSV and info.txt. */
const char *cr_outcome_name(int outcome);

#endif
